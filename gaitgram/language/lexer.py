"""The scanner: .gg text to tokens for the lark parser, and runs of text to pieces.

It is compiled from the terminals of ``gaitgram.lark`` and works in two modes,
like lark's contextual lexer but cheaper: *body* (rule right-hand sides, and
whatever lies between items) and *arguments* (an annotation line).

In body mode only rule heads and annotation lines are structural. Everything
between two of them (a rule's right-hand side, or the blank lines, comments and
stray text between items) reaches the parser as one ``PIECES`` token, found by
a single regular-expression match; the model builder later splits it into
pieces with :func:`scan_pieces`. Both use the same terminals in the same order,
so a run ends exactly where a piece-by-piece scan would meet a structural token.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Sequence

from lark.common import LexerConf
from lark.lexer import Lexer, LexerState, TerminalDef, Token

STRUCTURAL_TERMINALS = ("RULE_HEAD", "ANNOTATION")
PIECE_TERMINALS = (
    "PIPE",
    "RANGE",
    "GE_RANGE",
    "NONTERMINAL",
    "STRING",
    "BAD_STRING",
    "LT",
    "COMMENT",
    "WS",
    "NEWLINE",
    "TEXT",
)
ARGUMENT_TERMINALS = (
    "RULE_HEAD",
    "ANNOTATION",
    "NONTERMINAL",
    "STRING",
    "BAD_STRING",
    "ARG_NAME",
    "ARG_NUMBER",
    "EQUALS",
    "DOTS",
    "COMMENT",
    "WS",
    "NEWLINE",
    "ARG_JUNK",
)

#: (terminal name, start offset, end offset)
Piece = tuple[str, int, int]


def _ordered(terminals: Sequence[TerminalDef]) -> list[TerminalDef]:
    # The order lark itself uses, so that priorities mean what they say.
    return sorted(
        terminals,
        key=lambda t: (-t.priority, -t.pattern.max_width, -len(t.pattern.value), t.name),
    )


def _alternation(terminals: Sequence[TerminalDef], named: bool = True) -> str:
    parts = (
        f"(?P<{t.name}>{t.pattern.to_regexp()})" if named else f"(?:{t.pattern.to_regexp()})"
        for t in _ordered(terminals)
    )
    return "|".join(parts)


class Scanner:
    """The compiled regular expressions of one set of terminals."""

    def __init__(self, terminals: Sequence[TerminalDef]) -> None:
        by_name = {t.name: t for t in terminals}

        def pick(names: Sequence[str]) -> list[TerminalDef]:
            return [by_name[n] for n in names]

        structural = _alternation(pick(STRUCTURAL_TERMINALS), named=False)
        pieces = pick(PIECE_TERMINALS)
        self._pieces = re.compile(_alternation(pieces))
        self.run = re.compile(f"(?:(?!{structural})(?:{_alternation(pieces, named=False)}))*+")
        self.structural = re.compile(_alternation(pick(STRUCTURAL_TERMINALS)))
        self.arguments = re.compile(_alternation(pick(ARGUMENT_TERMINALS)))

    def pieces(self, text: str, start: int, end: int) -> list[Piece]:
        """Split a ``PIECES`` run into its pieces."""
        return [(m.lastgroup, m.start(), m.end()) for m in self._pieces.finditer(text, start, end)]  # type: ignore[misc]


class KeepScannerTerminals:
    """A pass-through lark post-lexer whose only job is ``always_accept``.

    Lark drops terminals that no parser rule names; the piece terminals are
    named only inside ``PIECES`` runs, so this keeps them for the scanner.
    """

    always_accept = tuple(sorted(set(PIECE_TERMINALS) | set(ARGUMENT_TERMINALS)))

    def process(self, stream: Iterator[Token]) -> Iterator[Token]:
        return stream


class GgLexer(Lexer):
    """Lark custom lexer for ``.gg`` documents: the whole text, or a window of it (lark's
    ``TextSlice``) read in place, its tokens at their offsets in the whole text."""

    __future_interface__ = 2  # lark hands over its lexer state, whose text may be a window

    def __init__(self, conf: LexerConf) -> None:
        self._scanner = Scanner(conf.terminals)

    def lex(self, lexer_state: LexerState, parser_state: object = None) -> Iterator[Token]:  # type: ignore[override]
        window = lexer_state.text
        return self.tokens(window.text, window.start, window.end)

    def tokens(self, text: str, pos: int, size: int) -> Iterator[Token]:
        """The tokens of ``text[pos:size]``; ``pos`` is a line start (or 0)."""
        run, structural, arguments = self._scanner.run, self._scanner.structural, self._scanner.arguments
        while pos < size:
            end = run.match(text, pos, size).end()  # type: ignore[union-attr]  # matches the empty run too
            if end > pos:
                yield Token("PIECES", text[pos:end], pos, end_pos=end)
                pos = end
                continue
            match = structural.match(text, pos, size)
            assert match is not None, f"no terminal matches at offset {pos}"
            yield _token(match)
            pos = match.end()
            if match.lastgroup == "ANNOTATION":
                # An annotation's arguments run to the end of its line.
                while pos < size:
                    match = arguments.match(text, pos, size)
                    # ARG_JUNK, WS and NEWLINE between them match any character.
                    assert match is not None, f"no terminal matches at offset {pos}"
                    yield _token(match)
                    pos = match.end()
                    if match.lastgroup in ("NEWLINE", "RULE_HEAD"):
                        break


def _token(match: re.Match[str]) -> Token:
    return Token(match.lastgroup or "", match.group(), match.start(), end_pos=match.end())
