"""Running a study: every (arm, run) pair is one task, scheduled in parallel and resumable.

A study directory holds one run directory per arm (``arms/NAME/``, exactly what
``gaitgram evolve --runs N`` makes, so ``evolve --resume`` and ``report`` work on
an arm alone) and ``study.json``. A task runs one run of one arm to its end,
checkpointing every generation; a run's results depend only on its arm's
configuration and its index, so a study gives the same numbers whether its
runs go one at a time, in parallel processes, or to Dask workers, and however
often it is killed and started again.

Parallelism: by default one process per core, each running whole runs with one
simulation thread (``python -m benchmarks study`` measures this against one run
at a time on all threads). With ``--scheduler``/``--dask-local`` each run is one
Dask task; workers must see the study directory (a shared file system).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import signal
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from functools import cache
from multiprocessing import get_context
from pathlib import Path
from typing import Any

from gaitgram import jsonio
from gaitgram.backends.api import Evaluator
from gaitgram.evolution.engine import load_checkpoint, run_evolution
from gaitgram.evolution.rundir import RunDirectory, fingerprint
from gaitgram.evolution.session import summary
from gaitgram.extras import MissingExtra
from gaitgram.fileio import write_atomically
from gaitgram.strategies.registry import load_strategy
from gaitgram.study.spec import Study, StudyError

STUDY_MANIFEST = "study.json"
STUDY_FORMAT = 1
STOP_FILE = ".stop"
LOCK_FILE = ".lock"


@dataclass(frozen=True)
class Task:
    arm: str
    run: int


@dataclass(frozen=True)
class RunProgress:
    arm: str
    run: int
    generation: int
    evaluations: int


@dataclass(frozen=True)
class StudyDirectory:
    path: Path
    study: Study
    arms: dict[str, RunDirectory]

    def arm_path(self, name: str) -> Path:
        return self.path / "arms" / name

    @property
    def tasks(self) -> list[Task]:
        """Every run of every arm, interleaved so that a partial study has balanced arms."""
        return [Task(arm.name, run) for run in range(self.study.runs) for arm in self.study.arms]

    def progress(self, task: Task) -> RunProgress:
        """How far a run has got, from its statistics file (cheap; the checkpoint is the truth)."""
        stats = self.arms[task.arm].run_dir(task.run) / "stats.jsonl"
        generation, evaluations = -1, 0
        with contextlib.suppress(OSError, ValueError):
            for line in stats.read_text(encoding="utf-8").splitlines():
                record = json.loads(line)
                generation = max(generation, int(record["generation"]))
                evaluations += int(record["evaluations"])
        return RunProgress(task.arm, task.run, generation, evaluations)

    def finished(self, task: Task) -> bool:
        directory = self.arms[task.arm]
        path = directory.run_dir(task.run) / "checkpoint.json"
        if not path.exists():
            return False
        state = load_checkpoint(
            path, directory.pipeline, fingerprint=directory.fingerprints, run=task.run, with_memory=False
        )
        return state.generation == directory.config.generations


def prepare_study(study: Study, out: Path) -> StudyDirectory:
    """Create the study directory, or open it again and verify that nothing would change.

    Every arm was built when the study was loaded (grammar, configuration, backend and strategy
    settings checked); its backend is loaded once here before anything is written, so a bad arm
    leaves nothing behind.
    """
    pipelines = {arm.name: arm.pipeline for arm in study.arms}
    existing = _read_manifest(out)
    if existing is not None:
        names = [a["name"] for a in existing["arms"]]
        if names != [a.name for a in study.arms]:
            raise StudyError(
                f"{out} holds another study (arms {', '.join(names)}, {existing['runs']} runs each); "
                "give the same study file and flags to continue it, or choose another -o"
            )
        if study.runs < existing["runs"]:
            raise StudyError(
                f"{out} holds {existing['runs']} runs per arm and a study never drops runs: give --runs "
                f"{existing['runs']} to continue it (or more, to add runs), or choose another -o"
            )
    elif out.exists() and (
        not out.is_dir() or any(p.name not in (LOCK_FILE, STOP_FILE) for p in out.iterdir())
    ):
        raise StudyError(f"{out} exists and is not a study directory; choose another -o")
    for name, pipeline in pipelines.items():  # every backend and strategy loads, before anything is written
        pipeline.load_evaluator().close()
        try:
            load_strategy(pipeline)
        except MissingExtra as error:
            raise StudyError(f"arm {name!r}: {error}") from None
    arms: dict[str, RunDirectory] = {}
    for arm in study.arms:
        pipeline = pipelines[arm.name]
        path = out / "arms" / arm.name
        if (path / "manifest.json").exists():
            directory = RunDirectory.open(path)
            changed = directory.fingerprint != fingerprint(pipeline, arm.defines)
            if changed or directory.config.runs > study.runs:
                found = directory.differences(
                    grammar=pipeline.grammar.source, defines=arm.defines, config=arm.config
                )
                raise StudyError(
                    f"cannot continue {out}: arm {arm.name!r} differs from the one it started with:\n  - "
                    + "\n  - ".join(found or ["its backend or engine changed"])
                    + "\ngive the same study file and flags, or choose another -o"
                )
            directory = directory.grow(study.runs)  # more runs than before: the new ones are added
        else:
            directory = RunDirectory.create(path, pipeline, defines=arm.defines, origin=str(arm.grammar))
        arms[arm.name] = directory
    if existing is None or existing["runs"] != study.runs:  # written last: a killed growth grows again
        manifest = {
            "format": STUDY_FORMAT,
            "title": study.title,
            "study_file": str(study.path),
            "runs": study.runs,
            "arms": [
                {
                    "name": arm.name,
                    "strategy": arm.strategy,
                    "grammar": str(arm.grammar),
                    "fingerprint": arms[arm.name].fingerprint,
                }
                for arm in study.arms
            ],
        }
        write_atomically(out / STUDY_MANIFEST, jsonio.dumps(manifest, indent=1) + "\n")
    return StudyDirectory(out, study, arms)


def _read_manifest(out: Path) -> dict[str, Any] | None:
    path = out / STUDY_MANIFEST
    if not path.exists():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as error:
        raise StudyError(f"{path}: cannot read the study manifest: {error}") from None
    if (
        not isinstance(data, dict)
        or data.get("format") != STUDY_FORMAT
        or not isinstance(data.get("arms"), list)
    ):
        raise StudyError(f"{path}: not a study manifest this gaitgram can continue")
    return data


@contextlib.contextmanager
def locked(out: Path) -> Iterator[None]:
    """One gaitgram at a time in a study directory: two would write the same checkpoints.

    A directory made here only to hold the lock is removed again if nothing else was written.
    """
    made = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    handle = (out / LOCK_FILE).open("a+")
    try:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise StudyError(f"{out} is in use by another gaitgram study; wait for it, or stop it") from None
        yield
    finally:
        handle.close()
        if made and {p.name for p in out.iterdir()} <= {LOCK_FILE, STOP_FILE}:
            for name in (LOCK_FILE, STOP_FILE):
                (out / name).unlink(missing_ok=True)
            out.rmdir()


# ---- tasks -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class TaskResult:
    arm: str
    run: int
    generation: int
    best_fitness: float
    finished: bool


@cache
def _opened(arm_path: str) -> RunDirectory:
    return RunDirectory.open(Path(arm_path))


@cache
def _evaluator(arm_path: str, threads: int) -> Evaluator:
    pipeline = _opened(arm_path).pipeline
    runtime = {"threads": threads} if "threads" in pipeline.spec.runtime_settings else {}
    return pipeline.load_evaluator(runtime)


def run_task(arm_path: str, run: int, threads: int, stop_file: str) -> TaskResult:
    """One run of one arm to its end (or until the stop file appears), from its checkpoint if any."""
    directory = _opened(arm_path)
    state = run_evolution(
        directory.pipeline,
        _evaluator(arm_path, threads),
        run,
        directory.run_dir(run),
        fingerprint=directory.fingerprint,
        earlier_fingerprints=directory.earlier_fingerprints,
        resume=True,
        should_stop=lambda: os.path.exists(stop_file),
    )
    done = state.generation == directory.config.generations
    return TaskResult(Path(arm_path).name, run, state.generation, state.best.fitness, done)


def _worker_init() -> None:
    """Workers ignore Ctrl-C (the parent stops them between generations) and die with the parent,
    so a killed study never leaves a process writing into its directory."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    with contextlib.suppress(OSError, AttributeError):
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        pr_set_pdeathsig = 1
        libc.prctl(pr_set_pdeathsig, signal.SIGKILL)
    if os.getppid() == 1:  # the parent died before prctl took effect
        os._exit(1)


def run_study(
    directory: StudyDirectory,
    *,
    jobs: int,
    threads: int,
    scheduler: str | None = None,
    dask_local: int | None = None,
    on_progress: Callable[[list[RunProgress], list[TaskResult]], None] | None = None,
    should_stop: Callable[[], bool] = lambda: False,
) -> list[TaskResult]:
    """Run every unfinished task; returns the results of the tasks run this time."""
    stop_file = directory.path / STOP_FILE
    stop_file.unlink(missing_ok=True)
    pending = [t for t in directory.tasks if not directory.finished(t)]
    if not pending:
        _write_arm_summaries(directory)
        return []
    results: list[TaskResult] = []
    if scheduler or dask_local:
        results = _run_on_dask(
            directory, pending, threads, stop_file, scheduler, dask_local, on_progress, should_stop
        )
    else:
        results = _run_locally(directory, pending, jobs, threads, stop_file, on_progress, should_stop)
    _write_arm_summaries(directory)
    return results


def _run_locally(
    directory: StudyDirectory,
    pending: list[Task],
    jobs: int,
    threads: int,
    stop_file: Path,
    on_progress: Callable[[list[RunProgress], list[TaskResult]], None] | None,
    should_stop: Callable[[], bool],
) -> list[TaskResult]:
    results: list[TaskResult] = []
    queue = list(pending)
    running: dict[Future[TaskResult], Task] = {}
    with ProcessPoolExecutor(
        max_workers=jobs, mp_context=get_context("spawn"), initializer=_worker_init
    ) as pool:
        try:
            while queue or running:
                while queue and len(running) < jobs and not stop_file.exists():
                    task = queue.pop(0)
                    path = str(directory.arm_path(task.arm))
                    running[pool.submit(run_task, path, task.run, threads, str(stop_file))] = task
                if not running:
                    break
                done, _ = wait(running, timeout=0.5, return_when=FIRST_COMPLETED)
                for future in done:
                    running.pop(future)
                    results.append(future.result())
                if should_stop() and not stop_file.exists():
                    stop_file.touch()  # workers finish their current generation, then return
                if on_progress:
                    on_progress([directory.progress(t) for t in running.values()], results)
        finally:
            if running:  # an error or a second Ctrl-C: tell the others to stop too
                stop_file.touch()
    return results


def _run_on_dask(
    directory: StudyDirectory,
    pending: list[Task],
    threads: int,
    stop_file: Path,
    scheduler: str | None,
    dask_local: int | None,
    on_progress: Callable[[list[RunProgress], list[TaskResult]], None] | None,
    should_stop: Callable[[], bool],
) -> list[TaskResult]:
    from gaitgram.evolution.distributed import _import_distributed

    distributed = _import_distributed()
    cluster = None
    if scheduler:
        client = distributed.Client(scheduler)
    else:
        cluster = distributed.LocalCluster(
            n_workers=dask_local or 1, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = distributed.Client(cluster)
    results: list[TaskResult] = []
    try:
        futures = {
            client.submit(
                run_task,
                str(directory.arm_path(t.arm)),
                t.run,
                threads,
                str(stop_file),
                pure=False,
                retries=2,
            ): t
            for t in pending
        }
        remaining = set(futures)
        while remaining:
            done, remaining = distributed.wait(list(remaining), timeout=0.5, return_when="FIRST_COMPLETED")
            results += [f.result() for f in done]
            remaining = set(remaining)
            if should_stop() and not stop_file.exists():
                stop_file.touch()
            if on_progress:
                active = [futures[f] for f in remaining if f.status == "pending"]
                on_progress([directory.progress(t) for t in active], results)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return results


def _write_arm_summaries(directory: StudyDirectory) -> None:
    """``summary.json`` of every arm whose runs have all finished (as ``evolve`` writes it)."""
    for arm in directory.arms.values():
        states = []
        for run in range(directory.study.runs):
            path = arm.run_dir(run) / "checkpoint.json"
            if not path.exists():
                break
            state = load_checkpoint(
                path, arm.pipeline, fingerprint=arm.fingerprints, run=run, with_memory=False
            )
            if state.generation != arm.config.generations:
                break
            states.append(state)
        if len(states) == directory.study.runs:
            write_atomically(arm.path / "summary.json", jsonio.dumps(summary(arm, states), indent=1) + "\n")
