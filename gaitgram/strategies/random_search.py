"""``random``: random search at GE's budget, genomes drawn as GE's initialisation draws them.

Generation 0 is GE's initial population (the same seed gives the same one);
every later generation draws ``population - elite`` fresh ramped trees and
keeps the best ``elite`` found so far, so the two differ only in GE's
variation and selection: the baseline that tells whether they help.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from gaitgram.pipeline import Individual, Pipeline
from gaitgram.strategies.api import Genome, RunContext, RunState, Strategy
from gaitgram.strategies.common import batch_size, elitist, initial_genomes, known_keys, with_elites
from gaitgram.strategies.registry import StrategySpec


class RandomSearch(Strategy):
    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        pipeline = context.pipeline
        fresh = initial_genomes(pipeline, state.rng, batch_size(pipeline.config, state.generation + 1))
        return with_elites(state, pipeline, fresh)

    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        return elitist(state, context.pipeline, evaluated)[0]


def check(pipeline: Pipeline) -> Mapping[str, Any]:
    known_keys(pipeline.config.strategy_settings, (), "random")
    return {}


STRATEGY = StrategySpec(
    name="random",
    summary="Random search: fresh random trees every generation at GE's budget, the best kept.",
    load=RandomSearch,
    check=check,
)
