"""What several strategies share: GE's initialisation and variation, the budget, carried elites,
settings checks."""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from gaitgram.backends.api import SettingsError
from gaitgram.evolution.config import RunConfig
from gaitgram.ge.initialisation import ramped_population
from gaitgram.ge.mapper import Mapper
from gaitgram.ge.operators import Genome, int_flip_mutation, one_point_crossover
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.strategies.api import RunContext, RunState, Strategy, StrategyError, elites_of


def initial_genomes(pipeline: Pipeline, rng: np.random.Generator, size: int) -> list[Genome]:
    """``size`` genomes of random trees, as GE initialises (RampedFullGrow, Table 1)."""
    config = pipeline.config
    trees = ramped_population(
        pipeline.facts,
        rng,
        size,
        max_depth=config.init_max_depth,
        grow_probability=config.grow_probability,
        codons=config.codons,
        codon_size=config.codon_size,
        tail=config.tail,
    )
    return [t.genome for t in trees]


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


class GEVariation:
    """GE's crossover and mutation with a run's settings (Table 1), for strategies that vary
    genomes. The mapper, needed to know the codons a genome uses, is attached for each generation
    and never pickled."""

    def __init__(self, config: RunConfig) -> None:
        self.crossover = config.crossover
        self.fixed_point = config.fixed_point
        self.crossover_within_used = config.crossover_within_used
        self.mutation = config.mutation
        self.mutation_within_used = config.mutation_within_used
        self.codon_size = config.codon_size
        self.mapper: Mapper | None = None

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "mapper": None}

    def _used(self, genomes: Sequence[Genome]) -> list[int]:
        if self.mapper is None:
            raise RuntimeError("GEVariation.mapper is not attached")
        return [m.used_codons for m in self.mapper.map_many(genomes)]

    def cross(
        self,
        first: Genome,
        second: Genome,
        rng: np.random.Generator,
        used: tuple[int, int] | None = None,
    ) -> tuple[Genome, Genome]:
        """One-point crossover of two parents (whether to cross at all is the caller's draw);
        ``used``, the codons each parent's mapping reads, when the caller knows them."""
        if not self.crossover_within_used:
            used = None
        elif used is None:
            used = tuple(self._used([first, second]))  # type: ignore[assignment]
        return one_point_crossover(first, second, rng, fixed_point=self.fixed_point, used=used)

    def mutate(self, genomes: Sequence[Genome], rng: np.random.Generator) -> list[Genome]:
        """Int-flip mutation of each genome (within the codons it uses, if the run says so)."""
        used: Sequence[int | None] = (
            self._used(genomes) if self.mutation_within_used else [None] * len(genomes)
        )
        return [
            int_flip_mutation(g, rng, probability=self.mutation, codon_size=self.codon_size, used=u)
            for g, u in zip(genomes, used, strict=True)
        ]


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
