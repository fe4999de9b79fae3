"""Running a study: every (arm, run) pair is one task, scheduled in parallel and resumable.

A study directory holds one run directory per arm (``arms/NAME/``, exactly what
``gaitgram evolve --runs N`` makes, so ``evolve --resume`` and ``report`` work on
an arm alone) and ``study.json``. A task runs one run of one arm to its end,
checkpointing every generation; a run's results depend only on its arm's
configuration and its index, so a study gives the same numbers whether its
runs go one at a time, in parallel processes, or to Dask workers, and however
often it is killed and started again.

The directory is made whole (every arm and ``study.json`` under a temporary
name, then renamed into place), so a kill at any instant leaves no study
directory or a complete one. One gaitgram at a time works in it: the study and
each of its arms are locked while it runs.

Parallelism: by default one process per core, each running whole runs with one
simulation thread (``python -m benchmarks study`` measures this against one run
at a time on all threads). On a Dask cluster (:func:`gaitgram.evolution.distributed.connect`)
each run is one task; workers must see the study directory (a shared file
system). A worker that dies takes its run's current generation with it: the
scheduler gives the task to another worker, which continues from the run's last
checkpoint, to the same results.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from functools import lru_cache
from multiprocessing import get_context
from pathlib import Path
from typing import Any

from gaitgram.backends.api import Evaluator
from gaitgram.evolution.checkpoint import CheckpointError, load_checkpoint
from gaitgram.evolution.distributed import DaskCluster, import_distributed
from gaitgram.evolution.engine import run_evolution
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError, fingerprint
from gaitgram.evolution.session import write_summary
from gaitgram.evolution.transfer import start_genomes
from gaitgram.extras import MissingExtra
from gaitgram.fileio import (
    LOCK_FILE,
    DirectoryInUse,
    DirectoryLock,
    created_directory,
    is_empty_directory,
    write_atomically,
)
from gaitgram.pipeline import PipelineError
from gaitgram.runlayout import ARMS, STATS_JSONL, STUDY_MANIFEST, runs_in
from gaitgram.strategies.api import StrategyError
from gaitgram.strategies.registry import load_strategy
from gaitgram.study.manifest import ManifestArm, StudyManifest, read_study_manifest
from gaitgram.study.spec import Study, StudyError

STOP_FILE = ".stop"
#: Errors a task raises that say what is wrong in gaitgram's own words.
TASK_ERRORS = (StudyError, RunDirectoryError, CheckpointError, PipelineError, StrategyError)


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
        return self.path / ARMS / name

    @property
    def tasks(self) -> list[Task]:
        """Every run of every arm, interleaved so that a partial study has balanced arms."""
        return [Task(arm.name, run) for run in range(self.study.runs) for arm in self.study.arms]

    def progress(self, task: Task) -> RunProgress:
        """How far a run has got, from its statistics file (cheap, for the progress display only:
        the checkpoint is the truth, and a line that does not read is not counted)."""
        stats = self.arms[task.arm].run_dir(task.run) / STATS_JSONL
        generation, evaluations = -1, 0
        with contextlib.suppress(OSError, ValueError):
            for line in stats.read_text(encoding="utf-8").splitlines():
                record = json.loads(line)
                if isinstance(record, dict) and _counts(record.get("generation"), record.get("evaluations")):
                    generation = max(generation, record["generation"])
                    evaluations += record["evaluations"]
        return RunProgress(task.arm, task.run, generation, evaluations)

    def finished(self, task: Task) -> bool:
        directory = self.arms[task.arm]
        path = directory.checkpoint(task.run)
        if not path.exists():
            return False
        state = load_checkpoint(
            path, directory.pipeline, fingerprint=directory.fingerprints, run=task.run, with_memory=False
        )
        return state.generation == directory.config.generations


def _counts(*values: Any) -> bool:
    return all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in values)


# ---- the directory ---------------------------------------------------------------------------


@contextlib.contextmanager
def open_study(study: Study, out: Path) -> Iterator[StudyDirectory]:
    """The study directory, made whole or opened and verified, and locked (the study and each
    arm) while the block runs. Every backend and strategy is loaded before anything is written."""
    _loadable(study)
    if not (out.exists() or out.is_symlink()) or is_empty_directory(out):
        with contextlib.suppress(FileExistsError):  # made by another gaitgram meanwhile: open it
            _create(study, out)
    if not (out / STUDY_MANIFEST).is_file():
        raise StudyError(f"{out} {_not_a_study(out)}")
    with contextlib.ExitStack() as locks:
        locks.enter_context(_lock(out, f"{out} is in use by another gaitgram study"))
        directory = _verified(study, out)
        for name, arm in directory.arms.items():
            message = f"arm {name!r} of {out} ({arm.path}) is in use by another gaitgram"
            locks.enter_context(_lock(arm.path, message))
        yield directory


@dataclass(frozen=True)
class ArmStatus:
    """An arm of a study file, as its directory holds it."""

    name: str
    #: Runs its directory is set up for (0: no directory: it starts from scratch; fewer than the
    #: study's: it grows).
    held: int
    finished: int


@dataclass(frozen=True)
class StudyCheck:
    """What ``gaitgram study`` would find in a study directory (:func:`check_study`)."""

    arms: tuple[ArmStatus, ...]
    held: bool  # the directory holds this study (its study.json names these arms)
    running: bool  # another gaitgram is running it now: a second is refused until it stops


def check_study(study: Study, out: Path | None) -> StudyCheck:
    """What ``gaitgram study`` would do with ``study`` and ``out``, writing nothing: each arm's
    runs held and finished there, and whether it runs now, or the :class:`StudyError` the study
    would be refused with."""
    _loadable(study)
    if out is None or not (out.exists() or out.is_symlink()) or is_empty_directory(out):
        return StudyCheck(tuple(ArmStatus(arm.name, 0, 0) for arm in study.arms), held=False, running=False)
    if not (out / STUDY_MANIFEST).is_file():
        raise StudyError(f"{out} {_not_a_study(out)}")
    try:
        directory = _verified(study, out, write=False)
        statuses = []
        for arm in study.arms:
            held = directory.arms.get(arm.name)
            runs = held.config.runs if held is not None else 0
            finished = sum(directory.finished(Task(arm.name, run)) for run in range(runs))
            statuses.append(ArmStatus(arm.name, runs, finished))
    except OSError as error:
        raise StudyError(f"cannot read {error.filename or out}: {error.strerror or error}") from None
    return StudyCheck(tuple(statuses), held=True, running=DirectoryLock.held(out))


def _loadable(study: Study) -> None:
    """Every arm's backend and strategy load (their extras are installed)."""
    for arm in study.arms:
        try:
            arm.pipeline.load_evaluator().close()
            load_strategy(arm.pipeline)
        except (MissingExtra, PipelineError) as error:
            raise StudyError(f"{study.path}: arm {arm.name!r}: {error}") from None


def _lock(directory: Path, message: str) -> DirectoryLock:
    try:
        return DirectoryLock(directory)
    except DirectoryInUse:
        raise StudyError(f"{message}; wait for it to finish, or stop it") from None


def _not_a_study(out: Path) -> str:
    if not out.is_dir():
        return "exists and is not a directory; choose another -o"
    leftovers = {p.name for p in out.iterdir()} - {LOCK_FILE, STOP_FILE}
    if leftovers == {ARMS} and not any(runs_in(arm) for arm in (out / ARMS).glob("*")):
        return (
            f"holds the start of a study that was stopped before its {STUDY_MANIFEST} was written (by a "
            "gaitgram that did not yet make study directories whole), and no runs; delete it and run "
            "the same command again"
        )
    return "exists and is not a study directory; choose another -o"


def _manifest(study: Study, fingerprints: dict[str, str]) -> StudyManifest:
    arms = tuple(
        ManifestArm(arm.name, arm.strategy, str(arm.grammar), fingerprints[arm.name]) for arm in study.arms
    )
    return StudyManifest(study.title, str(study.path), study.runs, arms)


def _create(study: Study, out: Path) -> None:
    """A new study directory, made whole: every arm's run directory, then ``study.json``."""
    try:
        with created_directory(out) as building:
            fingerprints = {}
            for arm in study.arms:
                made = RunDirectory.create(
                    building / ARMS / arm.name, arm.pipeline, defines=arm.defines, origin=str(arm.grammar)
                )
                fingerprints[arm.name] = made.fingerprint
            write_atomically(building / STUDY_MANIFEST, _manifest(study, fingerprints).text())
    except FileExistsError:
        raise
    except OSError as error:
        raise StudyError(f"cannot write {out}: {error.strerror or error}") from None


def _verified(study: Study, out: Path, *, write: bool = True) -> StudyDirectory:
    """Open a study directory and check that the study given is the one it holds; grow it if the
    study asks for more runs. Not ``write``: only check (an arm without a directory is left out,
    none grows)."""
    existing = read_study_manifest(out)
    names = [a.name for a in existing.arms]
    if names != [a.name for a in study.arms]:
        raise StudyError(
            f"{out} holds another study (arms {', '.join(names)}, {existing.runs} runs each); "
            "give the same study file and flags to continue it, or choose another -o"
        )
    if study.runs < existing.runs:
        raise StudyError(
            f"{out} holds {existing.runs} runs per arm and a study never drops runs: give --runs "
            f"{existing.runs} to continue it (or more, to add runs), or choose another -o"
        )
    arms: dict[str, RunDirectory] = {}
    for arm in study.arms:
        path = out / ARMS / arm.name
        if not (path.exists() or path.is_symlink()):  # an arm deleted to run it again from scratch
            if not write:
                continue
            directory = RunDirectory.create(path, arm.pipeline, defines=arm.defines, origin=str(arm.grammar))
        else:
            directory = RunDirectory.open(path)
        changed = directory.fingerprint != fingerprint(arm.pipeline, arm.defines)
        if not changed and directory.config.runs > study.runs:
            raise StudyError(
                f"cannot continue {out} with {study.runs} runs per arm: arm {arm.name!r} already has "
                f"{directory.config.runs}, from a growth that did not finish; give --runs "
                f"{directory.config.runs} to finish it"
            )
        if changed:
            found = directory.differences(
                grammar=arm.pipeline.grammar.source, defines=arm.defines, config=arm.config
            )
            raise StudyError(
                f"cannot continue {out}: arm {arm.name!r} differs from the one it started with:\n  - "
                + "\n  - ".join(found or ["its backend or engine changed"])
                + "\ngive the same study file and flags, or choose another -o"
            )
        if not write:
            arms[arm.name] = directory
            continue
        arms[arm.name] = directory.grow(study.runs)  # more runs than before: the new ones are added
    if write and existing.runs != study.runs:  # written last: a killed growth grows again
        fingerprints = {name: arm.fingerprint for name, arm in arms.items()}
        write_atomically(out / STUDY_MANIFEST, _manifest(study, fingerprints).text())
    return StudyDirectory(out, study, arms)


# ---- tasks -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class TaskResult:
    arm: str
    run: int
    generation: int
    finished: bool


@lru_cache(maxsize=64)
def _opened(arm_path: str, expected: str, runs: int, thread: int) -> RunDirectory:
    """An arm as a worker sees it, opened once per worker thread (``dask worker`` runs a task per
    thread; a backend is never used by two at once). Keyed by what the study expects of it, so a
    worker that outlives one study (a Dask cluster's) never runs another's arm as the old one was."""
    directory = RunDirectory.open(Path(arm_path))
    if directory.fingerprint != expected or directory.config.runs != runs:
        raise RunDirectoryError(
            f"{arm_path} changed while the study ran (its fingerprint or run count is not the study's); "
            "run the same command again"
        )
    return directory


@lru_cache(maxsize=64)
def _evaluator(arm_path: str, expected: str, runs: int, threads: int, thread: int) -> Evaluator:
    pipeline = _opened(arm_path, expected, runs, thread).pipeline
    runtime = {"threads": threads} if "threads" in pipeline.spec.runtime_settings else {}
    return pipeline.load_evaluator(runtime)


def run_task(arm_path: str, expected: str, runs: int, run: int, threads: int, stop_file: str) -> TaskResult:
    """One run of one arm to its end (or until the stop file appears), from its checkpoint if any."""
    name = Path(arm_path).name
    if os.path.exists(stop_file):  # stopped before this task started: leave the run as it is
        return TaskResult(name, run, -1, False)
    thread = threading.get_ident()
    directory = _opened(arm_path, expected, runs, thread)
    fresh = not directory.checkpoint(run).exists()
    state = run_evolution(
        directory.pipeline,
        _evaluator(arm_path, expected, runs, threads, thread),
        run,
        directory.run_dir(run),
        fingerprint=directory.fingerprint,
        earlier_fingerprints=directory.earlier_fingerprints,
        resume=True,
        should_stop=lambda: os.path.exists(stop_file),
        start=start_genomes(directory.pipeline, run) if fresh else (),
    )
    return TaskResult(name, run, state.generation, state.generation == directory.config.generations)


def _task_arguments(directory: StudyDirectory, task: Task, threads: int, stop_file: Path) -> tuple[Any, ...]:
    arm = directory.arms[task.arm]
    return (str(arm.path), arm.fingerprint, arm.config.runs, task.run, threads, str(stop_file))


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


Progress = Callable[[list[RunProgress], list[TaskResult]], None]


@dataclass(frozen=True)
class StudyRun:
    results: list[TaskResult]  # the tasks run this time
    restored: list[Path]  # records of runs finished before, rewritten from their checkpoints


def run_study(
    directory: StudyDirectory,
    *,
    jobs: int,
    threads: int,
    cluster: DaskCluster | None = None,
    on_progress: Progress | None = None,
    should_stop: Callable[[], bool] = lambda: False,
) -> StudyRun:
    """Run every unfinished task (on ``cluster`` if given, else in ``jobs`` local processes).
    The records of runs finished before are rewritten first where they disagree with their
    checkpoints (deleted, edited, or stale after a kill)."""
    stop_file = directory.path / STOP_FILE
    stop_file.unlink(missing_ok=True)
    pending, restored = [], []
    for task in directory.tasks:
        if directory.finished(task):
            run_dir = directory.arms[task.arm].run_dir(task.run)
            restored += [run_dir / name for name in directory.arms[task.arm].restore_records(task.run)]
        else:
            pending.append(task)
    results: list[TaskResult] = []
    if pending and cluster is not None:
        results = _run_on_dask(directory, pending, threads, stop_file, cluster, on_progress, should_stop)
    elif pending:
        results = _run_locally(directory, pending, jobs, threads, stop_file, on_progress, should_stop)
    _write_arm_summaries(directory)
    return StudyRun(results, restored)


def _run_locally(
    directory: StudyDirectory,
    pending: list[Task],
    jobs: int,
    threads: int,
    stop_file: Path,
    on_progress: Progress | None,
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
                    arguments = _task_arguments(directory, task, threads, stop_file)
                    running[pool.submit(run_task, *arguments)] = task
                if not running:
                    break
                done, _ = wait(running, timeout=0.5, return_when=FIRST_COMPLETED)
                for future in done:
                    task = running.pop(future)
                    try:
                        results.append(future.result())
                    except BrokenProcessPool:
                        raise StudyError(
                            f"the process running run {task.run} of arm {task.arm!r} died (killed, or out of "
                            "memory); its last checkpoint is intact: run the same command again to continue"
                        ) from None
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
    cluster: DaskCluster,
    on_progress: Progress | None,
    should_stop: Callable[[], bool],
) -> list[TaskResult]:
    """One Dask task per run. A worker that dies mid-run loses its current generation only: the
    scheduler hands the task to another worker, which resumes from the run's checkpoint."""
    distributed = import_distributed()
    client = cluster.client
    futures = {
        client.submit(
            run_task, *_task_arguments(directory, task, threads, stop_file), pure=False, retries=2
        ): task
        for task in pending
    }
    remaining = set(futures)
    results: list[TaskResult] = []
    try:
        while remaining:
            try:
                distributed.wait(list(remaining), timeout=0.5, return_when="FIRST_COMPLETED")
            except TimeoutError:  # none finished within the poll: not an error
                pass
            except Exception:  # the scheduler went away: every future is cancelled
                raise StudyError(
                    f"lost the connection to the Dask scheduler ({cluster.flag}); the runs' last checkpoints "
                    "are intact: start the scheduler and its workers again, then run the same command again "
                    "to continue"
                ) from None
            done = {f for f in remaining if f.done()}
            remaining -= done
            for future in sorted(done, key=lambda f: (futures[f].run, futures[f].arm)):
                results.append(_dask_result(future, futures[future], cluster))
            if should_stop() and not stop_file.exists():
                stop_file.touch()
            if on_progress:
                on_progress([directory.progress(futures[f]) for f in remaining], results)
    finally:
        if remaining:  # an error or a second Ctrl-C: runs on the workers stop after their generation
            stop_file.touch()
            with contextlib.suppress(Exception):
                client.cancel(list(remaining))
    return results


def _dask_result(future: Any, task: Task, cluster: DaskCluster) -> TaskResult:
    """A task's result, or an error that says what happened on the cluster."""
    where = f"run {task.run} of arm {task.arm!r}"
    try:
        return future.result()
    except TASK_ERRORS:
        raise
    except Exception as error:
        kind = type(error).__name__
        if kind == "KilledWorker":
            raise StudyError(
                f"{where}: the Dask workers that took it kept dying ({error}); its last checkpoint is "
                "intact: check the workers (memory, logs), then run the same command again to continue"
            ) from None
        if kind == "CancelledError" or future.status == "cancelled":
            raise StudyError(
                f"{where}: the Dask scheduler ({cluster.flag}) dropped it (stopped or restarted?); its last "
                "checkpoint is intact: run the same command again to continue"
            ) from None
        raise StudyError(
            f"{where} failed on a Dask worker ({cluster.flag}): {kind}: {error}; every worker needs "
            "gaitgram with the arms' backends and strategies installed, as here, and must see the study "
            "directory at the same path (docs/study.md)"
        ) from None


def _write_arm_summaries(directory: StudyDirectory) -> None:
    """``summary.json`` of every arm whose runs have all finished (as ``evolve`` writes it)."""
    for arm in directory.arms.values():
        states = []
        for run in range(directory.study.runs):
            path = arm.checkpoint(run)
            if not path.exists():
                break
            state = load_checkpoint(
                path, arm.pipeline, fingerprint=arm.fingerprints, run=run, with_memory=False
            )
            if state.generation != arm.config.generations:
                break
            states.append(state)
        if len(states) == directory.study.runs:
            write_summary(arm, states)
