"""A run's gaits played on another body: the paper's "retarget gait cycles from one animal to
another", for a backend with bodies (``mujoco-horse``: the horse, a draft horse, ponies).

The gaits keep their joint curves; the backend times them on the new body (by dynamic
similarity, or as evolved: :attr:`BackendSpec.retarget_scalings`), and they are scored by that
body's fitness and checked over its horizon, as a run checks the gaits it keeps.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

from gaitgram.backends.api import Evaluation, SettingsError
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError, finished_bests
from gaitgram.ge.registry import Genome
from gaitgram.motion.gait import MotionBatch
from gaitgram.pipeline import Individual, Pipeline, PipelineError


class RetargetError(ValueError):
    """Gaits that cannot be played on the body asked for; says why."""


@dataclass(frozen=True)
class Retargeted:
    """Gaits played on ``body``: through ``pipeline`` (the run's, with the body's settings), at
    ``frequencies`` (Hz per gait), having been evolved at ``evolved_frequencies``; None where a
    gait has no frequency of its own and the body's target frequency was played."""

    body: str
    scaling: str
    pipeline: Pipeline
    frequencies: tuple[float | None, ...]
    evolved_frequencies: tuple[float | None, ...]
    individuals: tuple[Individual, ...]


def retarget(
    pipeline: Pipeline, genomes: Sequence[Genome], generation: int, body: str, scaling: str
) -> Retargeted:
    """Play ``genomes``, evolved through ``pipeline``, on ``body``, as they would be scored in
    ``generation``; raises :class:`RetargetError` for a backend without bodies, an unknown body
    or scaling (:func:`check_playing`)."""
    check_playing(pipeline, body, [scaling])
    spec = pipeline.spec
    assert spec.retarget is not None
    motion = pipeline.motion(pipeline.map(genomes), generation)
    try:
        settings, played = spec.retarget(pipeline.config.backend_settings, motion, body, scaling)
        target = Pipeline.build(pipeline.checked, replace(pipeline.config, backend_settings=settings))
    except (SettingsError, PipelineError, ValueError) as error:
        raise RetargetError(f"cannot play the gaits on {body}: {error}") from None
    evaluator = target.load_evaluator()
    try:
        individuals = target.verify(genomes, evaluator, generation, played=lambda _: played)
    finally:
        close_evaluator = getattr(evaluator, "close", None)
        if close_evaluator is not None:
            close_evaluator()
    return Retargeted(
        body,
        scaling,
        target,
        _hertz(played, len(genomes)),
        _hertz(motion, len(genomes)),
        tuple(individuals),
    )


def check_playing(pipeline: Pipeline, body: str, scalings: Sequence[str]) -> None:
    """Raise :class:`RetargetError` unless ``pipeline``'s backend has bodies, ``body`` among them,
    and knows each of ``scalings``: before anything is played, whatever is asked. The body is
    checked where the backend defines its bodies, as its ``body`` setting (with a "did you mean")."""
    spec = pipeline.spec
    if spec.retarget is None or not spec.bodies:
        raise RetargetError(f"backend {pipeline.backend!r} has one body: its gaits cannot be retargeted")
    try:
        spec.checked_settings({**pipeline.config.backend_settings, "body": body})
    except SettingsError as error:
        why = error.message if error.key == "body" else str(error)
        raise RetargetError(f"backend {pipeline.backend!r}: {why}") from None
    for scaling in scalings:
        if scaling not in spec.retarget_scalings:
            known = ", ".join(spec.retarget_scalings)
            raise RetargetError(f"no frequency scaling {scaling!r}; {pipeline.backend!r} knows {known}")


def _hertz(motion: MotionBatch, count: int) -> tuple[float | None, ...]:
    if motion.frequencies is None:
        return (None,) * count
    return tuple(None if math.isnan(f) else float(f) for f in motion.frequencies)


@dataclass(frozen=True)
class RunBest:
    """A finished run's best gait as recorded, and as played on another body under each scaling."""

    run: int
    generation: int
    genome: Genome
    evolved_frequency: float | None  # Hz, None where the gait was played at its body's target
    recorded: Evaluation
    played: tuple[tuple[str, float | None, Evaluation], ...]  # (scaling, Hz or None, evaluation)


def retarget_runs(
    directory: RunDirectory, body: str, scalings: Sequence[str], runs: int | None = None
) -> list[RunBest]:
    """Every finished run's best gait of ``directory`` (of its first ``runs`` alone, if given: an arm
    that has grown since) played on ``body`` under each of ``scalings`` (the runs' bests played
    together, one batch per scaling); raises :class:`RetargetError`."""
    check_playing(directory.pipeline, body, scalings)
    planned = directory.config.runs
    if runs is not None and not 1 <= runs <= planned:
        raise RetargetError(
            f"{directory.path}: --runs {runs} asks for its first {runs} runs, but it plans {planned}; "
            f"give --runs from 1 to {planned}"
        )
    try:
        bests = finished_bests(directory, None if runs is None else range(runs))
    except RunDirectoryError as error:
        raise RetargetError(str(error)) from None
    if not bests:
        raise RetargetError(f"{directory.path} has no finished run yet: retarget its results once it has")
    genomes = [tuple(best.genome) for _, _, best in bests]
    generation = bests[0][1]
    played = [retarget(directory.pipeline, genomes, generation, body, scaling) for scaling in scalings]
    return [
        RunBest(
            run,
            at,
            genomes[i],
            played[0].evolved_frequencies[i] if played else None,
            best.evaluation,
            tuple((p.scaling, p.frequencies[i], p.individuals[i].evaluation) for p in played),
        )
        for i, (run, at, best) in enumerate(bests)
    ]
