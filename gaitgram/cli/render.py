"""``gaitgram render``: a gait as an animation and a strip of frames, rendered offscreen."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated

import typer

from gaitgram.cli.common import err
from gaitgram.cli.options import Defines
from gaitgram.cli.selection import SelectionError, select_gait
from gaitgram.ge import CodonMode
from gaitgram.pipeline import PipelineError


def fail(message: str, code: int = 2) -> typer.Exit:
    err.print(f"error: {message}", style="bold red", markup=False)
    return typer.Exit(code)


def command(
    output: Annotated[
        Path,
        typer.Option("--output", "-o", help="The animation to write: walk.gif, or walk.mp4 with ffmpeg."),
    ],
    grammar: Annotated[Path | None, typer.Argument(help="The grammar (not with --run).")] = None,
    run: Annotated[
        Path | None,
        typer.Option(
            "--run", help="Render with this run directory's own pipeline; by default its best gait."
        ),
    ] = None,
    genome: Annotated[str | None, typer.Option(help="Codons, for example 12,7,301.")] = None,
    genome_file: Annotated[
        Path | None, typer.Option(help="Read the codons from a file; - for standard input.")
    ] = None,
    generation: Annotated[
        int | None,
        typer.Option(min=0, help="Show the gait as in this generation's joint freedom (default: the last)."),
    ] = None,
    config: Annotated[
        Path | None,
        typer.Option("--config", "-c", help="A run.toml: codons, backend settings (not with --run)."),
    ] = None,
    codons: Annotated[
        CodonMode | None, typer.Option(help="Codon consumption, lazy or eager (default lazy).")
    ] = None,
    max_wraps: Annotated[int | None, typer.Option(min=0, help="Wraps allowed (default 3).")] = None,
    strip: Annotated[
        Path | None, typer.Option(help="Also write a PNG strip of frames (default: OUTPUT with .png).")
    ] = None,
    fps: Annotated[int, typer.Option(min=1, max=60, help="Frames per second of the animation.")] = 25,
    force: Annotated[bool, typer.Option("--force", help="Overwrite existing output files.")] = False,
    defines: Defines = None,
) -> None:
    """Render a gait on the mujoco-horse backend offscreen (MUJOCO_GL=egl by default).

    The gait goes through the same pipeline as scoring: the run's codons, wraps, backend settings
    (its Froude number sets the stride frequency) and joint freedom.
    """
    os.environ.setdefault("MUJOCO_GL", "egl")  # before MuJoCo is imported
    try:
        import PIL  # noqa: F401
    except ImportError:
        raise fail("rendering needs Pillow: pip install 'gaitgram[plot]'") from None
    overrides = {"codons": codons.value if codons is not None else None, "max_wraps": max_wraps}
    try:
        chosen = select_gait(
            run=run,
            grammar=grammar,
            genome=genome,
            genome_file=genome_file,
            generation=generation,
            config=config,
            overrides=overrides,
            defines=defines,
        )
    except SelectionError as error:
        raise fail(str(error)) from None
    pipeline = chosen.pipeline
    if pipeline.backend != "mujoco-horse":
        raise fail(f"render draws the mujoco-horse backend; this gait is scored by {pipeline.backend!r}")
    strip = strip or output.with_suffix(".png")
    for path in (output, strip):
        if path.exists() and not force:
            raise fail(f"{path} exists; pass --force to overwrite it")
    (mapped,) = pipeline.map([chosen.genome])
    if not mapped.valid:
        raise fail(f"the genome is invalid ({mapped.reason}); nothing to render", 1)
    batch = pipeline.motion([mapped], chosen.generation)
    if batch.problems[0] is not None:
        raise fail(f"{batch.details[0]}", 1)

    import numpy as np

    from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
    from gaitgram.backends.mujoco_horse.render import RenderError, render_frames, write_animation, write_strip

    try:
        evaluator = pipeline.load_evaluator({"threads": 1})
    except PipelineError as error:
        raise fail(str(error)) from None
    try:
        assert isinstance(evaluator, HorseEvaluator)
        control = evaluator.controls(batch, np.array([0]))[0]
        frames = render_frames(evaluator, control, fps=fps)
        write_animation(frames, output, fps)
        write_strip(frames, strip)
    except RenderError as error:
        raise fail(str(error)) from None
    except OSError as error:
        raise fail(f"cannot write {error.filename or output}: {error.strerror or error}") from None
    finally:
        evaluator.close()
    err.print(f"wrote {output} ({len(frames)} frames) and {strip}; {chosen.describe}", markup=False)
