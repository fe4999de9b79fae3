"""``gaitgram fmt``: layout only, idempotent, comments kept, broken files refused."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from language.test_fuzz import PIECES

from gaitgram.language import load, parse
from gaitgram.language.formatter import FormatRefused, format_text


def meaning(text: str) -> list[object]:
    grammar = parse(text)
    return [
        (r.name, [[getattr(s, "text", getattr(s, "name", None)) for s in a.symbols] for a in r.alternatives])
        for r in grammar.rules
    ]


def test_layout() -> None:
    text = (
        "# A grammar\n   @start <e>\n\n\n\n"
        "<e>::=<e>+<e>|<v>   # recurse\n      |   'x'\n"
        "# section\n<v> ::= a\n   | b\n\n\n"
        "<w> ::= multi   \n   line | z   \n\n"
    )
    assert format_text(text) == (
        "# A grammar\n@start <e>\n\n"
        "<e> ::= <e>+<e> | <v>  # recurse\n      | 'x'\n"
        "# section\n<v> ::= a\n      | b\n\n"
        "<w> ::= multi   \n   line | z\n"
    )


def test_vector_grammars_keep_their_meaning_and_format_idempotently(vector_grammar: Path) -> None:
    text = vector_grammar.read_text()
    once = format_text(text)
    assert meaning(once) == meaning(text)
    assert format_text(once) == once


def test_comments_are_kept() -> None:
    text = "# head\n<a> ::= x  # one\n  # two\n  | y\n# tail\n"
    formatted = format_text(text)
    for comment in ("# head", "# one", "# two", "# tail"):
        assert comment in formatted


def test_trailing_spaces_in_a_bad_annotation_argument() -> None:
    assert format_text("@start' ::= ") == "@start ' ::=\n"  # found by hypothesis in CI


def test_syntax_errors_are_refused() -> None:
    with pytest.raises(FormatRefused) as refused:
        format_text("<a> ::= 'unterminated\n")
    assert [d.code.code for d in refused.value.diagnostics] == ["GG102"]


grammar_texts = st.lists(st.sampled_from(PIECES), max_size=50).map("".join)


@settings(max_examples=300)
@given(grammar_texts)
def test_formatting_never_changes_meaning_and_is_idempotent(text: str) -> None:
    try:
        once = format_text(text)
    except FormatRefused:
        return
    # format_text itself re-parses and raises FormatError on any change of meaning.
    assert format_text(once) == once


def test_bundled_grammars_are_formatted() -> None:
    for path in Path(__file__).resolve().parents[2].joinpath("grammars").glob("*.gg"):
        assert format_text(path.read_text()) == path.read_text(), path
        assert not load(path).has_errors
