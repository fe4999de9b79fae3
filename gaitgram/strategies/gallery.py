"""Animations of chosen gaits from a run directory: trade-offs of a front, elites of a repertoire.

Each gait goes through the run's own pipeline, as ``gaitgram render --run``
draws one: the run's codons, backend settings and joint freedom at its last
generation. Only the ``mujoco-horse`` backend draws; MuJoCo must find an
offscreen OpenGL (``MUJOCO_GL=egl``, set by the report command before MuJoCo
is imported).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError
from gaitgram.pipeline import PipelineError


class GalleryError(ValueError):
    """A gait that cannot be drawn; says why."""


def render_gaits(
    run_directory: Path, genomes: Sequence[Sequence[int]], paths: Sequence[Path], fps: int = 20
) -> None:
    """One GIF per genome (``paths[i]`` for ``genomes[i]``), scored as the run scored it."""
    try:
        directory = RunDirectory.open(run_directory)
    except RunDirectoryError as error:
        raise GalleryError(str(error)) from None
    pipeline = directory.pipeline
    if pipeline.backend != "mujoco-horse":
        raise GalleryError(
            f"gaits are drawn on the mujoco-horse backend; {run_directory} uses {pipeline.backend!r}"
        )
    import numpy as np

    from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
    from gaitgram.backends.mujoco_horse.render import RenderError, render_frames, write_animation

    generation = pipeline.config.generations
    try:
        evaluator = pipeline.load_evaluator({"threads": 1})
    except PipelineError as error:
        raise GalleryError(str(error)) from None
    try:
        assert isinstance(evaluator, HorseEvaluator)
        for genome, path in zip(genomes, paths, strict=True):
            mapped = pipeline.map([tuple(genome)])
            batch = pipeline.motion(mapped, generation)
            if batch.problems[0] is not None:
                raise GalleryError(f"{path.name}: {batch.details[0]}")
            control = evaluator.controls(batch, np.array([0]))[0]
            write_animation(render_frames(evaluator, control, fps=fps), path, fps)
    except RenderError as error:
        raise GalleryError(str(error)) from None
    finally:
        evaluator.close()
