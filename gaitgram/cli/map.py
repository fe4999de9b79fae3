"""``gaitgram map``: one genome through a grammar, with its derivation tree; a closed loop's curves
split into their open-loop part and their feedback terms."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated, NoReturn

import typer
from rich.console import Console

from gaitgram import jsonio
from gaitgram.analysis.motion_text import closed_loops
from gaitgram.cli.common import err, fail, load_usable, read_genome
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.ge import CodonMode, compile_mapper, python_filter
from gaitgram.ge.visualise import GraphvizMissing, TreeTooLarge, check_derivation_size, render_tree


class TreeFormat(StrEnum):
    ASCII = "ascii"
    DOT = "dot"
    SVG = "svg"
    MERMAID = "mermaid"


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar.", show_default=False)],
    genome: Annotated[str | None, typer.Option(help="Codons, e.g. 12,7,301.")] = None,
    genome_file: Annotated[
        Path | None, typer.Option(help="Read the codons from a file; - for standard input.")
    ] = None,
    codons: Annotated[
        CodonMode, typer.Option(help="lazy (GEVA, the paper) or eager (PonyGE2).")
    ] = CodonMode.LAZY,
    max_wraps: Annotated[int, typer.Option(min=0, help="W wraps allow W+1 passes over the genome.")] = 3,
    max_depth: Annotated[int | None, typer.Option(min=1, help="Deepest allowed rule node.")] = None,
    tree: Annotated[TreeFormat | None, typer.Option(help="Also print the derivation tree.")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    defines: Defines = None,
) -> None:
    """Map a genome to its phenotype: used codons, wraps, depth, nodes, joint curves, and the tree."""
    codon_values = read_genome(genome, genome_file)
    result = load_usable(grammar, parse_defines(defines))
    mapper = compile_mapper(result.grammar, codons=codons, max_wraps=max_wraps, max_depth=max_depth)
    try:
        check_derivation_size(mapper.map_fast(codon_values).used_codons, drawn=tree is not None)
    except TreeTooLarge as refusal:
        _refuse_tree(refusal, drawn=tree is not None)
    derivation = mapper.map(codon_values)
    if grammar.suffix == ".pybnf" and derivation.phenotype is not None:  # PonyGE2's python mode
        derivation.phenotype = python_filter(derivation.phenotype)
    rendered = None
    if tree is not None:
        try:
            rendered = render_tree(derivation, tree.value)
        except GraphvizMissing as missing:
            raise fail(str(missing)) from None
        except TreeTooLarge as refusal:
            _refuse_tree(refusal, drawn=tree is not None)
    loops = closed_loops(result.grammar, result.facts, derivation.joints) if derivation.valid else None
    if as_json:
        record = derivation.summary()
        if loops is not None:
            record["closed_loop"] = loops.summary()
        if rendered is not None:
            record["tree"] = rendered
        typer.echo(jsonio.dumps(record))
    else:
        out = Console(highlight=False, soft_wrap=True, markup=False)
        if derivation.valid:
            out.print(derivation.phenotype, markup=False)
        else:
            out.print(f"invalid: {derivation.reason}", style="bold red")
        err.print(
            f"used codons {derivation.used_codons}, wraps {derivation.wraps}, depth {derivation.depth}, "
            f"nodes {derivation.nodes}"
        )
        for joint, text in derivation.joints.items():
            out.print(f"{joint}: {text}", markup=False)
        for line in loops.lines() if loops is not None else ():
            err.print(line)
        if rendered is not None:
            typer.echo(rendered, nl=False)
    if not derivation.valid:
        raise typer.Exit(1)


def _refuse_tree(refusal: TreeTooLarge, *, drawn: bool) -> NoReturn:
    hint = "use a shorter genome, fewer --max-wraps or a --max-depth" + (", or no --tree" if drawn else "")
    raise fail(f"{refusal}; {hint}")
