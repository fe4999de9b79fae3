"""Sensible initialisation: trees within depth that their genomes map back to."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import GRAMMARS, VECTOR_DEFINES, vector_grammars
from gaitgram.analysis import analyse
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.ge.initialisation import (
    InitialisationError,
    Method,
    ramped_population,
    random_genomes,
    random_tree,
)
from gaitgram.language import load, parse

GRAMMAR_FILES = [*vector_grammars(), *sorted(GRAMMARS.glob("*.gg"))]


def expansions_of_mapping(grammar_path: Path, genome: tuple[int, ...], codons: CodonMode) -> list[tuple]:
    grammar = load(grammar_path, defines=VECTOR_DEFINES)
    derivation = compile_mapper(grammar, codons=codons, max_wraps=0).map(genome)
    assert derivation.valid, derivation.reason
    return [(n.symbol, n.choice, level) for n, level in derivation.tree.walk() if not n.is_terminal]


@settings(max_examples=40)
@given(
    path=st.sampled_from(GRAMMAR_FILES),
    seed=st.integers(0, 2**32 - 1),
    depth=st.integers(1, 12),
    method=st.sampled_from([Method.GROW, Method.FULL]),
    codons=st.sampled_from(list(CodonMode)),
)
def test_generated_trees_map_back_from_their_genomes(
    path: Path, seed: int, depth: int, method: Method, codons: CodonMode
) -> None:
    grammar = load(path, defines=VECTOR_DEFINES)
    facts = analyse(grammar)
    rng = np.random.default_rng(seed)
    try:
        tree = random_tree(facts, rng, max_depth=depth, method=method, codons=codons)
    except InitialisationError:
        assert facts.min_depth[facts.cfg.start] > depth
        return
    assert tree.depth <= depth
    assert len(tree.genome) >= tree.used_codons
    mapped = expansions_of_mapping(path, tree.genome, codons)
    assert mapped == [(e.rule, e.choice, e.depth) for e in tree.expansions]
    derivation = compile_mapper(grammar, codons=codons, max_wraps=0).map(tree.genome)
    assert derivation.used_codons == tree.used_codons
    assert derivation.depth == tree.depth


def test_full_trees_reach_deeper_than_grown_ones_on_average() -> None:
    facts = analyse(parse("<e> ::= <e>+<e> | <e>*<e> | x | y"))
    rng = np.random.default_rng(1)
    full = [random_tree(facts, rng, max_depth=6, method=Method.FULL).depth for _ in range(50)]
    grow = [random_tree(facts, rng, max_depth=6, method=Method.GROW).depth for _ in range(50)]
    assert all(d == 6 for d in full)
    assert np.mean(grow) < 6


def test_ramped_population_cycles_depths_and_is_reproducible() -> None:
    facts = analyse(parse("<e> ::= <e>+<e> | x"))
    first = ramped_population(facts, np.random.default_rng(7), 20, max_depth=5)
    again = ramped_population(facts, np.random.default_rng(7), 20, max_depth=5)
    assert [t.genome for t in first] == [t.genome for t in again]
    assert all(t.depth <= 5 for t in first)
    assert {t.method for t in first} == {Method.GROW, Method.FULL}
    assert max(t.depth for t in first) == 5


def test_depth_below_the_shortest_derivation_is_an_error() -> None:
    facts = analyse(parse("<a> ::= <b>\n<b> ::= <c>\n<c> ::= x"))
    with pytest.raises(InitialisationError, match="3 levels deep"):
        ramped_population(facts, np.random.default_rng(0), 5, max_depth=2)


def test_random_genomes() -> None:
    genomes = random_genomes(np.random.default_rng(3), 10, length=(5, 8), codon_size=100)
    assert len(genomes) == 10
    assert all(5 <= len(g) <= 8 and all(0 <= c < 100 for c in g) for g in genomes)
    assert genomes == random_genomes(np.random.default_rng(3), 10, length=(5, 8), codon_size=100)
