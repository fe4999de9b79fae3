"""``gaitgram render``: a gait as an animation and a strip of frames, rendered offscreen."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Annotated

import typer

from gaitgram.cli.common import err, load_usable, read_genome
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.ge import CodonMode, compile_mapper


def command(
    output: Annotated[Path, typer.Option("--output", "-o", help="walk.gif, or walk.mp4 with ffmpeg.")],
    grammar: Annotated[Path | None, typer.Argument(help="The grammar (not needed with --run).")] = None,
    run: Annotated[
        Path | None, typer.Option("--run", help="Render the best gait of this `gaitgram evolve` directory.")
    ] = None,
    genome: Annotated[str | None, typer.Option(help="Codons, e.g. 12,7,301.")] = None,
    genome_file: Annotated[
        Path | None, typer.Option(help="Read the codons from a file; - for stdin.")
    ] = None,
    strip: Annotated[Path | None, typer.Option(help="Also a PNG strip of frames [OUTPUT with .png].")] = None,
    fps: Annotated[int, typer.Option(min=1, max=60)] = 25,
    codons: Annotated[CodonMode, typer.Option(help="lazy or eager codon consumption.")] = CodonMode.LAZY,
    max_wraps: Annotated[int, typer.Option(min=0)] = 3,
    force: Annotated[bool, typer.Option("--force", help="Overwrite existing files.")] = False,
    defines: Defines = None,
) -> None:
    """Render the gait of a genome on the mujoco-horse backend offscreen (MUJOCO_GL=egl by default)."""
    os.environ.setdefault("MUJOCO_GL", "egl")  # before MuJoCo is imported
    try:
        import PIL  # noqa: F401
    except ImportError:
        err.print("error: rendering needs Pillow: pip install 'gaitgram[plot]'", style="bold red")
        raise typer.Exit(2) from None
    if run is not None:
        grammar, codon_values = _best_of_run(run)
    elif grammar is None:
        raise typer.BadParameter("give a grammar and a genome, or --run DIR", param_hint="GRAMMAR")
    else:
        codon_values = read_genome(genome, genome_file)
    checked = load_usable(grammar, parse_defines(defines))
    strip = strip or output.with_suffix(".png")
    for path in (output, strip):
        if path.exists() and not force:
            err.print(f"error: {path} exists; pass --force to overwrite it", style="bold red")
            raise typer.Exit(2)
    from gaitgram.backends.mujoco_horse.evaluator import load
    from gaitgram.backends.mujoco_horse.render import RenderError, render_frames, write_animation, write_strip
    from gaitgram.motion.gait import motion_batch

    mapped = compile_mapper(checked.grammar, codons=codons, max_wraps=max_wraps).map_fast(codon_values)
    if not mapped.valid:
        err.print(f"error: the genome is invalid ({mapped.reason}); nothing to render", style="bold red")
        raise typer.Exit(1)
    evaluator = load({"threads": 1})
    try:
        batch = motion_batch([mapped.joints], evaluator.layout.curves, units=checked.grammar.units)
        if batch.problems[0] is not None:
            err.print(f"error: {batch.details[0]}", style="bold red")
            raise typer.Exit(1)
        import numpy as np

        control = evaluator.controls(batch, np.array([0]))[0]
        frames = render_frames(evaluator, control, fps=fps)
        write_animation(frames, output, fps)
        write_strip(frames, strip)
    except RenderError as error:
        err.print(f"error: {error}", style="bold red")
        raise typer.Exit(2) from None
    finally:
        evaluator.close()
    err.print(f"wrote {output} ({len(frames)} frames) and {strip}")


def _best_of_run(directory: Path) -> tuple[Path, tuple[int, ...]]:
    """The run directory's grammar and the genome of its best individual over all runs."""
    bests = []
    for path in sorted(directory.glob("run-*/best.json")):
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError) as error:
            raise typer.BadParameter(f"{path}: cannot read: {error}", param_hint="--run") from None
        bests.append((record["fitness"], tuple(record["genome"])))
    if not bests or not (directory / "grammar.gg").exists():
        raise typer.BadParameter(f"{directory} is not a `gaitgram evolve` run directory", param_hint="--run")
    return directory / "grammar.gg", min(bests)[1]
