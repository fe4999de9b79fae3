"""The GE loop: initialise, evaluate, select, vary, replace; checkpoint every generation.

A run is a pure function of its config, grammar, backend and seed: all
randomness comes from one generator whose state is checkpointed with the
population, so a resumed run continues exactly where it stopped. Generation 0
is the initial population; then ``config.generations`` generations follow.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram.analysis import CheckResult
from gaitgram.backends.api import Evaluation, Evaluator, GaitStatus
from gaitgram.evolution.config import RunConfig
from gaitgram.fileio import write_atomically
from gaitgram.ge import compile_mapper
from gaitgram.ge.initialisation import ramped_population
from gaitgram.ge.operators import Genome, elite, int_flip_mutation, one_point_crossover, tournament
from gaitgram.motion.gait import motion_batch

CHECKPOINT_VERSION = 1


@dataclass(frozen=True)
class Individual:
    genome: Genome
    used_codons: int
    phenotype: str | None
    joints: Mapping[str, str]
    evaluation: Evaluation

    @property
    def fitness(self) -> float:
        return self.evaluation.fitness


@dataclass(frozen=True)
class GenerationStats:
    generation: int
    best: float
    average: float  # over viable individuals (status ok); NaN if none
    std: float
    invalid: int  # individuals with no viable gait (invalid genome, fell, ...)
    evaluations: int  # gaits evaluated this generation
    components: Mapping[str, float] = field(default_factory=dict)  # means over viable individuals

    def as_record(self) -> dict[str, Any]:
        return {
            "generation": self.generation,
            "best": self.best,
            "average": self.average,
            "std": self.std,
            "invalid": self.invalid,
            "evaluations": self.evaluations,
            **{f"mean_{k}": v for k, v in sorted(self.components.items())},
        }


class Problem:
    """The grammar side of a run: mapper, analyses, joints and their freedom schedule."""

    def __init__(
        self, checked: CheckResult, config: RunConfig, joint_names: Sequence[str] | None = None
    ) -> None:
        grammar = checked.grammar
        self.grammar = grammar
        self.facts = checked.facts
        self.config = config
        self.mapper = compile_mapper(
            grammar, codons=config.codons, max_wraps=config.max_wraps, max_depth=config.max_depth
        )
        self.joint_names = tuple(joint_names) if joint_names else tuple(j.joint for j in grammar.joints)
        self._freedom = {j.joint: j for j in grammar.joints}

    def frozen_at(self, generation: int) -> frozenset[str]:
        """Joints that hold neutral this generation (Table 3)."""
        return frozenset(name for name, decl in self._freedom.items() if not decl.is_free(generation))

    def evaluate(self, genomes: Sequence[Genome], evaluator: Evaluator, generation: int) -> list[Individual]:
        mapped = self.mapper.map_many(genomes)
        batch = motion_batch(
            [m.joints if m.valid else None for m in mapped],
            self.joint_names,
            units=self.grammar.units,
            n_samples=self.config.samples,
            frozen=self.frozen_at(generation),
        )
        evaluations = evaluator.evaluate(
            batch, generation=generation, weights=self.config.weights_at(generation) or None
        )
        if len(evaluations) != len(genomes):
            raise RuntimeError(
                f"the backend returned {len(evaluations)} evaluations for {len(genomes)} gaits"
            )
        return [
            Individual(tuple(g), m.used_codons, m.phenotype, m.joints, e)
            for g, m, e in zip(genomes, mapped, evaluations, strict=True)
        ]


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
    )


@dataclass
class RunState:
    generation: int
    population: list[Individual]
    rng: np.random.Generator
    history: list[GenerationStats]


def run_seed(config: RunConfig, run: int) -> np.random.SeedSequence:
    """Independent, reproducible seeds for each run of an invocation."""
    return np.random.SeedSequence(config.seed).spawn(config.runs)[run]


def initial_state(problem: Problem, evaluator: Evaluator, config: RunConfig, run: int) -> RunState:
    rng = np.random.default_rng(run_seed(config, run))
    trees = ramped_population(
        problem.facts,
        rng,
        config.population,
        max_depth=config.init_max_depth,
        grow_probability=config.grow_probability,
        codons=config.codons,
        codon_size=config.codon_size,
        tail=config.tail,
    )
    population = problem.evaluate([t.genome for t in trees], evaluator, 0)
    return RunState(0, population, rng, [generation_stats(0, population, len(population))])


def step(state: RunState, problem: Problem, evaluator: Evaluator, config: RunConfig) -> RunState:
    """One generation: tournament, crossover, mutation, evaluation, elitist generational replacement."""
    generation = state.generation + 1
    rng, population = state.rng, state.population
    fitness = [i.fitness for i in population]
    n_offspring = config.population - config.elite
    parents = tournament(fitness, rng, size=config.tournament, count=n_offspring + n_offspring % 2)
    offspring: list[Genome] = []
    for a, b in zip(parents[::2], parents[1::2], strict=True):
        first, second = population[a], population[b]
        if rng.random() < config.crossover:
            used = (first.used_codons, second.used_codons) if config.crossover_within_used else None
            child_a, child_b = one_point_crossover(
                first.genome, second.genome, rng, fixed_point=config.fixed_point, used=used
            )
        else:
            child_a, child_b = first.genome, second.genome
        offspring += [child_a, child_b]
    offspring = [
        int_flip_mutation(
            g,
            rng,
            probability=config.mutation,
            codon_size=config.codon_size,
            used=None if not config.mutation_within_used else len(g),
        )
        for g in offspring[:n_offspring]
    ]
    elites = [population[i] for i in elite(fitness, config.elite)]
    changed = problem.frozen_at(generation) != problem.frozen_at(state.generation) or config.weights_at(
        generation
    ) != config.weights_at(state.generation)
    if changed:  # the elites' scores are stale: a joint came free or the weights moved
        evaluated = problem.evaluate([i.genome for i in elites] + offspring, evaluator, generation)
        new_population = evaluated
    else:
        new_population = elites + problem.evaluate(offspring, evaluator, generation)
    evaluations = len(offspring) + (len(elites) if changed else 0)
    history = [*state.history, generation_stats(generation, new_population, evaluations)]
    return RunState(generation, new_population, rng, history)


# ---- checkpoints -------------------------------------------------------------------------


def save_checkpoint(path: Path, state: RunState, config_text: str) -> None:
    data = {
        "version": CHECKPOINT_VERSION,
        "config": config_text,
        "generation": state.generation,
        "rng": state.rng.bit_generator.state,
        "population": [
            {"genome": list(i.genome), "evaluation": i.evaluation.as_record()} for i in state.population
        ],
        "history": [s.as_record() for s in state.history],
    }
    write_atomically(path, json.dumps(data))


class CheckpointError(ValueError):
    pass


def load_checkpoint(path: Path, problem: Problem, config_text: str) -> RunState:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as error:
        raise CheckpointError(f"{path}: cannot read the checkpoint: {error}") from None
    if data.get("version") != CHECKPOINT_VERSION:
        raise CheckpointError(f"{path}: checkpoint version {data.get('version')} is not {CHECKPOINT_VERSION}")
    if data["config"] != config_text:
        raise CheckpointError(
            f"{path}: the run was started with a different configuration; resume with the same one"
        )
    rng = np.random.default_rng()
    rng.bit_generator.state = data["rng"]
    genomes = [tuple(entry["genome"]) for entry in data["population"]]
    mapped = problem.mapper.map_many(genomes)
    population = [
        Individual(g, m.used_codons, m.phenotype, m.joints, _evaluation(entry["evaluation"]))
        for g, m, entry in zip(genomes, mapped, data["population"], strict=True)
    ]
    history = [_stats(record) for record in data["history"]]
    return RunState(data["generation"], population, rng, history)


def _evaluation(record: Mapping[str, Any]) -> Evaluation:
    return Evaluation(
        record["fitness"], GaitStatus(record["status"]), dict(record["components"]), record["detail"]
    )


def _stats(record: Mapping[str, Any]) -> GenerationStats:
    components = {k.removeprefix("mean_"): v for k, v in record.items() if k.startswith("mean_")}
    return GenerationStats(
        record["generation"],
        record["best"],
        record["average"],
        record["std"],
        record["invalid"],
        record["evaluations"],
        components,
    )


def run_evolution(
    problem: Problem,
    evaluator: Evaluator,
    config: RunConfig,
    run: int,
    run_dir: Path,
    *,
    resume: bool = False,
    on_generation: Callable[[int, GenerationStats], None] | None = None,
    should_stop: Callable[[], bool] = lambda: False,
) -> RunState:
    """One run, checkpointed to ``run_dir`` after every generation; stops early if asked."""
    from gaitgram.evolution.records import write_run_records  # records depend on the engine's types

    config_text = config.to_toml()
    checkpoint = run_dir / "checkpoint.json"
    if resume and checkpoint.exists():
        state = load_checkpoint(checkpoint, problem, config_text)
    else:
        state = initial_state(problem, evaluator, config, run)
        save_checkpoint(checkpoint, state, config_text)
        write_run_records(run_dir, problem, state)
        if on_generation:
            on_generation(run, state.history[-1])
    while state.generation < config.generations and not should_stop():
        state = step(state, problem, evaluator, config)
        save_checkpoint(checkpoint, state, config_text)
        write_run_records(run_dir, problem, state)
        if on_generation:
            on_generation(run, state.history[-1])
    return state
