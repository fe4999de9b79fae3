"""Kept gaits measured beyond their scores, once, into the study directory: ``gaitgram report --assess``.

The report's realism and robustness sections (:mod:`gaitgram.report.realism_robustness`) need simulation:
each run's best gait (its last checkpoint's best, which ``best.json`` records) is measured by the
backend that scored it (``BackendSpec.assess``: on the horse, beside the DLC_Horse walks and
under each disturbance), which declares what it keeps (``BackendSpec.assessment``). That is slow, so
it is an explicit step whose results are kept in the run directory, ``run-NNN/assessment.json``;
a report only reads them, and so stays fast and the same, byte for byte, however often it is
made.

A kept assessment names the gait (genome, generation, fitness), what scored it (backend and
version) and :data:`FORMAT`: when any of these no longer matches, the report calls it stale and
``--assess`` measures the gait again. Only the runs of a backend that declares both are measured
(:func:`assesses`); runs that have not finished are left for later (``gaitgram report --watch``
measures them as they finish).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from gaitgram import jsonio
from gaitgram.backends.api import Assessment
from gaitgram.backends.registry import BackendSpec, installed_backend
from gaitgram.evolution.checkpoint import load_checkpoint
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError, best_walk_of_runs, read_manifest
from gaitgram.fileio import write_atomically
from gaitgram.report.records import ArmRecord, ReportError
from gaitgram.runlayout import ASSESSMENT, best_walk_window, run_path

#: Raised when what is measured, or how, changes: every kept assessment is then stale.
#: 2: the bumps are ten floors, and each trial keeps on how many it was played and held.
FORMAT = 2


def assesses(spec: BackendSpec) -> bool:
    """Whether a backend measures its kept gaits (``assess``) and declares what it keeps
    (``assessment``), as a report needs both."""
    return spec.assess is not None and spec.assessment is not None


def assessing(backend: str) -> Assessment | None:
    """What the backend named ``backend`` declares it keeps of the gaits it measures; None if it
    measures none (or is not installed here: its runs' assessments are then not read)."""
    spec = installed_backend(backend)
    return spec.assessment() if spec is not None and spec.assessment is not None and assesses(spec) else None


def assessment_path(arm: Path, run: int) -> Path:
    return run_path(arm, run) / ASSESSMENT


def best_walk_path(arm: Path, window: int | None = None) -> Path:
    """Where the best walk of an arm's runs is kept: of all of them, or of its first ``window``
    (a report over fewer runs than the arm has, whose best walk may be another)."""
    return arm / best_walk_window(window)


def kept_key(record: dict[str, Any]) -> tuple[Any, ...]:
    """What a kept assessment must match to be current."""
    return (
        record.get("format"),
        record.get("backend_version"),
        record.get("generation"),
        record.get("genome"),
        record.get("fitness"),
    )


def assess_arm(
    path: Path,
    *,
    window: int | None = None,
    force: bool = False,
    progress: Callable[[str], None] | None = None,
) -> list[Path]:
    """Measure the best gait of each finished run of the run directory ``path`` (of its first
    ``window`` runs, if given) whose kept assessment is missing, stale or damaged (every one with
    ``force``), and the best walk they hand back; the files written. A run directory of another
    backend is left alone (nothing written)."""
    try:
        directory = RunDirectory.open(path)
    except RunDirectoryError as error:
        raise ReportError(str(error)) from None
    pipeline = directory.pipeline
    if not assesses(pipeline.spec):
        return []
    manifest = read_manifest(path)
    version = manifest["backend_version"] if manifest else ""
    wanted: list[tuple[int, dict[str, Any]]] = []
    runs = range(len(directory.checkpoints) if window is None else window)
    for run, checkpoint in zip(runs, directory.checkpoints, strict=False):
        if not checkpoint.exists():
            continue
        try:
            state = load_checkpoint(
                checkpoint, pipeline, fingerprint=directory.fingerprints, run=run, with_memory=False
            )
        except (RunDirectoryError, ValueError) as error:
            raise ReportError(f"{checkpoint}: {error}") from None
        if state.generation < pipeline.config.generations:
            continue  # not finished: measured once it is
        best = state.best
        record = {
            "format": FORMAT,
            "backend": pipeline.backend,
            "backend_version": version,
            "generation": state.generation,
            "genome": pipeline.representation.to_json(best.genome),
            "fitness": float(best.fitness),
        }
        if not force and _kept(assessment_path(path, run), record):
            continue
        wanted.append((run, record))
    walk = _best_walk(directory, version, runs)
    if walk is not None and (force or not _kept(best_walk_path(path, window), walk)):
        wanted.append((-1, walk))
    if not wanted:
        return []
    if progress:
        runs = sum(run >= 0 for run, _ in wanted)
        also = " and its best walk" if wanted[-1][0] < 0 else ""
        progress(f"measuring the best gaits of {runs} run(s){also} of {path}")
    batch = pipeline.motion(
        pipeline.map([pipeline.representation.from_json(r["genome"]) for _, r in wanted]),
        pipeline.config.generations,
    )
    measured = measure(dict(pipeline.config.backend_settings), batch, pipeline.spec)
    written = []
    for (run, record), found in zip(wanted, measured, strict=True):
        target = assessment_path(path, run) if run >= 0 else best_walk_path(path, window)
        write_atomically(target, jsonio.dumps({**record, **found}, indent=1) + "\n")
        written.append(target)
    return written


def _best_walk(directory: RunDirectory, version: str, runs: range) -> dict[str, Any] | None:
    """The record naming the best walk any of ``runs`` hands back (as the report's gallery picks
    it); None if none does."""
    if directory.pipeline.spec.verdict is None:
        return None
    try:
        walk = best_walk_of_runs(directory, finished_only=True, runs=runs)
    except RunDirectoryError:
        return None
    return {
        "format": FORMAT,
        "backend": directory.pipeline.backend,
        "backend_version": version,
        "generation": walk.generation,
        "genome": directory.pipeline.representation.to_json(walk.genome),
        "fitness": float(walk.evaluation.fitness),
        "run": walk.run,
    }


def _kept(path: Path, record: dict[str, Any]) -> bool:
    """Whether ``path`` keeps a current, complete assessment of ``record``'s gait: one made before
    the graded trial existed is measured again (its other parts come out the same, bit for bit)."""
    try:
        kept = jsonio.read_object(path)
    except jsonio.ObjectError:  # a damaged one is measured again
        return False
    return kept_key(kept) == kept_key(record) and "graded" in kept


def measure(settings: dict[str, Any], batch: Any, spec: BackendSpec) -> list[dict[str, Any]]:
    """Each gait of ``batch`` measured by the backend ``spec`` that scored it (its ``assess``),
    with the run's backend ``settings``, as kept in ``assessment.json``."""
    if spec.assess is None:
        raise ReportError(f"backend {spec.name!r} measures nothing beyond the score")
    return list(spec.assess(settings, batch))


def assess_arms(
    arms: Sequence[ArmRecord], *, force: bool = False, progress: Callable[[str], None] | None = None
) -> list[Path]:
    """:func:`assess_arm` on each arm whose backend measures its gaits, in turn, over the runs a
    report reads."""
    return [
        p
        for arm in arms
        if assessing(arm.backend) is not None
        for p in assess_arm(arm.path, window=arm.window, force=force, progress=progress)
    ]
