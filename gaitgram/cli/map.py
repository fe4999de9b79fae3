"""``gaitgram map``: one genome through a grammar, with its derivation tree; a closed loop's curves
split into their open-loop part and their feedback terms. The genome is written in its
representation's syntax (GE's codons by default; ``--representation sge`` reads SGE's genes)."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated, NoReturn

import typer
from rich.console import Console

from gaitgram import jsonio
from gaitgram.analysis.motion_text import ClosedLoops, closed_loops
from gaitgram.cli.common import compiled_or_exit, err, fail, load_usable, read_genome
from gaitgram.cli.options import Defines, Representation, RepresentationSettings, ge_default, parse_defines
from gaitgram.ge import CodonMode, python_filter
from gaitgram.ge.derivation import Derivation
from gaitgram.ge.registry import DEFAULT_REPRESENTATION, Compiled, mapping_summary
from gaitgram.ge.visualise import GraphvizMissing, TreeTooLarge, check_derivation_size, render_tree


class TreeFormat(StrEnum):
    ASCII = "ascii"
    DOT = "dot"
    SVG = "svg"
    MERMAID = "mermaid"


_Codons = Annotated[
    CodonMode | None,
    typer.Option(help=f"GE: lazy (GEVA, the paper) or eager (PonyGE2); default {ge_default('codons')}."),
]
_MaxWraps = Annotated[
    int | None,
    typer.Option(
        min=0, help=f"W wraps allow W+1 passes over the genome (GE: default {ge_default('max_wraps')})."
    ),
]


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar.", show_default=False)],
    genome: Annotated[
        str | None,
        typer.Option(help="The genome in its representation's syntax: GE's codons, e.g. 12,7,301."),
    ] = None,
    genome_file: Annotated[
        Path | None, typer.Option(help="Read the genome from a file; - for standard input.")
    ] = None,
    representation: Representation = DEFAULT_REPRESENTATION,
    setting: RepresentationSettings = None,
    codons: _Codons = None,
    max_wraps: _MaxWraps = None,
    max_depth: Annotated[int | None, typer.Option(min=1, help="Deepest allowed rule node.")] = None,
    tree: Annotated[TreeFormat | None, typer.Option(help="Also print the derivation tree.")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    defines: Defines = None,
) -> None:
    """Map a genome to its phenotype: what it used, wraps, depth, nodes, joint curves, and the tree."""
    result = load_usable(grammar, parse_defines(defines))
    compiled = compiled_or_exit(
        result,
        representation,
        setting,
        codons=codons.value if codons is not None else None,
        max_wraps=max_wraps,
        max_depth=max_depth,
    )
    genome_value = read_genome(genome, genome_file, compiled)
    try:
        check_derivation_size(compiled.map_many([genome_value])[0].used, drawn=tree is not None)
    except TreeTooLarge as refusal:
        _refuse_tree(refusal, drawn=tree is not None)
    derivation = compiled.derivation(genome_value)
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
        record = mapping_summary(compiled, derivation)
        if loops is not None:
            record["closed_loop"] = loops.summary()
        if rendered is not None:
            record["tree"] = rendered
        typer.echo(jsonio.dumps(record))
    else:
        _show(compiled, derivation, loops, rendered)
    if not derivation.valid:
        raise typer.Exit(1)


def _show(
    compiled: Compiled, derivation: Derivation, loops: ClosedLoops | None, rendered: str | None
) -> None:
    """For people: the phenotype (or why there is none), what the mapping used, the joints, a
    closed loop's split and the tree."""
    out = Console(highlight=False, soft_wrap=True, markup=False)
    if derivation.valid:
        out.print(derivation.phenotype, markup=False)
    else:
        out.print(f"invalid: {derivation.reason}", style="bold red")
    wraps = f", wraps {derivation.wraps}" if compiled.counts == "codons" else ""
    err.print(
        f"used {compiled.counts} {derivation.used_codons}{wraps}, depth {derivation.depth}, "
        f"nodes {derivation.nodes}"
    )
    for joint, text in derivation.joints.items():
        out.print(f"{joint}: {text}", markup=False)
    for line in loops.lines() if loops is not None else ():
        err.print(line)
    if rendered is not None:
        typer.echo(rendered, nl=False)


def _refuse_tree(refusal: TreeTooLarge, *, drawn: bool) -> NoReturn:
    hint = "use a shorter genome, fewer --max-wraps or a --max-depth" + (", or no --tree" if drawn else "")
    raise fail(f"{refusal}; {hint}")
