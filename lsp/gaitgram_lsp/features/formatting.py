"""Formatting: ``gaitgram fmt``, as one edit covering the lines that change."""

from __future__ import annotations

import logging

from lsprotocol import types

from gaitgram.language.formatter import FormatError, FormatRefused, format_text
from gaitgram.language.source import Span
from gaitgram_lsp.documents import Snapshot

log = logging.getLogger(__name__)


def formatting(snapshot: Snapshot) -> list[types.TextEdit]:
    """No edits for a document with syntax errors: its layout may carry meaning."""
    text = snapshot.text
    try:
        formatted = format_text(text)
    except FormatRefused:
        return []
    except FormatError:  # the formatter's own safety check caught a bug: never apply it
        log.exception("formatting %s would change its meaning", snapshot.uri)
        return []
    if formatted == text:
        return []
    old, new = text.splitlines(keepends=True), formatted.splitlines(keepends=True)
    head = 0
    while head < min(len(old), len(new)) and old[head] == new[head]:
        head += 1
    tail = 0
    while tail < min(len(old), len(new)) - head and old[-1 - tail] == new[-1 - tail]:
        tail += 1
    start = sum(len(line) for line in old[:head])
    end = len(text) - sum(len(line) for line in old[len(old) - tail :])
    replacement = "".join(new[head : len(new) - tail])
    return [types.TextEdit(range=snapshot.positions.range(Span(start, end)), new_text=replacement)]
