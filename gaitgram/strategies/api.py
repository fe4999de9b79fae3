"""The strategy plug-in API: ask for genomes, tell what the pipeline made of them.

A run is a loop that the engine owns (:func:`gaitgram.evolution.engine.run_evolution`)::

    memory = strategy.start(context, rng)
    for each generation g = 0, 1, ...:
        genomes    = strategy.ask(context, state)          # g = state.generation + 1
        evaluated  = pipeline.evaluate(genomes, evaluator, g)
        evaluated  = what the strategy keeps, checked over the backend's horizon
        population = strategy.tell(context, state, evaluated)
        checkpoint (population, rng, history, memory)

so every strategy is scored by the same pipeline as every command, and none can
skip the checkpoint. A strategy object is stateless; what it must remember
between generations is the run's :class:`RunState`: the population it returned,
the run's generator ``rng`` (checkpointed as JSON) and ``memory``, anything
picklable the strategy keeps of its own (a library's optimiser, an archive),
pickled beside the checkpoint after every generation. Libraries draw from
generators of their own (:meth:`RunContext.generator`), never from ``rng`` and
never from NumPy's global state, so that a resumed run continues exactly where
it stopped.

The contract, checked when a checkpoint is read back: the population a
strategy returns has ``config.population`` individuals. For the budget to be
comparable across strategies (``gaitgram report`` refuses arms at different
budgets), generation 0 evaluates ``population`` genomes and every later
generation ``population - elite`` new ones (elites re-scored after a weight or
joint-freedom change come on top, as in GE).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gaitgram.backends.api import GaitStatus
from gaitgram.ge.operators import elite
from gaitgram.pipeline import Genome, Individual, Pipeline

__all__ = [
    "GenerationStats",
    "Genome",
    "RunContext",
    "RunState",
    "Strategy",
    "StrategyError",
    "elites_of",
    "generation_stats",
]


@dataclass(frozen=True)
class GenerationStats:
    generation: int
    best: float
    average: float  # over viable individuals (status ok); NaN if none
    std: float
    invalid: int  # individuals with no viable gait (invalid genome, fell, ...)
    evaluations: int  # gaits evaluated this generation
    components: Mapping[str, float] = field(default_factory=dict)  # means over viable individuals
    #: Over every individual, unviable ones at their (finite) score: the paper's "average fitness".
    average_all: float = math.nan

    def as_record(self) -> dict[str, Any]:
        return {
            "generation": self.generation,
            "best": self.best,
            "average_all": self.average_all,
            "average": self.average,
            "std": self.std,
            "invalid": self.invalid,
            "evaluations": self.evaluations,
            **{f"mean_{k}": v for k, v in sorted(self.components.items())},
        }


def generation_stats(generation: int, population: Sequence[Individual], evaluations: int) -> GenerationStats:
    fitness = np.array([i.fitness for i in population])
    viable = [i for i in population if i.evaluation.status is GaitStatus.OK]
    values = np.array([i.fitness for i in viable])
    components: dict[str, float] = {}
    for name in sorted({k for i in viable for k in i.evaluation.components}):
        components[name] = float(np.mean([i.evaluation.components.get(name, math.nan) for i in viable]))
    return GenerationStats(
        generation=generation,
        best=float(fitness.min()),
        average=float(values.mean()) if len(values) else math.nan,
        std=float(values.std()) if len(values) else math.nan,
        invalid=len(population) - len(viable),
        evaluations=evaluations,
        components=components,
        average_all=float(fitness.mean()),
    )


@dataclass
class RunState:
    """A run between two generations: what a strategy is asked from and what a checkpoint holds."""

    generation: int
    population: list[Individual]
    rng: np.random.Generator
    history: list[GenerationStats]
    #: The strategy's own state (None for GE): pickled beside the checkpoint.
    memory: Any = None

    @property
    def best(self) -> Individual:
        return min(self.population, key=lambda i: i.fitness)


def elites_of(population: Sequence[Individual], count: int) -> list[Individual]:
    """The ``count`` best individuals, best first (ties by position)."""
    return [population[i] for i in elite([i.fitness for i in population], count)]


class StrategyError(ValueError):
    """A strategy that cannot run this grammar or configuration; says why and what would work."""


@dataclass(frozen=True)
class RunContext:
    """What a strategy knows of the run it searches for."""

    pipeline: Pipeline
    run: int
    #: The run's seed; a library's generators come from :meth:`generator` and :meth:`integer_seed`.
    seed: np.random.SeedSequence
    #: Genomes the first generation starts from (another run's final population), for a strategy
    #: that ``takes_start``; empty: its own.
    start: tuple[Genome, ...] = ()

    @property
    def settings(self) -> dict[str, Any]:
        """The strategy's settings, as its spec's ``check`` normalised them."""
        return dict(self.pipeline.config.strategy_settings)

    def _child(self, stream: int) -> np.random.SeedSequence:
        # Built, not spawned: spawning counts children, so a second call would give another stream.
        return np.random.SeedSequence(self.seed.entropy, spawn_key=(*self.seed.spawn_key, 1 + stream))

    def generator(self, stream: int = 0) -> np.random.Generator:
        """A generator of the strategy's own, independent of the run's ``rng``: the same for the
        same run and ``stream``."""
        return np.random.default_rng(self._child(stream))

    def integer_seed(self, stream: int = 0) -> int:
        """An integer seed, for libraries that take one (the same for the same run and stream)."""
        return int(self._child(stream).generate_state(1, dtype=np.uint32)[0])


class Strategy(ABC):
    """A search method; one object serves every run (the state is in :class:`RunState`)."""

    def start(self, context: RunContext, rng: np.random.Generator) -> Any:
        """Before generation 0: the strategy's memory (None if it keeps none beyond the population)."""
        return None

    def restore(self, context: RunContext, memory: Any) -> Any:
        """A memory read back from a checkpoint: check it is this strategy's and reattach anything
        that was not pickled; raise :class:`StrategyError` if it cannot be used."""
        return memory

    @abstractmethod
    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        """The genomes to evaluate in generation ``state.generation + 1`` (generation 0 when
        ``state.generation`` is -1 and the population empty)."""

    @abstractmethod
    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        """Learn from ``evaluated`` (the asked genomes, in order) and return the next population."""

    def keeps(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[int]:
        """Which of ``evaluated`` (the asked genomes, scored) this strategy would hand back if told
        them now, beyond the best of them: the new members of a front, the new elites of a
        repertoire. The run checks them, and the best, over the backend's horizon first (and asks
        again if one fails), so that nothing a run hands back has fallen within it. By default
        none: an elitist strategy hands back its best."""
        return []

    def records(self, context: RunContext, state: RunState) -> dict[str, Any]:
        """JSON files for the run directory beside ``best.json`` (name -> content), rewritten after
        every generation; derived from the state, so they always agree with the checkpoint."""
        return {}
