"""``gaitgram compile``: a grammar to mapper tables (of any representation), a standalone Python
mapper (GE's), or PonyGE2 BNF."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from gaitgram import jsonio
from gaitgram.cli.common import (
    check_output,
    compiled_or_exit,
    err,
    fail,
    load_usable,
    read_inputs,
    write_or_exit,
)
from gaitgram.cli.options import Defines, Representation, RepresentationSettings, ge_default, parse_defines
from gaitgram.ge import CodonMode, MappingOptions
from gaitgram.ge.export import to_ponyge2, to_python
from gaitgram.ge.registry import DEFAULT_REPRESENTATION


class Target(StrEnum):
    JSON = "json"
    PYTHON = "python"
    PONYGE2 = "ponyge2"


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar to compile.", show_default=False)],
    output: Annotated[Path, typer.Option("--output", "-o", help="Where to write; - for standard output.")],
    target: Annotated[Target, typer.Option("--target", "-t", help="What to write.")] = Target.JSON,
    codons: Annotated[
        CodonMode | None,
        typer.Option(help=f"GE: codon consumption stored as the default ({ge_default('codons')})."),
    ] = None,
    max_wraps: Annotated[
        int | None, typer.Option(min=0, help=f"GE: wraps stored as the default ({ge_default('max_wraps')}).")
    ] = None,
    max_depth: Annotated[int | None, typer.Option(min=1, help="Depth limit stored as the default.")] = None,
    representation: Representation = DEFAULT_REPRESENTATION,
    setting: RepresentationSettings = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite OUTPUT if it exists.")] = False,
    defines: Defines = None,
) -> None:
    """Compile a grammar to mapper tables, a standalone Python mapper, or PonyGE2 BNF.

    json: portable tables of the representation's mapping (docs/ge.md; SGE's unrolled genes, say);
    python: a module that maps GE genomes with no gaitgram installed; ponyge2: plain BNF with typed
    ranges expanded, for PonyGE2 and GEVA.
    """
    result = load_usable(grammar, parse_defines(defines))  # the grammar's errors come first
    if str(output) != "-":
        check_output(output, force=force, flag="-o", inputs=read_inputs((grammar, "the grammar")))
    if target is Target.PYTHON and representation != DEFAULT_REPRESENTATION:
        raise fail(
            f"--target python writes GE's mapper; for {representation}, write its tables (--target json)"
        )
    compiled = compiled_or_exit(
        result,
        representation,
        setting,
        codons=codons.value if codons is not None else None,
        max_wraps=max_wraps,
        max_depth=max_depth,
    )
    if target is Target.JSON:
        text = jsonio.dumps(compiled.tables(), indent=1) + "\n"
    elif target is Target.PYTHON:
        options: MappingOptions = compiled.options  # type: ignore[attr-defined]  # GE's, checked above
        text = to_python(result.grammar, options, module=output.stem if str(output) != "-" else "mapper")
    else:
        text = to_ponyge2(result.grammar)
    if str(output) == "-":
        typer.echo(text, nl=False)
        return
    write_or_exit(output, text)
    err.print(f"wrote {output} ({target.value})")
