"""``ge``: the paper's grammatical evolution (Table 1), the one place GE's generation is written.

Ask gives the offspring of tournament selection, one-point crossover and
int-flip mutation (after the elites when their scores are stale); tell keeps
the elites and the offspring. All randomness is the run's ``rng``, so a GE run
is what it always was, checkpoint for checkpoint.
"""

from __future__ import annotations

from gaitgram.ge.operators import tournament
from gaitgram.pipeline import Pipeline
from gaitgram.strategies.api import Genome, RunContext, RunState
from gaitgram.strategies.common import Elitist, GEVariation, initial_genomes, no_settings, with_elites
from gaitgram.strategies.registry import StrategySpec


class GrammaticalEvolution(Elitist):
    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        if state.generation < 0:
            if context.start:
                return list(context.start)
            return initial_genomes(context.pipeline, state.rng, context.pipeline.config.population)
        return offspring(state, context.pipeline)


def offspring(state: RunState, pipeline: Pipeline) -> list[Genome]:
    """GE's offspring: tournaments, one-point crossover and int-flip mutation, all from the run's
    ``rng``; after the elites when their scores are stale (``with_elites``)."""
    config = pipeline.config
    rng, population = state.rng, state.population
    variation = GEVariation(config)
    variation.mapper = pipeline.mapper
    n_offspring = config.population - config.elite
    parents = tournament(
        [i.fitness for i in population], rng, size=config.tournament, count=n_offspring + n_offspring % 2
    )
    children: list[Genome] = []
    for a, b in zip(parents[::2], parents[1::2], strict=True):
        first, second = population[a], population[b]
        if rng.random() < config.crossover:
            children += variation.cross(
                first.genome, second.genome, rng, used=(first.used_codons, second.used_codons)
            )
        else:
            children += [first.genome, second.genome]
    return with_elites(state, pipeline, variation.mutate(children[:n_offspring], rng))


STRATEGY = StrategySpec(
    name="ge",
    summary="Grammatical evolution: tournaments, one-point crossover, int-flip mutation, elitism.",
    load=GrammaticalEvolution,
    check=no_settings("ge"),
    takes_start=True,
)
