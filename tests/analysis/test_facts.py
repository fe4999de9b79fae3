"""Rule facts against slow, obviously-correct references, and against Bison.

The references iterate to a fixed point over the whole grammar; the library's
analyses are worklist algorithms. They must agree on every random grammar.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import GRAMMARS
from gaitgram.analysis import analyse, build_cfg, check
from gaitgram.analysis.cfg import Cfg
from gaitgram.analysis.facts import derived_exactly_once, occurrence_bounds, reachable_from
from gaitgram.language import parse

# A grammar here: rules r0..rN-1, each a list of alternatives, each a list of
# symbols: an int is a reference to that rule, None the terminal "t".
RawGrammar = list[list[list[int | None]]]


@st.composite
def raw_grammars(draw: st.DrawFn, max_rules: int = 6) -> RawGrammar:
    n = draw(st.integers(1, max_rules))
    symbol = st.one_of(st.none(), st.integers(0, n - 1))
    alternative = st.lists(symbol, max_size=3)
    return [draw(st.lists(alternative, min_size=1, max_size=3)) for _ in range(n)]


def to_text(raw: RawGrammar) -> str:
    def alt(symbols: list[int | None]) -> str:
        return " ".join("t" if s is None else f"<r{s}>" for s in symbols) or "''"

    return "\n".join(f"<r{i}> ::= " + " | ".join(alt(a) for a in alts) for i, alts in enumerate(raw)) + "\n"


def reference_productive(raw: RawGrammar) -> list[bool]:
    productive = [False] * len(raw)
    changed = True
    while changed:
        changed = False
        for i, alts in enumerate(raw):
            if not productive[i] and any(all(s is None or productive[s] for s in a) for a in alts):
                productive[i] = changed = True
    return productive


def reference_reachable(raw: RawGrammar, start: int = 0) -> list[bool]:
    seen = {start}
    stack = [start]
    while stack:
        for alt in raw[stack.pop()]:
            for s in alt:
                if s is not None and s not in seen:
                    seen.add(s)
                    stack.append(s)
    return [i in seen for i in range(len(raw))]


def reference_min_depth(raw: RawGrammar) -> list[int | None]:
    inf = float("inf")
    depth = [inf] * len(raw)
    for _ in range(len(raw) + 1):  # Bellman-Ford: n rounds are enough
        for i, alts in enumerate(raw):
            for a in alts:
                depth[i] = min(depth[i], 1 + max((depth[s] for s in a if s is not None), default=0))
    return [None if d == inf else int(d) for d in depth]


def reference_recursive(raw: RawGrammar) -> list[bool]:
    def reaches(i: int) -> set[int]:
        seen: set[int] = set()
        stack = [s for a in raw[i] for s in a if s is not None]
        while stack:
            s = stack.pop()
            if s not in seen:
                seen.add(s)
                stack += [c for a in raw[s] for c in a if c is not None]
        return seen

    return [i in reaches(i) for i in range(len(raw))]


def facts_agree_with_references(raw: RawGrammar) -> None:
    grammar = parse(to_text(raw))
    facts = analyse(grammar)
    order = [facts.cfg.index[f"r{i}"] for i in range(len(raw))]
    assert [facts.productive[i] for i in order] == reference_productive(raw)
    assert [facts.reachable[i] for i in order] == reference_reachable(raw)
    assert [facts.min_depth[i] for i in order] == reference_min_depth(raw)
    assert [facts.recursive[i] for i in order] == reference_recursive(raw)
    assert [len(facts.cfg.choices[i]) for i in order] == [len(a) for a in raw]


# 250 grammars in the default run, 2,000 in the slow set.
test_facts_agree_with_references = settings(max_examples=250)(
    given(raw_grammars())(facts_agree_with_references)
)
test_facts_agree_with_references_at_length = pytest.mark.slow(
    settings(max_examples=2000)(given(raw_grammars())(facts_agree_with_references))
)


@given(raw_grammars())
def test_lint_reports_exactly_the_unproductive_and_unreachable_rules(raw: RawGrammar) -> None:
    found = check(parse(to_text(raw))).diagnostics
    productive, reachable = reference_productive(raw), reference_reachable(raw)
    # The start rule gets its own code, GG205, instead of GG203.
    assert {d.rule for d in found if d.code.code == "GG203"} == {
        f"r{i}" for i in range(1, len(raw)) if not productive[i]
    }
    assert {d.rule for d in found if d.code.code == "GG204"} == {
        f"r{i}" for i in range(len(raw)) if not reachable[i]
    }
    assert any(d.code.code == "GG205" for d in found) == (not productive[0])


@given(raw_grammars())
def test_rules_derived_exactly_once_agree_with_the_search(raw: RawGrammar) -> None:
    # The linter's shortcut before a search per joint rule: wherever it answers, so does the search.
    facts = analyse(parse(to_text(raw)))
    for rule in derived_exactly_once(facts.cfg, facts.productive):
        assert occurrence_bounds(facts.cfg, rule, facts.productive) == (1, 1)


def test_every_joint_rule_of_a_bundled_grammar_is_found_once_without_a_search() -> None:
    grammar = parse((GRAMMARS / "sine-walk.gg").read_text(encoding="utf-8"))
    facts = analyse(grammar)
    once = derived_exactly_once(facts.cfg, facts.productive)
    assert {facts.cfg.index[joint.rule] for joint in grammar.joints} <= once


def test_min_depth_per_choice() -> None:
    facts = analyse(parse("<e> ::= <e> + <v> | <v>\n<v> ::= x | (<e>)"))
    e = facts.rule("e")
    assert e is not None
    assert (e.min_depth, e.choice_min_depths, e.recursive, e.choices) == (2, (3, 2), True, 2)
    v = facts.rule("v")
    assert v is not None
    assert (v.min_depth, v.choice_min_depths) == (1, (1, 3))


def test_joint_reach() -> None:
    grammar = parse("<g> ::= <a><b>\n@joint hip_hind\n<a> ::= <c> | <d>\n<c> ::= 1\n<d> ::= <c>2\n<b> ::= 3")
    assert analyse(grammar).joint_reach == {"a": frozenset({"a", "c", "d"})}


# ---- Bison, the trusted reference for useless non-terminals ------------------------------------

BISON = shutil.which("bison")


def to_bison(raw: RawGrammar) -> str:
    def alt(symbols: list[int | None]) -> str:
        return " ".join("'t'" if s is None else f"r{s}" for s in symbols) or "%empty"

    rules = "\n".join(f"r{i}: " + " | ".join(alt(a) for a in alts) + ";" for i, alts in enumerate(raw))
    return f"%start r0\n%%\n{rules}\n"


def bison_verdict(raw: RawGrammar, tmp: Path) -> tuple[bool, set[str]]:
    """(start derives nothing, useless non-terminals) as Bison reports them."""
    path = tmp / "g.y"
    path.write_text(to_bison(raw))
    assert BISON is not None
    run = subprocess.run([BISON, "-Wall", "-o", str(tmp / "g.c"), str(path)], capture_output=True, text=True)
    start_dead = "start symbol r0 does not derive any sentence" in run.stderr
    useless = set(re.findall(r"nonterminal useless in grammar: (r\d+)", run.stderr))
    return start_dead, useless


def ours(raw: RawGrammar) -> tuple[bool, set[str]]:
    """Bison's useless set: unproductive, or unreachable once unproductive rules are dropped."""
    grammar = parse(to_text(raw))
    facts = analyse(grammar)
    cfg = facts.cfg
    productive_only = Cfg(
        cfg.names,
        cfg.kinds,
        tuple(
            tuple(c for c in choices if all(not isinstance(s, int) or facts.productive[s] for s in c))
            for choices in cfg.choices
        ),
        cfg.alternative_of,
        cfg.start,
        cfg.index,
    )
    reachable = reachable_from(productive_only, [cfg.start] if cfg.start is not None else [])
    useless = {name for i, name in enumerate(cfg.names) if not facts.productive[i] or not reachable[i]}
    return not facts.start_productive, useless


@pytest.mark.skipif(BISON is None, reason="needs Debian's bison; .ci/run installs it")
@settings(max_examples=60)
@given(raw=raw_grammars())
def test_agrees_with_bison(raw: RawGrammar, tmp_path_factory: pytest.TempPathFactory) -> None:
    tmp = tmp_path_factory.mktemp("bison")
    start_dead, useless = bison_verdict(raw, tmp)
    our_dead, our_useless = ours(raw)
    assert our_dead == start_dead
    if not start_dead:  # Bison stops before listing useless symbols when the start is dead
        assert our_useless == useless


@pytest.mark.skipif(BISON is None, reason="needs Debian's bison; .ci/run installs it")
@pytest.mark.parametrize(
    ("raw", "expected"),
    [
        # r1 never finishes, r2 loops on itself, r3 is unreachable.
        ([[[1], [None]], [[1, None]], [[2]], [[0, None]]], (False, {"r1", "r2", "r3"})),
        # Expression grammar: all useful.
        ([[[0, None, 1], [1]], [[None], [None, 0, None]]], (False, set())),
        # r2 is reachable only through r1, which cannot finish: Bison calls r2 useless too.
        ([[[None], [1]], [[1, 2]], [[None]]], (False, {"r1", "r2"})),
        # The start rule cannot finish.
        ([[[0, 1]], [[None]]], (True, set())),
        # A long chain that finishes at the end.
        ([[[1]], [[2]], [[3]], [[None]]], (False, set())),
    ],
)
def test_bison_agrees_on_hand_written_grammars(
    raw: RawGrammar, expected: tuple[bool, set[str]], tmp_path: Path
) -> None:
    assert bison_verdict(raw, tmp_path) == expected
    our_dead, our_useless = ours(raw)
    assert our_dead == expected[0]
    if not our_dead:  # Bison lists no useless symbols once the start is dead
        assert our_useless == expected[1]


def test_cfg_of_empty_grammar() -> None:
    cfg = build_cfg(parse(""))
    assert (len(cfg), cfg.start) == (0, None)


def reference_removed_with(raw: RawGrammar, rule: int, limit: int) -> set[int] | None:
    """The unreachable-rule fix's rules, by a search per rule: ``rule`` and every rule using it,
    transitively; None if one of them is reachable or more than ``limit`` would go."""
    reachable = reference_reachable(raw)
    users = {i: {u for u, alts in enumerate(raw) for a in alts if i in a and u != i} for i in range(len(raw))}
    removed, frontier = {rule}, [rule]
    while frontier:
        for user in users[frontier.pop()]:
            if user in removed:
                continue
            if reachable[user]:
                return None
            removed.add(user)
            frontier.append(user)
    return removed if len(removed) <= limit else None


@given(raw_grammars(max_rules=8), st.integers(1, 4))
def test_unreachable_rule_fixes_remove_every_user_or_nothing(raw: RawGrammar, limit: int) -> None:
    from gaitgram.analysis.lint import rule_checks

    grammar = parse(to_text(raw))
    original, rule_checks.MAX_REMOVED_WITH = rule_checks.MAX_REMOVED_WITH, limit
    try:
        found = {d.rule: d.fixes for d in check(grammar).diagnostics if d.code.code == "GG204"}
    finally:
        rule_checks.MAX_REMOVED_WITH = original
    for name, fixes in found.items():
        expected = reference_removed_with(raw, int(name.removeprefix("r")), limit)
        if expected is None:
            assert fixes == ()
            continue
        (fix,) = fixes
        others = len(expected) - 1
        assert fix.title.endswith("using it") == (others > 0)
        deleted = "".join(grammar.source.text[e.span.start : e.span.end] for e in fix.edits)
        assert {f"r{i}" for i in expected} == set(re.findall(r"^<(r\d+)> ::=", deleted, re.MULTILINE))
