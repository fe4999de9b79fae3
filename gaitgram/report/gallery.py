"""Animated gaits for a report: each arm's best walk, trade-offs along a front, repertoire cells.

Which gaits (:func:`gaits_section`) is data, decided before anything is
written: a cell no run filled is refused then. Each gait is drawn through its
run's own pipeline, as ``gaitgram render --run`` draws one: the run's codons,
backend settings and joint freedom at its last generation, played as scored by the
backend's render hook (``BackendSpec.render``; a backend without one draws nothing). MuJoCo
must find an offscreen OpenGL (``MUJOCO_GL=egl``, set by the report command before MuJoCo is
imported).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram.animation import RenderError, write_animation
from gaitgram.backends.registry import installed_backend
from gaitgram.evolution.rundir import KeptGait, RunDirectory, RunDirectoryError, best_walk_of_runs
from gaitgram.ge.registry import Genome
from gaitgram.pipeline import PipelineError
from gaitgram.report import escape
from gaitgram.report.records import ArmRecord, ReportError
from gaitgram.report.sections import Figure, Gait, Section, figure_name
from gaitgram.strategies.kept import Front, Repertoire


class GalleryError(ValueError):
    """A gait that cannot be drawn; says why."""


def draws(backend: str) -> bool:
    """Whether the backend named ``backend`` draws its gaits (declares a render hook; not when it
    is not installed here)."""
    spec = installed_backend(backend)
    return spec is not None and spec.render is not None


def _spread(count: int, wanted: int) -> np.ndarray:
    """``wanted`` indices spread evenly over ``count`` items, both ends included."""
    return np.unique(np.linspace(0, count - 1, min(wanted, count)).round().astype(int))


def trade_offs(front: Front, count: int) -> list[dict[str, Any]]:
    """``count`` members spread along the front, from the best in the first objective to the best
    in the last (both extremes included when ``count`` >= 2)."""
    if not front.members or count <= 0:
        return []
    order = np.argsort(front.points[:, 0], kind="stable")
    return [front.members[order[i]] for i in _spread(len(order), count)]


def spread_cells(repertoire: Repertoire, count: int) -> list[tuple[int, ...]]:
    """``count`` filled cells spread along the first descriptor (slow to fast on the horse)."""
    cells = sorted(repertoire.elites, key=lambda c: (c, repertoire.best[c]))
    if not cells or count <= 0:
        return []
    return [cells[i] for i in _spread(len(cells), count)]


def _gif(stem: str, caption: str, arm: ArmRecord, genome: Genome) -> Figure:
    return Figure(stem, caption, Gait(arm.path, tuple(genome)), ("gif",))


def gaits_section(
    arms: Sequence[ArmRecord],
    fronts: Mapping[str, Sequence[Front]],
    repertoires: Mapping[str, Repertoire | None],
    cells: Mapping[str, Sequence[tuple[int, ...]]],
    *,
    gaits: int,
) -> Section | None:
    """The GIFs a report makes: with ``gaits``, each arm's best walk (arms whose backend draws
    gaits and judges walks, that hand back one) and ``gaits`` trade-offs spread along each front
    (run 0's); the best gaits of the ``cells`` of each repertoire. A cell no run filled is a
    :class:`ReportError`."""
    figures: list[Figure] = []
    for arm in arms:
        walk = best_walk(arm) if gaits else None
        if walk is not None:
            fitness = walk.evaluation.fitness
            caption = f"{escape.markdown(arm.name)}: its best walk (run {walk.run}, fitness {fitness:.4g})"
            figures.append(_gif(figure_name("walk", arm.name, ""), caption, arm, walk.genome))
        found = fronts[arm.name]
        if found and gaits:
            members = trade_offs(found[0], gaits)
            for k, member in enumerate(members):
                caption = (
                    f"{escape.markdown(arm.name)}: trade-off {k + 1} of {len(members)} along run 0's front"
                )
                figures.append(
                    _gif(figure_name("front", f"{arm.name}-{k}", ""), caption, arm, member["genome"])
                )
        repertoire = repertoires[arm.name]
        if repertoire is not None:
            chosen = cells.get(arm.name, ())
            missing = [c for c in chosen if c not in repertoire.elites]
            if missing:
                raise ReportError(
                    f"arm {arm.name}: cell {','.join(map(str, missing[0]))} is empty in every run; filled: "
                    + " ".join(",".join(map(str, c)) for c in sorted(repertoire.elites))
                )
            for cell in chosen:
                where = ",".join(map(str, cell))
                stem = figure_name("cell", f"{arm.name}-{'-'.join(map(str, cell))}", "")
                caption = f"{escape.markdown(arm.name)}: the best gait of cell {where}"
                figures.append(_gif(stem, caption, arm, repertoire.elites[cell]["genome"]))
    if not figures:
        return None
    return Section("gaits", "Gaits", "animated, as scored", figures=tuple(figures))


def check_cells(arm: str, repertoire: Repertoire, cells: Sequence[tuple[int, ...]]) -> None:
    """Refuse a cell given with another number of indices than the repertoire has descriptors
    (``--cell 1`` of a grid), rather than call it empty."""
    names = [str(d["name"]) for d in repertoire.descriptors]
    for cell in cells:
        if len(cell) != len(names):
            shape = ",".join("IJ"[: len(names)])
            raise ReportError(
                f"--cell {','.join(map(str, cell))}: the repertoire of arm {arm} has {len(names)} "
                f"descriptor(s) ({', '.join(names)}); give a cell as {shape}"
            )


def best_walk(arm: ArmRecord) -> KeptGait | None:
    """The best walk any finished run of an arm hands back (of the runs the report reads); None if
    its backend draws no gaits or judges no walks, or no run hands one back."""
    if arm.walk_held_rate == 0:
        return None
    try:
        directory = RunDirectory.open(arm.path)
    except RunDirectoryError as error:
        raise ReportError(str(error)) from None
    if directory.pipeline.spec.render is None or directory.pipeline.spec.verdict is None:
        return None
    try:
        return best_walk_of_runs(directory, finished_only=True, runs=arm.numbers)
    except RunDirectoryError as error:
        if arm.walk_held_rate is None:  # the records did not say; the checkpoints say there is none
            return None
        raise ReportError(str(error)) from None


#: A report's animations: small enough that a study's report.html, which embeds them, stays a page
#: (480 x 360 at 20 fps made 3.6 MB a gait, 21 MB for four arms); ``gaitgram render`` draws large.
GIF_FPS = 12
GIF_SIZE = (320, 240)


def render_gaits(
    run_directory: Path, genomes: Sequence[Genome], paths: Sequence[Path], fps: int = GIF_FPS
) -> None:
    """One GIF per genome (``paths[i]`` for ``genomes[i]``), played as the run scored it."""
    try:
        directory = RunDirectory.open(run_directory)
    except RunDirectoryError as error:
        raise GalleryError(str(error)) from None
    pipeline = directory.pipeline
    batch = pipeline.motion(pipeline.map([tuple(g) for g in genomes]), pipeline.config.generations)
    for g, path in enumerate(paths):
        if batch.problems[g] is not None:
            raise GalleryError(f"{path.name}: {batch.details[g]}")
    width, height = GIF_SIZE
    try:
        drawn = pipeline.render(batch, fps=fps, width=width, height=height)
        for frames, path in zip(drawn, paths, strict=True):
            write_animation(frames, path, fps)
    except (RenderError, PipelineError) as error:
        raise GalleryError(str(error)) from None
