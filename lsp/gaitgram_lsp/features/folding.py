"""Folding regions (``gaitgram.ide.layout``) as LSP FoldingRanges."""

from __future__ import annotations

from lsprotocol import types

from gaitgram.ide.layout import FoldKind, folds
from gaitgram_lsp.documents import Snapshot

_KINDS = {FoldKind.RULE: types.FoldingRangeKind.Region, FoldKind.COMMENT: types.FoldingRangeKind.Comment}


def folding_ranges(snapshot: Snapshot) -> list[types.FoldingRange]:
    return [
        types.FoldingRange(start_line=f.first_line, end_line=f.last_line, kind=_KINDS[f.kind])
        for f in folds(snapshot.result.grammar)
    ]
