"""Run parameters: the paper's Table 1 by default, overridable from TOML and flags.

One frozen :class:`RunConfig` is resolved before a run starts and written to
the run directory; nothing else reads parameters from anywhere (no global
parameter dict). Every key is checked when it is read, with the file and the
key named: an unknown key, a non-finite number, a value out of range or one
inconsistent with another is refused before anything runs.

What a genome is belongs to the run's representation (``representation = "sge"``, GE by default)
and its settings to ``[representation_settings]``, checked against what the representation
declares (:mod:`gaitgram.ge.registry`). GE's settings were keys of their own once (``max_wraps =
3`` at the top level): a file that writes them so still reads as it always did, as GE's settings.
"""

from __future__ import annotations

import difflib
import math
import os
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from gaitgram.backends.api import SettingsError
from gaitgram.ge.registry import (
    DEFAULT_REPRESENTATION,
    RepresentationLoadError,
    RepresentationNotFound,
    get_representation,
)
from gaitgram.language.source import describe_os_error
from gaitgram.tomlplaces import key_location


class ConfigError(ValueError):
    """A config file or flag that cannot be used; the message says where and how to fix it."""

    def __init__(self, message: str, *, keys: tuple[str, ...] = ()) -> None:
        super().__init__(message)
        #: The keys at fault, most to blame first (for a line and column once a file is known).
        self.keys = keys


@dataclass(frozen=True)
class WeightStage:
    """Fitness weights from generation ``start`` on (the paper's Table 2)."""

    start: int
    weights: Mapping[str, float]


#: Bounds that catch typos long before they cost hours or memory (inclusive).
LIMITS: dict[str, tuple[float, float]] = {
    "generations": (1, 100_000),
    "population": (2, 1_000_000),
    "runs": (1, 10_000),
    "seed": (0, 2**63 - 1),
    "elite": (0, 1_000_000),
    "tournament": (1, 1_000_000),
    "samples": (8, 65_536),
}


@dataclass(frozen=True)
class RunConfig:
    generations: int = 50
    population: int = 75
    runs: int = 1
    seed: int = 0
    elite: int = 7
    tournament: int = 3
    samples: int = 256  # samples per cycle of each joint curve
    backend: str | None = None  # None: the grammar's @backend, else mujoco-horse
    backend_settings: Mapping[str, Any] = field(default_factory=dict)
    weight_schedule: tuple[WeightStage, ...] = ()
    #: The search strategy (docs/strategies.md) and its settings; GE's loop by default.
    strategy: str = "ge"
    strategy_settings: Mapping[str, Any] = field(default_factory=dict)
    #: A run directory (or a study's arm) whose final population the first generation starts
    #: from, instead of random trees: a gait transferred to another body (seeded transfer).
    start_from: str | None = None
    #: What a genome is (docs/ge.md), GE by default, and its settings, checked against what it
    #: declares (normalised, defaults spelt out, once the run's pipeline is built).
    representation: str = DEFAULT_REPRESENTATION
    representation_settings: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for key, (low, high) in LIMITS.items():
            value = getattr(self, key)
            if value is None:
                continue
            if isinstance(value, float) and not math.isfinite(value):
                raise ConfigError(f"{key}: must be a finite number, not {value}", keys=(key,))
            if not low <= value <= high:
                raise ConfigError(
                    f"{key}: must be in [{_show(low)}, {_show(high)}], not {value}", keys=(key,)
                )
        if self.elite >= self.population:
            raise ConfigError(
                f"elite: {self.elite} elites leave no room for offspring in a population of "
                f"{self.population}; make elite smaller than population",
                keys=("elite", "population"),
            )
        if self.tournament > self.population:
            raise ConfigError(
                f"tournament: a tournament of {self.tournament} is larger than the population of "
                f"{self.population}; make it at most the population",
                keys=("tournament", "population"),
            )
        starts = [stage.start for stage in self.weight_schedule]
        if len(set(starts)) != len(starts):
            raise ConfigError(
                "weight_schedule: two stages start at the same generation", keys=("weight_schedule",)
            )
        for stage in self.weight_schedule:
            if not 0 <= stage.start <= self.generations:
                raise ConfigError(
                    f"weight_schedule: a stage starts at generation {stage.start}, outside the run's "
                    f"generations 0..{self.generations}",
                    keys=("weight_schedule", "generations"),
                )
        if self.weight_schedule and min(starts) != 0:
            raise ConfigError(
                f"weight_schedule: the first stage starts at generation {min(starts)}; start one at 0 "
                "so that every generation has stated weights",
                keys=("weight_schedule",),
            )

    @property
    def budget(self) -> int:
        """Evaluations of new genomes a run makes, whatever its strategy: the initial population,
        then every generation's offspring (elites re-scored after a schedule change are not new
        search). Runs compare only at equal budgets."""
        return self.population + self.generations * (self.population - self.elite)

    def weights_at(self, generation: int) -> dict[str, float]:
        """The weights in force at ``generation``: the last stage that has started."""
        current: dict[str, float] = {}
        for stage in sorted(self.weight_schedule, key=lambda s: s.start):
            if stage.start <= generation:
                current = dict(stage.weights)
        return current

    def to_toml(self) -> str:
        """The resolved config, as a TOML file that :func:`load_config` reads back."""
        lines = ["# gaitgram evolve: the resolved configuration of this run", ""]
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in _TABLES or value is None:
                continue
            if f.name == "strategy" and value == "ge":  # the default: a GE run's file is what it always was
                continue
            if f.name == "representation" and value == DEFAULT_REPRESENTATION:
                continue
            lines.append(f"{f.name} = {_toml_value(value)}")
        settings = {k: v for k, v in self.representation_settings.items() if v is not None}  # None: left out
        lines += _toml_table("representation_settings", settings)
        for table in ("backend_settings", "strategy_settings"):
            lines += _toml_table(table, getattr(self, table))
        for stage in self.weight_schedule:
            lines += ["", "[[weight_schedule]]", f"start = {stage.start}"]
            lines += [f"weights.{_key(k)} = {_toml_value(v)}" for k, v in stage.weights.items()]
        return "\n".join(lines) + "\n"

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


#: Fields written as tables of their own, after the plain keys.
_TABLES = ("backend_settings", "weight_schedule", "strategy_settings", "representation_settings")


def _toml_table(name: str, table: Mapping[str, Any]) -> list[str]:
    """A settings table: plain keys first, then one sub-table per nested table."""
    if not table:
        return []
    lines = ["", f"[{name}]"]
    lines += [f"{_key(k)} = {_toml_value(v)}" for k, v in table.items() if not isinstance(v, Mapping)]
    for k, v in table.items():
        if isinstance(v, Mapping):
            lines += ["", f"[{name}.{_key(k)}]"] + [f"{_key(kk)} = {_toml_value(vv)}" for kk, vv in v.items()]
    return lines


def _show(number: float) -> str:
    return f"{number:g}" if isinstance(number, float) else f"{number:,}".replace(",", "_")


def _key(key: str) -> str:
    bare = key and all(c.isascii() and (c.isalnum() or c in "_-") for c in key)
    return key if bare else _toml_string(key)


def _toml_string(text: str) -> str:
    escaped = text.replace("\\", "\\\\").replace('"', '\\"')
    escaped = "".join(c if c.isprintable() or c == " " else f"\\u{ord(c):04x}" for c in escaped)
    return '"' + escaped + '"'


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ConfigError(f"cannot write the non-finite number {value} to a config file")
        return repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{_key(str(k))} = {_toml_value(v)}" for k, v in value.items()) + " }"
    raise ConfigError(f"cannot write {value!r} to a config file")


_FIELDS = {f.name: f for f in fields(RunConfig)}


def read_toml(path: Path) -> dict[str, Any]:
    """A TOML file's table, every failure a :class:`ConfigError` naming the file."""
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ConfigError(f"{path}: not UTF-8 text") from None
    except OSError as error:
        raise ConfigError(f"{path}: cannot read: {describe_os_error(error)}") from None
    except ValueError:  # a NUL in the name: no file can have it
        raise ConfigError(f"{str(path)!r}: cannot read: a file name cannot hold a NUL character") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ConfigError(f"{path}: not valid TOML: {error}") from None


#: Tables of settings that flags and a study's layers add to key by key rather than replace.
NESTED = ("backend_settings", "strategy_settings", "representation_settings")
#: The tables of settings a plug-in declares, checked (and shown in a difference) key by key.
SETTINGS_TABLES = ("backend_settings", "strategy_settings", "representation_settings")


def load_config(path: Path | None, overrides: Mapping[str, Any] | None = None) -> RunConfig:
    """Defaults, then the TOML file, then ``overrides`` (command-line flags, None = not given)."""
    data: dict[str, Any] = read_toml(path) if path is not None else {}
    where = str(path) if path is not None else "the command line"
    values: dict[str, Any] = {}
    for key, value in data.items():
        if key not in _FIELDS and key not in ge_setting_names():
            raise ConfigError(f"{_located(path, key)}: unknown key {key!r}{_suggest(key, _FIELDS)}")
        values[key] = value
    if path is not None and isinstance(values.get("start_from"), str):  # relative to the file
        values["start_from"] = os.path.abspath(path.parent / values["start_from"])
    flags = {k: v for k, v in (overrides or {}).items() if v is not None}
    ge_keys = ge_setting_names()
    for key, value in flags.items():
        if key in NESTED:  # flags add to the file's table (one that is no table stays, refused below)
            below = values.get(key, {})
            values[key] = {**below, **value} if isinstance(below, Mapping) else below
        elif key in ge_keys and key not in values:  # a GE setting's flag (--max-wraps): into the table
            below = values.get("representation_settings", {})
            values["representation_settings"] = {**below, key: value} if isinstance(below, Mapping) else below
        else:
            values[key] = value
    if path is not None and flags:
        where = f"{path} with {', '.join('--' + k.replace('_', '-') for k in flags)}"

    def locate(key: str) -> str:
        """Where a key's value came from: its flag, or its place in the file."""
        table, _, name = key.partition(".")
        if table == "representation_settings" and name in ge_keys and name in flags:
            key = name
        if key in flags and key not in NESTED:
            return "--" + key.replace("_", "-")
        return where if path is None else _located(path, key)

    return config_from_mapping(values, where, locate)


def _located(path: Path | None, key: str) -> str:
    return "the command line" if path is None else key_location(path, "", key)


def config_from_mapping(
    values: Mapping[str, Any], where: str, locate: Callable[[str], str] | None = None
) -> RunConfig:
    """A config from plain TOML values, every key checked; errors start with where the key is
    (``locate(key)``: a file's line and column) or else ``where``. GE's settings written at the
    top level, as older files write them, are GE's ``representation_settings``."""
    values, moved = _representation_keys(values, where, locate)
    if locate is not None and moved:
        locate = _moved_located(locate, moved)
    converted: dict[str, Any] = {}
    for key, value in values.items():
        here = locate(key) if locate is not None else where
        if key not in _FIELDS:
            raise ConfigError(f"{here}: unknown key {key!r}{_suggest(key, _FIELDS)}")
        if key == "weight_schedule":
            converted[key] = _schedule(value, here)
        elif key in SETTINGS_TABLES:
            if not isinstance(value, Mapping):
                raise ConfigError(f"{here}: {key}: must be a table [{key}]")
            for name, setting in value.items() if key != "representation_settings" else ():  # (declared)
                at = locate(f"{key}.{name}") if locate is not None else where
                _check_finite(setting, f"{at}: [{key}] {name}")
            converted[key] = dict(value)
        else:
            converted[key] = _typed(key, value, here)
    if "representation_settings" in converted:
        converted["representation_settings"] = _representation_settings(converted, moved, where, locate)
    try:
        return RunConfig(**converted)
    except ConfigError as error:
        written = [locate(key) for key in error.keys if key in values] if locate is not None else []
        flags = [at for at in written if at.startswith("--")]  # a flag given overrides the file
        here = (flags or written or [where])[0]
        raise ConfigError(f"{here}: {error}", keys=error.keys) from None


def ge_setting_names() -> tuple[str, ...]:
    """GE's settings: keys of a run.toml's top level once, read as GE's representation settings."""
    return tuple(s.name for s in get_representation(DEFAULT_REPRESENTATION).settings)


def _representation_keys(
    values: Mapping[str, Any], where: str, locate: Callable[[str], str] | None
) -> tuple[dict[str, Any], tuple[str, ...]]:
    """``values`` with GE's settings written at the top level moved into ``representation_settings``
    (a GE run's; another representation's run is refused them, with the edit to make), and the
    keys moved."""
    legacy = [key for key in values if key not in _FIELDS and key in ge_setting_names()]
    if not legacy:
        return dict(values), ()
    moved = {k: v for k, v in values.items() if k not in legacy}
    representation = values.get("representation", DEFAULT_REPRESENTATION)
    first = legacy[0]
    here = locate(first) if locate is not None else where
    if representation != DEFAULT_REPRESENTATION:
        spec = _spec_or_none(representation)
        takes = spec is not None and spec.setting(first) is not None
        edit = (
            f"move it into [representation_settings] ({first} = {_toml_value(values[first])} there), "
            f"as {representation}'s {first}"
            if takes
            else f"remove it ({representation} has no setting {first})"
        )
        raise ConfigError(
            f"{here}: {first}: GE's setting, written at the top level as older files write it; this "
            f"run's representation is {representation}: {edit}",
            keys=(first,),
        )
    table = values.get("representation_settings", {})
    if isinstance(table, Mapping):
        twice = [key for key in legacy if key in table]
        if twice:
            raise ConfigError(
                f"{here}: {twice[0]}: given twice, at the top level and in [representation_settings]; "
                f"remove the top-level {twice[0]} = ...",
                keys=(twice[0],),
            )
        moved["representation_settings"] = {**{k: values[k] for k in legacy}, **table}
    return moved, tuple(legacy)


def _moved_located(locate: Callable[[str], str], moved: tuple[str, ...]) -> Callable[[str], str]:
    """``locate`` for settings moved from the top level: found where they are written."""

    def located(key: str) -> str:
        table, _, name = key.partition(".")
        return locate(name if table == "representation_settings" and name in moved else key)

    return located


def setting_location(path: Path, key: str) -> str:
    """``path:line:column`` where a run.toml writes ``key`` (dotted), a GE setting also where an
    older file writes it, at the top level."""
    at = key_location(path, "", key)
    table, _, name = key.partition(".")
    if at == str(path) and table == "representation_settings" and name in ge_setting_names():
        return key_location(path, "", name)
    return at


def _spec_or_none(name: Any) -> Any:
    try:
        return get_representation(name) if isinstance(name, str) else None
    except (RepresentationNotFound, RepresentationLoadError):
        return None


def _representation_settings(
    converted: Mapping[str, Any],
    moved: tuple[str, ...],
    where: str,
    locate: Callable[[str], str] | None,
) -> dict[str, Any]:
    """The representation's settings checked against its declaration (names, types, ranges), each
    error located where the setting is written. Unchecked when the representation is not
    installed: building the pipeline says so, naming the representation. A setting written at the
    top level (``moved``) is named as it is written."""
    name = converted.get("representation", DEFAULT_REPRESENTATION)
    spec = _spec_or_none(name)
    settings = converted["representation_settings"]
    if spec is None:
        return dict(settings)
    try:
        checked = spec.checked_settings(settings)
    except SettingsError as error:
        at = locate(f"representation_settings.{error.key}") if locate is not None else where
        table = "" if error.key in moved else "[representation_settings] "
        raise ConfigError(
            f"{at}: {table}{error.key}: {error.message}",
            keys=(f"representation_settings.{error.key}",),
        ) from None
    return {key: checked[key] for key in settings}  # as given: defaults are spelt out when built


def _suggest(key: str, known: Mapping[str, Any]) -> str:
    """A did-you-mean among the known keys and GE's settings (still read at the top level), else
    the known keys."""
    candidates = [*known, *ge_setting_names()]
    close = difflib.get_close_matches(key.replace("-", "_"), candidates, n=1, cutoff=0.75)
    return f"; did you mean {close[0]}?" if close else f"; known keys: {', '.join(sorted(known))}"


def _check_finite(value: Any, where: str) -> None:
    """TOML has ``nan`` and ``inf``: no setting means them."""
    if isinstance(value, float) and not math.isfinite(value):
        raise ConfigError(f"{where}: {value} is not a finite number")
    if isinstance(value, Mapping):
        for k, v in value.items():
            _check_finite(v, f"{where} {k}")
    elif isinstance(value, list):
        for v in value:
            _check_finite(v, where)


def _typed(key: str, value: Any, where: str) -> Any:
    default = getattr(RunConfig(), key)
    if key in ("backend", "start_from") and value is None:
        return None
    expected: type = type(default) if default is not None else str
    if expected is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if not isinstance(value, expected) or (expected is int and isinstance(value, bool)):
        article = "an" if expected.__name__[0] in "aeiou" else "a"
        raise ConfigError(f"{where}: {key}: must be {article} {expected.__name__}, not {value!r}")
    if isinstance(value, float) and not math.isfinite(value):
        raise ConfigError(f"{where}: {key}: must be a finite number, not {value}")
    if key in ("backend", "strategy", "start_from", "representation") and not value.strip():
        raise ConfigError(f"{where}: {key}: must name a {key}, not an empty string")
    return value


def _schedule(value: Any, where: str) -> tuple[WeightStage, ...]:
    if not isinstance(value, list):
        raise ConfigError(f"{where}: weight_schedule must be an array of tables [[weight_schedule]]")
    stages = []
    for i, stage in enumerate(value):
        if not isinstance(stage, Mapping):
            raise ConfigError(f"{where}: weight_schedule[{i}] must be a table with start and weights")
        unknown = set(stage) - {"start", "weights"}
        if unknown:
            raise ConfigError(
                f"{where}: weight_schedule[{i}]: unknown key {sorted(unknown)[0]!r}; a stage has only "
                "start = N and a weights table"
            )
        start, weights = stage.get("start"), stage.get("weights")
        if isinstance(start, bool) or not isinstance(start, int) or not isinstance(weights, Mapping):
            raise ConfigError(f"{where}: weight_schedule[{i}] needs start = N and a weights table")
        checked = {}
        for name, weight in weights.items():
            if isinstance(weight, bool) or not isinstance(weight, int | float):
                raise ConfigError(f"{where}: weight_schedule[{i}].weights.{name} must be a number")
            if not math.isfinite(weight) or weight < 0:
                raise ConfigError(
                    f"{where}: weight_schedule[{i}].weights.{name} must be a finite number >= 0, not {weight}"
                )
            checked[str(name)] = float(weight)
        stages.append(WeightStage(start, checked))
    return tuple(stages)


def with_overrides(config: RunConfig, **changes: Any) -> RunConfig:
    return replace(config, **{k: v for k, v in changes.items() if v is not None})


def differences(saved: RunConfig, given: RunConfig, *, ignore: frozenset[str] = frozenset()) -> list[str]:
    """``key: saved -> given`` for every field (and backend setting) where two configs differ."""
    found = []
    for f in fields(RunConfig):
        a, b = getattr(saved, f.name), getattr(given, f.name)
        if f.name in SETTINGS_TABLES:
            skip = ignore if f.name == "backend_settings" else frozenset()
            for key in sorted(set(a) | set(b)):
                if key not in skip and a.get(key) != b.get(key):
                    found.append(f"{f.name}.{key}: {a.get(key)!r} -> {b.get(key)!r}")
        elif a != b:
            found.append(f"{f.name}: {a!r} -> {b!r}")
    return found
