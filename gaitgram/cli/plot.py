"""``gaitgram plot``: the joint-angle curves of a genome, beside the seed (a closed loop's nominal)."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Annotated

import typer

from gaitgram.cli.common import (
    check_output,
    compiled_or_exit,
    err,
    fail,
    load_usable,
    read_genome,
    read_inputs,
    require_extra,
    write_or_exit,
)
from gaitgram.cli.options import Defines, Representation, RepresentationSettings, ge_default, parse_defines
from gaitgram.ge import CodonMode
from gaitgram.ge.registry import DEFAULT_REPRESENTATION


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar.", show_default=False)],
    output: Annotated[Path, typer.Option("--output", "-o", help="curves.png or curves.svg.")],
    genome: Annotated[
        str | None,
        typer.Option(help="The genome in its representation's syntax (GE: codons, e.g. 12,7,301)."),
    ] = None,
    genome_file: Annotated[Path | None, typer.Option(help="The genome from a file; - for stdin.")] = None,
    seed: Annotated[bool, typer.Option(help="Draw the bundled seed curves dashed.")] = True,
    codons: Annotated[
        CodonMode | None,
        typer.Option(help=f"GE: lazy or eager codon consumption (default {ge_default('codons')})."),
    ] = None,
    max_wraps: Annotated[
        int | None, typer.Option(min=0, help=f"GE: wraps allowed (default {ge_default('max_wraps')}).")
    ] = None,
    representation: Representation = DEFAULT_REPRESENTATION,
    setting: RepresentationSettings = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite OUTPUT.")] = False,
    defines: Defines = None,
) -> None:
    """Plot each joint's curve over one cycle (one panel per joint), the seed dashed beside it."""
    require_extra("matplotlib", "plots")
    if output.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise typer.BadParameter("the output must end in .png, .svg or .pdf", param_hint="--output")
    inputs = read_inputs((grammar, "the grammar"), (genome_file, "the --genome-file"))
    check_output(output, force=force, flag="-o", inputs=inputs)
    checked = load_usable(grammar, parse_defines(defines))
    compiled = compiled_or_exit(
        checked, representation, setting, codons=codons.value if codons else None, max_wraps=max_wraps
    )
    derivation = compiled.derivation(read_genome(genome, genome_file, compiled))
    if not derivation.valid:
        raise fail(f"the genome is invalid ({derivation.reason}); nothing to plot", 1)
    from gaitgram.analysis.motion_text import closed_loops
    from gaitgram.backends.registry import get_backend
    from gaitgram.motion.plot import curves_figure
    from gaitgram.pipeline import DEFAULT_BACKEND, sensors_of
    from gaitgram.seed import load_seed

    joints = [j.joint for j in checked.grammar.joints] or list(derivation.joints)
    loops = closed_loops(checked.grammar, checked.facts, derivation.joints)
    sensors = sensors_of(get_backend(checked.grammar.backend or DEFAULT_BACKEND)) if loops else None
    figure = curves_figure(
        joints, derivation.joints, load_seed().angles if seed else None, title=grammar.name, sensors=sensors
    )
    image = io.BytesIO()
    figure.savefig(image, format=output.suffix.lower()[1:], dpi=110)
    write_or_exit(output, image.getvalue())
    if loops is not None:
        err.print(loops.note())
    err.print(f"wrote {output}")
