"""Semantic tokens (``gaitgram.ide.tokens``) in LSP's relative encoding."""

from __future__ import annotations

from lsprotocol import types

from gaitgram.ide.tokens import Token, TokenType, overlapping, sensor_spans, tokens
from gaitgram_lsp.documents import Snapshot
from gaitgram_lsp.positions import units

#: LSP's names for the token types, in ``TokenType`` order: a sensor is a ``variable`` that is
#: ``readonly`` (a curve reads it, nothing writes it).
TOKEN_TYPES = (
    "function",
    "string",
    "number",
    "decorator",
    "comment",
    "operator",
    "parameter",
    "enumMember",
    "variable",
)
TOKEN_MODIFIERS = ("declaration", "readonly")
LEGEND = types.SemanticTokensLegend(token_types=list(TOKEN_TYPES), token_modifiers=list(TOKEN_MODIFIERS))
assert len(TOKEN_TYPES) == len(TokenType)
#: The modifiers each type always has, as LSP's bit set over ``TOKEN_MODIFIERS``.
_TYPE_MODIFIERS = {TokenType.SENSOR: 1 << TOKEN_MODIFIERS.index("readonly")}


def _tokens(snapshot: Snapshot) -> list[Token]:
    """Cached on the snapshot: full and range requests ask again and again while scrolling."""
    cached = getattr(snapshot, "_semantic_tokens", None)
    if cached is None:
        cached = tokens(snapshot.result.grammar, sensor_spans(snapshot.result))
        snapshot._semantic_tokens = cached  # type: ignore[attr-defined]
    return cached


def encode(snapshot: Snapshot, found: list[Token]) -> types.SemanticTokens:
    """LSP's relative encoding, in the position encoding's units, one line per token."""
    positions = snapshot.positions
    text = snapshot.text
    data: list[int] = []
    previous_line = previous_character = 0
    starts = positions.line_column(t.start for t in found)
    for token, (line, character) in zip(found, starts, strict=True):
        offset, length = token.start, token.length
        end_of_line = text.find("\n", offset, offset + length)
        if end_of_line != -1:  # no token spans lines today; keep to the first line if one does
            length = end_of_line - offset
        if not positions.simple:
            length = units(text[offset : offset + length], positions.encoding)
        if length <= 0:
            continue
        delta_line = line - previous_line
        delta_start = character - previous_character if delta_line == 0 else character
        modifiers = int(token.declaration) | _TYPE_MODIFIERS.get(token.type, 0)
        data += (delta_line, delta_start, length, int(token.type), modifiers)
        previous_line, previous_character = line, character
    return types.SemanticTokens(data=data)


def full(snapshot: Snapshot) -> types.SemanticTokens:
    return encode(snapshot, _tokens(snapshot))


def in_range(snapshot: Snapshot, start: int, end: int) -> types.SemanticTokens:
    return encode(snapshot, overlapping(_tokens(snapshot), start, end))
