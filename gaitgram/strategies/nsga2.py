"""``nsga2``: multi-objective GE, pymoo's NSGA-II over the fitness components.

The paper's fitness is a weighted sum, and its authors note that similar scores
hide very different gaits. NSGA-II keeps the trade-offs instead: its objectives
are the components the backend measures (by default the ones its fitness
weighs: velocity, duty factor, stride and energy on ``mujoco-horse``), each
minimised on its own. pymoo does the non-dominated sorting, crowding and binary
tournaments; the genomes are GE's, drawn as GE initialises them (generation 0
is GE's for the same seed) and varied by GE's one-point crossover and int-flip
mutation with the run's settings. ``population - elite`` offspring per
generation keep GE's budget.

The run's population is NSGA-II's; its statistics still report the weighted
fitness, so runs compare with the other strategies. ``front.json`` in each run
directory holds the current Pareto front; ``gaitgram report`` draws it as a
pairwise scatter. Unviable gaits score ``WORST_FITNESS`` in every objective.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitgram.backends.api import WORST_FITNESS, GaitStatus, SettingsError
from gaitgram.extras import require
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.runlayout import FRONT
from gaitgram.strategies.api import Genome, RunContext, RunState, Strategy, StrategyError
from gaitgram.strategies.common import (
    GEVariation,
    component,
    initial_genomes,
    known_keys,
    names,
    reported,
    require_fixed_scores,
)
from gaitgram.strategies.registry import StrategySpec, library_version

REVISION = 1


@dataclass
class NsgaMemory:
    algorithm: Any  # pymoo NSGA2, set up
    problem: Any
    variation: GEVariation
    objectives: tuple[str, ...]
    pending: Any = None  # the asked population, until it is told


class Nsga2(Strategy):
    def __init__(self) -> None:
        require("pymoo", "nsga2 runs")

    def start(self, context: RunContext, rng: np.random.Generator) -> NsgaMemory:
        from pymoo.algorithms.moo.nsga2 import NSGA2, binary_tournament
        from pymoo.core.mating import Mating
        from pymoo.core.termination import NoTermination
        from pymoo.operators.selection.tournament import TournamentSelection

        from gaitgram.strategies.pymoo_operators import (
            GECrossover,
            GEMutation,
            GenomeProblem,
            PhenotypeDuplicates,
            as_objects,
        )

        config = context.pipeline.config
        objectives = tuple(context.settings["objectives"])
        variation = GEVariation(config.representation_settings)
        problem = GenomeProblem(len(objectives))
        algorithm = NSGA2(
            pop_size=config.population,
            n_offsprings=config.population - config.elite,
            sampling=as_objects(initial_genomes(context.pipeline, rng, config.population)),
            # Offspring are bred again (up to 100 times) until their gaits are new; generation 0 is
            # GE's initial population as drawn, duplicates and all.
            mating=Mating(
                TournamentSelection(func_comp=binary_tournament),
                GECrossover(variation),
                GEMutation(variation),
                eliminate_duplicates=PhenotypeDuplicates(variation),
                n_max_iterations=100,
            ),
            eliminate_duplicates=False,
        )
        algorithm.setup(problem, termination=NoTermination(), seed=context.integer_seed(), verbose=False)
        return NsgaMemory(algorithm, problem, variation, objectives)

    def restore(self, context: RunContext, memory: Any) -> NsgaMemory:
        if not isinstance(memory, NsgaMemory):
            raise StrategyError("its strategy state is not an nsga2 state")
        if memory.objectives != tuple(context.settings["objectives"]):
            raise StrategyError("its nsga2 state has other objectives than the run's")
        return memory

    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        memory: NsgaMemory = state.memory
        memory.variation.mapper = context.pipeline.representation.mapper  # type: ignore[attr-defined]
        try:
            memory.pending = memory.algorithm.ask()
        finally:
            memory.variation.mapper = None
        return [x[0] for x in memory.pending.get("X")]

    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        from pymoo.core.evaluator import Evaluator
        from pymoo.problems.static import StaticProblem

        memory: NsgaMemory = state.memory
        infills, memory.pending = memory.pending, None
        values = np.array([objective_values(i, memory.objectives) for i in evaluated], dtype=float)
        Evaluator().eval(StaticProblem(memory.problem, F=values), infills)
        for slot, individual in zip(infills, evaluated, strict=True):
            slot.set("individual", individual)
        memory.algorithm.tell(infills=infills)
        return [slot.get("individual") for slot in memory.algorithm.pop]

    def keeps(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[int]:
        """The new gaits no member of the current front and no other new gait dominates."""
        memory: NsgaMemory = state.memory
        new = [k for k, i in enumerate(evaluated) if i.evaluation.status is GaitStatus.OK]
        front = [] if state.generation < 0 else _front(memory)
        points = np.array(
            [objective_values(i, memory.objectives) for i in front]
            + [objective_values(evaluated[k], memory.objectives) for k in new],
            dtype=float,
        ).reshape(-1, len(memory.objectives))
        return [k for j, k in enumerate(new) if not _dominated(points, len(front) + j)]

    def records(self, context: RunContext, state: RunState) -> dict[str, Any]:
        memory: NsgaMemory = state.memory
        return {FRONT: front_record(state.generation, memory.objectives, _front(memory))}


def _front(memory: NsgaMemory) -> list[Individual]:
    """The viable members of NSGA-II's first front."""
    ranks = memory.algorithm.pop.get("rank")
    return [
        slot.get("individual")
        for slot, rank in zip(memory.algorithm.pop, ranks, strict=True)
        if rank == 0 and slot.get("individual").evaluation.status is GaitStatus.OK
    ]


def _dominated(points: np.ndarray, index: int) -> bool:
    """Whether some other point is no worse in every objective and better in one."""
    others = np.delete(points, index, axis=0)
    point = points[index]
    return bool(np.any(np.all(others <= point, axis=1) & np.any(others < point, axis=1)))


def objective_values(individual: Individual, objectives: tuple[str, ...]) -> list[float]:
    """What NSGA-II minimises for one gait: its components, or the worst score if it is unviable."""
    if individual.evaluation.status is not GaitStatus.OK:
        return [WORST_FITNESS] * len(objectives)
    return [component(individual, name) for name in objectives]


def front_record(generation: int, objectives: tuple[str, ...], front: list[Individual]) -> dict[str, Any]:
    ordered = sorted(front, key=lambda i: objective_values(i, objectives))
    return {
        "generation": generation,
        "objectives": list(objectives),
        "front": [
            {
                "objectives": objective_values(i, objectives),
                "fitness": i.fitness,
                "components": dict(i.evaluation.components),
                "cycles": {name: list(values) for name, values in i.evaluation.cycles.items()},
                "genome": list(i.genome),
                "phenotype": i.phenotype,
            }
            for i in ordered
        ],
    }


def default_objectives(pipeline: Pipeline) -> list[str]:
    spec, settings = pipeline.spec, pipeline.config.backend_settings
    if spec.objectives is not None:
        return list(spec.objectives(settings))
    if spec.weight_names is not None:
        return sorted(spec.weight_names(settings))
    raise SettingsError(
        "objectives",
        f"backend {spec.name!r} does not say which components to minimise; name two or more: "
        'objectives = ["a", "b"]',
    )


def check(pipeline: Pipeline) -> Mapping[str, Any]:
    settings = pipeline.config.strategy_settings
    known_keys(settings, ("objectives",), "nsga2")
    default = [] if "objectives" in settings else default_objectives(pipeline)
    objectives = names(settings, "objectives", default)
    if len(objectives) < 2:
        raise SettingsError("objectives", f"nsga2 needs two or more objectives, not {objectives!r}")
    for index, name in enumerate(objectives):
        reported(pipeline, name, f"objectives[{index}]")
    require_fixed_scores(pipeline, "nsga2", "its population")
    return {"objectives": objectives}


STRATEGY = StrategySpec(
    name="nsga2",
    summary="Multi-objective GE: pymoo's NSGA-II over the fitness components, GE's variation.",
    load=Nsga2,
    check=check,
    version=f"nsga2 r{REVISION}; {library_version('pymoo')}",
    representations=frozenset({"ge"}),
)
