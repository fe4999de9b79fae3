"""Fixes as data: every code that has fixes has a sample here, and on it every fix removes the
problem and adds no error; safe fixes keep the grammar's meaning where they promise to;
``fix_source`` (``gaitgram check --fix``) never makes a file worse and leaves clean files alone."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from conftest import GRAMMARS
from gaitgram.analysis import CheckResult, check
from gaitgram.analysis.diagnostic_codes import CODES
from gaitgram.analysis.fixes import chosen_fix, combine, error_keys, fix_all, fix_source, no_worse
from gaitgram.language import parse
from gaitgram.language.diagnostics import Applicability, Diagnostic, Fix, TextEdit
from gaitgram.language.edits import EditConflict, apply_edits, removal
from gaitgram.language.model import Grammar, NonTerminal, RangeSymbol, Terminal
from gaitgram.language.source import SourceText, Span

#: For every code with fixes: a grammar with the problem, and the text after its chosen fix
#: (the safe one, else the preferred one), applied alone.
SAMPLES: dict[str, tuple[str, str]] = {
    "GG102": ("<a> ::= x | 'abc \n", "<a> ::= x | 'abc '\n"),
    "GG103": ("<a> ::= 'a\\x4'\n", "<a> ::= 'a\\\\x4'\n"),
    "GG104": ("<a> ::= int[1..5 | int[0..9 step 3]\n", "<a> ::= int[1..5] | int[0..9 step 3]\n"),
    "GG106": ("<a> ::= x | | y\n", "<a> ::= x | y\n"),
    "GG107": ("<a> ::= x # c\n  y\n", "<a> ::= x # c\n  | y\n"),
    "GG108": ("<a> ::= <b>\n<b> ::=\n", "<a> ::= <b>\n<b> ::= ''\n"),
    "GG109": ("<a> ::= '\ud83d\ude00'\n", "<a> ::= '😀'\n"),
    "GG201": (
        "<a> ::= <b> | <bee>\n<b> ::= x\n<beef> ::= y\n",
        "<a> ::= <b> | <beef>\n<b> ::= x\n<beef> ::= y\n",
    ),
    "GG202": ("<a> ::= x # first\n<a> ::= y | z\n", "<a> ::= x | y | z # first\n"),
    "GG204": ("<a> ::= x\n<b> ::= <c>\n<c> ::= y\n", "<a> ::= x\n<c> ::= y\n"),
    "GG301": ("<a> ::= int[5..1]\n", "<a> ::= int[1..5]\n"),
    "GG303": ("<a> ::= float[0..1 step 0.3]\n", "<a> ::= float[0..0.9 step 0.3]\n"),
    "GG305": ("<a> ::= int[0..1 step 0.5]\n", "<a> ::= float[0..1 step 0.5]\n"),
    "GG309": ("<a> ::= 2*flaot[0..1 step 0.5]\n", "<a> ::= 2*float[0..1 step 0.5]\n"),
    "GG401": ("@jont hip_hind\n<a> ::= t\n", "@joint hip_hind\n<a> ::= t\n"),
    "GG403": ("<a> ::= x\n@joint hip_hind  # dangling\n", "<a> ::= x\n"),
    "GG404": ("@start <a>\n@start <a>\n<a> ::= x\n", "@start <a>\n<a> ::= x\n"),
    "GG501": ("@backend mujoco-hors\n<a> ::= x\n", "@backend mujoco-horse\n<a> ::= x\n"),
    "GG502": (
        "@backend mujoco-horse\n@joint hip_hnd\n<a> ::= t\n",
        "@backend mujoco-horse\n@joint hip_hind\n<a> ::= t\n",
    ),
    "GG508": (
        "@backend mujoco-horse\n@joint hip_hind\n<a> ::= 2*Sin(2*PI*t)+0.1*pich\n",
        "@backend mujoco-horse\n@joint hip_hind\n<a> ::= 2*sin(2*PI*t)+0.1*pich\n",
    ),
}

#: Safe fixes that keep what the grammar derives (GG104 and GG309 make text a range, as meant).
MEANING_KEPT = {"GG102", "GG106", "GG107", "GG303"}

FIXABLE = sorted(code for code, c in CODES.items() if c.fix is not None)


def test_every_code_with_fixes_has_a_sample() -> None:
    assert sorted(SAMPLES) == FIXABLE


def of(text: str, code: str) -> list[Diagnostic]:
    return [d for d in check(parse(text)).diagnostics if d.code.code == code]


@pytest.mark.parametrize("code", FIXABLE)
def test_each_fix_fixes_its_problem_and_adds_no_error(code: str) -> None:
    text, expected = SAMPLES[code]
    before = check(parse(text))
    found = [d for d in before.diagnostics if d.code.code == code]
    assert found, f"the sample has no {code}"
    for diagnostic in found:
        assert diagnostic.fixes
        for fix in diagnostic.fixes:
            assert fix.applicability is CODES[code].fix  # the docs say how safe a code's fixes are
            fixed = apply_edits(text, fix.edits)
            after = check(parse(fixed))
            assert no_worse(before, after), (fix.title, fixed, after.diagnostics)
            assert len(of(fixed, code)) < len(found), (fix.title, fixed)
            if fix.safe and code in MEANING_KEPT:
                assert meaning(after.grammar) == meaning(before.grammar), fix.title
    chosen = chosen_fix(found[0], unsafe=True)
    assert chosen is not None
    assert apply_edits(text, chosen.edits) == expected


def meaning(grammar: Grammar) -> list[tuple[str, list[list[str]]]]:
    """What each rule derives, symbol by symbol (spans left out)."""

    def symbol(s: Terminal | NonTerminal | RangeSymbol) -> str:
        if isinstance(s, Terminal):
            return f"text {s.text!r}"
        if isinstance(s, NonTerminal):
            return f"rule {s.name}"
        return f"range {s.spec.values!r}"

    return [(r.name, [[symbol(s) for s in a.symbols] for a in r.alternatives]) for r in grammar.rules]


def test_fixes_carry_the_names_they_are_about() -> None:
    undefined = of(SAMPLES["GG201"][0], "GG201")[0]
    assert undefined.data == {"name": "bee"}
    assert [f.title for f in undefined.fixes] == ["Define <bee>", "Replace with <beef>"]
    look_alike = of(SAMPLES["GG309"][0], "GG309")[0]
    assert look_alike.data == {"text": "flaot[0..1 step 0.5]", "kind": "float"}


def test_an_unreachable_rule_goes_with_the_unreachable_rules_that_use_it() -> None:
    text = SAMPLES["GG204"][0]
    titles = {d.data["name"]: [f.title for f in d.fixes] for d in of(text, "GG204")}
    assert titles == {"b": ["Remove unreachable <b>"], "c": ["Remove unreachable <c> and the rule using it"]}
    # An ignored duplicate of a reachable rule still names <c>: removing <c> would leave it undefined.
    assert of("<a> ::= x\n<a> ::= <c>\n<c> ::= y\n", "GG204")[0].fixes == ()


def test_fix_all_combines_the_chosen_fixes_of_one_code() -> None:
    text = "<a> ::= x\n@joint hip_hind\n<lost> ::= y  # gone too\n  | z\n<also> ::= w\n"
    everything = fix_all(check(parse(text)).diagnostics, "GG204")
    assert everything is not None
    assert everything.title == "Remove all 2 unreachable rules"
    assert apply_edits(text, everything.edits) == "<a> ::= x\n"
    assert fix_all(check(parse("<a> ::= x\n<b> ::= y\n")).diagnostics, "GG204") is None  # only one


def test_edits_that_overlap_are_refused_and_removals_take_whole_lines() -> None:
    text = "abcdef"
    assert apply_edits(text, [TextEdit(Span(1, 2), "X"), TextEdit(Span(4, 4), "Y")]) == "aXcdYef"
    assert apply_edits(text, [TextEdit(Span(1, 2), "X")] * 2) == "aXcdef"  # the same edit is one edit
    with pytest.raises(EditConflict):
        apply_edits(text, [TextEdit(Span(1, 3), "X"), TextEdit(Span(2, 4), "Y")])
    with pytest.raises(EditConflict):
        apply_edits(text, [TextEdit(Span(2, 2), "X"), TextEdit(Span(2, 2), "Y")])
    with pytest.raises(EditConflict):
        apply_edits(text, [TextEdit(Span(0, 9), "")])
    deletion = Fix("d", (TextEdit(Span(0, 3), ""),))
    assert combine("both", [deletion, Fix("e", (TextEdit(Span(2, 5), ""),))]) == Fix(
        "both", (TextEdit(Span(0, 5), ""),), Applicability.UNSAFE
    )
    assert (
        combine("clash", [Fix("x", (TextEdit(Span(1, 3), "X"),)), Fix("y", (TextEdit(Span(2, 4), "Y"),))])
        is None
    )
    lines = "<a> ::= x\n  @joint j  # note\n<b> ::= y <c> ::= z\n"
    start = lines.index("@")
    assert removal(lines, start, start + len("@joint j")) == Span(lines.index("  @"), lines.index("<b>"))
    assert removal(lines, lines.index("<c>"), len(lines) - 1) == Span(lines.index("<c>"), len(lines) - 1)


# ---- gaitgram check --fix -----------------------------------------------------------------------


def test_fix_source_applies_safe_fixes_and_reports_them() -> None:
    text = "<a> ::= x | | y | flaot[0..1 step 0.5] | <bee>\n<b> ::= 'open\n<beef> ::= z\n"
    outcome = fix_source(SourceText(text, "t.gg"))
    assert outcome.text == "<a> ::= x | y | float[0..1 step 0.5] | <bee>\n<b> ::= 'open'\n<beef> ::= z\n"
    assert [a.code.code for a in outcome.applied] == ["GG106", "GG309", "GG102"]
    assert (outcome.applied[0].location.line, outcome.applied[0].location.column) == (1, 13)
    assert outcome.unsafe_available == 3  # <bee> -> <beef>, and the two unreachable rules
    unsafe = fix_source(SourceText(text, "t.gg"), unsafe=True)
    assert unsafe.text == "<a> ::= x | y | float[0..1 step 0.5] | <beef>\n<beef> ::= z\n"
    assert not [d for d in unsafe.result.diagnostics if d.is_error]


def test_a_fix_that_would_add_an_error_is_not_applied() -> None:
    # Replacing <bee> by <beef> would make <a> unproductive (it needs <beef>, which needs <a>).
    text = "<a> ::= <b> <bee>\n<b> ::= x\n<beef> ::= <a>\n"
    outcome = fix_source(SourceText(text), unsafe=True)
    assert not any(a.title == "Replace with <beef>" for a in outcome.applied)
    assert no_worse(check(parse(text)), outcome.result)
    assert outcome.refused >= 1


@pytest.mark.parametrize("path", sorted(GRAMMARS.glob("*.gg")), ids=lambda p: p.name)
def test_the_bundled_grammars_are_left_alone(path: Path) -> None:
    text = path.read_text()
    for unsafe in (False, True):
        outcome = fix_source(SourceText(text, str(path)), unsafe=unsafe)
        assert outcome.text == text
        assert not outcome.applied


PIECES = [
    "<a> ::= ",
    "<b> ::= ",
    "<bee> ::= ",
    "<a>",
    "<b>",
    "<be>",
    " | ",
    "|",
    "\n",
    "  ",
    "# c\n",
    "'",
    "'x'",
    "\\x4",
    "x",
    "int[1..5",
    "int[5..1]",
    "flaot[0..1 step 0.5]",
    "Int[0..2]",
    "float[0..1 step 0.3]",
    "int[0..1 step 0.5]",
    "]",
    "@start <a>\n",
    "@joint hip_hind\n",
    "@jont x\n",
    "@frequency\n",
    "<amp> ::= ",
    "'open |",
    " # c\n",
]
texts = st.lists(st.sampled_from(PIECES), max_size=30).map("".join)


def errors(result: CheckResult) -> Counter[tuple[str, str | None, str]]:
    return error_keys(result)


@settings(max_examples=300, deadline=None)
@given(texts)
@example("@joint hip_hind\n<a> ::= 'x'int[1..5")  # the range's fix turns the curve's name xint into x
def test_every_fix_is_well_formed_and_safe_ones_add_no_error(text: str) -> None:
    before = check(parse(text))
    text = before.grammar.source.text  # spans are offsets of the newline-normalised text
    for diagnostic in before.diagnostics:
        for fix in diagnostic.fixes:
            assert fix.applicability is diagnostic.code.fix
            fixed = apply_edits(text, fix.edits)  # in bounds, no overlaps
            if fix.safe:
                after = check(parse(fixed))
                assert no_worse(before, after), (diagnostic.code.code, fix.title, fixed, errors(after))


@settings(max_examples=200, deadline=None)
@given(texts, st.booleans())
def test_check_fix_never_makes_a_text_worse_and_leaves_clean_ones_alone(text: str, unsafe: bool) -> None:
    before = check(parse(text))
    outcome = fix_source(SourceText(text), unsafe=unsafe)
    assert no_worse(before, outcome.result)
    assert outcome.result.grammar.source.text == outcome.text
    if not before.diagnostics or not outcome.applied:
        assert outcome.text == before.grammar.source.text
        assert not outcome.changed


#: Whole rules, often defined twice, with unterminated strings, comments and fixable ranges:
#: fixes that wait for one another.
rule_lines = st.builds(
    lambda head, alternatives, bar, comment: f"{head} ::= {bar.join(alternatives)}{comment}\n",
    st.sampled_from(["<a>", "<b>", "<amp>", "<bee>"]),
    st.lists(
        st.sampled_from(
            [
                *["x", "1", "'open ", "'q'", "<a>", "<b>", "<amp>", "<be>", "", "\\x4"],
                *["int[5..1]", "flaot[0..1 step 0.5]", "float[0..1 step 0.3]"],
            ]
        ),
        min_size=1,
        max_size=4,
    ),
    st.sampled_from([" | ", " |", "|", "\t|\t"]),
    st.sampled_from(["", " # c", "\t# c"]),
)
rules = st.lists(rule_lines, min_size=1, max_size=6).map("".join)


def fixing_reaches_a_fixed_point(text: str, unsafe: bool) -> None:
    once = fix_source(SourceText(text), unsafe=unsafe)
    again = fix_source(SourceText(once.text), unsafe=unsafe)
    assert again.applied == (), (once.text, [a.title for a in again.applied])
    assert again.text == once.text
    assert once.converged


# 150 texts in the default run, 800 in the slow set.
test_fixing_reaches_a_fixed_point_so_fixing_again_changes_nothing = settings(max_examples=150, deadline=None)(
    given(rules, st.booleans())(fixing_reaches_a_fixed_point)
)
test_fixing_reaches_a_fixed_point_at_length = pytest.mark.slow(
    settings(max_examples=800, deadline=None)(given(rules, st.booleans())(fixing_reaches_a_fixed_point))
)


def test_a_fix_refused_in_one_text_is_tried_again_once_others_changed_it() -> None:
    # The merge of the two <amp> rules would move the unterminated string; once it is closed,
    # the merge adds no error.
    outcome = fix_source(SourceText("<amp> ::= x # c\n<amp> ::= 1 |'open |2\n<legs> ::= y\n"), unsafe=True)
    assert outcome.text == "<amp> ::= x | 1 |'open |2' # c\n"
    assert [a.code.code for a in outcome.applied] == ["GG204", "GG102", "GG202"]
    assert outcome.converged


def test_a_misspelt_backend_gets_the_nearest_name_as_hint() -> None:
    (near,) = [
        d for d in check(parse("@backend mujoco-hors\n<a> ::= x\n")).diagnostics if d.code.code == "GG501"
    ]
    (far,) = [d for d in check(parse("@backend zzz\n<a> ::= x\n")).diagnostics if d.code.code == "GG501"]
    assert near.hint == "did you mean mujoco-horse?"
    assert far.hint is not None
    assert far.hint.startswith("installed backends:")
    assert "mujoco-horse" in far.hint
