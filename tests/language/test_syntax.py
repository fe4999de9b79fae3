"""The syntax layer is lossless (its tokens give the text back, whatever the text) and reads as
the parser does."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import GRAMMARS
from gaitgram.language import parse
from gaitgram.language.syntax import is_rule_name, tokenize

FRAGMENTS = [
    "<a>",
    " ::= ",
    "|",
    "@joint hip_hind limits=-5..5\n",
    "@start <a>",
    "# c\n",
    "'x",
    '"y"',
    "float[0..1 step 0.1]",
    "int[",
    "GE_RANGE:n",
    "\n",
    "\r\n",
    "\t",
    " ",
    "é",
    "😀",
    "\\",
    "x",
]
texts = st.one_of(st.text(), st.lists(st.sampled_from(FRAGMENTS), max_size=60).map("".join))


@settings(max_examples=400, deadline=None)
@given(texts)
def test_the_tokens_give_the_text_back_exactly(text: str) -> None:
    found = tokenize(text)
    assert "".join(token.text(text) for token in found) == text
    position = 0
    for token in found:
        assert token.span.start == position < token.span.end  # no gap, no overlap, never empty
        position = token.span.end


@pytest.mark.parametrize("path", sorted(GRAMMARS.glob("*.gg")), ids=lambda p: p.name)
def test_tokens_agree_with_the_model(path: Path) -> None:
    text = path.read_text()
    grammar = parse(text)
    found = tokenize(text)
    heads = [t.span.start for t in found if t.kind == "RULE_HEAD"]
    assert heads == [rule.span.start for rule in grammar.rules]
    assert [t.span.start for t in found if t.kind == "ANNOTATION"] == [
        a.span.start for a in grammar.annotations
    ]
    comments = [t.text(text) for t in found if t.kind == "COMMENT"]
    assert comments
    assert all(c.startswith("#") for c in comments)


@pytest.mark.parametrize(("name", "valid"), [("a", True), ("hip_hind", True), ("", False), ("a>", False)])
def test_rule_names(name: str, valid: bool) -> None:
    assert is_rule_name(name) is valid
