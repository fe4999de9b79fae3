"""``cma-es``: CMA-ES (the ``cma`` package) over a grammar's parameter vector.

For a grammar whose derivations differ only in typed-range values
(:mod:`gaitgram.strategies.parameters`), each range read is one coordinate in
[0, 1]; CMA-ES samples vectors, each becomes the genome that picks those values,
and the pipeline scores it as any genome. A grammar with structural choices is
refused when the run is built, with the reason.

The budget is GE's: generation 0 samples ``population`` points from the
initial distribution (centre 0.5, ``sigma0``), every later generation
``population - elite`` (CMA-ES's lambda); the run's population is the best
``elite`` gaits so far and the newest sample, so its statistics compare with
GE's. CMA-ES draws its normals from a generator of its own, pickled with it,
never from NumPy's global one, and its stopping rules are not consulted: every
strategy spends the whole budget.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitgram.extras import require
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.strategies.api import Genome, RunContext, RunState, Strategy, StrategyError
from gaitgram.strategies.common import batch_size, elitist, known_keys, number, with_elites
from gaitgram.strategies.parameters import ParameterSpace, parameter_space
from gaitgram.strategies.registry import StrategySpec, library_version

#: Bumped whenever the same run could come out differently.
REVISION = 1
#: CMA-ES needs a few samples per generation to rank (and cma refuses fewer than 3).
MIN_LAMBDA = 4


class Normal:
    """``randn(*shape)`` from a generator of the run's own (cma's ``randn`` option), picklable."""

    def __init__(self, generator: np.random.Generator) -> None:
        self.generator = generator

    def __call__(self, *shape: int) -> np.ndarray:
        return self.generator.standard_normal(size=shape)


@dataclass
class CmaMemory:
    es: Any  # cma.CMAEvolutionStrategy
    #: The vectors asked for in this generation, until they are told (never checkpointed mid-way).
    pending: np.ndarray | None = None


@contextmanager
def _quiet() -> Iterator[None]:
    """cma warns when told more points than lambda (generation 0 is larger, by design)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


class CmaEs(Strategy):
    def __init__(self) -> None:
        self.cma = require("cma", "cma-es runs")

    def _space(self, context: RunContext) -> ParameterSpace:
        return parameter_space(context.pipeline, "cma-es")

    def start(self, context: RunContext, rng: np.random.Generator) -> CmaMemory:
        config = context.pipeline.config
        space = self._space(context)
        options = {
            "bounds": [0.0, 1.0],
            "popsize": config.population - config.elite,
            "randn": Normal(context.generator()),
            "seed": context.integer_seed(),
            "verbose": -9,
            "verb_disp": 0,
            "verb_log": 0,  # no outcmaes/ files in the working directory
        }
        with _quiet():
            es = self.cma.CMAEvolutionStrategy(
                np.full(space.dimension, 0.5), context.settings["sigma0"], options
            )
        return CmaMemory(es)

    def restore(self, context: RunContext, memory: Any) -> CmaMemory:
        if not isinstance(memory, CmaMemory) or not isinstance(memory.es, self.cma.CMAEvolutionStrategy):
            raise StrategyError("its strategy state is not a cma-es state")
        if self._space(context).dimension != memory.es.N:
            raise StrategyError("its cma-es state has another dimension than the grammar's parameters")
        return memory

    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        memory: CmaMemory = state.memory
        generation = state.generation + 1
        with _quiet():
            vectors = memory.es.ask(number=batch_size(context.pipeline.config, generation))
        memory.pending = np.array(vectors, dtype=float)
        space = self._space(context)
        return with_elites(state, context.pipeline, [space.genome(x) for x in memory.pending])

    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        memory: CmaMemory = state.memory
        population, new = elitist(state, context.pipeline, evaluated)
        assert memory.pending is not None
        assert len(memory.pending) == len(new)
        with _quiet():
            memory.es.tell(list(memory.pending), [i.fitness for i in new])
        memory.pending = None
        return population

    def records(self, context: RunContext, state: RunState) -> dict[str, Any]:
        """``cma.json``: the search distribution, and the values its mean stands for."""
        es = state.memory.es
        space = self._space(context)
        mean = np.clip(np.asarray(es.mean, dtype=float), 0.0, 1.0)
        return {
            "cma.json": {
                "generation": state.generation,
                "sigma": float(es.sigma),
                "dimension": space.dimension,
                "mean": [round(float(x), 6) for x in mean],
                "mean_genome": list(space.genome(mean)),
                "parameters": list(space.labels),
            }
        }


def check(pipeline: Pipeline) -> Mapping[str, Any]:
    settings = pipeline.config.strategy_settings
    known_keys(settings, ("sigma0",), "cma-es")
    sigma0 = number(settings, "sigma0", 0.3, 0.0, 1.0)
    parameter_space(pipeline, "cma-es")
    offspring = pipeline.config.population - pipeline.config.elite
    if offspring < MIN_LAMBDA:
        raise StrategyError(
            f"strategy cma-es samples population - elite = {offspring} points per generation; it needs "
            f"at least {MIN_LAMBDA}: raise population or lower elite"
        )
    return {"sigma0": sigma0}


STRATEGY = StrategySpec(
    name="cma-es",
    summary="CMA-ES over the parameter vector of a grammar whose derivations differ only in range values.",
    load=CmaEs,
    check=check,
    version=f"cma-es r{REVISION}; {library_version('cma')}",
    representations=frozenset({"ge"}),
)
