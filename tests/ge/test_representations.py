"""πGE, SGE, DSGE and CFG-GP as a run uses them: depth limits that hold, operators that keep genomes
valid, joints as GE gives them, genome text and JSON, and clear refusals.

Exactness against the reference codes is ``test_representation_vectors.py``'s.
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import GRAMMARS, VECTOR_DEFINES, vector_grammars
from gaitgram.analysis.facts import recursive_rules
from gaitgram.ge import InvalidReason, MapperError, compile_mapper
from gaitgram.ge.cfggp import CFGGPSettings, compile_cfggp
from gaitgram.ge.dsge import DSGESettings, compile_dsge
from gaitgram.ge.initialisation import InitialisationError
from gaitgram.ge.pige import PiGESettings, compile_pige
from gaitgram.ge.representation import GenomeError
from gaitgram.ge.sge import SGESettings, compile_sge
from gaitgram.language import load, parse

REPRESENTATIONS = ("pige", "sge", "dsge", "cfg-gp")
#: SGE's genes grow exponentially: PCRE's hold 521,833 values at level 2 (level 1 is tested
#: below), Dow's last level 659,680 alternatives (4 s to compile; the vector test compiles it),
#: and Word_Stats' genome is refused (a test below).
SGE_TOO_BIG = {"Dow.bnf", "PCRE.bnf", "Word_Stats.bnf"}
GRAMMAR_FILES = [*sorted(GRAMMARS.glob("*.gg")), *vector_grammars()]

JOINTS = """\
@start <gait>
<gait> ::= <hip>;<knee>;<hip>
@joint hip_hind
<hip> ::= <amp>*sin(t) | <amp>*sin(<k>*t)+(<hip>)
@joint knee
<knee> ::= <amp> | -<amp>
<amp> ::= int[0..20]
<k> ::= int[1..3]
"""


@cache
def compiled(path: Path, name: str, max_depth: int | None = None, stack: str = "inplace") -> Any:
    grammar = load(path, defines=VECTOR_DEFINES)
    if name == "pige":
        return compile_pige(grammar, PiGESettings(stack=stack, max_depth=max_depth))  # type: ignore[arg-type]
    if name == "sge":
        return compile_sge(grammar, SGESettings(recursion=2, max_depth=max_depth))
    if name == "dsge":
        return compile_dsge(grammar, DSGESettings(max_depth=max_depth or 18))
    return compile_cfggp(grammar, CFGGPSettings(max_depth=max_depth or 17))


def cases() -> st.SearchStrategy[tuple[Path, str]]:
    return st.sampled_from(
        [(p, r) for p in GRAMMAR_FILES for r in REPRESENTATIONS if not (r == "sge" and p.name in SGE_TOO_BIG)]
    )


def shortest(path: Path, representation: Any) -> int:
    depth = representation.tables.facts.min_depth[representation.tables.start]
    assert depth is not None
    return depth


# ---- depth limits -------------------------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(case=cases(), seed=st.integers(0, 2**32 - 1), max_depth=st.integers(1, 14))
def test_no_initialisation_exceeds_max_depth(case: tuple[Path, str], seed: int, max_depth: int) -> None:
    path, name = case
    representation = compiled(path, name)
    rng = np.random.default_rng(seed)
    if shortest(path, representation) > max_depth:
        with pytest.raises(InitialisationError, match="shortest derivation"):
            representation.initialise(rng, 4, max_depth)
        return
    genomes = representation.initialise(rng, 6, max_depth)
    assert len(genomes) == 6
    for mapped in representation.map_many(genomes):
        assert mapped.valid, mapped.reason
        assert mapped.depth <= max_depth


@settings(max_examples=60, deadline=None)
@given(case=cases(), seed=st.integers(0, 2**32 - 1), max_depth=st.integers(2, 12), parents=st.integers(1, 7))
def test_variation_keeps_genomes_valid_and_within_max_depth(
    case: tuple[Path, str], seed: int, max_depth: int, parents: int
) -> None:
    path, name = case
    representation = compiled(path, name, max_depth)
    rng = np.random.default_rng(seed)
    if shortest(path, representation) > max_depth:
        return
    population = representation.initialise(rng, parents, max_depth)
    for _ in range(3):  # generations: children of children
        population = representation.vary(rng, population)
        assert len(population) == parents
        for child, mapped in zip(population, representation.map_many(population), strict=True):
            assert representation.decode(representation.encode(child)) == child  # well-formed
            if name == "pige":  # GE's variation: a child may be invalid, never deeper than the limit
                assert all(0 <= c < representation.settings.codon_size for c in child)
                assert not mapped.valid or mapped.depth <= max_depth
            else:
                assert mapped.valid, (mapped.reason, child)
                assert mapped.depth <= max_depth
            if name == "sge":
                assert tuple(map(len, child)) == representation.sizes
            if name == "dsge":
                assert representation.complete(child, rng) == child  # no gene runs out


def test_crossover_that_would_pass_the_limit_keeps_the_parents() -> None:
    """Whigham's rule: a swap that makes a child deeper than MAX-TREE-DEPTH is not made."""
    cfggp = compile_cfggp(parse("<e> ::= (<e>+<e>) | x\n"), CFGGPSettings(max_depth=4, retries=20))
    deep = cfggp.decode("<e>0(<e>0(<e>0(<e>1 <e>1) <e>1) <e>1)")  # depth 4: room for nothing deeper
    assert cfggp.map(deep).depth == 4
    rng = np.random.default_rng(3)
    for _ in range(30):
        for child in cfggp.crossover(rng, deep, deep):
            assert cfggp.map(child).depth <= 4


def test_dsge_fills_past_max_depth_with_shortest_path_choices() -> None:
    """sge3's rule for a gene that runs out: any choice down to max_depth, the shortest ways out below."""
    dsge = compile_dsge(
        parse("<s> ::= <e>\n<e> ::= <e>+<e> | (<e>) | <v> | <w>\n<v> ::= x | y\n<w> ::= <v>\n"),
        DSGESettings(max_depth=3),
    )
    assert dsge.shortest[dsge.genes.index("e")] == (2,)  # <v>: depth 2; <w> needs 3
    # <s> -> <e> (+) at depth 2, its two <e> at depth 3 are past nothing yet; cut every later value.
    genome = ((0,), (0, 0, 0, 0), (), ())
    completed = dsge.complete(genome, np.random.default_rng(0))
    mapped = dsge.map(completed)
    assert mapped.valid
    assert completed[1][:4] == (0, 0, 0, 0)  # its own values are kept
    assert set(completed[1][4:]) <= {2}  # what it filled, below depth 3, took the shortest way
    assert dsge.map(genome).reason is InvalidReason.CODONS  # mapped as it is, it runs out


# ---- mapping as GE maps the same tree -----------------------------------------------------------


def preorder(representation: Any, genome: Any) -> list[int]:
    """The tree's choices in pre-order, by the definition: leftmost rule first, each rule taking its
    gene's next value (DSGE) or the sequence's (CFG-GP)."""
    tables = representation.tables
    if representation.name == "cfg-gp":
        return list(genome)
    used = [0] * len(genome)
    choices = []
    stack = [tables.start]
    while stack:
        rule = stack.pop()
        choice = genome[rule][used[rule]]
        used[rule] += 1
        choices.append(choice)
        stack.extend(reversed(tables.children[rule][choice]))
    return choices


@pytest.mark.parametrize("name", ["dsge", "cfg-gp"])
@pytest.mark.parametrize("path", sorted(GRAMMARS.glob("*.gg")), ids=lambda p: p.stem)
def test_phenotype_joints_and_depth_are_ges_on_the_same_tree(path: Path, name: str) -> None:
    """GE in eager mode reads one codon per expansion: the tree's choices, as codons, derive it."""
    representation = compiled(path, name)
    ge = compile_mapper(load(path), codons="eager", max_wraps=0)
    genomes = representation.initialise(np.random.default_rng(5), 30, 12)
    for genome, mapped in zip(genomes, representation.map_many(genomes), strict=True):
        derivation = ge.map(preorder(representation, genome))
        expected = (derivation.phenotype, derivation.joints, derivation.depth, derivation.nodes)
        assert (mapped.phenotype, mapped.joints, mapped.depth, mapped.nodes) == expected
        assert mapped.joints  # the bundled grammars declare joints


def pige_reference(pige: Any, genome: tuple[int, ...]) -> tuple[str, dict[str, str], int] | None:
    """πGE as its definition reads, on a tree of ``[rule, children, depth]`` nodes: the phenotype,
    each joint rule's first subtree in pre-order (GE's joints) and the depth; None if invalid."""
    tables, mode = pige.tables, pige.settings.stack
    root: list[Any] = [tables.start, None, 1]
    stack, used, n = [root], 0, len(genome)
    while stack:
        if used // n > pige.settings.max_wraps:
            return None
        i = genome[used % n] % len(stack)
        node = stack.pop(i)
        options = tables.base.productions[node[0]]
        items = options[genome[(used + 1) % n] % len(options)]
        used += 2
        node[1] = [[x, None, node[2] + 1] if isinstance(x, int) else x for x in items]
        at = {"inplace": i, "end": len(stack), "start": 0}[mode]
        stack[at:at] = [child for child in node[1] if not isinstance(child, str)]
    first: dict[int, str] = {}
    depth = 0
    todo: list[Any] = [root]
    while todo:  # pre-order
        node = todo.pop()
        if isinstance(node, str):
            continue
        depth = max(depth, node[2])
        if node[0] in tables.joint_rules and node[0] not in first:
            first[node[0]] = _leaves(node)
        todo.extend(reversed(node[1]))
    return _leaves(root), tables.base._name_joints(first), depth


def _leaves(node: Any) -> str:
    out, todo = [], [node]
    while todo:
        x = todo.pop()
        if isinstance(x, str):
            out.append(x)
        else:
            todo.extend(reversed(x[1]))
    return "".join(out)


@settings(max_examples=40, deadline=None)
@given(
    stack=st.sampled_from(["inplace", "end", "start"]),
    seed=st.integers(0, 2**32 - 1),
    length=st.integers(1, 60),
)
def test_pige_maps_as_its_definition_reads(stack: str, seed: int, length: int) -> None:
    grammar = parse(JOINTS)
    pige = compile_pige(grammar, PiGESettings(stack=stack))  # type: ignore[arg-type]
    genome = tuple(int(c) for c in np.random.default_rng(seed).integers(0, 1000, size=length))
    mapped = pige.map(genome)
    expected = pige_reference(pige, genome)
    if expected is None:
        assert mapped.reason is InvalidReason.CODONS
    else:
        assert (mapped.phenotype, mapped.joints, mapped.depth) == expected
        assert mapped.used == 2 * mapped.nodes


def test_sge_of_a_grammar_without_recursion_is_dsge_of_the_same_genes() -> None:
    """No recursion: nothing is unrolled, each rule has its gene, read the same way."""
    path = GRAMMARS / "hybrid.gg"
    sge, dsge = compiled(path, "sge"), compiled(path, "dsge")
    assert sge.genes == dsge.genes
    for genome in sge.initialise(np.random.default_rng(2), 20, 12):
        assert sge.map(genome) == dsge.map(genome)


# ---- SGE's unrolled grammar ---------------------------------------------------------------------


@pytest.mark.parametrize("name", ["PCRE.bnf", "pymax.pybnf", "Word_Stats.bnf"])
def test_sge_unrolls_indirect_recursion_or_refuses_a_genome_too_large(name: str) -> None:
    path = next(p for p in vector_grammars() if p.name == name)
    if name == "Word_Stats.bnf":
        with pytest.raises(MapperError, match=r"genome would hold [\d,]+ values .*lower the recursion level"):
            compile_sge(load(path, defines=VECTOR_DEFINES), SGESettings(recursion=1))
        return
    sge = compile_sge(load(path, defines=VECTOR_DEFINES), SGESettings(recursion=1))
    unrolled = sge.unrolled.as_cfg(sge.tables.start)
    assert not any(recursive_rules(unrolled))  # unrolled: nothing recurses
    for mapped in sge.map_many(sge.initialise(np.random.default_rng(0), 10, 30)):
        assert mapped.valid


# ---- genome text and JSON -----------------------------------------------------------------------


@settings(max_examples=40, deadline=None)
@given(case=cases(), seed=st.integers(0, 2**32 - 1))
def test_text_and_json_round_trip(case: tuple[Path, str], seed: int) -> None:
    path, name = case
    representation = compiled(path, name)
    if shortest(path, representation) > 8:
        return
    for genome in representation.initialise(np.random.default_rng(seed), 3, 8):
        assert representation.decode(representation.encode(genome)) == genome
        as_json = json.loads(json.dumps(representation.to_json(genome)))
        assert representation.from_json(as_json) == genome
        assert representation.decode(json.dumps(as_json)) == genome  # JSON is text too


def test_cfggp_text_is_the_tree() -> None:
    cfggp = compile_cfggp(parse("<e> ::= <e><o><e> | <v>\n<o> ::= + | -\n<v> ::= x | y\n"))
    tree = (0, 1, 0, 1, 1, 1)
    assert cfggp.encode(tree) == "<e>0(<e>1(<v>0) <o>1 <e>1(<v>1))"
    assert cfggp.map(tree).phenotype == "x-y"
    assert cfggp.decode("<e>0( <e>1(<v>0)  <o>1\n<e>1(<v>1) )") == tree


BAD_TEXT = [
    ("pige", "1,2,x", "1:5: 'x' is not a codon"),
    ("pige", "", "the genome is empty"),
    ("dsge", "[[0], [0]]", "has 2 gene(s); this grammar needs 3"),
    ("dsge", "[[0], [7], []]", "gene 1 (<o>), value 0: 7 is not a choice of the rule; it has 2"),
    ("dsge", "[[0], [0], [[1]]]", "lists nest two deep at most"),
    ("dsge", "[[0], [0], [1]] 2", "text after the genome's closing ']'"),
    ("dsge", "[[0], [0]", "ends inside a list"),
    (
        "sge",
        "[[0], [0, 1], [], [], []]",
        "gene 1 (<o>) has 2 value(s); SGE's genes have fixed sizes, and this one has 12",
    ),
    ("sge", "[[0], [0]]", "this grammar needs 5, one per rule, in this order: e, o, v, e_lvl_0, e_lvl_1"),
    ("cfg-gp", "<e>0(<v>0)", "choice 0 of <e> has 3 rule child(ren); the text gives 1"),
    ("cfg-gp", "<e>1(<o>0)", "<o> here, but the grammar expands <v> at this node"),
    ("cfg-gp", "<e>3", "<e> has 2 choice(s) (0 to 1), not 3"),
    ("cfg-gp", "<e>1(<v>0))", "')' closes nothing"),
    ("cfg-gp", "<e>1(<v>0) <e>1(<v>0)", "holds 2 trees"),
    ("cfg-gp", "e1", "cannot read 'e1"),
]


@pytest.mark.parametrize(("name", "text", "message"), BAD_TEXT)
def test_bad_genome_text_says_where_and_what(name: str, text: str, message: str) -> None:
    grammar = parse("<e> ::= <e><o><e> | <v>\n<o> ::= + | -\n<v> ::= x | y\n")
    representation = {
        "pige": compile_pige,
        "sge": lambda g: compile_sge(g, SGESettings(recursion=1)),
        "dsge": compile_dsge,
        "cfg-gp": compile_cfggp,
    }[name](grammar)
    with pytest.raises(GenomeError) as caught:
        representation.decode(text)
    assert message in str(caught.value)


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("pige", [1, -2], "[1] must be a non-negative integer, not -2"),
        ("pige", [], "at least one codon"),
        ("dsge", [[0], [True], []], "gene 1 (<o>)[0] must be a non-negative integer, not True"),
        ("dsge", {"e": [0]}, "must be a list of genes"),
        ("cfg-gp", [0, 1, 0], "the tree is incomplete"),
        ("cfg-gp", [1, 0, 0], "value(s) left over"),
    ],
)
def test_bad_genome_json_says_what(name: str, value: Any, message: str) -> None:
    grammar = parse("<e> ::= <e><o><e> | <v>\n<o> ::= + | -\n<v> ::= x | y\n")
    representation = {"pige": compile_pige, "dsge": compile_dsge, "cfg-gp": compile_cfggp}[name](grammar)
    with pytest.raises(GenomeError) as caught:
        representation.from_json(value)
    assert message in str(caught.value)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: PiGESettings(stack="middle"), "pige: stack must be one of inplace, end, start"),  # type: ignore[arg-type]
        (lambda: PiGESettings(max_wraps=None, max_expansions=None), "cannot both be None"),
        (lambda: SGESettings(recursion=-1), "sge: recursion must be an integer >= 0"),
        (lambda: DSGESettings(mutation=1.5), "dsge: mutation must be a probability in [0, 1]"),
        (lambda: CFGGPSettings(max_depth=0), "cfg-gp: max_depth must be an integer >= 1"),
    ],
)
def test_bad_settings_name_the_setting(make: Any, message: str) -> None:
    with pytest.raises(MapperError) as caught:
        make()
    assert message in str(caught.value)


def test_a_grammar_with_errors_is_refused_as_ge_refuses_it() -> None:
    grammar = parse("<e> ::= float[0..1 step 0]\n")
    for make in (compile_pige, compile_sge, compile_dsge, compile_cfggp):
        with pytest.raises(MapperError, match="a grammar with errors is not compiled"):
            make(grammar)
