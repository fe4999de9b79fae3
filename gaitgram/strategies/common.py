"""What several strategies share: the representation's initialisation, GE's variation (for the
strategies that search GE's codons), the budget, carried elites, settings checks."""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from gaitgram.backends.api import SettingsError
from gaitgram.configuration import RunConfig
from gaitgram.ge.classic import Variation
from gaitgram.pipeline import Genome, Individual, Pipeline
from gaitgram.strategies.api import RunContext, RunState, Strategy, StrategyError, elites_of

#: GE's crossover and mutation with a run's settings, under the name ``nsga2`` and ``map-elites``
#: pickled it by (their pickled state holds one).
GEVariation = Variation


def initial_genomes(pipeline: Pipeline, rng: np.random.Generator, size: int) -> list[Genome]:
    """``size`` genomes of a first generation, as the run's representation initialises them
    (GE: RampedFullGrow, Table 1)."""
    return pipeline.representation.initialise(rng, size)


def batch_size(config: RunConfig, generation: int) -> int:
    """New gaits a strategy evaluates in ``generation``: GE's budget, the same for every strategy
    (the population, then the offspring: ``population - elite``)."""
    return config.population if generation == 0 else config.population - config.elite


def with_elites(state: RunState, pipeline: Pipeline, new: list[Genome]) -> list[Genome]:
    """``new``, after the elites' genomes when their scores are stale (a weight or joint-freedom
    change, as GE re-scores them)."""
    if state.generation >= 0 and pipeline.scores_change(state.generation + 1):
        return [i.genome for i in elites_of(state.population, pipeline.config.elite)] + new
    return new


def elitist(
    state: RunState, pipeline: Pipeline, evaluated: list[Individual]
) -> tuple[list[Individual], list[Individual]]:
    """(the next population: the best ``elite`` so far, then the new gaits; the new gaits alone),
    for what :func:`with_elites` asked."""
    if state.generation < 0:
        return evaluated, evaluated
    elites = elites_of(state.population, pipeline.config.elite)
    if pipeline.scores_change(state.generation + 1):
        return evaluated, evaluated[len(elites) :]
    return elites + evaluated, evaluated


class Elitist(Strategy):
    """A strategy whose next population is the best ``elite`` so far and the new gaits
    (:func:`elitist`), for genomes asked with :func:`with_elites`: ``ge`` and ``random``."""

    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        return elitist(state, context.pipeline, evaluated)[0]


def require_fixed_scores(pipeline: Pipeline, strategy: str, keeps: str) -> None:
    """Refuse a run whose scores change during it (a weight schedule or a joint coming free):
    ``keeps`` would hold stale scores."""
    config = pipeline.config
    for generation in range(1, config.generations + 1):
        if pipeline.scores_change(generation):
            raise StrategyError(
                f"strategy {strategy}: the scores change at generation {generation} (a weight schedule "
                f"stage or an @joint free= annotation), and {keeps} would keep the old ones; give it "
                "fixed weights and joints free from the start, or use ge, random or cma-es"
            )


def component(individual: Individual, name: str) -> float:
    """A viable individual's fitness component ``name`` (its measurements included)."""
    value = individual.evaluation.components.get(name)
    if value is None:
        known = ", ".join(sorted(individual.evaluation.components)) or "none"
        raise StrategyError(
            f"the backend reports no component {name!r} for a viable gait; it reports: {known}"
        )
    return float(value)


# ---- settings -----------------------------------------------------------------------------------


def known_keys(settings: Mapping[str, Any], keys: Sequence[str], strategy: str) -> None:
    for key in settings:
        if key not in keys:
            known = f"its settings: {', '.join(keys)}" if keys else "it takes none"
            raise SettingsError(str(key), f"unknown setting of strategy {strategy}; {known}")


def no_settings(strategy: str) -> Callable[[Pipeline], Mapping[str, Any]]:
    """The settings check of a strategy that takes none: any setting is refused."""

    def check(pipeline: Pipeline) -> Mapping[str, Any]:
        known_keys(pipeline.config.strategy_settings, (), strategy)
        return {}

    return check


def number(settings: Mapping[str, Any], key: str, default: float, low: float, high: float) -> float:
    """A float setting in ``(low, high]``."""
    value = settings.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise SettingsError(key, f"must be a number, not {value!r}")
    if not low < value <= high:
        raise SettingsError(key, f"must be in ({low:g}, {high:g}], not {value!r}")
    return float(value)


def reported(pipeline: Pipeline, name: str, key: str) -> None:
    """Refuse a component the backend does not report, before the run starts: a misspelt
    objective or descriptor would otherwise fail at the first viable gait, files written."""
    declared = pipeline.spec.components
    if declared is None:
        return
    known = sorted(declared(pipeline.config.backend_settings))
    if name not in known:
        close = difflib.get_close_matches(name, known, n=1)
        hint = f"did you mean {close[0]}? " if close else ""
        raise SettingsError(
            key,
            f"backend {pipeline.backend!r} reports no component {name!r}; {hint}it reports: "
            f"{', '.join(known)}",
        )


def names(settings: Mapping[str, Any], key: str, default: Sequence[str]) -> list[str]:
    """A list of distinct component names."""
    value = settings.get(key, list(default))
    if not isinstance(value, list) or not value or not all(isinstance(v, str) and v for v in value):
        raise SettingsError(key, f"must be a list of component names, not {value!r}")
    if len(set(value)) != len(value):
        raise SettingsError(key, f"names a component twice: {value!r}")
    return list(value)
