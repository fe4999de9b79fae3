"""``gaitgram sample``: random derivations, to see what a grammar produces, made as a run's first
generation is (GE's methods by default; ``--representation`` another's initialisation)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from gaitgram import jsonio
from gaitgram.analysis.facts import GrammarFacts
from gaitgram.cli.common import compiled_or_exit, fail, load_usable
from gaitgram.cli.options import Defines, Representation, RepresentationSettings, ge_default, parse_defines
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.ge.initialisation import (
    GeneratedTree,
    InitialisationError,
    Method,
    ramped_population,
    random_tree,
)
from gaitgram.ge.registry import DEFAULT_REPRESENTATION, Compiled

#: GE's initial depth and codon consumption, as a run's are by default.
_INIT_DEPTH = ge_default("init_max_depth")
_CODONS = CodonMode(ge_default("codons"))


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar.", show_default=False)],
    count: Annotated[int, typer.Option("-n", "--count", min=1, help="How many derivations.")] = 10,
    method: Annotated[
        Method | None, typer.Option(help="GE: grow, full, or ramped (half each, depths ramped; default).")
    ] = None,
    max_depth: Annotated[
        int | None,
        typer.Option(min=1, help=f"Deepest rule node (GE: default {_INIT_DEPTH}; else the setting's)."),
    ] = None,
    seed: Annotated[int, typer.Option(help="Random seed: the same seed gives the same samples.")] = 0,
    codons: Annotated[
        CodonMode, typer.Option(help="GE: codon consumption the genomes are made for.")
    ] = _CODONS,
    representation: Representation = DEFAULT_REPRESENTATION,
    setting: RepresentationSettings = None,
    as_json: Annotated[bool, typer.Option("--json", help="One JSON object per line.")] = False,
    defines: Defines = None,
) -> None:
    """Print random derivations (phenotypes), made by the same initialisation evolution uses."""
    result = load_usable(grammar, parse_defines(defines))
    rng = np.random.default_rng(seed)
    if representation != DEFAULT_REPRESENTATION:
        if method is not None:
            raise fail(f"--method picks GE's initialisation; {representation} initialises as its own does")
        compiled = compiled_or_exit(result, representation, setting, max_depth=max_depth)
        _sample(compiled, rng, count, as_json)
        return
    mapper = compile_mapper(result.grammar, codons=codons, max_wraps=0)
    try:
        for tree in _trees(
            result.facts, rng, count, method or Method.RAMPED, max_depth or _INIT_DEPTH, codons
        ):
            mapped = mapper.map_fast(tree.genome)
            if as_json:
                record = {
                    "phenotype": mapped.phenotype,
                    "genome": list(tree.genome),
                    "depth": tree.depth,
                    "method": tree.method.value,
                    "joints": mapped.joints,
                }
                typer.echo(jsonio.dumps(record))
            else:
                typer.echo(mapped.phenotype)
    except InitialisationError as error:
        raise fail(str(error), 1) from None


def _sample(compiled: Compiled, rng: np.random.Generator, count: int, as_json: bool) -> None:
    """A first generation of ``count`` genomes of another representation than GE, as a run's."""
    try:
        genomes = compiled.initialise(rng, count)
    except InitialisationError as error:
        raise fail(str(error), 1) from None
    for genome, mapped in zip(genomes, compiled.map_many(genomes), strict=True):
        if as_json:
            record = {
                "phenotype": mapped.phenotype,
                "genome": compiled.encode(genome),
                "depth": compiled.derivation(genome).depth,
                "representation": compiled.name,
                "joints": dict(mapped.joints),
            }
            typer.echo(jsonio.dumps(record))
        else:
            typer.echo(mapped.phenotype)


def _trees(
    facts: GrammarFacts,
    rng: np.random.Generator,
    count: int,
    method: Method,
    max_depth: int,
    codons: CodonMode,
) -> Iterator[GeneratedTree]:
    """The trees one at a time, so each is printed as it is made and ``-n`` costs no memory.

    The same trees, from the same random draws, as ``ramped_population(count)`` (or ``count``
    calls of ``random_tree``): a ramp's i-th tree is the first tree of a ramp starting at the
    i-th depth.
    """
    if method is not Method.RAMPED:
        for _ in range(count):
            yield random_tree(facts, rng, max_depth=max_depth, method=method, codons=codons, tail=0)
        return
    start = facts.cfg.start
    shortest = (facts.min_depth[start] if start is not None else None) or 1
    ramp = max(1, max_depth - shortest + 1)  # ramped_population itself refuses a ramp that is empty
    for i in range(count):
        (tree,) = ramped_population(
            facts, rng, 1, max_depth=max_depth, min_depth=shortest + i % ramp, codons=codons, tail=0
        )
        yield tree
