"""The document as the scanner reads it: every token, comments and whitespace included.

The model (:mod:`gaitgram.language.model`) keeps what a grammar *means*; editors also
need what the text *is*: where each comment, string, range and reference lies, and
which text is a rule name. This module gives that from the parser's own scanner
(compiled from ``gaitgram.lark``), so it can never disagree with the parser.

:func:`tokenize` is lossless: the tokens cover the text without gap or overlap, so
joining their texts gives the document back exactly, whatever it holds.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache

from gaitgram.language.parser import scanner
from gaitgram.language.source import Span

__all__ = ["Piece", "SyntaxToken", "is_rule_name", "item_lines", "pieces", "tokenize"]

#: (terminal name, start offset, end offset): one piece of a rule's right-hand side.
Piece = tuple[str, int, int]


@dataclass(frozen=True, slots=True)
class SyntaxToken:
    """One token: its terminal name in ``gaitgram.lark`` (``RULE_HEAD``, ``COMMENT``, ``WS``,
    ``NONTERMINAL``, ``RANGE``, ...) and where it lies."""

    kind: str
    span: Span

    def text(self, document: str) -> str:
        return document[self.span.start : self.span.end]


def tokenize(text: str) -> tuple[SyntaxToken, ...]:
    """Every token of ``text`` in order; ``"".join(t.text(text) for t in tokenize(text)) == text``."""
    found: list[SyntaxToken] = []
    compiled = scanner()
    run, structural, arguments = compiled.run, compiled.structural, compiled.arguments
    position, size = 0, len(text)
    while position < size:
        end = run.match(text, position).end()  # type: ignore[union-attr]  # the empty run matches
        if end > position:
            found += (SyntaxToken(kind, Span(a, b)) for kind, a, b in compiled.pieces(text, position, end))
            position = end
            continue
        match = structural.match(text, position)
        assert match is not None, f"no terminal matches at offset {position}"  # the grammar is total
        found.append(SyntaxToken(match.lastgroup or "", Span(match.start(), match.end())))
        position = match.end()
        if match.lastgroup == "ANNOTATION":  # its arguments run to the end of its line
            while position < size:
                match = arguments.match(text, position)
                assert match is not None, f"no terminal matches at offset {position}"
                found.append(SyntaxToken(match.lastgroup or "", Span(match.start(), match.end())))
                position = match.end()
                if match.lastgroup in ("NEWLINE", "RULE_HEAD"):
                    break
    return tuple(found)


def pieces(text: str, start: int, end: int) -> list[Piece]:
    """The pieces of ``text[start:end]``, a rule's right-hand side (or text between items), as
    the builder splits it: references, ranges, strings, comments, spaces, ``|`` and plain text."""
    return scanner().pieces(text, start, end)


@cache
def item_lines() -> re.Pattern[str]:
    """Rule heads and annotations at line starts: where items begin."""
    return re.compile(f"(?m:^)(?:{scanner().structural.pattern})")


def is_rule_name(name: str) -> bool:
    """Whether ``<name>`` reads as one reference and ``<name> ::=`` as a rule head (a new name
    for a rename must)."""
    if not name:
        return False
    reference = f"<{name}>"
    head = scanner().structural.fullmatch(f"{reference} ::=")
    return (
        head is not None
        and head.lastgroup == "RULE_HEAD"
        and scanner().pieces(reference, 0, len(reference)) == [("NONTERMINAL", 0, len(reference))]
    )
