"""The run loop: any search strategy, generation after generation, checkpointed.

A run is a pure function of its pipeline (grammar, config, backend) and seed: all randomness
comes from the run's generator, checkpointed with the population
(:mod:`gaitgram.evolution.checkpoint`), so a resumed run continues exactly where it stopped.
Generation 0 is the initial population; then ``config.generations`` generations follow. The loop
drives every strategy (:mod:`gaitgram.strategies`) the same way, by ask and tell, and checks
what a strategy would keep over the backend's horizon before it is told (:func:`verify_kept`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from gaitgram.backends.api import Evaluator, VerifyingEvaluator
from gaitgram.evolution.checkpoint import CheckpointError, load_checkpoint, save_checkpoint
from gaitgram.evolution.records import record_text, run_records
from gaitgram.evolution.usage import (
    GenerationUsage,
    RunUsage,
    UsageError,
    metered,
    read_usage,
    recorded,
    write_usage,
)
from gaitgram.fileio import write_atomically
from gaitgram.pipeline import Genome, Individual, Pipeline
from gaitgram.runlayout import CHECKPOINT
from gaitgram.strategies.api import (
    GenerationStats,
    RunContext,
    RunState,
    Strategy,
    StrategyError,
    generation_stats,
)
from gaitgram.strategies.registry import load_strategy

__all__ = [
    "ENGINE_REVISION",
    "MAX_CANDIDATE_CHECKS",
    "advance",
    "begin",
    "run_context",
    "run_evolution",
    "run_files",
    "run_seed",
    "verify_kept",
]

#: Bumped whenever the same pipeline and seed could give a different run (operators, selection,
#: initialisation, statistics). Run directories record it; another revision is not resumed.
ENGINE_REVISION = 1
#: Candidates for the backend's verdict (walks) checked over its horizon per generation, best
#: first, until one passes: bounds the cost when candidates fail the check.
MAX_CANDIDATE_CHECKS = 3


def run_seed(seed: int, runs: int, run: int) -> np.random.SeedSequence:
    """Independent, reproducible seeds for each run of an invocation (run ``i`` of any count is the
    same: ``spawn`` keys children by index)."""
    return np.random.SeedSequence(seed).spawn(runs)[run]


def run_context(pipeline: Pipeline, run: int) -> RunContext:
    """What a strategy knows of run ``run`` of a pipeline's config: its seed among the runs'."""
    config = pipeline.config
    return RunContext(pipeline, run, run_seed(config.seed, config.runs, run))


def run_files(pipeline: Pipeline, strategy: Strategy, context: RunContext, state: RunState) -> dict[str, str]:
    """Every record file a run directory holds beside its checkpoint, derived from the state:
    statistics, the best individual, and the strategy's own records (a front, a repertoire)."""
    files = run_records(pipeline, state)
    files.update({name: record_text(content) for name, content in strategy.records(context, state).items()})
    return files


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
    start: Sequence[Genome] = (),
) -> RunState:
    """One run of the config's strategy, checkpointed to ``run_dir`` after every generation; stops
    early if asked. A checkpoint under one of ``earlier_fingerprints`` (the same run, as an older
    gaitgram fingerprinted it) resumes too; what is saved carries ``fingerprint``. ``start``: the
    genomes a new run's first generation starts from (``start_from``), if any."""
    config = pipeline.config
    strategy = load_strategy(pipeline)
    context = replace(run_context(pipeline, run), start=tuple(start))
    checkpoint = run_dir / CHECKPOINT
    meter = metered(evaluator)  # what each generation spends in the backend, kept in backend.json
    spent: list[GenerationUsage] = []

    def record(state: RunState) -> None:
        # Usage first: a kill before the checkpoint leaves an entry the resume redoes and replaces.
        spent.append(meter.take(state.generation))
        write_usage(run_dir, RunUsage(tuple(spent)))
        save_checkpoint(checkpoint, state, fingerprint=fingerprint, run=run, pipeline=pipeline)
        for name, text in run_files(pipeline, strategy, context, state).items():
            write_atomically(run_dir / name, text)
        if on_generation:
            on_generation(run, state.history[-1])

    if resume and checkpoint.exists():
        accepted = (fingerprint, *earlier_fingerprints)
        state = load_checkpoint(checkpoint, pipeline, fingerprint=accepted, run=run, with_memory=False)
        if state.generation >= config.generations:
            return state  # finished: its strategy's memory (perhaps not kept) is not needed
        state = load_checkpoint(checkpoint, pipeline, fingerprint=accepted, run=run)
        try:
            state.memory = strategy.restore(context, state.memory)
        except StrategyError as error:
            raise CheckpointError(f"{checkpoint}: {error}; it cannot be resumed") from None
        try:
            before = read_usage(run_dir)
        except UsageError:  # a damaged record of measurements: counted afresh from here
            before = None
        spent += recorded(before.generations if before else (), state.generation)
    else:
        state = begin(strategy, context, meter)
        record(state)
    while state.generation < config.generations and not should_stop():
        state = advance(strategy, context, state, meter)
        record(state)
    return state
