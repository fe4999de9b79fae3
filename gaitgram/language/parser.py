"""The lark parsers generated from ``gaitgram.lark``, and its terminals for whoever else needs the
language's syntax (the range look-alike finder, the rewrites), so it is written only there."""

from __future__ import annotations

import re
from functools import cache

from lark import Lark, Token, Tree
from lark.utils import TextSlice

from gaitgram.language.lexer import GgLexer, KeepScannerTerminals, Scanner
from gaitgram.language.parser_cache import cached_lark
from gaitgram.packaged import packaged


@cache
def grammar_text() -> str:
    return packaged(__package__, "gaitgram.lark").read_text(encoding="utf-8")


@cache
def document_parser() -> Lark:
    return cached_lark(
        "document",
        grammar_text(),
        start="start",
        parser="lalr",
        lexer=GgLexer,
        postlex=KeepScannerTerminals(),
        maybe_placeholders=False,
    )


@cache
def scanner() -> Scanner:
    """The scanner the document parser uses, for splitting ``PIECES`` runs."""
    return Scanner(document_parser().terminals)


@cache
def range_parser() -> Lark:
    return cached_lark("range", grammar_text(), start="range_spec", parser="lalr", lexer="contextual")


@cache
def terminal(name: str) -> re.Pattern[str]:
    """Terminal ``name`` of ``gaitgram.lark`` (``RANGE``, ``RANGE_NUMBER``, ...), compiled as the
    parsers match it."""
    for parser in (document_parser, range_parser):
        found = {t.name: t for t in parser().terminals}.get(name)
        if found is not None:
            return re.compile(found.pattern.to_regexp())
    raise KeyError(f"gaitgram.lark has no terminal {name}")


def parse_tree(text: str, start: int = 0, end: int | None = None) -> Tree:
    """Parse a whole document, or the part of it from ``start`` (a line start) to ``end``, read in
    place: its tokens have their offsets in ``text``. The grammar is total, so this does not fail
    on bad input."""
    if start == 0 and end is None:
        return document_parser().parse(text)
    return document_parser().parse(TextSlice(text, start, len(text) if end is None else end))


def tree_start(tree: Tree) -> int:
    """Offset of a subtree's first token."""
    while not isinstance(tree, Token):
        tree = tree.children[0]
    return tree.start_pos


def tree_end(tree: Tree) -> int:
    while not isinstance(tree, Token):
        tree = tree.children[-1]
    return tree.end_pos
