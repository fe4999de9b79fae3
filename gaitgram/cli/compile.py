"""``gaitgram compile``: a grammar to mapper tables, a standalone Python mapper, or PonyGE2 BNF."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from gaitgram.cli.common import check_output, err, load_usable, read_inputs, write_or_exit
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.ge import CodonMode, MappingOptions
from gaitgram.ge.export import to_json, to_ponyge2, to_python


class Target(StrEnum):
    JSON = "json"
    PYTHON = "python"
    PONYGE2 = "ponyge2"


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar to compile.", show_default=False)],
    output: Annotated[Path, typer.Option("--output", "-o", help="Where to write; - for standard output.")],
    target: Annotated[Target, typer.Option("--target", "-t", help="What to write.")] = Target.JSON,
    codons: Annotated[
        CodonMode, typer.Option(help="Codon consumption stored as the default.")
    ] = CodonMode.LAZY,
    max_wraps: Annotated[int, typer.Option(min=0, help="Wraps stored as the default.")] = 3,
    max_depth: Annotated[int | None, typer.Option(min=1, help="Depth limit stored as the default.")] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite OUTPUT if it exists.")] = False,
    defines: Defines = None,
) -> None:
    """Compile a grammar to mapper tables, a standalone Python mapper, or PonyGE2 BNF.

    json: portable tables (docs/ge.md); python: a module that maps genomes with no gaitgram
    installed; ponyge2: plain BNF with typed ranges expanded, for PonyGE2 and GEVA.
    """
    result = load_usable(grammar, parse_defines(defines))  # the grammar's errors come first
    if str(output) != "-":
        check_output(output, force=force, flag="-o", inputs=read_inputs((grammar, "the grammar")))
    options = MappingOptions(codons, max_wraps, max_depth)
    if target is Target.JSON:
        text = to_json(result.grammar, options)
    elif target is Target.PYTHON:
        text = to_python(result.grammar, options, module=output.stem if str(output) != "-" else "mapper")
    else:
        text = to_ponyge2(result.grammar)
    if str(output) == "-":
        typer.echo(text, nl=False)
        return
    write_or_exit(output, text)
    err.print(f"wrote {output} ({target.value})")
