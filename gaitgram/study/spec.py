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
    config = "weights.toml"             # optional: this arm's own run.toml
    defines = { n = 5 }                 # optional: GE_RANGE values
    [arm.settings]                      # optional: keys for this arm only
    elite = 5
    [arm.settings.strategy_settings]    # optional: the strategy's own settings

A run configuration is resolved per arm in this order, each over the last:
defaults, the study's ``config`` file, the study's ``[settings]``, the arm's
``config`` file, the arm's ``[settings]``, then the command line's scale-down
flags (``--runs``, ``--generations``, ``--population``). Every key is checked
as a run.toml's is, with the file and the arm named.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gaitgram.evolution.config import ConfigError, RunConfig, config_from_mapping, read_toml
from gaitgram.strategies.registry import strategy_names

STUDY_KEYS = ("title", "runs", "seed", "config", "settings", "arm")
ARM_KEYS = ("name", "grammar", "strategy", "config", "settings", "defines")
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")
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


def load_study(path: Path, scale: ScaleDown = ScaleDown()) -> Study:
    """Read and check a study file; every arm's run configuration is resolved."""
    try:
        data = read_toml(path)
    except ConfigError as error:
        raise StudyError(str(error)) from None
    where = str(path)
    _known(data, STUDY_KEYS, where)
    base = path.parent
    title = data.get("title", path.stem)
    if not isinstance(title, str):
        raise StudyError(f"{where}: title: must be text")
    runs = scale.runs if scale.runs is not None else data.get("runs", 1)
    if isinstance(runs, bool) or not isinstance(runs, int) or not 1 <= runs <= MAX_RUNS:
        raise StudyError(f"{where}: runs: must be a whole number in [1, {MAX_RUNS}], not {runs!r}")
    seed = data.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise StudyError(f"{where}: seed: must be a whole number >= 0, not {seed!r}")
    shared = {**_config_file(data.get("config"), base, where), **_table(data, "settings", where)}
    arms_data = data.get("arm")
    if not isinstance(arms_data, list) or not arms_data:
        raise StudyError(f"{where}: a study needs at least one [[arm]] with a name and a grammar")
    arms = []
    for index, arm in enumerate(arms_data):
        arms.append(_arm(arm, index, base, where, shared, seed, runs, scale))
    names = [a.name for a in arms]
    for name in names:
        if names.count(name) > 1:
            raise StudyError(f"{where}: two arms are named {name!r}; arm names must differ")
    return Study(path, title, runs, tuple(arms))


def _arm(
    data: Any,
    index: int,
    base: Path,
    where: str,
    shared: Mapping[str, Any],
    seed: int,
    runs: int,
    scale: ScaleDown,
) -> Arm:
    if not isinstance(data, Mapping):
        raise StudyError(f"{where}: arm {index + 1} must be a table [[arm]]")
    name = data.get("name")
    label = f"{where}: arm {name!r}" if isinstance(name, str) else f"{where}: arm {index + 1}"
    _known(data, ARM_KEYS, label)
    if not isinstance(name, str) or not _NAME.match(name):
        raise StudyError(
            f"{label}: name: must be 1-64 letters, digits, '.', '_' or '-' (it names a directory), "
            f"not {name!r}"
        )
    grammar = data.get("grammar")
    if not isinstance(grammar, str) or not grammar:
        raise StudyError(f"{label}: grammar: give the grammar file, relative to the study file")
    strategy = data.get("strategy")
    if strategy is not None and strategy not in strategy_names():
        close = difflib.get_close_matches(str(strategy), strategy_names(), n=1)
        hint = f"did you mean {close[0]}? " if close else ""
        raise StudyError(
            f"{label}: strategy: {strategy!r} is not an installed strategy; {hint}"
            f"installed: {', '.join(strategy_names())}"
        )
    defines = data.get("defines", {})
    if not isinstance(defines, Mapping) or not all(
        isinstance(v, int) and not isinstance(v, bool) for v in defines.values()
    ):
        raise StudyError(f"{label}: defines: must be a table of NAME = whole number")
    values: dict[str, Any] = {"seed": seed, **shared}
    values.update(_config_file(data.get("config"), base, label))
    values.update(_table(data, "settings", label))
    if strategy is not None:
        values["strategy"] = strategy
    values["runs"] = runs
    if scale.generations is not None:
        _scale_generations(values, scale.generations)
    if scale.population is not None:
        _scale_population(values, scale.population)
    try:
        config = config_from_mapping(values, label)
    except ConfigError as error:
        raise StudyError(str(error)) from None
    return Arm(name, (base / grammar), config.strategy, config, dict(defines))


def _scale_generations(values: dict[str, Any], generations: int) -> None:
    """``--generations N``: a weight schedule's stages start at the same share of the run (the
    same design, shorter), as long as each still starts at a generation of its own."""
    old = values.get("generations", RunConfig().generations)
    schedule = values.get("weight_schedule")
    if isinstance(old, int) and old > 0 and isinstance(schedule, list):
        values["weight_schedule"] = [
            {**stage, "start": round(stage["start"] * generations / old)}
            if isinstance(stage, Mapping) and isinstance(stage.get("start"), int)
            else stage
            for stage in schedule
        ]
    values["generations"] = generations


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


def _config_file(value: Any, base: Path, where: str) -> dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, str):
        raise StudyError(f"{where}: config: give a run.toml file name")
    try:
        return read_toml(base / value)
    except ConfigError as error:
        raise StudyError(f"{where}: config: {error}") from None


def _table(data: Mapping[str, Any], key: str, where: str) -> dict[str, Any]:
    value = data.get(key, {})
    if not isinstance(value, Mapping):
        raise StudyError(f"{where}: {key}: must be a table of run.toml keys")
    return dict(value)


def _known(data: Mapping[str, Any], keys: tuple[str, ...], where: str) -> None:
    for key in data:
        if key not in keys:
            close = difflib.get_close_matches(key, keys, n=1)
            hint = f"; did you mean {close[0]}?" if close else f"; known keys: {', '.join(keys)}"
            raise StudyError(f"{where}: unknown key {key!r}{hint}")
