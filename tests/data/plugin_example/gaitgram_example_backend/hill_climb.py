"""An example search strategy: a hill climber that mutates the best gaits found so far.

A complete plug-in: ``ask`` proposes genomes, the run scores them through its pipeline, ``tell``
returns the next population; ``check`` normalises the settings before anything runs. All its
randomness is the run's generator (``state.rng``), so a run resumes exactly.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from gaitgram.backends.api import SettingsError
from gaitgram.ge.operators import int_flip_mutation
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.strategies.api import Genome, RunContext, RunState, Strategy, StrategyError, elites_of
from gaitgram.strategies.common import initial_genomes
from gaitgram.strategies.registry import StrategySpec


class HillClimb(Strategy):
    """Mutate the elites in turn; keep the elites and their mutants (GE's budget per generation)."""

    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        config = context.pipeline.config
        if state.generation < 0:  # generation 0: random trees, as GE starts
            return initial_genomes(context.pipeline, state.rng, config.population)
        parents = elites_of(state.population, config.elite)
        rate = context.settings["rate"]
        size = config.representation_settings["codon_size"]  # GE's, spelt out when the run was built
        return [
            int_flip_mutation(parents[k % len(parents)].genome, state.rng, probability=rate, codon_size=size)
            for k in range(config.population - config.elite)
        ]

    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        if state.generation < 0:
            return evaluated
        return elites_of(state.population, context.pipeline.config.elite) + evaluated


def check(pipeline: Pipeline) -> Mapping[str, Any]:
    settings = dict(pipeline.config.strategy_settings)
    rate = settings.pop("rate", 0.1)
    if settings:
        raise SettingsError(next(iter(settings)), "unknown hill-climb setting; its only setting is rate")
    if isinstance(rate, bool) or not isinstance(rate, int | float) or not 0 < rate <= 1:
        raise SettingsError("rate", f"must be a number in (0, 1], not {rate!r}")
    if pipeline.config.elite < 1:
        raise StrategyError("hill-climb climbs from the elites: set elite to 1 or more")
    if pipeline.config.weight_schedule or any(j.free for j in pipeline.grammar.joints):
        raise StrategyError("hill-climb keeps its elites' scores: give it fixed weights and free joints")
    return {"rate": float(rate)}


STRATEGY = StrategySpec(
    name="hill-climb",
    summary="Example: mutate the best gaits found so far.",
    load=HillClimb,
    check=check,
    version="hill-climb r1",
    representations=frozenset({"ge"}),  # it flips codons: GE's genomes only
)
