"""Hover (``gaitgram.ide.hover``) as an LSP Hover."""

from __future__ import annotations

from lsprotocol import types

from gaitgram.ide import hover as ide
from gaitgram_lsp.documents import Snapshot


def hover(snapshot: Snapshot, offset: int, markdown: bool = True) -> types.Hover | None:
    found = ide.hover(snapshot.result, offset)
    if found is None:
        return None
    kind = types.MarkupKind.Markdown if markdown else types.MarkupKind.PlainText
    return types.Hover(
        contents=types.MarkupContent(kind=kind, value=found.markdown),
        range=snapshot.positions.range(found.span) if found.span is not None else None,
    )
