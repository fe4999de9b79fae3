"""``random``: random search at GE's budget, genomes drawn as the representation initialises them.

Generation 0 is the ``ge`` strategy's initial population (the same seed gives the same one);
every later generation draws ``population - elite`` fresh genomes (GE: ramped trees) and keeps
the best ``elite`` found so far, so the two differ only in variation and selection: the baseline
that tells whether they help.
"""

from __future__ import annotations

from gaitgram.strategies.api import Genome, RunContext, RunState
from gaitgram.strategies.common import Elitist, batch_size, initial_genomes, no_settings, with_elites
from gaitgram.strategies.registry import StrategySpec


class RandomSearch(Elitist):
    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        pipeline = context.pipeline
        fresh = initial_genomes(pipeline, state.rng, batch_size(pipeline.config, state.generation + 1))
        return with_elites(state, pipeline, fresh)


STRATEGY = StrategySpec(
    name="random",
    summary="Random search: fresh random genomes every generation at GE's budget, the best kept.",
    load=RandomSearch,
    check=no_settings("random"),
)
