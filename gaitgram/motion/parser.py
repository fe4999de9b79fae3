"""Parsing, the first stage: phenotype text to postfix nodes, or a syntax error that says where.

``expression.lark`` specifies the syntax; this module is its only parser. It is an
operator-precedence parser (one regular expression for the tokens, one loop, no
recursion, so nesting depth is unlimited) that emits each node as soon as its operands
are complete: children before parents, the order the compiler consumes them in, so no
tree is built on the way. The tests check it against lark's LALR parser of
``expression.lark`` on arbitrary text (random strings, near misses, huge numbers, deep
nesting, other scripts): it accepts the same texts, gives the same trees with the same
spans, and reports the first error at the same token with the words lark's exception
would give.

Names are not resolved here (that is :mod:`gaitgram.motion.checker`), so an unknown
name is reported as such rather than as a syntax error.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from enum import IntEnum

from gaitgram.motion.names import NAME_PATTERN, NUMBER_PATTERN, WHITESPACE
from gaitgram.motion.results import MotionError, MotionStatus
from gaitgram.motion.tree import BINARY_PRECEDENCE, UNARY_PRECEDENCE, Binary, Call, Expr, Name, Number, Unary


class NodeKind(IntEnum):
    NUMBER = 0
    NAME = 1
    UNARY = 2
    BINARY = 3
    CALL = 4


#: One node, as ``(kind, value, start, end, a, b)``: ``value`` is the number (a float), the
#: name or the operator; ``text[start:end]`` is the node's span, parentheses around it
#: included. For BINARY, ``(a, b)`` is the right operand's span (a divisor, in messages); for
#: CALL, ``a`` is the argument count. Otherwise both are 0. Plain tuples: the compiler's loop
#: unpacks them cheaply.
Node = tuple[NodeKind, float | str, int, int, int, int]


@dataclass(frozen=True, slots=True)
class Syntax:
    """A parsed expression: its nodes in postfix order (every node after its operands)."""

    text: str
    nodes: tuple[Node, ...]

    def tree(self) -> Expr:
        """The syntax tree, built from the nodes (iteratively, for any depth)."""
        stack: list[Expr] = []
        for kind, value, start, end, a, _ in self.nodes:
            if kind is NUMBER:
                stack.append(Number(value, start, end))  # type: ignore[arg-type]
            elif kind is NAME:
                stack.append(Name(value, start, end))  # type: ignore[arg-type]
            elif kind is UNARY:
                stack[-1] = Unary(value, stack[-1], start, end)  # type: ignore[arg-type]
            elif kind is BINARY:
                right = stack.pop()
                stack[-1] = Binary(value, stack[-1], right, start, end)  # type: ignore[arg-type]
            else:
                args = tuple(stack[len(stack) - a :])
                del stack[len(stack) - a :]
                stack.append(Call(value, args, start, end))  # type: ignore[arg-type]
        (root,) = stack
        return root


NUMBER, NAME, UNARY, BINARY, CALL = NodeKind

# expression.lark's terminals (NUMBER_PATTERN, NAME_PATTERN: gaitgram.motion.names), spelt as the
# grammar spells them (a test compares them).
PUNCTUATION = "+-*/(),"

_SPACE = f"[{re.escape(WHITESPACE)}]"
# One match a token, the whitespace before it included. Groups: 1 NUMBER; 2 NAME, with 3 the
# "(" that makes it a call; 4 punctuation; 5 a character no terminal matches (lark's error).
# The text is scanned up to its trailing whitespace, where a match would fail at every
# position in turn, in quadratic time; anywhere else some token follows.
_TOKEN = re.compile(
    f"{_SPACE}*(?:"
    f"({NUMBER_PATTERN})"
    f"|({NAME_PATTERN})(?:{_SPACE}*(\\())?"
    f"|([{re.escape(PUNCTUATION)}])"
    f"|(?!{_SPACE})([\\s\\S]))"
)

# Operator-stack entries are (precedence, operator or name, start): "(" and calls are barriers
# (precedence 0) that reductions stop at; a call's entry is a list whose fourth item counts
# its arguments. A binary operator's start is its left operand's, the start of its node.
#
# No stack of operand spans is needed: an operand is complete when the next token comes, and
# the last node emitted is then its root, which holds its span.
_BARRIER = 0
_OPERAND = "a number, t, PI, a function call or '('"


def parse(text: str) -> Syntax | MotionError:
    """The postfix nodes of ``text``, or the PARSE_ERROR at its first token that cannot be."""
    nodes: list[Node] = []
    ops: list = []
    depth = 0  # open parentheses and calls
    expect_operand = True
    call_opened = False  # the last token was a call's "(": ")" may come next
    precedence = BINARY_PRECEDENCE
    append = nodes.append
    for match in _TOKEN.finditer(text, 0, len(text.rstrip(WHITESPACE))):
        group = match.lastindex
        if expect_operand:
            if group == 1:
                start, end = match.span(1)
                append((NUMBER, float(match.group(1)), start, end, 0, 0))
                expect_operand = call_opened = False
                continue
            if group == 2:
                start, end = match.span(2)
                append((NAME, match.group(2), start, end, 0, 0))
                expect_operand = call_opened = False
                continue
            if group == 3:
                ops.append([_BARRIER, match.group(2), match.start(2), 1])
                depth += 1
                call_opened = True
                continue
            if group == 5:
                return _bad_character(text, match.start(5))
            char = match.group(4)
            start = match.start(4)
            if char == "-" or char == "+":
                ops.append((UNARY_PRECEDENCE, char, start))
            elif char == "(":
                ops.append((_BARRIER, char, start))
                depth += 1
            elif char == ")" and call_opened:
                _, name, call_start, _ = ops.pop()
                depth -= 1
                append((CALL, name, call_start, start + 1, 0, 0))
                expect_operand = False
            else:
                return _unexpected(text, "", char, start, _OPERAND)
            call_opened = False
            continue
        if group != 4:
            if group == 5:
                return _bad_character(text, match.start(5))
            if group == 1:
                return _unexpected(text, "number ", match.group(1), match.start(1), _after_operand(depth))
            return _unexpected(text, "name ", match.group(2), match.start(2), _after_operand(depth))
        char = match.group(4)
        level = precedence.get(char)
        if level is not None:
            while ops and ops[-1][0] >= level:
                _reduce(ops.pop(), nodes)
            ops.append((level, char, nodes[-1][2]))
            expect_operand = True
            continue
        start = match.start(4)
        if char == "(":
            return _unexpected(text, "", char, start, _after_operand(depth))
        # ")" or ","
        if depth == 0:
            return _unexpected(text, "", char, start, _after_operand(depth))
        while ops[-1][0] != _BARRIER:
            _reduce(ops.pop(), nodes)
        opener = ops[-1]
        if char == ",":
            if opener[1] == "(":
                return _unexpected(text, "", char, start, _after_operand(depth))
            opener[3] += 1
            expect_operand = True
            continue
        ops.pop()
        depth -= 1
        if opener[1] == "(":  # a group: its content's root, the last node, takes the parentheses
            kind, value, _, _, a, b = nodes[-1]
            nodes[-1] = (kind, value, opener[2], start + 1, a, b)
        else:
            append((CALL, opener[1], opener[2], start + 1, opener[3], 0))
    if expect_operand:
        return _early_end(text, _OPERAND)
    if depth:
        return _early_end(text, _after_operand(depth))
    while ops:
        _reduce(ops.pop(), nodes)
    return Syntax(text, tuple(nodes))


def _reduce(entry: tuple[int, str, int], nodes: list[Node]) -> None:
    """Emit the node of an operator whose operands are complete (the right one's root is last)."""
    level, op, start = entry
    _, _, operand_start, end, _, _ = nodes[-1]
    if level == UNARY_PRECEDENCE:
        nodes.append((UNARY, op, start, end, 0, 0))
    else:
        nodes.append((BINARY, op, start, end, operand_start, end))


def parse_expression(text: str) -> Expr | MotionError:
    """The syntax tree of ``text``, or a PARSE_ERROR. Names are not checked here."""
    syntax = parse(text)
    return syntax if isinstance(syntax, MotionError) else syntax.tree()


# ---------------------------------------------------------------------------------------------
# Syntax errors, in the words of lark's exceptions for expression.lark: the first token that
# cannot continue the text, and what could have.


def _after_operand(depth: int) -> str:
    return "an operator (+ - * /) or " + ("')'" if depth else "the end")


def _bad_character(text: str, offset: int) -> MotionError:
    char = text[offset]
    hint = None
    if char in "'\"":
        hint = "a motion expression has no strings"
    elif char == "^":
        hint = "powers are not supported: multiply instead"
    elif char.isdigit():
        hint = "write numbers with ASCII digits"
    return MotionError(
        MotionStatus.PARSE_ERROR, f"unexpected character {char!r} at offset {offset}", offset, 1, hint
    )


def _unexpected(text: str, kind: str, token: str, offset: int, expected: str) -> MotionError:
    hint = None
    if token == "*" and text[:offset].rstrip().endswith("*"):
        hint = "powers (**) are not supported: multiply instead"
    elif kind or token == "(":
        hint = "write '*' for a product"
    message = f"unexpected {kind}{token!r} at offset {offset}; expected {expected}"
    return MotionError(MotionStatus.PARSE_ERROR, message, offset, len(token), hint)


def _early_end(text: str, expected: str) -> MotionError:
    message = (
        "empty motion expression" if not text.strip() else f"unexpected end of text; expected {expected}"
    )
    return MotionError(MotionStatus.PARSE_ERROR, message, len(text), 0)
