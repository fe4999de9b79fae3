"""Study files: arms (grammar + run configuration + strategy) and how many runs each.

A study file is TOML::

    title = "Table 5: the five grammars"
    runs = 30                       # runs per arm
    seed = 0                        # every arm's seed, unless an arm sets its own
    config = "table1.toml"          # optional: a run.toml shared by every arm
    [settings]                      # optional: run.toml keys shared by every arm
    generations = 50

    [[arm]]
    name = "hybrid"
    grammar = "../grammars/hybrid.gg"   # paths are relative to the study file
    strategy = "ge"                     # the search strategy (default ge; docs/strategies.md)
    representation = "sge"              # what a genome is (default ge; docs/ge.md)
    config = "weights.toml"             # optional: this arm's own run.toml
    defines = { n = 5 }                 # optional: GE_RANGE values
    [arm.settings]                      # optional: keys for this arm only
    elite = 5
    [arm.settings.strategy_settings]    # optional: the strategy's own settings
    [arm.settings.representation_settings]  # optional: the representation's own settings

A run configuration is resolved per arm in this order, each over the last:
defaults, the study's ``config`` file, the study's ``[settings]``, the arm's
``config`` file, the arm's ``[settings]``, then the command line's scale-down
flags (``--runs``, ``--generations``, ``--population``) and ``--representation``, which
gives every arm that representation (an arm's representation settings are kept where it
already had it).

Everything is checked here, before anything is written: every key as a
run.toml's is, every arm's grammar, backend settings and strategy settings by
building its pipeline, and the arms' budgets against each other (a study whose
arms cannot be compared is no study). An error names the line and column of
the key at fault (in the study file, or the run.toml a ``config`` names) and
the arm, or the flag when only the flag makes it wrong.
"""

from __future__ import annotations

import difflib
import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gaitgram.configuration import (
    LIMITS,
    ConfigError,
    RunConfig,
    config_from_mapping,
    ge_setting_names,
    read_toml,
)
from gaitgram.evolution.rundir import build_pipeline
from gaitgram.evolution.transfer import TransferError, start_genomes
from gaitgram.ge.registry import DEFAULT_REPRESENTATION, representation_names
from gaitgram.language import parse
from gaitgram.language.diagnostics import TextEdit
from gaitgram.language.edits import apply_edits
from gaitgram.language.ranges import MAX_RANGE_VALUES
from gaitgram.language.source import SourceError, SourceText, read_source
from gaitgram.pipeline import Pipeline, PipelineError
from gaitgram.strategies.registry import strategy_names
from gaitgram.tomlplaces import key_location

STUDY_KEYS = ("title", "runs", "seed", "config", "settings", "arm")
ARM_KEYS = ("name", "grammar", "strategy", "representation", "config", "settings", "defines")
#: An arm's name names its directory: matched whole (``fullmatch``: ``$`` would let "a\n" through).
ARM_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}")
MAX_RUNS = 10_000


class StudyError(ValueError):
    """A study file that cannot be used; the message names the file, the arm and the key."""


@dataclass(frozen=True)
class Arm:
    name: str
    grammar: Path
    strategy: str
    config: RunConfig
    defines: Mapping[str, int]
    #: Built and checked: the grammar, the configuration, the backend's and the strategy's settings.
    pipeline: Pipeline


@dataclass(frozen=True)
class Study:
    path: Path
    title: str
    runs: int
    arms: tuple[Arm, ...]

    def arm(self, name: str) -> Arm:
        return next(a for a in self.arms if a.name == name)


@dataclass(frozen=True)
class ScaleDown:
    """The command line's flags for a quick look at a study (None: as the file says)."""

    runs: int | None = None
    generations: int | None = None
    population: int | None = None
    #: ``--representation``: every arm's representation (not a scale, but as much the command line's).
    representation: str | None = None

    @property
    def flags(self) -> str:
        """The flags given, as the user typed them (for messages)."""
        given = [("--generations", self.generations), ("--population", self.population)]
        return " ".join(f"{flag} {value}" for flag, value in given if value is not None)


def is_arm_name(name: object) -> bool:
    return isinstance(name, str) and ARM_NAME.fullmatch(name) is not None


def load_study(path: Path, scale: ScaleDown = ScaleDown()) -> Study:
    """Read and check a study file, and build every arm's pipeline."""
    try:
        data = read_toml(path)
    except ConfigError as error:
        raise StudyError(str(error)) from None
    where = str(path)

    def at(key: str) -> str:
        return key_location(path, "", key)

    _known(data, STUDY_KEYS, at)
    base = path.parent
    title = data.get("title", path.stem)
    if not isinstance(title, str):
        raise StudyError(f"{at('title')}: title: must be text")
    runs = _runs(data.get("runs", 1), f"{at('runs')}: runs")
    if scale.runs is not None:
        runs = _runs(scale.runs, "--runs")
    seed = data.get("seed", 0)
    low, high = LIMITS["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or not low <= seed <= high:
        raise StudyError(f"{at('seed')}: seed: must be a whole number in [0, {high:_}], not {seed!r}")
    shared = [
        _Source(_table(data, "settings", at, "[settings]"), lambda key: key_location(path, "settings", key)),
        _config_file(data.get("config"), base, at),
        # the study's own run keys (its seed), below every table and file: blamed on their line
        _Source({key: data[key] for key in ("seed",) if key in data}, at),
    ]
    arms_data = data.get("arm")
    if not isinstance(arms_data, list) or not arms_data:
        raise StudyError(f"{at('arm')}: a study needs at least one [[arm]] with a name and a grammar")
    names = [a.get("name") if isinstance(a, Mapping) else None for a in arms_data]
    for index, name in enumerate(names):
        if isinstance(name, str) and name in names[:index]:
            raise StudyError(
                f"{key_location(path, 'arm', 'name', item=index)}: two arms are named {name!r}; "
                "arm names must differ"
            )
    arms = [_arm(arm, index, path, shared, seed, runs, scale) for index, arm in enumerate(arms_data)]
    _check_budgets(arms, where, scale)
    return Study(path, title, runs, tuple(arms))


@dataclass(frozen=True)
class _Source:
    """Run.toml keys from one place (a study's table, or a run.toml it names), and where each is."""

    values: Mapping[str, Any]
    locate: Callable[[str], str]


def _merged(*layers: Mapping[str, Any]) -> dict[str, Any]:
    """Each layer over the last. The backend's settings are merged key by key at every depth (one
    backend scores every arm): an arm's ``backend_settings = { body = "pony" }`` keeps the study's
    weights, and its ``weights = { energy = 0.1 }`` the study's other weights. A strategy's settings
    belong to that strategy and are replaced whole."""
    merged: dict[str, Any] = {}
    for layer in layers:
        for key, value in layer.items():
            merged[key] = _deep(merged[key], value) if key == "backend_settings" and key in merged else value
    return merged


def _deep(below: Any, above: Any) -> Any:
    if not (isinstance(below, Mapping) and isinstance(above, Mapping)):
        return above  # not two tables: the upper layer's value, refused later if it is no table
    merged = dict(below)
    for key, value in above.items():
        merged[key] = _deep(below[key], value) if key in below else value
    return merged


def _located(sources: list[_Source], label: str, path: Path) -> Callable[[str], str]:
    """Where a (dotted) key of the merged configuration was written: the first source holding it
    (else the study file ``path``)."""

    def locate(key: str) -> str:
        first, *rest = key.split(".")
        for source in sources:
            value = source.values.get(first)
            if (isinstance(value, Mapping) and rest[0] in value) if rest else first in source.values:
                return f"{source.locate(key)}: {label}"
        if first == "representation_settings" and rest and rest[0] in ge_setting_names():
            return locate(rest[0])  # GE's setting, where older files write it: at the top level
        return f"{path}: {label}"

    return locate


def _runs(value: Any, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_RUNS:
        raise StudyError(f"{where}: must be a whole number in [1, {MAX_RUNS}], not {value!r}")
    return value


def _arm(
    data: Any,
    index: int,
    path: Path,
    shared: list[_Source],
    seed: int,
    runs: int,
    scale: ScaleDown,
) -> Arm:
    where = str(path)
    base = path.parent
    if not isinstance(data, Mapping):
        raise StudyError(f"{key_location(path, '', 'arm')}: arm {index + 1} must be a table [[arm]]")
    name = data.get("name")
    label = f"arm {name!r}" if isinstance(name, str) else f"arm {index + 1}"

    def at(key: str) -> str:
        """``file:line:column: arm 'name'``, the line where the arm writes ``key``, or else its
        ``[[arm]]`` (a key it lacks)."""
        where = key_location(path, "arm", key, item=index)
        if where == str(path):
            where = key_location(path, "", "arm", item=index)
        return f"{where}: {label}"

    _known(data, ARM_KEYS, at)
    if not is_arm_name(name):
        raise StudyError(
            f"{at('name')}: name: must be 1-64 letters, digits, '.', '_' or '-' (it names a directory), "
            f"not {name!r}"
        )
    assert isinstance(name, str)
    grammar = data.get("grammar")
    if not isinstance(grammar, str) or not grammar:
        raise StudyError(f"{at('grammar')}: grammar: give the grammar file, relative to the study file")
    strategy = _installed(data.get("strategy"), "strategy", strategy_names(), at)
    representation = _installed(data.get("representation"), "representation", representation_names(), at)
    defines = data.get("defines", {})
    if not isinstance(defines, Mapping) or not all(
        isinstance(v, int) and not isinstance(v, bool) for v in defines.values()
    ):
        raise StudyError(f"{at('defines')}: defines: must be a table of NAME = whole number")
    for define, value in defines.items():
        if not 1 <= value <= MAX_RANGE_VALUES:  # blamed here, where it is written, not in the grammar
            raise StudyError(
                f"{at('defines')}: defines: {define} = {value}: a GE_RANGE size must be from 1 to "
                f"{MAX_RANGE_VALUES:,}"
            )
    sources = [  # highest precedence first
        _Source(
            _table(data, "settings", at, "[arm.settings]"),
            lambda key: key_location(path, "arm.settings", key, item=index),
        ),
        _config_file(data.get("config"), base, at),
        *shared,
    ]
    own = _merged(sources[1].values, sources[0].values)
    if isinstance(own.get("start_from"), str):  # relative to the study file, as the grammar is
        own["start_from"] = os.path.abspath(base / own["start_from"])
    if strategy is not None and own.get("strategy", strategy) != strategy:
        raise StudyError(
            f"{at('strategy')}: strategy is {strategy!r}, but the arm's settings say {own['strategy']!r}; "
            "give it once"
        )
    if representation is not None and own.get("representation", representation) != representation:
        raise StudyError(
            f"{at('representation')}: representation is {representation!r}, but the arm's settings say "
            f"{own['representation']!r}; give it once"
        )
    values = _merged({"seed": seed}, sources[3].values, sources[2].values, own)
    if strategy is not None:
        values["strategy"] = strategy
    if representation is not None:
        values["representation"] = representation
    if scale.representation is not None:
        _represent(values, scale.representation, f"--representation {scale.representation} on arm {name!r}")
    values["runs"] = runs
    grammar_path = base / grammar
    try:
        source = read_source(grammar_path)
    except SourceError as error:
        raise StudyError(f"{at('grammar')}: grammar: {error}") from None
    config, pipeline = _build(values, source, defines, f"{where}: {label}", _located(sources, label, path))
    if scale.generations is not None or scale.population is not None:
        # Valid as the file says; now as the flags scale it, which are to blame for what fails.
        blame = f"{scale.flags} on arm {name!r} of {where}"
        values = dict(values)
        if scale.generations is not None:
            source = _scale_generations(values, source, defines, scale.generations, blame)
        if scale.population is not None:
            _scale_population(values, scale.population)
        config, pipeline = _build(values, source, defines, blame)
    for run in range(runs):  # every source run there and finished, before anything runs
        try:
            start_genomes(pipeline, run)
        except TransferError as error:
            raise StudyError(f"{where}: {label}: {error}") from None
    return Arm(name, grammar_path, config.strategy, config, dict(defines), pipeline)


def _installed(name: Any, kind: str, installed: tuple[str, ...], at: Callable[[str], str]) -> str | None:
    """An arm's strategy or representation: one installed, else a "did you mean"."""
    if name is None or name in installed:
        return name
    close = difflib.get_close_matches(str(name), installed, n=1)
    hint = f"did you mean {close[0]}? " if close else ""
    raise StudyError(
        f"{at(kind)}: {kind}: {name!r} is not an installed {kind}; {hint}installed: {', '.join(installed)}"
    )


def _represent(values: dict[str, Any], representation: str, blame: str) -> None:
    """``--representation``: the arm's configuration with ``representation``; its representation
    settings (GE's also where older files write them, at the top level) kept only if they are that
    representation's."""
    if representation not in representation_names():
        close = difflib.get_close_matches(representation, representation_names(), n=1)
        hint = f"did you mean {close[0]}? " if close else ""
        raise StudyError(
            f"{blame}: not an installed representation; {hint}installed: {', '.join(representation_names())}"
        )
    if values.get("representation", DEFAULT_REPRESENTATION) != representation:
        values.pop("representation_settings", None)
        for key in ge_setting_names():
            values.pop(key, None)
    values["representation"] = representation


def _build(
    values: Mapping[str, Any],
    source: SourceText,
    defines: Mapping[str, int],
    label: str,
    locate: Callable[[str], str] | None = None,
) -> tuple[RunConfig, Pipeline]:
    try:
        config = config_from_mapping(values, label, locate)
        return config, build_pipeline(source, defines, config)
    except ConfigError as error:
        raise StudyError(str(error)) from None
    except PipelineError as error:
        if error.key is not None and locate is not None:
            raise StudyError(f"{locate(error.key)}: {error}") from None
        raise StudyError(f"{label}: {error}") from None


def _check_budgets(arms: list[Arm], where: str, scale: ScaleDown) -> None:
    """A study's arms spend the same evaluations per run, or its report could compare nothing."""
    budgets = {a.config.budget for a in arms}
    if len(budgets) > 1:
        listing = ", ".join(
            f"{a.name}: {a.config.budget} ({a.config.population} + {a.config.generations} x "
            f"{a.config.population - a.config.elite})"
            for a in arms
        )
        cause = f"with {scale.flags}, " if scale.flags else ""
        raise StudyError(
            f"{where}: {cause}the arms would run at different budgets (new gaits per run, population + "
            f"generations x (population - elite): {listing}), and a report never compares arms of "
            "different budgets; give every arm the same generations, population and elite"
        )


def _scale_generations(
    values: dict[str, Any], source: SourceText, defines: Mapping[str, int], generations: int, blame: str
) -> SourceText:
    """``--generations N``: what changes by generation moves with the run (the same design,
    shorter): a weight schedule's stages and the grammar's ``@joint free=`` generations start at
    the same share of the run, rounded. Returns the grammar with its ``free=`` scaled."""
    old = values.get("generations", RunConfig().generations)
    if not isinstance(old, int) or old == generations:
        values["generations"] = generations
        return source
    schedule = values.get("weight_schedule")
    if isinstance(schedule, list):
        starts = [s.get("start") if isinstance(s, Mapping) else None for s in schedule]
        scaled = [_scaled(s, old, generations) if isinstance(s, int) else s for s in starts]
        whole = [s for s in starts if isinstance(s, int)]
        if len(set(whole)) == len(whole) and len(set(scaled)) != len(scaled):
            more = range(generations + 1, old + 1)
            enough = next((n for n in more if _distinct([_scaled(s, old, n) for s in whole])), old)
            raise StudyError(
                f"{blame}: too few generations for the arm's {len(whole)} weight stages: starting at "
                f"generations {', '.join(map(str, whole))} of {old}, they would start at "
                f"{', '.join(map(str, scaled))} of {generations}, some together; give --generations "
                f"{enough} or more"
            )
        values["weight_schedule"] = [
            {**stage, "start": start} if isinstance(stage, Mapping) else stage
            for stage, start in zip(schedule, scaled, strict=True)
        ]
    values["generations"] = generations
    return _scale_freedom(source, defines, old, generations)


def _scaled(generation: int, old: int, new: int) -> int:
    return round(generation * new / old)


def _distinct(values: list[int]) -> bool:
    return len(set(values)) == len(values)


def _scale_freedom(source: SourceText, defines: Mapping[str, int], old: int, new: int) -> SourceText:
    """The grammar with each ``@joint ... free=A..B`` scaled from ``old`` to ``new`` generations,
    and a closing comment that says so (the run directory keeps this text: what the run used)."""
    grammar = parse(source, defines=defines)
    declared = {j.rule: j for j in grammar.joints}
    edits = []
    for rule in grammar.rules:
        joint = declared.get(rule.name)
        annotation = next((a for a in rule.annotations if a.name == "joint"), None)
        argument = annotation.keyword("free") if annotation is not None else None
        if joint is None or joint.free is None or argument is None:
            continue
        low, high = joint.free
        last = "" if high is None else str(_scaled(high, old, new))
        edits.append(TextEdit(argument.span, f"free={_scaled(low, old, new)}..{last}"))
    if not edits:
        return source
    text = apply_edits(source.text, edits)
    note = (  # no path in it: the same command from another directory makes the same text
        f"# gaitgram study --generations {new}: the @joint free= generations above are scaled from "
        f"the {old} generations of the study file\n"
    )
    return SourceText(text + ("" if text.endswith("\n") else "\n") + note, source.name)


def _scale_population(values: dict[str, Any], population: int) -> None:
    """``--population N``: the elite keeps its share of the population (at least 1 if it had any)
    and a tournament never exceeds it, so a scaled-down study is the same design, smaller."""
    defaults = RunConfig()
    old = values.get("population", defaults.population)
    elite = values.get("elite", defaults.elite)
    if isinstance(old, int) and isinstance(elite, int) and old > 0:
        values["elite"] = min(population - 1, max(1 if elite else 0, round(elite * population / old)))
    tournament = values.get("tournament", defaults.tournament)
    if isinstance(tournament, int):
        values["tournament"] = min(tournament, population)
    values["population"] = population


def _config_file(value: Any, base: Path, at: Callable[[str], str]) -> _Source:
    if value is None:
        return _Source({}, lambda key: str(base))
    if not isinstance(value, str):
        raise StudyError(f"{at('config')}: config: give a run.toml file name")
    path = base / value
    try:
        data = read_toml(path)
    except ConfigError as error:
        raise StudyError(f"{at('config')}: config: {error}") from None
    if "runs" in data:
        _no_runs(f"{key_location(path, '', 'runs')} (the config of {at('config')})")
    return _Source(data, lambda key: key_location(path, "", key))


def _table(data: Mapping[str, Any], key: str, at: Callable[[str], str], header: str) -> dict[str, Any]:
    value = data.get(key, {})
    if not isinstance(value, Mapping):
        raise StudyError(f"{at(key)}: {key}: must be a table of run.toml keys")
    if "runs" in value:
        _no_runs(f"{at(key + '.runs')}: {header}")
    return dict(value)


def _no_runs(where: str) -> None:
    """``runs`` under a table would be overridden by the study's: refuse it rather than ignore it.
    (TOML puts every key after a ``[table]`` header into that table, a common slip.)"""
    raise StudyError(
        f"{where}: runs: a study's runs per arm are its top-level runs (or --runs), the same for "
        "every arm; move `runs = N` above the study's first [table], or remove it here"
    )


def _known(data: Mapping[str, Any], keys: tuple[str, ...], at: Callable[[str], str]) -> None:
    for key in data:
        if key not in keys:
            close = difflib.get_close_matches(key, keys, n=1)
            hint = f"; did you mean {close[0]}?" if close else f"; known keys: {', '.join(keys)}"
            raise StudyError(f"{at(key)}: unknown key {key!r}{hint}")
