"""``ge``: the paper's grammatical evolution loop (Table 1), as :mod:`gaitgram.evolution.engine` runs it.

Ask gives the offspring of tournament selection, one-point crossover and
int-flip mutation (after the elites when their scores are stale); tell keeps
the elites and the offspring. All randomness is the run's ``rng``, so a GE run
is what it always was, checkpoint for checkpoint.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from gaitgram.evolution.engine import RunState, initial_genomes, next_population, offspring
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.strategies.api import Genome, RunContext, Strategy
from gaitgram.strategies.common import known_keys
from gaitgram.strategies.registry import StrategySpec


class GrammaticalEvolution(Strategy):
    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        if state.generation < 0:
            return initial_genomes(context.pipeline, state.rng, context.pipeline.config.population)
        return offspring(state, context.pipeline)

    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        if state.generation < 0:
            return evaluated
        return next_population(state, context.pipeline, evaluated)


def check(pipeline: Pipeline) -> Mapping[str, Any]:
    known_keys(pipeline.config.strategy_settings, (), "ge")
    return {}


STRATEGY = StrategySpec(
    name="ge",
    summary="Grammatical evolution: tournaments, one-point crossover, int-flip mutation, elitism.",
    load=GrammaticalEvolution,
    check=check,
)
