"""Joints cut from the phenotype: where a grammar's start rule is ``<j1>;<j2>;...`` (every bundled
gait grammar) the fast loops map without joint markers and split the phenotype instead; every
other grammar keeps the markers. Either way the fast path gives what the tree mapper gives."""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import GRAMMARS
from gaitgram.analysis import analyse, build_cfg
from gaitgram.ge import CodonMode, Mapper, compile_mapper
from gaitgram.ge.cfggp import CFGGPSettings, compile_cfggp
from gaitgram.ge.dsge import DSGESettings, compile_dsge
from gaitgram.ge.initialisation import ramped_population
from gaitgram.ge.pige import compile_pige
from gaitgram.ge.sge import SGESettings, compile_sge
from gaitgram.language import load, parse

BUNDLED = sorted(p for p in GRAMMARS.glob("*.gg") if load(p).joints)

_RULES = """\
@joint a
<a> ::= <e> | -<e>
@joint b
<b> ::= <d> | (<d>+<b2>)
<b2> ::= <d> | <d>*<d>
<e> ::= <d> | <e>+<d> | sin(<e>)
<d> ::= 0 | 1 | 2 | 3 | 4 | 5 | 6 | 7 | 8 | 9
"""

#: Grammars whose joints can be cut from the phenotype (the start rule's shape allows it).
CUT = {
    "two joints": "@start <s>\n<s> ::= <a>;<b>\n" + _RULES,
    # Separators of two kinds, an item that is no joint, and the joints declared in another order.
    "mixed separators": "@start <s>\n<s> ::= <c>,<b>/<x>;<a>\n@joint c\n<c> ::= <d>\n<x> ::= <e>\n" + _RULES,
    # A terminal between a joint and the separator: the separator is "x;" (no x in the joints).
    "glued separator": "@start <s>\n<s> ::= <a>x;<b>\n" + _RULES,
    "one joint": "@start <s>\n<s> ::= <a>\n" + _RULES.replace("@joint b\n", ""),
    "empty joint text": '@start <s>\n<s> ::= <a>;<n>;<b>\n@joint n\n<n> ::= "" | 7\n' + _RULES,
}

#: Grammars that must keep the markers, each for the reason its name gives.
MARKED = {
    "separator in a joint's terminal": "@start <s>\n<s> ::= <a>;<b>\n<d0> ::= 1;2\n"
    + _RULES.replace("<d> ::= 0 |", "<d> ::= <d0> |"),
    "separator in an item's terminal": "@start <s>\n<s> ::= <a>;<x>;<b>\n<x> ::= k | k;k\n" + _RULES,
    # ";;" split would cut "1;" + ";;" + "2" at the wrong place.
    "separator's character in a terminal": "@start <s>\n<s> ::= <a>;;<b>\n"
    + _RULES.replace("<d> ::= 0 |", "<d> ::= ; |"),
    "glued separator's character in a joint": "@start <s>\n<s> ::= <a>x;<b>\n"
    + _RULES.replace("<d> ::= 0 |", "<d> ::= x |"),
    "joint item twice": "@start <s>\n<s> ::= <a>;<b>;<a>\n" + _RULES,
    "joint reachable again": "@start <s>\n<s> ::= <a>;<b>\n"
    + _RULES.replace("<b2> ::= <d> |", "<b2> ::= <a> |"),
    "joint inside an item": "@start <s>\n<s> ::= <x>;<b>\n<x> ::= <a>\n" + _RULES,
    "recursive joint": "@start <s>\n<s> ::= <a>;<b>\n" + _RULES.replace("<a> ::= <e> |", "<a> ::= (<a>) |"),
    "start rule with two choices": "@start <s>\n<s> ::= <a>;<b> | <b>;<a>\n" + _RULES,
    "terminal before the first joint": "@start <s>\n<s> ::= (<a>;<b>\n" + _RULES,
    "terminal after the last item": "@start <s>\n<s> ::= <a>;<b>.\n" + _RULES,
    "items side by side": "@start <s>\n<s> ::= <a><b>\n" + _RULES,
    "start rule reached again": "@start <s>\n<s> ::= <a>;<x>;<b>\n<x> ::= k | [<s>]\n" + _RULES,
    "start rule a joint": "@start <s>\n@joint whole\n<s> ::= <a>;<b>\n" + _RULES,
    "a joint never derived": "@start <s>\n<s> ::= <a>;<b>\n@joint z\n<z> ::= 1\n" + _RULES,
}

HAND = {**CUT, **MARKED}


@cache
def hand(name: str, codons: str, max_depth: int | None) -> Mapper:
    grammar = parse(HAND[name], name=name)
    assert not grammar.has_errors, [d.message for d in grammar.diagnostics]
    return compile_mapper(grammar, codons=codons, max_depth=max_depth)


@cache
def bundled(path: Path, codons: str, max_depth: int | None) -> Mapper:
    return compile_mapper(load(path), codons=codons, max_depth=max_depth)


@cache
def pool(path: Path, codons: str) -> list[list[int]]:
    """Genomes of GE's own initialisation: on the gait grammars random codons are mostly invalid."""
    trees = ramped_population(
        analyse(load(path)), np.random.default_rng(3), 40, max_depth=10, codons=CodonMode(codons)
    )
    return [list(t.genome) for t in trees]


def test_every_bundled_gait_grammar_cuts_its_joints() -> None:
    assert len(BUNDLED) >= 9
    for path in BUNDLED:
        for codons in ("lazy", "eager"):
            for max_depth in (None, 12):
                assert bundled(path, codons, max_depth).joints_from_phenotype is not None, path.name


@pytest.mark.parametrize("name", sorted(CUT))
def test_grammars_of_the_shape_cut_their_joints(name: str) -> None:
    assert hand(name, "lazy", None).joints_from_phenotype is not None


@pytest.mark.parametrize("name", sorted(MARKED))
def test_other_grammars_keep_the_markers(name: str) -> None:
    m = hand(name, "lazy", None)
    assert m.joint_list, "the grammar declares joints"
    assert m.joints_from_phenotype is None


def test_a_rule_under_two_joint_names_keeps_the_markers() -> None:
    cfg = build_cfg(parse(CUT["two joints"]))
    assert compile_mapper(cfg, joints={"a": "a", "b": "b"}).joints_from_phenotype is not None
    twice = compile_mapper(cfg, joints={"left": "a", "right": "a", "b": "b"})
    assert twice.joints_from_phenotype is None
    assert twice.map_fast([0, 0, 3, 0, 4]).joints == {"left": "3", "right": "3", "b": "4"}


def test_cut_joints_by_hand() -> None:
    m = hand("mixed separators", "lazy", None)
    # <c>'s <d> 1; <b> (<d>+<b2>): 2, <b2> <d>*<d>: 3, 4; <x>'s <e> sin(<e>), <e> <d>: 6;
    # <a> -<e>, <e> <d>: 7 (lazy: <s>, <c> and <x> read no codon)
    mapped = m.map_fast([1, 1, 2, 1, 3, 4, 2, 0, 6, 1, 0, 7])
    assert mapped.phenotype == "1,(2+3*4)/sin(6);-7"
    # In the order the joints are declared, not the order of the items.
    assert list(mapped.joints.items()) == [("c", "1"), ("a", "-7"), ("b", "(2+3*4)")]
    assert hand("empty joint text", "eager", None).map_fast([0, 0, 0, 0, 0, 0, 0, 0]).joints == {
        "a": "0",
        "n": "",
        "b": "0",
    }


def _check(m: Mapper, genomes: list[list[int]]) -> None:
    """The batch's fast results are the tree mapper's, genome by genome, joints in order."""
    for genome, fast in zip(genomes, m.map_many(genomes), strict=True):
        tree = m.map(genome)
        assert tuple(fast) == (tree.phenotype, tree.used_codons, tree.wraps, tree.joints, tree.reason)
        assert list(fast.joints) == list(tree.joints)


@settings(max_examples=300, deadline=None)
@given(
    name=st.sampled_from(sorted(HAND)),
    codons=st.sampled_from(["lazy", "eager"]),
    max_depth=st.none() | st.integers(2, 9),
    genomes=st.lists(st.lists(st.integers(0, 60), max_size=30), min_size=1, max_size=4),
)
def test_hand_grammars_map_fast_as_the_tree_does(
    name: str, codons: str, max_depth: int | None, genomes: list[list[int]]
) -> None:
    _check(hand(name, codons, max_depth), genomes)


@settings(max_examples=120, deadline=None)
@given(
    path=st.sampled_from(BUNDLED),
    codons=st.sampled_from(["lazy", "eager"]),
    max_depth=st.none() | st.integers(4, 14),
    picks=st.lists(st.integers(0, 39), min_size=1, max_size=4),
    mutations=st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 10**4)), max_size=4),
)
def test_bundled_grammars_map_fast_as_the_tree_does(
    path: Path, codons: str, max_depth: int | None, picks: list[int], mutations: list[tuple[int, int]]
) -> None:
    genomes = [list(pool(path, codons)[i]) for i in picks]
    for at, codon in mutations:  # point mutations on the first genome: other trees, some invalid
        genomes[0][at % len(genomes[0])] = codon
    _check(bundled(path, codons, max_depth), genomes)


def _representations(path: Path) -> list[Any]:
    grammar = load(path)
    return [
        compile_pige(grammar),
        compile_sge(grammar, SGESettings(recursion=2)),
        compile_dsge(grammar, DSGESettings(max_depth=14)),
        compile_cfggp(grammar, CFGGPSettings(max_depth=14)),
    ]


@pytest.mark.parametrize("path", [GRAMMARS / "hybrid.gg", GRAMMARS / "sine-walk.gg"], ids=lambda p: p.stem)
def test_other_representations_cut_the_same_joints(path: Path) -> None:
    """SGE, DSGE and CFG-GP decode without markers where GE cuts (πGE never had them); each valid
    genome's joints, in order, are the GE tree's of the same derivation."""
    for representation in _representations(path):
        tables = representation.tables
        assert tables.base.joints_from_phenotype is not None
        ops = getattr(representation, "_ops", tables.ops)  # SGE's are its unrolled grammar's
        assert not any(
            i.__class__ is int and i < 0 for per in ops for op in per if op.__class__ is tuple for i in op[2]
        )
        genomes = representation.initialise(np.random.default_rng(11), 20, 12)
        valid = 0
        for genome, mapped in zip(genomes, representation.map_many(genomes), strict=True):
            if mapped.phenotype is None:
                continue
            valid += 1
            tree = tables.base.map(representation.choices(genome))
            assert (mapped.phenotype, list(mapped.joints.items())) == (
                tree.phenotype,
                list(tree.joints.items()),
            ), representation.name
        assert valid, representation.name
