"""The one motion parser against lark's parser of ``expression.lark``, on arbitrary text.

The grammar file specifies the syntax and lark is its reference reading: the parser must
accept exactly the texts lark accepts, build the same trees with the same spans, and
report the same first error (offset, length, message, hint) for everything else.
"""

from __future__ import annotations

import re

import pytest
from hypothesis import example, given, settings
from lark_oracle import lark_parse, lark_parser
from motion_texts import arbitrary_texts, deep_nesting, near_misses

from gaitgram.motion import MotionError, MotionStatus, parse_expression
from gaitgram.motion.parser import NAME_PATTERN, NUMBER_PATTERN, PUNCTUATION, WHITESPACE, Syntax, parse
from gaitgram.motion.tree import Binary, Call, Expr, Name, Number, Unary, postorder


def assert_same_as_lark(text: str) -> None:
    ours, lark = parse_expression(text), lark_parse(text)
    if isinstance(lark, MotionError):
        assert ours == lark, text
        return
    assert not isinstance(ours, MotionError), (text, ours)
    assert nodes(ours) == nodes(lark)


def nodes(tree: Expr) -> list[tuple[str, object, int, int]]:
    """Each node's type, own field (number, name or operator) and span, in postorder: the tree
    compared without recursion, so at any depth."""
    return [(type(node).__name__, _own(node), node.start, node.end) for node in postorder(tree)]


def _own(node: Expr) -> object:
    match node:
        case Number(value=value):
            return value
        case Name(name=name):
            return name
        case Unary(op=op) | Binary(op=op):
            return op
        case Call(name=name, args=args):
            return (name, len(args))
    raise AssertionError(node)


@example("")
@example("2**t")
@example("sin()")
@example("sin(,t)")
@example("sin(t,)")
@example("(t,2)")
@example("t)")
@example("t (2)")
@example("2 sin (t)")
@example("1e")
@example("1e+")
@example("..5")
@example("٣+t")
@example("t\u00a0")
def parser_agrees_with_the_grammar(text: str) -> None:
    assert_same_as_lark(text)


# 300 texts (and every example above) in the default run, 1,500 in the slow set.
test_the_parser_agrees_with_the_grammar_on_any_text = settings(max_examples=300)(
    given(arbitrary_texts)(parser_agrees_with_the_grammar)
)
test_the_parser_agrees_with_the_grammar_on_any_text_at_length = pytest.mark.slow(
    settings(max_examples=1500)(given(arbitrary_texts)(parser_agrees_with_the_grammar))
)


@settings(max_examples=300)
@given(near_misses())
def test_the_parser_agrees_with_the_grammar_on_near_misses(text: str) -> None:
    assert_same_as_lark(text)


@settings(max_examples=40)
@given(deep_nesting())
def test_the_parser_agrees_with_the_grammar_at_any_depth(text: str) -> None:
    assert_same_as_lark(text)


def test_the_tokens_are_the_grammars_terminals() -> None:
    terminals = {t.name: t.pattern for t in lark_parser().terminals}
    assert terminals.pop("NUMBER").to_regexp() == NUMBER_PATTERN
    assert terminals.pop("NAME").to_regexp() == NAME_PATTERN
    ignored = re.compile(terminals.pop("__IGNORE_0").to_regexp())
    assert {c for c in map(chr, range(0x3100)) if ignored.fullmatch(c)} == set(WHITESPACE)
    assert sorted(p.value for p in terminals.values()) == sorted(PUNCTUATION)
    assert all(p.type == "str" for p in terminals.values())


@pytest.mark.parametrize("depth", [10_000, 100_000])
def test_parsing_is_iterative(depth: int) -> None:
    syntax = parse("(" * depth + "-t" + ")" * depth)
    assert not isinstance(syntax, MotionError)
    assert len(syntax.nodes) == 2
    assert syntax.nodes[-1][2:4] == (0, 2 * depth + 2)  # the outermost parentheses' span


@pytest.mark.parametrize("spaces", [" ", "\t", "\r\n"])
def test_long_whitespace_parses(spaces: str) -> None:
    """Trailing whitespace once took quadratic time (a token match tried at each of its
    positions): these took hours then, milliseconds now (``benchmarks motion`` times it)."""
    assert isinstance(parse("t" + spaces * 50_000), Syntax)
    assert parse(spaces * 50_000) == MotionError(
        MotionStatus.PARSE_ERROR, "empty motion expression", 50_000 * len(spaces), 0
    )
    error = parse("t" + spaces * 50_000 + "+")
    assert isinstance(error, MotionError)
    assert error.message.startswith("unexpected end of text")
