"""Formatting: ``gaitgram fmt``, as one edit covering the lines that change."""

from __future__ import annotations

import logging

from lsprotocol import types

from gaitgram.language.edits import smallest_edit
from gaitgram.language.formatter import FormatError, FormatRefused, format_text
from gaitgram_lsp.documents import Snapshot

log = logging.getLogger(__name__)


def formatting(snapshot: Snapshot) -> list[types.TextEdit]:
    """No edits for a document with syntax errors: its layout may carry meaning."""
    try:
        edit = smallest_edit(snapshot.text, format_text(snapshot.text))
    except FormatRefused:
        return []
    except FormatError:  # the formatter's own safety check caught a bug: never apply it
        log.exception("formatting %s would change its meaning", snapshot.uri)
        return []
    if edit is None:
        return []
    return [types.TextEdit(range=snapshot.positions.range(edit.span), new_text=edit.text)]
