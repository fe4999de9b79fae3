"""Running the runs of a run directory, one after another, resumably."""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from gaitgram import jsonio
from gaitgram.backends.api import Evaluator
from gaitgram.evolution.engine import run_evolution
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.evolution.transfer import start_genomes
from gaitgram.evolution.usage import UsageError, read_usage
from gaitgram.fileio import write_atomically
from gaitgram.runlayout import GRAMMAR, SUMMARY
from gaitgram.strategies.api import GenerationStats, RunState


def run_session(
    directory: RunDirectory,
    evaluator: Evaluator,
    *,
    resume: bool,
    on_generation: Callable[[int, GenerationStats], None] | None = None,
    on_restored: Callable[[Path], None] | None = None,
    should_stop: Callable[[], bool] = lambda: False,
) -> list[RunState]:
    """Every run of ``directory`` in order; writes ``summary.json`` when all have finished. On a
    resume, a finished run's records that disagree with its checkpoint are rewritten (each file
    is passed to ``on_restored``)."""
    config = directory.config
    states = []
    for run in range(config.runs):
        if should_stop():
            break
        state = run_evolution(
            directory.pipeline,
            evaluator,
            run,
            directory.run_dir(run),
            fingerprint=directory.fingerprint,
            earlier_fingerprints=directory.earlier_fingerprints,
            resume=resume,
            on_generation=on_generation,
            should_stop=should_stop,
            start=()
            if resume and directory.checkpoints[run].exists()
            else start_genomes(directory.pipeline, run),
        )
        if resume and state.generation == config.generations:
            for name in directory.restore_records(run):
                if on_restored:
                    on_restored(directory.run_dir(run) / name)
        states.append(state)
    finished = len(states) == config.runs and all(s.generation == config.generations for s in states)
    if finished:
        write_summary(directory, states)
    return states


def write_summary(directory: RunDirectory, states: list[RunState]) -> None:
    """``summary.json``, once every run of ``directory`` has finished (``states``, by run)."""
    write_atomically(directory.path / SUMMARY, jsonio.dumps(summary(directory, states), indent=1) + "\n")


def summary(directory: RunDirectory, states: list[RunState]) -> dict[str, Any]:
    """What the runs found, and what each spent in the backend where it recorded it
    (``backend_usage``: steps simulated, seconds inside the backend, the generations counted)."""
    bests = [s.best for s in states]
    return {
        "grammar": GRAMMAR,  # the copy in the run directory: the text the runs used
        "origin": directory.origin,
        "backend": directory.pipeline.backend,
        "fingerprint": directory.fingerprint,
        "runs": [
            {
                "run": r,
                "best_fitness": b.fitness,
                "status": b.evaluation.status.value,
                "phenotype": b.phenotype,
                "generations": s.generation,
                **_usage(directory.run_dir(r)),
            }
            for r, (s, b) in enumerate(zip(states, bests, strict=True))
        ],
        "best_fitness": min(b.fitness for b in bests),
    }


def _usage(run_dir: Path) -> dict[str, Any]:
    """A run's recorded usage as a summary shows it: nothing for a run that records none (runs
    made before runs recorded it keep their summaries) or whose record is damaged."""
    try:
        usage = read_usage(run_dir)
    except UsageError:
        return {}
    return {} if usage is None else {"backend_usage": usage.as_record()}


@contextmanager
def stop_on_interrupt() -> Iterator[Callable[[], bool]]:
    """First Ctrl-C: finish the current generation, then stop. Second: stop now."""
    requested = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield requested.is_set
        return
    previous = signal.getsignal(signal.SIGINT)

    def handler(signum: int, frame: object) -> None:
        if requested.is_set():
            signal.signal(signal.SIGINT, previous)
            raise KeyboardInterrupt
        requested.set()

    signal.signal(signal.SIGINT, handler)
    try:
        yield requested.is_set
    finally:
        signal.signal(signal.SIGINT, previous)
