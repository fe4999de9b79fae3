"""The GE loop: initialise, evaluate, select, vary, replace; checkpoint every generation.

A run is a pure function of its pipeline (grammar, config, backend) and seed:
all randomness comes from one generator whose state is checkpointed with the
population, so a resumed run continues exactly where it stopped. Generation 0
is the initial population; then ``config.generations`` generations follow.

A checkpoint is untrusted input when it is read back: it carries a digest of
its content and the fingerprint of the run it belongs to, and every field is
checked, so a hand-edited, truncated or foreign checkpoint is refused as
corrupt instead of resuming into different results.

The loop itself (:func:`run_evolution`) drives any search strategy
(:mod:`gaitgram.strategies`) by ask and tell; GE's own generation is
:func:`initial_state` and :func:`step`. A strategy's memory (a library's
optimiser state) is pickled beside the checkpoint, in a file named by the
generation, and the checkpoint records that file's digest: a kill between the
two writes leaves the previous checkpoint naming the previous file, intact.
Unpickling runs code, so resume only run directories you made or trust.
"""

from __future__ import annotations

import hashlib
import json
import math
import pickle
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram import jsonio
from gaitgram.backends.api import Evaluation, Evaluator, GaitStatus, VerifyingEvaluator
from gaitgram.fileio import write_atomically
from gaitgram.ge.initialisation import ramped_population
from gaitgram.ge.operators import Genome, elite, int_flip_mutation, one_point_crossover, tournament
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.strategies.api import RunContext, Strategy, StrategyError

__all__ = [
    "ENGINE_REVISION",
    "CheckpointError",
    "GenerationStats",
    "Individual",
    "RunState",
    "advance",
    "begin",
    "elites_of",
    "generation_stats",
    "initial_genomes",
    "initial_state",
    "load_checkpoint",
    "next_population",
    "offspring",
    "run_evolution",
    "run_seed",
    "save_checkpoint",
    "scores_change",
    "step",
    "verify_kept",
]

#: Bumped whenever the same pipeline and seed could give a different run (operators, selection,
#: initialisation, statistics). Run directories record it; another revision is not resumed.
ENGINE_REVISION = 1
CHECKPOINT_VERSION = 2
#: Candidates for the backend's verdict (walks) checked over its horizon per generation, best
#: first, until one passes: bounds the cost when candidates fail the check.
MAX_CANDIDATE_CHECKS = 3
#: Longest genome a checkpoint may hold: far beyond what initialisation and crossover make.
MAX_CHECKPOINT_GENOME = 10_000_000


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
    generation: int
    population: list[Individual]
    rng: np.random.Generator
    history: list[GenerationStats]
    #: The strategy's own state (None for GE): pickled beside the checkpoint.
    memory: Any = None

    @property
    def best(self) -> Individual:
        return min(self.population, key=lambda i: i.fitness)


def run_seed(seed: int, runs: int, run: int) -> np.random.SeedSequence:
    """Independent, reproducible seeds for each run of an invocation (run ``i`` of any count is the
    same: ``spawn`` keys children by index)."""
    return np.random.SeedSequence(seed).spawn(runs)[run]


def initial_state(pipeline: Pipeline, evaluator: Evaluator, run: int) -> RunState:
    """GE's generation 0: a ramped population, evaluated."""
    config = pipeline.config
    rng = np.random.default_rng(run_seed(config.seed, config.runs, run))
    population = pipeline.evaluate(initial_genomes(pipeline, rng, config.population), evaluator, 0)
    return RunState(0, population, rng, [generation_stats(0, population, len(population))])


def initial_genomes(pipeline: Pipeline, rng: np.random.Generator, size: int) -> list[Genome]:
    """``size`` genomes of random trees, as GE initialises (RampedFullGrow, Table 1)."""
    config = pipeline.config
    trees = ramped_population(
        pipeline.facts,
        rng,
        size,
        max_depth=config.init_max_depth,
        grow_probability=config.grow_probability,
        codons=config.codons,
        codon_size=config.codon_size,
        tail=config.tail,
    )
    return [t.genome for t in trees]


def step(state: RunState, pipeline: Pipeline, evaluator: Evaluator) -> RunState:
    """One generation: tournament, crossover, mutation, evaluation, elitist generational replacement."""
    generation = state.generation + 1
    genomes = offspring(state, pipeline)
    evaluated = pipeline.evaluate(genomes, evaluator, generation)
    new_population = next_population(state, pipeline, evaluated)
    history = [*state.history, generation_stats(generation, new_population, len(genomes))]
    return RunState(generation, new_population, state.rng, history)


def scores_change(pipeline: Pipeline, generation: int) -> bool:
    """Whether the same gait scores differently in ``generation`` than in the one before (a joint
    came free or the weights moved), so that individuals carried over must be scored again."""
    return pipeline.frozen_at(generation) != pipeline.frozen_at(generation - 1) or pipeline.weights_at(
        generation
    ) != pipeline.weights_at(generation - 1)


def offspring(state: RunState, pipeline: Pipeline) -> list[Genome]:
    """What GE evaluates in the next generation: the offspring, after the elites when their
    scores are stale (:func:`scores_change`)."""
    config = pipeline.config
    rng, population = state.rng, state.population
    fitness = [i.fitness for i in population]
    n_offspring = config.population - config.elite
    parents = tournament(fitness, rng, size=config.tournament, count=n_offspring + n_offspring % 2)
    children: list[Genome] = []
    for a, b in zip(parents[::2], parents[1::2], strict=True):
        first, second = population[a], population[b]
        if rng.random() < config.crossover:
            used = (first.used_codons, second.used_codons) if config.crossover_within_used else None
            child_a, child_b = one_point_crossover(
                first.genome, second.genome, rng, fixed_point=config.fixed_point, used=used
            )
        else:
            child_a, child_b = first.genome, second.genome
        children += [child_a, child_b]
    children = children[:n_offspring]
    # Within used: only the codons a child's own mapping reads may flip (PonyGE2's within_used).
    used_counts: list[int | None] = (
        [m.used_codons for m in pipeline.map(children)]
        if config.mutation_within_used
        else [None] * len(children)
    )
    children = [
        int_flip_mutation(g, rng, probability=config.mutation, codon_size=config.codon_size, used=used)
        for g, used in zip(children, used_counts, strict=True)
    ]
    if scores_change(pipeline, state.generation + 1):
        return [i.genome for i in elites_of(state.population, config.elite)] + children
    return children


def elites_of(population: Sequence[Individual], count: int) -> list[Individual]:
    """The ``count`` best individuals, best first (ties by position)."""
    return [population[i] for i in elite([i.fitness for i in population], count)]


def next_population(state: RunState, pipeline: Pipeline, evaluated: list[Individual]) -> list[Individual]:
    """Elitist generational replacement: the elites, then the evaluated offspring (the elites are
    among ``evaluated`` when :func:`offspring` asked for them to be scored again)."""
    if scores_change(pipeline, state.generation + 1):
        return evaluated
    return elites_of(state.population, pipeline.config.elite) + evaluated


# ---- checkpoints -------------------------------------------------------------------------


class CheckpointError(ValueError):
    """A checkpoint that cannot be resumed: unreadable, corrupt, or another run's."""


def _digest(content: Mapping[str, Any]) -> str:
    text = json.dumps(content, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


#: The file a strategy's memory is pickled to, beside the checkpoint: one per generation.
_MEMORY_FILE = re.compile(r"^strategy-[0-9]{6}\.pickle$")


def save_checkpoint(path: Path, state: RunState, *, fingerprint: str, run: int) -> None:
    """The state, atomically; a strategy's memory first, to a file of its own that the checkpoint
    names with its digest (older such files are removed once the checkpoint names the new one)."""
    memory: dict[str, str] | None = None
    if state.memory is not None:
        blob = pickle.dumps(state.memory, protocol=pickle.HIGHEST_PROTOCOL)
        name = f"strategy-{state.generation:06d}.pickle"
        write_atomically(path.parent / name, blob)
        memory = {"file": name, "sha256": hashlib.sha256(blob).hexdigest()}
    content = jsonio.finite_or_none(
        {
            "version": CHECKPOINT_VERSION,
            "fingerprint": fingerprint,
            "run": run,
            "generation": state.generation,
            "rng": state.rng.bit_generator.state,
            "population": [
                {"genome": list(i.genome), "evaluation": i.evaluation.as_record()} for i in state.population
            ],
            "history": [s.as_record() for s in state.history],
        }
    )
    if memory is not None:  # absent for GE: its checkpoints are what they always were
        content["strategy_state"] = memory
    write_atomically(path, jsonio.dumps({"digest": _digest(content), "checkpoint": content}))
    for stale in path.parent.glob("strategy-*.pickle"):
        if memory is None or stale.name != memory["file"]:
            stale.unlink(missing_ok=True)


def load_checkpoint(
    path: Path,
    pipeline: Pipeline,
    *,
    fingerprint: str | tuple[str, ...],
    run: int,
    with_memory: bool = True,
) -> RunState:
    """Read a checkpoint back, trusting nothing in it. ``with_memory=False`` leaves a strategy's
    pickled memory unread (None): enough to read the population, without the strategy's library.
    ``fingerprint`` may name several: the run's, and what the same run was fingerprinted as before
    (``RunDirectory.fingerprints``)."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as error:
        raise CheckpointError(f"{path}: cannot read the checkpoint: {error}") from None
    except json.JSONDecodeError as error:
        raise CheckpointError(f"{path}: corrupt checkpoint (not JSON: {error})") from None
    try:
        state = _checked_state(data, pipeline, fingerprint, run)
        if with_memory:
            state.memory = _memory(data["checkpoint"].get("strategy_state"), path.parent)
        return state
    except _Corrupt as problem:
        raise CheckpointError(
            f"{path}: corrupt checkpoint: {problem}; it cannot be resumed (restore it from a backup, "
            "or start the run again)"
        ) from None


class _Corrupt(Exception):
    pass


def _expect(condition: bool, problem: str) -> None:
    if not condition:
        raise _Corrupt(problem)


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _checked_state(data: Any, pipeline: Pipeline, fingerprint: str | tuple[str, ...], run: int) -> RunState:
    config = pipeline.config
    _expect(isinstance(data, dict) and set(data) == {"digest", "checkpoint"}, "not a gaitgram checkpoint")
    content = data["checkpoint"]
    _expect(isinstance(content, dict), "not a gaitgram checkpoint")
    version = content.get("version")
    _expect(version == CHECKPOINT_VERSION, f"format version {version!r}, expected {CHECKPOINT_VERSION}")
    _expect(data["digest"] == _digest(content), "its content does not match its digest (edited or damaged)")
    accepted = (fingerprint,) if isinstance(fingerprint, str) else fingerprint
    _expect(content.get("fingerprint") in accepted, "it belongs to another run (fingerprint differs)")
    _expect(content.get("run") == run, f"it is run {content.get('run')!r}'s, not run {run}'s")
    generation = content.get("generation")
    _expect(
        _is_int(generation) and 0 <= generation <= config.generations,
        f"generation {generation!r} is outside the run's 0..{config.generations}",
    )
    rng = np.random.default_rng()
    try:
        rng.bit_generator.state = content.get("rng")
    except (TypeError, ValueError, KeyError, OverflowError):
        raise _Corrupt("its random generator state is malformed") from None

    entries = content.get("population")
    _expect(
        isinstance(entries, list) and len(entries) == config.population,
        f"the population has {len(entries) if isinstance(entries, list) else 'no'} individuals, "
        f"the run {config.population}",
    )
    genomes: list[Genome] = []
    evaluations: list[Evaluation] = []
    for i, entry in enumerate(entries):
        _expect(isinstance(entry, dict), f"individual {i} is not a record")
        genome = entry.get("genome")
        _expect(
            isinstance(genome, list) and 0 < len(genome) <= MAX_CHECKPOINT_GENOME,
            f"individual {i} has no genome",
        )
        _expect(
            all(_is_int(c) and 0 <= c < config.codon_size for c in genome),
            f"individual {i}'s genome has codons outside [0, {config.codon_size})",
        )
        genomes.append(tuple(genome))
        evaluations.append(_evaluation(entry.get("evaluation"), i))
    mapped = pipeline.map(genomes)
    population = [
        Individual(g, m.used_codons, m.phenotype, m.joints, e)
        for g, m, e in zip(genomes, mapped, evaluations, strict=True)
    ]
    records = content.get("history")
    _expect(
        isinstance(records, list) and len(records) == generation + 1,
        f"the history does not cover generations 0..{generation}",
    )
    history = [_stats(record, index) for index, record in enumerate(records)]
    _expect(
        history[-1].best == min(e.fitness for e in evaluations),
        "the history's last best is not the population's best",
    )
    return RunState(generation, population, rng, history)


def _memory(record: Any, directory: Path) -> Any:
    """The strategy's memory that a (digest-checked) checkpoint names, checked against its digest."""
    if record is None:
        return None
    _expect(
        isinstance(record, dict)
        and isinstance(record.get("file"), str)
        and _MEMORY_FILE.match(record["file"]) is not None
        and isinstance(record.get("sha256"), str),
        "its strategy state record is malformed",
    )
    try:
        blob = (directory / record["file"]).read_bytes()
    except OSError as error:
        raise _Corrupt(
            f"its strategy state {record['file']} cannot be read ({error.strerror or error})"
        ) from None
    _expect(
        hashlib.sha256(blob).hexdigest() == record["sha256"],
        f"its strategy state {record['file']} does not match its digest (edited or damaged)",
    )
    try:
        return pickle.loads(blob)
    except Exception as error:  # an unpickling failure can be any exception
        raise _Corrupt(f"its strategy state {record['file']} cannot be unpickled ({error})") from None


def _evaluation(record: Any, index: int) -> Evaluation:
    _expect(isinstance(record, dict), f"individual {index} has no evaluation")
    fitness, status = record.get("fitness"), record.get("status")
    components, detail = record.get("components"), record.get("detail")
    _expect(_is_number(fitness) and math.isfinite(fitness), f"individual {index}'s fitness is not a number")
    _expect(status in {s.value for s in GaitStatus}, f"individual {index}'s status {status!r} is unknown")
    _expect(
        isinstance(components, dict)
        and all(isinstance(k, str) and _is_number(v) and math.isfinite(v) for k, v in components.items()),
        f"individual {index}'s components are not finite numbers",
    )
    _expect(detail is None or isinstance(detail, str), f"individual {index}'s detail is not text")
    cycles = record.get("cycles", {})
    _expect(
        isinstance(cycles, dict)
        and all(
            isinstance(k, str) and isinstance(v, list) and all(_is_number(x) and math.isfinite(x) for x in v)
            for k, v in cycles.items()
        ),
        f"individual {index}'s per-cycle measures are not lists of finite numbers",
    )
    return Evaluation(
        float(fitness),
        GaitStatus(status),
        dict(components),
        detail,
        {k: tuple(float(x) for x in v) for k, v in cycles.items()},
    )


def _stats(record: Any, index: int) -> GenerationStats:
    _expect(isinstance(record, dict), f"history entry {index} is not a record")
    _expect(record.get("generation") == index, f"history entry {index} is for another generation")
    number = {k: record.get(k) for k in ("best", "average", "std", "average_all")}
    for key, value in number.items():
        _expect(value is None or _is_number(value), f"history entry {index}: {key} is not a number")
    counts = {k: record.get(k) for k in ("invalid", "evaluations")}
    for key, value in counts.items():
        _expect(_is_int(value) and value >= 0, f"history entry {index}: {key} is not a count")
    components = {}
    for key, value in record.items():
        if key.startswith("mean_"):
            _expect(value is None or _is_number(value), f"history entry {index}: {key} is not a number")
            components[key.removeprefix("mean_")] = math.nan if value is None else float(value)
    return GenerationStats(
        index,
        *(math.nan if number[k] is None else float(number[k]) for k in ("best", "average", "std")),
        counts["invalid"],
        counts["evaluations"],
        components,
        math.nan if number["average_all"] is None else float(number["average_all"]),
    )


def advance(strategy: Strategy, context: RunContext, state: RunState, evaluator: Evaluator) -> RunState:
    """One generation of any strategy: ask, evaluate through the run's pipeline, check what it would
    keep over the backend's horizon, tell."""
    pipeline = context.pipeline
    generation = state.generation + 1
    genomes = strategy.ask(context, state)
    evaluated = pipeline.evaluate(genomes, evaluator, generation)
    evaluated = verify_kept(strategy, context, state, evaluated, evaluator)
    population = strategy.tell(context, state, evaluated)
    if len(population) != pipeline.config.population:
        raise StrategyError(
            f"strategy {pipeline.config.strategy!r} returned a population of {len(population)}, "
            f"not the run's {pipeline.config.population}"
        )
    history = [*state.history, generation_stats(generation, population, len(genomes))]
    return RunState(generation, population, state.rng, history, state.memory)


def verify_kept(
    strategy: Strategy,
    context: RunContext,
    state: RunState,
    evaluated: list[Individual],
    evaluator: Evaluator,
) -> list[Individual]:
    """``evaluated`` with what the strategy would keep, and the best candidate for the backend's
    verdict (the best walk), checked over the backend's horizon: what fails is unviable before the
    strategy is told, and the next best is checked in its place. So a run's best, front and
    repertoire, and the walk ``--walk`` hands back, have all passed the check. Candidates for the
    verdict are checked at most ``MAX_CANDIDATE_CHECKS`` a generation."""
    if not isinstance(evaluator, VerifyingEvaluator):
        return evaluated
    pipeline = context.pipeline
    generation = state.generation + 1
    found = list(evaluated)
    checked: set[int] = set()

    def check(indices: list[int]) -> None:
        for k, individual in zip(
            indices, pipeline.verify([found[k].genome for k in indices], evaluator, generation), strict=True
        ):
            found[k] = individual
            checked.add(k)

    def kept() -> set[int]:
        viable = [k for k, i in enumerate(found) if i.evaluation.status.viable]
        best = {min(viable, key=lambda k: (found[k].fitness, k))} if viable else set()
        return best | set(strategy.keeps(context, state, found))

    while pending := sorted(kept() - checked):
        check(pending)
    verdict = pipeline.spec.verdict
    if verdict is not None:
        candidates = sorted(
            (k for k, i in enumerate(found) if verdict.candidate(i.evaluation)),
            key=lambda k: (found[k].fitness, k),
        )
        tries = 0
        for k in candidates:
            if k not in checked:
                if tries == MAX_CANDIDATE_CHECKS:
                    break
                check([k])
                tries += 1
            if verdict.holds(found[k].evaluation):
                break
    return found


def begin(strategy: Strategy, context: RunContext, evaluator: Evaluator) -> RunState:
    """Generation 0 of any strategy, from the run's seed."""
    rng = np.random.default_rng(context.seed)
    memory = strategy.start(context, rng)
    return advance(strategy, context, RunState(-1, [], rng, [], memory), evaluator)


def run_evolution(
    pipeline: Pipeline,
    evaluator: Evaluator,
    run: int,
    run_dir: Path,
    *,
    fingerprint: str,
    earlier_fingerprints: tuple[str, ...] = (),
    resume: bool = False,
    on_generation: Callable[[int, GenerationStats], None] | None = None,
    should_stop: Callable[[], bool] = lambda: False,
) -> RunState:
    """One run of the config's strategy, checkpointed to ``run_dir`` after every generation; stops
    early if asked. A checkpoint under one of ``earlier_fingerprints`` (the same run, as an older
    gaitgram fingerprinted it) resumes too; what is saved carries ``fingerprint``."""
    from gaitgram.evolution.records import write_run_records  # records depend on the engine's types
    from gaitgram.strategies.registry import load_strategy

    config = pipeline.config
    strategy = load_strategy(pipeline)
    context = RunContext(pipeline, run, run_seed(config.seed, config.runs, run))
    checkpoint = run_dir / "checkpoint.json"

    def record(state: RunState) -> None:
        save_checkpoint(checkpoint, state, fingerprint=fingerprint, run=run)
        write_run_records(run_dir, pipeline, state)
        for name, content in strategy.records(context, state).items():
            write_atomically(run_dir / name, jsonio.dumps(content, indent=1) + "\n")
        if on_generation:
            on_generation(run, state.history[-1])

    if resume and checkpoint.exists():
        accepted = (fingerprint, *earlier_fingerprints)
        state = load_checkpoint(checkpoint, pipeline, fingerprint=accepted, run=run)
        try:
            state.memory = strategy.restore(context, state.memory)
        except StrategyError as error:
            raise CheckpointError(f"{checkpoint}: {error}; it cannot be resumed") from None
    else:
        state = begin(strategy, context, evaluator)
        record(state)
    while state.generation < config.generations and not should_stop():
        state = advance(strategy, context, state, evaluator)
        record(state)
    return state
