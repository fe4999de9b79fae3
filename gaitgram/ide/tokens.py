"""Semantic tokens: rule names, terminals, ranges, annotations and comments, as the parser
reads them (so ``'#'`` is a terminal and ``float[i]`` plain text, unlike in a regex
highlighter). Rule heads are declarations; the sensors a curve's text reads
(:func:`sensor_spans`) are cut out of their terminals as tokens of their own.

Each right-hand side is split into pieces by the parser's own scanner
(``gaitgram.language.syntax.pieces``); the model gives rule heads and annotation arguments.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import IntEnum

from gaitgram.analysis import CheckResult
from gaitgram.analysis.motion_text import sensor_uses
from gaitgram.language.model import Argument, Grammar, Interval, Name, RuleRef
from gaitgram.language.source import Span
from gaitgram.language.syntax import pieces as split_pieces

__all__ = ["Token", "TokenType", "overlapping", "sensor_spans", "tokens"]


class TokenType(IntEnum):
    RULE = 0
    STRING = 1
    NUMBER = 2
    ANNOTATION = 3
    COMMENT = 4
    OPERATOR = 5
    PARAMETER = 6
    NAME = 7  # a name given to an annotation: a backend, a joint, a unit
    SENSOR = 8  # a sensor a curve reads (inside terminal text)


@dataclass(frozen=True, slots=True, order=True)
class Token:
    start: int
    length: int  # code points
    type: TokenType
    declaration: bool = False


_PIECE_TYPES = {
    "NONTERMINAL": TokenType.RULE,
    "STRING": TokenType.STRING,
    "BAD_STRING": TokenType.STRING,
    "TEXT": TokenType.STRING,
    "LT": TokenType.STRING,
    "RANGE": TokenType.NUMBER,
    "GE_RANGE": TokenType.NUMBER,
    "COMMENT": TokenType.COMMENT,
    "PIPE": TokenType.OPERATOR,
}


def sensor_spans(result: CheckResult) -> list[Span]:
    """Where the grammar's curves read a backend's sensors, in order: what :func:`tokens` marks."""
    return [use.span for use, _, _ in sensor_uses(result.grammar, result.facts)]


def tokens(grammar: Grammar, sensors: Sequence[Span] = ()) -> list[Token]:
    """Every token of the document, in order; ``sensors`` (:func:`sensor_spans`) are cut out of
    the terminal text that holds them."""
    text = grammar.source.text
    items = sorted(
        [(r.span.start, 0, r) for r in grammar.rules] + [(a.span.start, 1, a) for a in grammar.annotations],
        key=lambda item: item[0],
    )
    found: list[Token] = []

    def scan(start: int, end: int, comments_only: bool) -> None:
        for kind, a, b in split_pieces(text, start, end):
            token_type = _PIECE_TYPES.get(kind)
            if token_type is None or (comments_only and token_type is not TokenType.COMMENT):
                continue
            if kind == "TEXT":  # terminal text: without the spaces around it
                stripped = text[a:b].strip()
                if not stripped:
                    continue
                a += len(text[a:b]) - len(text[a:b].lstrip())
                b = a + len(stripped)
            found.append(Token(a, b - a, token_type))

    position = 0
    for index, (start, is_annotation, item) in enumerate(items):
        following = items[index + 1][0] if index + 1 < len(items) else len(text)
        name = item.name_span
        if not is_annotation:
            scan(position, grammar.source.line_start_of(start), comments_only=True)
            found.append(Token(name.start, name.end - name.start, TokenType.RULE, declaration=True))
            define = text.find("::=", name.end)
            if define != -1:
                found.append(Token(define, 3, TokenType.OPERATOR))
                scan(define + 3, following, comments_only=False)
            position = max(following, define + 3)
        else:
            scan(position, grammar.source.line_start_of(start), comments_only=True)
            found.append(Token(name.start, name.end - name.start, TokenType.ANNOTATION))
            for argument in item.arguments:
                found += _argument_tokens(argument)
            scan(item.span.end, following, comments_only=True)
            position = following
    scan(position, len(text), comments_only=True)
    found.sort()
    return _carve(found, sensors) if sensors else found


def _carve(found: list[Token], sensors: Sequence[Span]) -> list[Token]:
    """``found`` with each sensor's span cut out of the terminal token that holds it whole (tokens
    must not overlap: an editor draws one type per character)."""
    carved: list[Token] = []
    wanted = iter(sorted(sensors, key=lambda span: span.start))
    span = next(wanted, None)
    for token in found:
        end = token.start + token.length
        while span is not None and span.start < token.start:
            span = next(wanted, None)
        if token.type is not TokenType.STRING:
            carved.append(token)
            continue
        start = token.start
        while span is not None and span.end <= end:
            if span.start > start:
                carved.append(Token(start, span.start - start, TokenType.STRING))
            carved.append(Token(span.start, span.end - span.start, TokenType.SENSOR))
            start = span.end
            span = next(wanted, None)
        if end > start:
            carved.append(Token(start, end - start, TokenType.STRING))
    return carved


def _argument_tokens(argument: Argument) -> list[Token]:
    start, end = argument.span.start, argument.span.end
    found = []
    if argument.key is not None:
        found.append(Token(start, len(argument.key), TokenType.PARAMETER))
        start += argument.raw.index("=") + 1
    value = argument.value
    if start >= end or value is None:
        return found
    if isinstance(value, RuleRef):
        token_type = TokenType.RULE
    elif isinstance(value, Name):
        token_type = TokenType.NAME
    elif isinstance(value, int | float | Interval):
        token_type = TokenType.NUMBER
    else:
        token_type = TokenType.STRING
    found.append(Token(start, end - start, token_type))
    return found


def overlapping(found: list[Token], start: int, end: int) -> list[Token]:
    """The tokens that touch offsets ``start`` to ``end`` (what a visible range needs)."""
    return [t for t in found if t.start + t.length >= start and t.start <= end]
