"""``ge``: the paper's evolutionary loop (Table 1), the one place its generation is written, over
any representation.

Ask gives the offspring of tournament selection and the representation's variation (GE's:
one-point crossover and int-flip mutation; SGE's, DSGE's, CFG-GP's own), after the elites when
their scores are stale; tell keeps the elites and the offspring. All randomness is the run's
``rng``, so a GE run is what it always was, checkpoint for checkpoint.
"""

from __future__ import annotations

from gaitgram.ge.operators import tournament
from gaitgram.pipeline import Pipeline
from gaitgram.strategies.api import Genome, RunContext, RunState
from gaitgram.strategies.common import Elitist, initial_genomes, no_settings, with_elites
from gaitgram.strategies.registry import StrategySpec


class GrammaticalEvolution(Elitist):
    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        if state.generation < 0:
            if context.start:
                return list(context.start)
            return initial_genomes(context.pipeline, state.rng, context.pipeline.config.population)
        return offspring(state, context.pipeline)


def offspring(state: RunState, pipeline: Pipeline) -> list[Genome]:
    """The offspring: tournaments, then the representation's variation of the winners (paired in
    order), all from the run's ``rng``; after the elites when their scores are stale
    (``with_elites``)."""
    config = pipeline.config
    rng, population = state.rng, state.population
    n_offspring = config.population - config.elite
    parents = tournament(
        [i.fitness for i in population], rng, size=config.tournament, count=n_offspring + n_offspring % 2
    )
    children = pipeline.representation.vary(rng, [population[i] for i in parents], n_offspring)
    return with_elites(state, pipeline, children)


STRATEGY = StrategySpec(
    name="ge",
    summary="Grammatical evolution: tournaments, the representation's variation (GE's one-point "
    "crossover and int-flip mutation), elitism.",
    load=GrammaticalEvolution,
    check=no_settings("ge"),
    takes_start=True,
)
