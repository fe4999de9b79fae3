"""Run parameters: the paper's Table 1 by default, overridable from TOML and flags.

One frozen :class:`RunConfig` is resolved before a run starts and written to
the run directory; nothing else reads parameters from anywhere (no global
parameter dict). Every key is checked when it is read, with the file and the
key named: an unknown key, a non-finite number, a value out of range or one
inconsistent with another is refused before anything runs.
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

from gaitgram.ge.mapper import CodonMode
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
    "max_wraps": (0, 1_000),
    "codon_size": (2, 2**31 - 1),
    "elite": (0, 1_000_000),
    "tournament": (1, 1_000_000),
    "init_max_depth": (1, 1_000),
    "grow_probability": (0.0, 1.0),
    "tail": (0.0, 100.0),
    "crossover": (0.0, 1.0),
    "mutation": (0.0, 1.0),
    "max_depth": (1, 100_000),
    "samples": (8, 65_536),
}


@dataclass(frozen=True)
class RunConfig:
    generations: int = 50
    population: int = 75
    runs: int = 1
    seed: int = 0
    max_wraps: int = 3
    codons: CodonMode = CodonMode.LAZY
    codon_size: int = 100_000
    elite: int = 7
    tournament: int = 3
    init_max_depth: int = 10
    grow_probability: float = 0.5
    tail: float = 0.5
    crossover: float = 0.9
    fixed_point: bool = True
    crossover_within_used: bool = True
    mutation: float = 0.02
    mutation_within_used: bool = False
    max_depth: int | None = None
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
            lines.append(f"{f.name} = {_toml_value(value)}")
        for table in ("backend_settings", "strategy_settings"):
            lines += _toml_table(table, getattr(self, table))
        for stage in self.weight_schedule:
            lines += ["", "[[weight_schedule]]", f"start = {stage.start}"]
            lines += [f"weights.{_key(k)} = {_toml_value(v)}" for k, v in stage.weights.items()]
        return "\n".join(lines) + "\n"

    def as_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data["codons"] = self.codons.value
        return data


#: Fields written as tables of their own, after the plain keys.
_TABLES = ("backend_settings", "weight_schedule", "strategy_settings")


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
NESTED = ("backend_settings", "strategy_settings")


def load_config(path: Path | None, overrides: Mapping[str, Any] | None = None) -> RunConfig:
    """Defaults, then the TOML file, then ``overrides`` (command-line flags, None = not given)."""
    data: dict[str, Any] = read_toml(path) if path is not None else {}
    where = str(path) if path is not None else "the command line"
    values: dict[str, Any] = {}
    for key, value in data.items():
        if key not in _FIELDS:
            raise ConfigError(f"{_located(path, key)}: unknown key {key!r}{_suggest(key, _FIELDS)}")
        values[key] = value
    if path is not None and isinstance(values.get("start_from"), str):  # relative to the file
        values["start_from"] = os.path.abspath(path.parent / values["start_from"])
    flags = {k: v for k, v in (overrides or {}).items() if v is not None}
    for key, value in flags.items():
        if key in NESTED:  # flags add to the file's table (one that is no table stays, refused below)
            below = values.get(key, {})
            values[key] = {**below, **value} if isinstance(below, Mapping) else below
        else:
            values[key] = value
    if path is not None and flags:
        where = f"{path} with {', '.join('--' + k.replace('_', '-') for k in flags)}"

    def locate(key: str) -> str:
        """Where a key's value came from: its flag, or its place in the file."""
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
    (``locate(key)``: a file's line and column) or else ``where``."""
    converted: dict[str, Any] = {}
    for key, value in values.items():
        here = locate(key) if locate is not None else where
        if key not in _FIELDS:
            raise ConfigError(f"{here}: unknown key {key!r}{_suggest(key, _FIELDS)}")
        if key == "weight_schedule":
            converted[key] = _schedule(value, here)
        elif key in ("backend_settings", "strategy_settings"):
            if not isinstance(value, Mapping):
                raise ConfigError(f"{here}: {key}: must be a table [{key}]")
            for name, setting in value.items():
                at = locate(f"{key}.{name}") if locate is not None else where
                _check_finite(setting, f"{at}: [{key}] {name}")
            converted[key] = dict(value)
        elif key == "codons":
            try:
                converted[key] = CodonMode(value)
            except ValueError:
                raise ConfigError(f"{here}: codons: must be 'lazy' or 'eager', not {value!r}") from None
        else:
            converted[key] = _typed(key, value, here)
    try:
        return RunConfig(**converted)
    except ConfigError as error:
        written = [locate(key) for key in error.keys if key in values] if locate is not None else []
        flags = [at for at in written if at.startswith("--")]  # a flag given overrides the file
        here = (flags or written or [where])[0]
        raise ConfigError(f"{here}: {error}", keys=error.keys) from None


def _suggest(key: str, known: Mapping[str, Any]) -> str:
    close = difflib.get_close_matches(key.replace("-", "_"), list(known), n=1, cutoff=0.75)
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
    if key in ("max_depth", "backend", "start_from") and value is None:
        return None
    expected: type = type(default) if default is not None else (int if key == "max_depth" else str)
    if expected is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if not isinstance(value, expected) or (expected is int and isinstance(value, bool)):
        article = "an" if expected.__name__[0] in "aeiou" else "a"
        raise ConfigError(f"{where}: {key}: must be {article} {expected.__name__}, not {value!r}")
    if isinstance(value, float) and not math.isfinite(value):
        raise ConfigError(f"{where}: {key}: must be a finite number, not {value}")
    if key in ("backend", "strategy", "start_from") and not value.strip():
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
        if f.name in ("backend_settings", "strategy_settings"):
            skip = ignore if f.name == "backend_settings" else frozenset()
            for key in sorted(set(a) | set(b)):
                if key not in skip and a.get(key) != b.get(key):
                    found.append(f"{f.name}.{key}: {a.get(key)!r} -> {b.get(key)!r}")
        elif a != b:
            found.append(f"{f.name}: {a!r} -> {b!r}")
    return found
