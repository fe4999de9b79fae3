"""``gaitgram sample``: random derivations, to see what a grammar produces."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from gaitgram.cli.common import err, load_usable
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.ge.initialisation import InitialisationError, Method, ramped_population, random_tree


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar.", show_default=False)],
    count: Annotated[int, typer.Option("-n", "--count", min=1, help="How many derivations.")] = 10,
    method: Annotated[
        Method, typer.Option(help="grow, full, or ramped (half each, depths ramped).")
    ] = Method.RAMPED,
    max_depth: Annotated[int, typer.Option(min=1, help="Deepest rule node.")] = 10,
    seed: Annotated[int, typer.Option(help="Random seed: the same seed gives the same samples.")] = 0,
    codons: Annotated[
        CodonMode, typer.Option(help="Codon consumption the genomes are made for.")
    ] = CodonMode.LAZY,
    as_json: Annotated[bool, typer.Option("--json", help="One JSON object per line.")] = False,
    defines: Defines = None,
) -> None:
    """Print random derivations (phenotypes), made by the same initialisation evolution uses."""
    result = load_usable(grammar, parse_defines(defines))
    rng = np.random.default_rng(seed)
    try:
        if method is Method.RAMPED:
            trees = ramped_population(result.facts, rng, count, max_depth=max_depth, codons=codons, tail=0)
        else:
            trees = [
                random_tree(result.facts, rng, max_depth=max_depth, method=method, codons=codons, tail=0)
                for _ in range(count)
            ]
    except InitialisationError as error:
        err.print(f"error: {error}", style="bold red")
        raise typer.Exit(1) from None
    mapper = compile_mapper(result.grammar, codons=codons, max_wraps=0)
    for tree in trees:
        mapped = mapper.map_fast(tree.genome)
        if as_json:
            record = {
                "phenotype": mapped.phenotype,
                "genome": list(tree.genome),
                "depth": tree.depth,
                "method": tree.method.value,
                "joints": mapped.joints,
            }
            typer.echo(json.dumps(record, ensure_ascii=False))
        else:
            typer.echo(mapped.phenotype)
