"""GG309: terminal text that looks like a typed range, which PonyGE2 compatibility keeps as text."""

from __future__ import annotations

import pytest

from conftest import VECTOR_DEFINES, vector_grammars
from gaitgram.analysis import check
from gaitgram.language import load, parse
from gaitgram.language.edits import apply_edits
from gaitgram.language.model import RangeSymbol, Terminal


def look_alikes(text: str) -> list[tuple[str, str | None]]:
    """(the text warned about, the text after its fix) for each GG309."""
    grammar = parse(text)
    found = []
    for d in grammar.diagnostics:
        if d.code.code == "GG309":
            fixed = apply_edits(text, d.fixes[0].edits) if d.fixes else None
            found.append((grammar.source.slice(d.span), fixed))
    return found


@pytest.mark.parametrize(
    ("rule", "warned", "fixed"),
    [
        ("<a> ::= flaot[0..1 step 0.1]\n", "flaot[0..1 step 0.1]", "<a> ::= float[0..1 step 0.1]\n"),
        ("<a> ::= int[1..5\n", "int[1..5", "<a> ::= int[1..5]\n"),
        ("<a> ::= float[0..1 step 0.1\n", "float[0..1 step 0.1", "<a> ::= float[0..1 step 0.1]\n"),
        ("<a> ::= x + Float[0..1 count 3] y\n", "Float[0..1 count 3]", "<a> ::= x + float[0..1 count 3] y\n"),
        ("<a> ::= integer[1..3 | x\n", "integer[1..3", "<a> ::= int[1..3] | x\n"),
        ("<a> ::= itn[0..9] <b>\n<b> ::= y\n", "itn[0..9]", "<a> ::= int[0..9] <b>\n<b> ::= y\n"),
        (
            "<a> ::= float[7.7 ± 25% count 21\n",
            "float[7.7 ± 25% count 21",
            "<a> ::= float[7.7 ± 25% count 21]\n",
        ),
        # A warning without a fix where the fixed range would be an error (a float needs a step).
        ("<a> ::= flaot[0..1]\n", "flaot[0..1]", None),
    ],
)
def test_a_look_alike_is_warned_about_with_its_fix(rule: str, warned: str, fixed: str | None) -> None:
    assert look_alikes(rule) == [(warned, fixed)]
    diagnostic = next(d for d in parse(rule).diagnostics if d.code.code == "GG309")
    assert not diagnostic.is_error
    assert "plain text" in diagnostic.message
    if fixed is not None:
        symbols = [s for a in parse(fixed).rules[0].alternatives for s in a.symbols]
        assert any(isinstance(s, RangeSymbol) for s in symbols)  # fixed, it is a range


@pytest.mark.parametrize(
    "rule",
    [
        "<a> ::= x[0..1]\n",  # not close to int or float
        "<a> ::= points[0..3]\n",
        "<a> ::= in[1..5]\n",  # too short a word to guess from
        "<a> ::= 'flaot[0..1 step 0.1]'\n",  # quoted: text on purpose
        "<a> ::= int[1-5\n",  # no range inside
        "<a> ::= int[1..5x\n",  # the number goes on into a word
        "<a> ::= float[0..1 step 0.1]\n",  # a range
        "<a> ::= xx_int[1..5]\n",
        "# flaot[0..1 step 0.1]\n<a> ::= x\n",  # a comment
    ],
)
def test_other_text_is_not_a_look_alike(rule: str) -> None:
    assert look_alikes(rule) == []


def test_the_text_stays_text_as_ponyge2_reads_it() -> None:
    grammar = parse("<a> ::= flaot[0..1 step 0.5]\n")
    assert [type(s) for s in grammar.rules[0].alternatives[0].symbols] == [Terminal]


def test_no_fix_that_would_close_another_bracket_or_turn_text_into_a_ge_range() -> None:
    assert look_alikes("<a> ::= x int[ y int[1..5\n") == [("int[1..5", None)]
    assert look_alikes("<a> ::= flaot[0..1 step 0.5] GE_RANGE:3\n") == [("flaot[0..1 step 0.5]", None)]


def test_ponyge2_grammars_have_no_look_alikes() -> None:
    for path in vector_grammars():
        found = check(load(path, defines=VECTOR_DEFINES)).diagnostics
        assert not [d for d in found if d.code.code == "GG309"], path.name
