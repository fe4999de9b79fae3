"""Inlay hints (``gaitgram.ide.layout``) as LSP InlayHints."""

from __future__ import annotations

from lsprotocol import types

from gaitgram.ide.layout import inlay_hints as ide_hints
from gaitgram_lsp.documents import Snapshot


def inlay_hints(snapshot: Snapshot, start: int, end: int) -> list[types.InlayHint]:
    return [
        types.InlayHint(
            position=snapshot.positions.position(hint.offset),
            label=hint.label,
            padding_left=True,
            tooltip=hint.tooltip,
        )
        for hint in ide_hints(snapshot.result, start, end)
    ]
