"""``gaitgram render``: a gait as an animation (GIF or MP4) and a strip of frames, rendered offscreen;
with ``--compare``, beside the walk seed or another run's best gait."""

from __future__ import annotations

import difflib
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from gaitgram import fileio
from gaitgram.backends.registry import backends_that
from gaitgram.cli.common import (
    as_they_were,
    check_output,
    err,
    fail,
    interrupted,
    mend_outputs,
    write_all_or_exit,
)
from gaitgram.cli.options import Defines, Settings, Walk, parse_settings
from gaitgram.cli.selection import (
    Codons,
    GenomeCodons,
    GenomeFile,
    Grammar,
    MaxWraps,
    SelectedGait,
    SelectionError,
    gait_inputs,
    select_gait,
)
from gaitgram.evolution.rundir import run_input
from gaitgram.evolution.selection import judged
from gaitgram.extras import MissingExtra
from gaitgram.pipeline import Pipeline, PipelineError

if TYPE_CHECKING:
    from collections.abc import Mapping

    import numpy as np

    from gaitgram.motion.gait import MotionBatch

#: ``--compare seed``: the bundled walk seed rather than a run directory.
SEED = "seed"


_Output = Annotated[
    Path,
    typer.Option(
        "--output",
        "-o",
        help="The animation to write, by its suffix: walk.gif, or walk.mp4 (pip install 'gaitgram[video]').",
    ),
]
_Run = Annotated[
    Path | None,
    typer.Option("--run", help="Render with this run directory's own pipeline; by default its best gait."),
]
_Generation = Annotated[
    int | None,
    typer.Option(min=0, help="Show the gait as in this generation's joint freedom (default: the last)."),
]
_Config = Annotated[
    Path | None,
    typer.Option("--config", "-c", help="A run.toml: codons, backend settings (not with --run)."),
]
_Compare = Annotated[
    str | None,
    typer.Option(
        "--compare",
        metavar="seed|BODY|DIR",
        help="Show a second gait beside this one, in step: 'seed' (the bundled walk seed, on the "
        "same horse and settings), a body (the same gait on it, its frequency scaled by dynamic "
        "similarity: shetland, pony, horse, draft) or a run directory (its best gait, through its "
        "own pipeline; ./seed or ./draft for a directory of that name).",
    ),
]
_Strip = Annotated[
    Path | None,
    typer.Option(
        help="Also write a PNG strip of frames (default: OUTPUT with .png); with --compare, the "
        "second gait's strip below."
    ),
]


def command(
    output: _Output,
    grammar: Grammar = None,
    run: _Run = None,
    genome: GenomeCodons = None,
    genome_file: GenomeFile = None,
    generation: _Generation = None,
    config: _Config = None,
    codons: Codons = None,
    max_wraps: MaxWraps = None,
    compare: _Compare = None,
    strip: _Strip = None,
    fps: Annotated[int, typer.Option(min=1, max=60, help="Frames per second of the animation.")] = 25,
    force: Annotated[bool, typer.Option("--force", help="Overwrite existing output files.")] = False,
    walk: Walk = False,
    defines: Defines = None,
    setting: Settings = None,
) -> None:
    """Render a gait offscreen, as its backend plays it when scoring (MUJOCO_GL=egl by default).

    The gait goes through the same pipeline as scoring: the run's codons, wraps, backend settings
    (its Froude number sets the stride frequency) and joint freedom. The output's suffix chooses
    the format: .gif, or .mp4 (H.264) with the video extra. With --compare, both gaits play side
    by side, each labelled, for example a run's best beside the seed it started from.
    """
    os.environ.setdefault("MUJOCO_GL", "egl")  # before MuJoCo is imported
    inputs = gait_inputs(run, grammar, genome_file, config)
    if compare not in (None, SEED) and Path(compare).is_dir():
        inputs.append(run_input(Path(compare)))
    strip = _check_outputs(output, strip, force, inputs)
    overrides = {
        "codons": codons.value if codons is not None else None,
        "max_wraps": max_wraps,
        "backend_settings": parse_settings(setting) or None,
    }
    try:
        chosen = select_gait(run, grammar, genome, genome_file, generation, config, overrides, defines, walk)
        shown, beside = _gaits(chosen, compare)
        animation, movie, pictures = _render(output, fps, shown, beside)
        verdict = _verdict(chosen)
    except SelectionError as error:
        raise fail(str(error)) from None
    except KeyboardInterrupt:
        raise interrupted(as_they_were([output, strip])) from None
    write_all_or_exit([(output, movie), (strip, pictures)])
    what = chosen.describe + (f", beside {beside.label}" if beside is not None else "")
    err.print(f"wrote {output} ({len(animation)} frames) and {strip}; {what}")
    if verdict is not None:
        err.print(f"the gait shown is {verdict}")


def _check_outputs(output: Path, strip: Path | None, force: bool, inputs: list[fileio.Input]) -> Path:
    """Refuse, before any work, outputs that cannot be written or would write over what the command
    reads (a new file in a run directory, beside its records, is fine: ``runs/x/best.gif``), and an
    animation format whose extra is missing; the strip's path (by default the animation's, with
    .png)."""
    from gaitgram.animation import RenderError, require_writers

    try:
        require_writers(output)  # the format from the suffix, and its extra: before any work
    except (RenderError, MissingExtra) as error:
        raise fail(str(error)) from None
    strip = strip or output.with_suffix(".png")
    mend_outputs(output, strip)  # a swap cut short there is put back before they are checked
    check_output(output, force=force, flag="-o", inputs=inputs)
    check_output(strip, force=force, flag="--strip", inputs=inputs)
    if not fileio.is_stream(strip) and os.path.realpath(strip) == os.path.realpath(output):
        raise fail(f"--strip {strip} is the animation's own file; give the strip another name")
    return strip


def _gaits(chosen: SelectedGait, compare: str | None) -> tuple[_Gait, _Gait | None]:
    """The chosen gait and, with ``--compare``, the one to show beside it (exit 2 if the backend of
    either draws no gaits, or cannot play the walk seed)."""
    bodies = chosen.pipeline.spec.bodies or {}
    body = compare if compare in bodies else None
    if compare not in (None, SEED) and body is None and not os.path.lexists(compare):  # a loop: said below
        close = difflib.get_close_matches(compare, [SEED, *bodies], n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise fail(
            f"--compare {compare}: no run directory, `{SEED}` or body by that name; {hint}"
            f"bodies: {', '.join(bodies) or 'none'}"
        )
    other = None if compare in (None, SEED) or body is not None else _best_of(Path(compare))
    for gait in (chosen, other):
        if gait is not None and gait.pipeline.spec.render is None:
            drawn = " or ".join(backends_that(lambda spec: spec.render is not None)) or "no installed"
            backend = gait.pipeline.backend
            raise fail(f"render draws the {drawn} backend; {gait.describe} is scored by {backend!r}")
    shown = _Gait.of(chosen)
    if compare is None:
        return shown, None
    if body is not None:
        return shown, shown.on(body)
    return shown, _Gait.of(other) if other is not None else _Gait.seed(chosen)


def _render(
    output: Path, fps: int, shown: _Gait, beside: _Gait | None
) -> tuple[list[np.ndarray], bytes, bytes]:
    """The animation's frames, the animation encoded as ``output``'s suffix says, and the strip."""
    from gaitgram.animation import (
        RenderError,
        animation_format,
        encode_animation,
        labelled,
        side_by_side,
        strip_png,
    )

    try:
        frames = shown.frames(fps)
        if beside is None:
            animation = frames
            pictures = strip_png(frames)
        else:
            second = beside.frames(fps)
            animation = side_by_side(labelled(frames, shown.label), labelled(second, beside.label))
            pictures = strip_png(frames, below=second, labels=(shown.label, beside.label))
        movie = encode_animation(animation, animation_format(output), fps)
    except (RenderError, PipelineError) as error:
        raise fail(str(error)) from None
    return animation, movie, pictures


def _verdict(chosen: SelectedGait) -> str | None:
    """Whether the gait shown is what its backend judges gaits by (a walk, say), as the run
    recorded it or, for a gait it did not record, scored now; None for a backend that judges none."""
    verdict = chosen.pipeline.spec.verdict
    if verdict is None:
        return None
    try:
        return verdict.sentence(judged(chosen))
    except PipelineError as error:
        raise fail(str(error)) from None


def _best_of(path: Path) -> SelectedGait:
    """``--compare DIR``: the run directory's best gait, through its own pipeline."""
    return select_gait(run=path)


@dataclass
class _Gait:
    """One gait to draw: its motion, the pipeline whose backend draws it (under ``settings``; None:
    the pipeline's own), and its label."""

    batch: MotionBatch
    pipeline: Pipeline
    label: str
    settings: Mapping[str, Any] | None = None

    @classmethod
    def of(cls, chosen: SelectedGait) -> _Gait:
        """A selected gait, mapped and made motion by its pipeline (exit 1 if it has none)."""
        pipeline = chosen.pipeline
        (mapped,) = pipeline.map([chosen.genome])
        if not mapped.valid:
            raise fail(f"the genome is invalid ({mapped.reason}); nothing to render", 1)
        batch = pipeline.motion([mapped], chosen.generation)
        if batch.problems[0] is not None:
            raise fail(f"{batch.details[0]}", 1)
        return cls(batch, pipeline, _short(chosen))

    @classmethod
    def seed(cls, chosen: SelectedGait) -> _Gait:
        """The bundled walk seed, played with the chosen gait's backend and settings (exit 2 if
        that backend lacks a joint the seed drives)."""
        from gaitgram.seed import load_seed

        batch = load_seed().motion_batch()
        catalogue = chosen.pipeline.spec.catalogue
        lacking = [j for j in batch.joints if catalogue is not None and catalogue.get(j) is None]
        if lacking:
            raise fail(
                f"--compare {SEED}: the walk seed drives {', '.join(lacking)}, which backend "
                f"{chosen.pipeline.backend!r} lacks; compare with a run directory instead"
            )
        return cls(batch, chosen.pipeline, "walk seed")

    def on(self, body: str) -> _Gait:
        """This gait on ``body``, its cycle frequency scaled by dynamic similarity."""
        retarget = self.pipeline.spec.retarget
        assert retarget is not None  # the backend names bodies
        try:
            settings, batch = retarget(self.pipeline.config.backend_settings, self.batch, body, "froude")
        except ValueError as error:
            raise fail(f"--compare {body}: {error}") from None
        return _Gait(batch, self.pipeline, f"on {body} (Froude-scaled)", settings)

    def frames(self, fps: int) -> list[np.ndarray]:
        (frames,) = self.pipeline.render(self.batch, settings=self.settings, fps=fps)
        return frames


def _short(chosen: SelectedGait) -> str:
    """A label that fits a frame: where the gait comes from (the last part of a long path), and
    its generation."""
    return chosen.describe if len(chosen.describe) <= 40 else chosen.describe.rsplit("/", 1)[-1]
