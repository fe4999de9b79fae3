"""``gaitgram.testing``'s genomes of every representation (issue 41.4): drawn as derivation trees,
they are valid genomes within the representation's depth limits, they map to the tree drawn, and a
failing example shrinks to a smallest tree, as GE's derivations always did."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import find, given, settings
from hypothesis import strategies as st

from conftest import GRAMMARS, VECTOR_DEFINES, VECTORS
from gaitgram.ge import Derivation
from gaitgram.ge.registry import Compiled, Genome
from gaitgram.language import load, parse
from gaitgram.language.model import Grammar
from gaitgram.testing import (
    compiled_representation,
    derivations,
    encode_derivation,
    representation_genomes,
)
from gaitgram.testing.trees import draw_tree, plan_of

REPRESENTATIONS = ["ge", "pige", "sge", "dsge", "cfg-gp"]

#: Every tree size is possible: ``x`` is 1 rule node, ``(x)`` 2, ``x+x`` 3, ...
EXPRESSIONS = parse("<e> ::= <e>+<e> | (<e>) | x\n")

#: The grammars the property tests draw from: recursive (two of PonyGE2's, one of them with
#: alternatives written twice and a rule of one choice) and gait grammars with joints.
GRAMMARS_DRAWN = {
    "expressions": lambda: EXPRESSIONS,
    "Vladislavleva4": lambda: load(VECTORS / "Vladislavleva4.bnf", defines=VECTOR_DEFINES),
    "pymax": lambda: load(VECTORS / "pymax.pybnf", defines=VECTOR_DEFINES),
    "hybrid": lambda: load(GRAMMARS / "hybrid.gg"),
    "hybrid-feedback": lambda: load(GRAMMARS / "hybrid-feedback.gg"),
}


def quick(**options: Any) -> settings:
    return settings(database=None, deadline=None, **options)


def nodes_at_least(compiled: Compiled, k: int) -> Callable[[Genome], bool]:
    return lambda genome: compiled.derivation(genome).nodes >= k


@pytest.mark.parametrize("representation", REPRESENTATIONS)
@pytest.mark.parametrize("name", GRAMMARS_DRAWN)
@pytest.mark.parametrize("limit", [7, None], ids=["max_depth=7", "own-limits"])
def test_every_drawn_genome_is_valid_within_the_depth_limits(
    representation: str, name: str, limit: int | None
) -> None:
    """Each genome maps without error to a valid derivation no deeper than the representation's
    max_depth (set, or its default: CFG-GP's 17, DSGE's 18, else 10), reads back from its text and
    its JSON, and is the genome of its own tree; the limit is reached, not only kept."""
    grammar = GRAMMARS_DRAWN[name]()
    options = {"max_depth": limit} if limit is not None else {}
    if representation == "sge":
        # PonyGE2's grammars unroll past any memory at the default level, 5; at 9 the expressions
        # reach depth 10 (at 5, 8: its last level and the alternative inlined there).
        options["recursion"] = 9 if name == "expressions" else 2
    compiled = compiled_representation(grammar, representation, options)
    ge = compiled_representation(grammar, "ge")
    deepest = limit or {"cfg-gp": 17, "dsge": 18}.get(representation, 10)
    seen: list[int] = []

    @quick(max_examples=60)
    @given(representation_genomes(compiled))
    def holds(genome: Genome) -> None:
        mapped = compiled.map_many([genome])[0]
        assert mapped.valid, mapped.reason
        derivation = compiled.derivation(genome)
        assert derivation.valid
        assert derivation.phenotype == mapped.phenotype
        assert derivation.depth <= deepest
        assert compiled.decode(compiled.encode(genome)) == genome
        assert compiled.from_json(compiled.to_json(genome)) == genome
        # The tree the representation reports is its genome's: GE maps the same tree to the same.
        again = ge.derivation(encode_derivation(ge, derivation))
        assert (again.phenotype, again.joints) == (derivation.phenotype, derivation.joints)
        seen.append(derivation.depth)

    holds()
    if name == "expressions":  # recursive without end: the limit is within reach
        assert max(seen) == deepest


#: Each representation, and the variants whose genomes are written otherwise: πGE's stack modes (where
#: an expanded rule's children join the open rules), GE's eager codons (one for every rule).
VARIANTS = {
    **{name: (name, {}) for name in REPRESENTATIONS},
    "pige-end": ("pige", {"stack": "end"}),
    "pige-start": ("pige", {"stack": "start"}),
    "ge-eager": ("ge", {"codons": "eager"}),
}


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("name", ["expressions", "hybrid", "Vladislavleva4"])
def test_a_drawn_tree_is_what_its_genome_maps_to(variant: str, name: str) -> None:
    """A GE derivation, drawn independently, written as the representation's genome maps back to
    the same tree, phenotype and joints."""
    grammar = GRAMMARS_DRAWN[name]()
    compiled = compiled_representation(grammar, *VARIANTS[variant])

    @quick(max_examples=40)
    @given(derivations(grammar, max_depth=6))
    def holds(drawn: Derivation) -> None:
        genome = encode_derivation(compiled, drawn)
        mapped = compiled.derivation(genome)
        assert (mapped.phenotype, mapped.joints) == (drawn.phenotype, drawn.joints)
        if name != "Vladislavleva4":  # its alternatives written twice read back as the first (πGE)
            assert mapped.tree == drawn.tree
        assert (mapped.depth, mapped.nodes) == (drawn.depth, drawn.nodes)

    holds()


@pytest.mark.parametrize("variant", ["pige", "pige-end", "pige-start"])
def test_pige_genomes_in_any_order_of_expansion_map_to_the_tree_drawn(variant: str) -> None:
    """πGE's order codons are drawn too (shrinking to 0, the first open rule): whatever the order,
    the genome maps to the tree whose choices were drawn, as GE maps those choices (eager codons:
    one per node, in pre-order)."""
    grammar = GRAMMARS_DRAWN["hybrid"]()
    compiled = compiled_representation(grammar, *VARIANTS[variant])
    ge = compiled_representation(grammar, "ge", {"codons": "eager"})
    plan = plan_of(compiled)
    assert plan is not None
    orders: list[int] = []

    @quick(max_examples=40)
    @given(st.data())
    def holds(data: st.DataObject) -> None:
        choices = draw_tree(data.draw, plan, 7)
        genome = plan.write(choices, lambda n: data.draw(st.integers(0, n - 1)))
        orders.extend(genome[::2])
        mapped, expected = compiled.derivation(genome), ge.derivation(tuple(choices))
        assert (mapped.phenotype, mapped.joints) == (expected.phenotype, expected.joints)
        assert mapped.tree == expected.tree

    holds()
    assert max(orders) > 0  # expansions out of pre-order were drawn


def test_a_tree_sge_cannot_hold_is_refused_saying_why() -> None:
    compiled = compiled_representation(EXPRESSIONS, "sge", {"recursion": 0})
    deep = find(derivations(EXPRESSIONS), lambda d: d.phenotype.count("(") >= 4, settings=quick())
    with pytest.raises(ValueError, match="recursion level 0"):
        encode_derivation(compiled, deep)


@pytest.mark.parametrize("representation", REPRESENTATIONS)
@pytest.mark.parametrize("k", [2, 5, 9])
def test_a_genome_of_at_least_k_nodes_shrinks_to_exactly_k(representation: str, k: int) -> None:
    compiled = compiled_representation(EXPRESSIONS, representation)
    found = find(representation_genomes(compiled), nodes_at_least(compiled, k), settings=quick())
    assert compiled.derivation(found).nodes == k


@pytest.mark.parametrize("representation", REPRESENTATIONS)
def test_a_failing_derivation_shrinks_to_the_smallest_tree_with_the_defect(representation: str) -> None:
    """``x+x`` (3 rule nodes) is the smallest tree with a ``+``, ``(x)+x`` or ``x+(x)`` (4) the
    smallest with both; the genome found is the smallest too: πGE's order codons 0 (the first open
    rule each time), SGE's unread values 0."""
    compiled = compiled_representation(EXPRESSIONS, representation)
    plus = find(
        derivations(EXPRESSIONS, representation=representation),
        lambda d: "+" in d.phenotype,
        settings=quick(),
    )
    assert (plus.phenotype, plus.nodes) == ("x+x", 3)
    both = find(
        representation_genomes(compiled),
        lambda g: {"+", "("} <= set(compiled.derivation(g).phenotype or ""),
        settings=quick(),
    )
    assert compiled.derivation(both).nodes == 4
    smallest = find(
        representation_genomes(compiled), lambda g: "+" in compiled.derivation(g).phenotype, settings=quick()
    )
    assert smallest == encode_derivation(compiled, plus)
    expected = {
        "ge": (0, 2, 2),
        "pige": (0, 0, 0, 2, 0, 2),  # (order, content) pairs: the first open rule each time
        "dsge": ((0, 2, 2),),
        "cfg-gp": (0, 2, 2),
    }
    if representation == "sge":
        assert smallest[:2] == ((0,), (2, 2))
        assert not any(any(gene) for gene in smallest[2:])
    else:
        assert smallest == expected[representation]


#: A defect in a typed range: the amplitude past 20 (21 is the smallest), beside a structural choice.
RANGED = parse("<g> ::= <a>*sin(t) | <a>*sin(t)+<g>\n<a> ::= int[0..30]\n")


@pytest.mark.parametrize("representation", REPRESENTATIONS)
def test_a_typed_range_shrinks_to_its_first_failing_value(representation: str) -> None:
    found = find(
        derivations(RANGED, representation=representation),
        lambda d: any(int(term.split("*")[0]) > 20 for term in d.phenotype.split("+")),
        settings=quick(),
    )
    assert found.phenotype == "21*sin(t)"


@pytest.mark.parametrize("representation", ["pige", "sge", "dsge", "cfg-gp"])
def test_a_user_property_test_composes_with_the_strategies(representation: str) -> None:
    """As a user writes one: genomes of two representations' settings in one test, via st.one_of."""
    shallow = compiled_representation(EXPRESSIONS, representation, {"max_depth": 3})
    deeper = compiled_representation(EXPRESSIONS, representation, {"max_depth": 6})
    drawn = st.one_of(
        representation_genomes(shallow).map(lambda g: (3, shallow.derivation(g))),
        representation_genomes(deeper, max_depth=5).map(lambda g: (5, deeper.derivation(g))),
    )

    @quick(max_examples=60)
    @given(drawn)
    def holds(example: tuple[int, Derivation]) -> None:
        limit, derivation = example
        assert derivation.valid
        assert derivation.depth <= limit

    holds()


def test_no_tree_within_the_depth_is_a_clear_error() -> None:
    grammar: Grammar = parse("<a> ::= <b>\n<b> ::= <c>\n<c> ::= x\n")
    compiled = compiled_representation(grammar, "cfg-gp", {"max_depth": 2})
    with pytest.raises(ValueError, match="no derivation within depth 2"):
        representation_genomes(compiled)


def test_pige_genomes_keep_to_max_expansions() -> None:
    compiled = compiled_representation(EXPRESSIONS, "pige", {"max_expansions": 5, "max_wraps": 0})
    seen: list[int] = []

    @quick(max_examples=60)
    @given(representation_genomes(compiled))
    def holds(genome: Genome) -> None:
        derivation = compiled.derivation(genome)
        assert derivation.valid
        seen.append(derivation.nodes)

    holds()
    assert max(seen) == 5
