"""The mapper on small hand grammars, and against a recursive reference on random ones."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gaitgram.analysis.cfg import Cfg, RuleKind, build_cfg
from gaitgram.ge import (
    CodonMode,
    Derivation,
    InvalidReason,
    Mapped,
    Mapper,
    MapperError,
    MappingOptions,
    Node,
    compile_mapper,
    python_filter,
)
from gaitgram.language import parse


def mapper(text: str, **options: Any) -> Mapper:
    grammar = parse(text)
    assert not grammar.has_errors, [d.message for d in grammar.diagnostics]
    return compile_mapper(grammar, **options)


def both(m: Mapper, genome: list[int]) -> tuple[Derivation, Mapped]:
    """The full and the fast mapping, checked to agree on everything they share."""
    full, fast = m.map(genome), m.map_fast(genome)
    assert (full.phenotype, full.used_codons, full.wraps, full.joints, full.reason) == tuple(fast)
    assert m.phenotype(genome) == full.phenotype
    if full.valid:
        assert full.tree.text() == full.phenotype
    return full, fast


# ---- codon consumption -------------------------------------------------------------------

UNITS = "<s> ::= <a><b>\n<a> ::= x | y\n<b> ::= <c>\n<c> ::= p | q\n"


def test_lazy_skips_single_choice_rules_eager_does_not() -> None:
    lazy, _ = both(mapper(UNITS, codons="lazy"), [0, 1])
    assert (lazy.phenotype, lazy.used_codons, lazy.wraps) == ("xq", 2, 0)
    # eager: <s> reads 0, <a> reads 1 -> y, <b> wraps to 0, <c> reads 1 -> q
    eager, _ = both(mapper(UNITS, codons="eager"), [0, 1])
    assert (eager.phenotype, eager.used_codons, eager.wraps) == ("yq", 4, 1)


def test_lazy_is_the_default() -> None:
    assert mapper(UNITS).options.codons is CodonMode.LAZY
    assert mapper(UNITS).options == MappingOptions()


def test_tree_records_codons_and_choices() -> None:
    m = mapper(UNITS, codons="lazy")
    d = m.map([4, 7])
    root = d.tree
    assert d.label(root) == "<s>"
    assert (root.choice, root.codon_index, root.codon) == (0, None, None)  # single choice: no codon
    a, b = root.children
    assert (d.label(a), a.choice, a.codon_index, a.codon) == ("<a>", 0, 0, 4)
    assert [d.label(n) for n in a.children] == ["x"]
    (c,) = b.children
    assert (d.label(c), c.choice, c.codon_index, c.codon) == ("<c>", 1, 1, 7)
    assert (d.depth, d.nodes) == (3, 4)
    assert [d.label(n) for n, _ in root.walk()] == ["<s>", "<a>", "x", "<b>", "<c>", "q"]
    eager = mapper(UNITS, codons="eager").map([4, 7])
    assert [n.codon_index for n, _ in eager.tree.walk() if not n.is_terminal] == [0, 1, 2, 3]


# ---- wrapping ------------------------------------------------------------------------------

DIGITS = "<s> ::= <d><d><d><d>\n<d> ::= 0 | 1 | 2 | 3\n"


@pytest.mark.parametrize("max_wraps", [0, 1, 2, 3, 5])
def test_max_wraps_allows_that_many_extra_passes(max_wraps: int) -> None:
    m = mapper(DIGITS, max_wraps=max_wraps)
    d, _ = both(m, [1])  # four codons needed from a one-codon genome: three wraps
    if max_wraps >= 3:
        assert (d.phenotype, d.used_codons, d.wraps) == ("1111", 4, 3)
    else:
        assert (d.phenotype, d.reason) == (None, InvalidReason.CODONS)
        assert (d.used_codons, d.wraps) == (max_wraps + 1, max_wraps)
        assert d.joints == {}


def test_wraps_counts_passes_begun_beyond_the_first() -> None:
    m = mapper(DIGITS, max_wraps=0)
    assert both(m, [1, 2, 3, 0])[0].wraps == 0
    m = mapper(DIGITS, max_wraps=1)
    d, _ = both(m, [1, 2, 3])
    assert (d.phenotype, d.used_codons, d.wraps) == ("1231", 4, 1)


def test_many_wraps_beyond_the_prefetched_passes() -> None:
    m = mapper("<s> ::= " + "<d>" * 30 + "\n<d> ::= 0 | 1 | 2\n", max_wraps=40)
    d, _ = both(m, [2])
    assert (d.phenotype, d.used_codons, d.wraps) == ("2" * 30, 30, 29)
    assert both(mapper("<s> ::= " + "<d>" * 30 + "\n<d> ::= 0 | 1\n", max_wraps=10), [1])[0].reason == (
        InvalidReason.CODONS
    )


def test_empty_genome() -> None:
    d, _ = both(mapper("<s> ::= <t>!\n<t> ::= hi\n", codons="lazy"), [])
    assert (d.phenotype, d.used_codons, d.wraps) == ("hi!", 0, 0)
    d, _ = both(mapper("<s> ::= <t>!\n<t> ::= hi\n", codons="eager"), [])
    assert (d.phenotype, d.reason, d.used_codons, d.wraps) == (None, InvalidReason.CODONS, 0, 0)


# ---- invalid individuals are values ------------------------------------------------------------

EXPR = "<e> ::= <e>+<e> | x\n"


def test_max_depth() -> None:
    genome = [0, 1, 1]  # <e> -> <e>+<e> -> x+x: depth 2
    assert both(mapper(EXPR), genome)[0].depth == 2
    assert both(mapper(EXPR, max_depth=2), genome)[0].phenotype == "x+x"
    d, _ = both(mapper(EXPR, max_depth=1), genome)
    assert (d.phenotype, d.reason, d.used_codons) == (None, InvalidReason.DEPTH, 1)
    assert d.tree.children[0].choice is None  # the partial tree stops where the mapping did
    assert both(mapper(EXPR, max_depth=1), [1])[0].phenotype == "x"


def test_undefined_rule_is_an_invalid_individual() -> None:
    text = "<s> ::= a<missing> | b\n"
    grammar = parse(text)  # the linter's problem, not the mapper's
    for codons in ("lazy", "eager"):
        m = compile_mapper(grammar, codons=codons)
        assert both(m, [1])[0].phenotype == "b"
        d, _ = both(m, [0])
        assert (d.phenotype, d.reason, d.used_codons) == (None, InvalidReason.UNDEFINED, 1)


def test_undefined_rule_outranks_running_out_of_codons() -> None:
    m = compile_mapper(parse("<s> ::= <t><missing>\n<t> ::= a | b\n"), max_wraps=0)
    d, _ = both(m, [0])
    assert (d.reason, d.used_codons) == (InvalidReason.UNDEFINED, 1)


@pytest.mark.parametrize(
    "text",
    [
        "<s> ::= <l>\n<l> ::= a<l>\n",  # a single-choice rule that recurses
        "<s> ::= <l>\n<l> ::= <l>\n",  # a pure self-loop
        "<s> ::= <l>\n<l> ::= <u><m>\n<m> ::= <l>!\n<u> ::= u\n",  # a longer cycle past a finished rule
    ],
)
def test_lazy_silent_loops_are_invalid_not_hangs(text: str) -> None:
    lazy, _ = both(mapper(text, codons="lazy"), [1, 2, 3])
    assert (lazy.reason, lazy.used_codons) == (InvalidReason.NONTERMINATING, 0)
    eager, _ = both(mapper(text, codons="eager"), [1, 2, 3])  # every step reads: codons run out
    assert (eager.reason, eager.used_codons) == (InvalidReason.CODONS, 12)
    limited, _ = both(mapper(text, codons="lazy", max_depth=20), [1, 2, 3])  # it runs into the limit
    assert (limited.reason, limited.used_codons) == (InvalidReason.DEPTH, 0)


def test_silent_loop_is_reached_only_after_the_codons_before_it() -> None:
    m = mapper("<s> ::= <c><l>\n<c> ::= a | b\n<l> ::= z<l>\n", codons="lazy")
    assert m.stops == {2: InvalidReason.NONTERMINATING}
    d, _ = both(m, [1])
    assert (d.reason, d.used_codons) == (InvalidReason.NONTERMINATING, 1)
    # A loop that reads codons on the way is bounded by them, not a hang.
    d, _ = both(mapper("<s> ::= <l>\n<l> ::= <c><l>\n<c> ::= a | b\n", codons="lazy"), [1, 0])
    assert (d.reason, d.used_codons) == (InvalidReason.CODONS, 8)


def test_deep_derivations_do_not_recurse() -> None:
    n = 30_000
    genome = [0] * n + [1]
    for codons in ("lazy", "eager"):
        m = mapper("<l> ::= a<l> | b\n", codons=codons, max_wraps=0)
        d, _ = both(m, genome)
        assert d.phenotype == "a" * n + "b"
        assert (d.depth, d.nodes, d.used_codons) == (n + 1, n + 1, n + 1)
        assert d.tree == m.map(genome).tree  # equality is iterative too
        limited = compile_mapper(m.cfg, codons=codons, max_wraps=0, max_depth=n + 1)
        assert limited.phenotype(genome) == d.phenotype
        too_shallow = compile_mapper(m.cfg, codons=codons, max_wraps=0, max_depth=n)
        assert too_shallow.map_fast(genome).reason == InvalidReason.DEPTH


# ---- typed ranges ----------------------------------------------------------------------------


def test_a_range_on_its_own_is_one_choice_set_of_its_rule() -> None:
    m = mapper("<s> ::= int[5..8] | z\n")
    assert m.n_choices == (5,)
    assert [m.phenotype([c]) for c in range(6)] == ["5", "6", "7", "8", "z", "5"]


def test_a_range_inside_an_alternative_reads_its_own_codon() -> None:
    grammar = parse("<s> ::= v=float[0..1 step 0.25];\n")
    values = grammar.rules[0].alternatives[0].symbols[1].spec.values  # type: ignore[union-attr]
    assert len(values) == 5
    lazy = compile_mapper(grammar, codons="lazy")
    eager = compile_mapper(grammar, codons="eager")
    for codon in range(12):
        assert both(lazy, [codon])[0].phenotype == f"v={values[codon % 5]};"
        assert both(eager, [99, codon])[0].phenotype == f"v={values[codon % 5]};"
    assert both(lazy, [7])[0].used_codons == 1


# ---- joints ------------------------------------------------------------------------------------

JOINTED = """\
@start <s>
@joint knee
<k> ::= <e> | (<k>)
@joint hip
<h> ::= <e>
@joint tail
<t> ::= wag
<s> ::= <h>;<k> | <k>
<e> ::= 1 | 2 | 3
"""


@pytest.mark.parametrize("max_depth", [None, 50])
@pytest.mark.parametrize("codons", ["lazy", "eager"])
def test_joint_phenotypes_are_their_first_subtrees(codons: str, max_depth: int | None) -> None:
    m = mapper(JOINTED, codons=codons, max_depth=max_depth)
    lazy = codons == "lazy"
    # lazy: <s> 0 -> <h>;<k>; <e> 1 -> 2; <k> 1 -> (<k>); <k> 1 -> (<k>); <k> 0 -> <e>; <e> 2 -> 3
    genome = [0, 1, 1, 1, 0, 2] if lazy else [0, 0, 1, 1, 1, 0, 2]
    d, _ = both(m, genome)
    assert d.phenotype == "2;((3))"
    assert d.joints == {"knee": "((3))", "hip": "2"}  # declaration order; <t> is never derived
    assert list(d.joints) == ["knee", "hip"]
    d, _ = both(m, [1, 0, 0] if lazy else [1, 0, 0, 0])
    assert d.joints == {"knee": "1"}
    d, _ = both(m, [1, 1])  # endless (((... : invalid, no joints
    assert not d.valid
    assert d.joints == {}


def test_joints_of_a_bare_cfg() -> None:
    cfg = build_cfg(parse(JOINTED))
    assert compile_mapper(cfg).map([0, 1, 0, 0]).joints == {}
    m = compile_mapper(cfg, joints={"left": "h", "right": "h", "ghost": "nowhere"})
    assert m.map([0, 1, 0, 0]).joints == m.map_fast([0, 1, 0, 0]).joints == {"left": "2", "right": "2"}


@pytest.mark.parametrize("max_depth", [None, 50])
@pytest.mark.parametrize("codons", ["lazy", "eager"])
def test_a_joint_rule_derived_twice_gives_its_first_text_in_the_fast_path(
    codons: str, max_depth: int | None
) -> None:
    m = mapper(
        "<s> ::= <a>+<a>+<b> | <b>\n@joint a\n<a> ::= x | y | (<a>)\n@joint b\n<b> ::= 1 | 2\n",
        codons=codons,
        max_depth=max_depth,
    )
    d, fast = both(m, [0, 0, 1, 0])  # x+y+1: <a> twice, the joints closing in their declared order
    assert (d.phenotype, d.joints) == ("x+y+1", {"a": "x", "b": "1"})
    assert fast.joints == d.joints
    d, fast = both(m, [0, 2, 0, 1, 0])  # (x)+y+1: the first <a> holds another
    assert (d.phenotype, fast.joints) == ("(x)+y+1", {"a": "(x)", "b": "1"})
    assert list(fast.joints) == ["a", "b"]


# ---- determinism, inputs, options --------------------------------------------------------------


def test_deterministic_and_input_types_agree() -> None:
    m = mapper(JOINTED)
    rng = np.random.default_rng(7)
    genomes = [rng.integers(0, 10_000, size=rng.integers(0, 12)) for _ in range(200)]
    as_lists = [g.tolist() for g in genomes]
    first = m.map_many(as_lists)
    assert m.map_many(as_lists) == first
    assert m.map_many(genomes) == first  # numpy arrays
    assert m.map_many(tuple(g) for g in as_lists) == first
    assert [m.map_fast(g) for g in as_lists] == first
    again = mapper(JOINTED)
    for g in as_lists:
        a, b = m.map(g), again.map(g)
        assert (a.tree, a.depth, a.nodes, a.summary()) == (b.tree, b.depth, b.nodes, b.summary())


def test_summary_is_json_ready() -> None:
    import json

    d = mapper(JOINTED).map([0, 1, 0, 0])
    assert json.loads(json.dumps(d.summary())) == {
        "phenotype": "2;1",
        "valid": True,
        "reason": None,
        "used_codons": 4,
        "wraps": 0,
        "depth": 3,
        "nodes": 5,
        "joints": {"knee": "1", "hip": "2"},
    }


@pytest.mark.parametrize(
    "options",
    [{"codons": "greedy"}, {"max_wraps": -1}, {"max_wraps": 1.5}, {"max_depth": 0}, {"max_depth": True}],
)
def test_bad_options_raise(options: dict[str, Any]) -> None:
    with pytest.raises(MapperError):
        mapper(EXPR, **options)


def test_a_grammar_without_rules_cannot_compile() -> None:
    with pytest.raises(MapperError, match="no rules"):
        compile_mapper(parse("# nothing here\n"))


@pytest.mark.parametrize(
    ("text", "code"),
    [
        ("<s> ::= float[0..1 step 0] | x\n", "GG302"),  # a malformed range must not map as raw text
        ("<s> ::= 'open | b\n", "GG102"),
        ("@joint\n<s> ::= a | b\n", "GG402"),
    ],
)
def test_a_grammar_with_an_error_is_never_compiled(text: str, code: str) -> None:
    grammar = parse(text)
    assert grammar.has_errors
    with pytest.raises(MapperError, match=rf"error\[{code}\].*a grammar with errors is not compiled"):
        compile_mapper(grammar)


def test_node_equality_ignores_codon_values() -> None:
    m = mapper(EXPR)
    assert m.map([0, 1, 1]).tree == m.map([2, 3, 5]).tree
    assert m.map([0, 1, 1]).tree != m.map([1]).tree
    assert Node("x") == Node("x")
    assert Node("x") != Node(0)


def test_python_filter() -> None:
    assert python_filter("def p():{:x = 1{::}for i in y:{:x = 2:}{::}return x:}{::}z = p()") == (
        "def p():\n  x = 1\n  for i in y:\n    x = 2\n  return x\nz = p()"
    )
    assert python_filter("a") == "a"
    assert python_filter("") == ""


# ---- against a recursive reference ---------------------------------------------------------------


class _Stop(Exception):
    def __init__(self, reason: InvalidReason) -> None:
        self.reason = reason


def reference(
    cfg: Cfg, genome: list[int], codons: str, max_wraps: int, max_depth: int | None, joint: int
) -> tuple[str | None, int, InvalidReason | None, str | None]:
    """GE mapping as the definition reads, recursively: (phenotype, used, reason, joint text).

    Lazy mapping without a depth limit can loop forever through single-choice
    rules without reading a codon. A derivation that finishes can be at most
    ``(codons read + 1) * (rules + 1)`` deep (a longer run of levels that read
    nothing repeats a rule with nothing read in between: such a loop), so
    anything deeper is that loop.
    """
    n = len(genome)
    limit = n * (max_wraps + 1)
    bound = (limit + 1) * (len(cfg) + 1) + 1
    used = 0
    joint_text: list[str] = []

    def expand(rule: int, level: int) -> str:
        nonlocal used
        if max_depth is not None and level > max_depth:
            raise _Stop(InvalidReason.DEPTH)
        if max_depth is None and level > bound:
            raise _Stop(InvalidReason.NONTERMINATING)
        choices = cfg.choices[rule]
        if not choices:
            raise _Stop(InvalidReason.UNDEFINED)
        if codons == "eager" or len(choices) > 1:
            if used >= limit:
                raise _Stop(InvalidReason.CODONS)
            c = genome[used % n] % len(choices)
            used += 1
        else:
            c = 0
        first = rule == joint and not joint_text
        if first:
            joint_text.append("")  # claimed: nested occurrences are not the first
        text = ""
        for item in choices[c]:
            text += item if isinstance(item, str) else expand(item, level + 1)
        if first:
            joint_text[0] = text
        return text

    try:
        phenotype = expand(cfg.start or 0, 1)
    except _Stop as stop:
        return None, used, stop.reason, None
    return phenotype, used, None, joint_text[0] if joint_text else None


@st.composite
def cfgs(draw: st.DrawFn) -> Cfg:
    """Rules r0.. (r0 the start), some possibly empty, and maybe an undefined name u."""
    defined = draw(st.integers(1, 4))
    undefined = draw(st.integers(0, 1))
    total = defined + undefined
    item = st.one_of(st.integers(0, total - 1), st.sampled_from(["a", "b", "", "cd"]))
    choice = st.lists(item, max_size=3).map(tuple)
    rule = st.lists(choice, min_size=1, max_size=3).map(tuple)
    empty = st.integers(0, 9).map(lambda x: x == 0)  # now and then a rule with no alternatives
    choices = [() if draw(empty) else draw(rule) for _ in range(defined)] + [()] * undefined
    names = tuple(f"r{i}" for i in range(defined)) + ("u",) * undefined
    kinds = (RuleKind.DEFINED,) * defined + (RuleKind.UNDEFINED,) * undefined
    return Cfg(
        names=names,
        kinds=kinds,
        choices=tuple(choices),
        alternative_of=tuple(tuple(range(len(c))) for c in choices),
        start=0,
        index={name: i for i, name in enumerate(names)},
    )


@settings(max_examples=400)
@given(
    cfg=cfgs(),
    genome=st.lists(st.integers(0, 40), max_size=8),
    codons=st.sampled_from(["lazy", "eager"]),
    max_wraps=st.integers(0, 2),
    max_depth=st.none() | st.integers(1, 8),
    joint=st.integers(0, 3),
)
def test_agrees_with_the_recursive_reference(
    cfg: Cfg, genome: list[int], codons: str, max_wraps: int, max_depth: int | None, joint: int
) -> None:
    joint %= len(cfg)
    m = compile_mapper(
        cfg, codons=codons, max_wraps=max_wraps, max_depth=max_depth, joints={"j": cfg.names[joint]}
    )
    phenotype, used, reason, joint_text = reference(cfg, genome, codons, max_wraps, max_depth, joint)
    d, fast = both(m, genome)
    assert (d.phenotype, d.used_codons, d.reason) == (phenotype, used, reason)
    assert d.wraps == ((used - 1) // len(genome) if used else 0)
    if reason is None and joint_text is not None and cfg.kinds[joint] is RuleKind.DEFINED:
        assert d.joints == {"j": joint_text}
    else:
        assert d.joints == {}
    assert m.map_many([genome, genome]) == [fast, fast]
    if d.valid:
        assert d.depth <= (max_depth or d.depth)
        assert d.nodes == sum(1 for node, _ in d.tree.walk() if not node.is_terminal)
