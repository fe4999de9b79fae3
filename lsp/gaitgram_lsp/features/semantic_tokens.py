"""Semantic tokens: rule names, terminals, ranges, annotations and comments, as the parser
reads them (so ``'#'`` is a terminal and ``float[i]`` plain text, unlike in a regex
highlighter). Rule heads carry the ``declaration`` modifier.

Each right-hand side is split into pieces by the parser's own scanner; the model gives
rule heads and annotation arguments.
"""

from __future__ import annotations

from lsprotocol import types

from gaitgram.language.model import Interval, Name, RuleRef
from gaitgram.language.syntax import pieces as split_pieces
from gaitgram_lsp.documents import Snapshot
from gaitgram_lsp.positions import units

TOKEN_TYPES = ("function", "string", "number", "decorator", "comment", "operator", "parameter", "enumMember")
TOKEN_MODIFIERS = ("declaration",)
LEGEND = types.SemanticTokensLegend(token_types=list(TOKEN_TYPES), token_modifiers=list(TOKEN_MODIFIERS))

_RULE, _STRING, _NUMBER, _DECORATOR, _COMMENT, _OPERATOR, _PARAMETER, _ENUM = range(len(TOKEN_TYPES))
_DECLARATION = 1

_PIECE_TYPES = {
    "NONTERMINAL": _RULE,
    "STRING": _STRING,
    "BAD_STRING": _STRING,
    "TEXT": _STRING,
    "LT": _STRING,
    "RANGE": _NUMBER,
    "GE_RANGE": _NUMBER,
    "COMMENT": _COMMENT,
    "PIPE": _OPERATOR,
}

#: (start offset, length in code points, type, modifiers)
Token = tuple[int, int, int, int]


def tokens(snapshot: Snapshot) -> list[Token]:
    """Every token of the document, in order (cached on the snapshot)."""
    cached = getattr(snapshot, "_semantic_tokens", None)
    if cached is None:
        cached = _tokens(snapshot)
        snapshot._semantic_tokens = cached  # type: ignore[attr-defined]
    return cached


def _tokens(snapshot: Snapshot) -> list[Token]:
    grammar = snapshot.result.grammar
    text = grammar.source.text
    pieces = split_pieces
    items = sorted(
        [(r.span.start, 0, r) for r in grammar.rules] + [(a.span.start, 1, a) for a in grammar.annotations],
        key=lambda item: item[0],
    )
    found: list[Token] = []

    def scan(start: int, end: int, comments_only: bool) -> None:
        for kind, a, b in pieces(text, start, end):
            token_type = _PIECE_TYPES.get(kind)
            if token_type is None or (comments_only and token_type != _COMMENT):
                continue
            if kind == "TEXT":  # terminal text: without the spaces around it
                stripped = text[a:b].strip()
                if not stripped:
                    continue
                a += len(text[a:b]) - len(text[a:b].lstrip())
                b = a + len(stripped)
            found.append((a, b - a, token_type, 0))

    position = 0
    for index, (start, is_annotation, item) in enumerate(items):
        following = items[index + 1][0] if index + 1 < len(items) else len(text)
        if not is_annotation:
            head = _line_start(text, start)
            scan(position, head, comments_only=True)
            found.append(
                (item.name_span.start, item.name_span.end - item.name_span.start, _RULE, _DECLARATION)
            )
            define = text.find("::=", item.name_span.end)
            if define != -1:
                found.append((define, 3, _OPERATOR, 0))
                scan(define + 3, following, comments_only=False)
            position = max(following, define + 3)
        else:
            scan(position, _line_start(text, start), comments_only=True)
            found.append((item.name_span.start, item.name_span.end - item.name_span.start, _DECORATOR, 0))
            for argument in item.arguments:
                found += _argument_tokens(argument)
            scan(item.span.end, following, comments_only=True)
            position = following
    scan(position, len(text), comments_only=True)
    found.sort()
    return found


def _line_start(text: str, offset: int) -> int:
    return text.rfind("\n", 0, offset) + 1


def _argument_tokens(argument) -> list[Token]:
    start, end = argument.span.start, argument.span.end
    found = []
    if argument.key is not None:
        found.append((start, len(argument.key), _PARAMETER, 0))
        start += argument.raw.index("=") + 1
    value = argument.value
    if start >= end or value is None:
        return found
    if isinstance(value, RuleRef):
        token_type = _RULE
    elif isinstance(value, Name):
        token_type = _ENUM
    elif isinstance(value, int | float | Interval):
        token_type = _NUMBER
    else:
        token_type = _STRING
    found.append((start, end - start, token_type, 0))
    return found


def encode(snapshot: Snapshot, found: list[Token]) -> types.SemanticTokens:
    """LSP's relative encoding, in the position encoding's units, one line per token."""
    positions = snapshot.positions
    text = snapshot.text
    data: list[int] = []
    previous_line = previous_character = 0
    starts = positions.line_column(t[0] for t in found)
    for (offset, length, token_type, modifiers), (line, character) in zip(found, starts, strict=True):
        end_of_line = text.find("\n", offset, offset + length)
        if end_of_line != -1:  # no token spans lines today; keep to the first line if one does
            length = end_of_line - offset
        if not positions.simple:
            length = units(text[offset : offset + length], positions.encoding)
        if length <= 0:
            continue
        delta_line = line - previous_line
        delta_start = character - previous_character if delta_line == 0 else character
        data += (delta_line, delta_start, length, token_type, modifiers)
        previous_line, previous_character = line, character
    return types.SemanticTokens(data=data)


def full(snapshot: Snapshot) -> types.SemanticTokens:
    return encode(snapshot, tokens(snapshot))


def in_range(snapshot: Snapshot, start: int, end: int) -> types.SemanticTokens:
    return encode(snapshot, [t for t in tokens(snapshot) if t[0] + t[1] >= start and t[0] <= end])
