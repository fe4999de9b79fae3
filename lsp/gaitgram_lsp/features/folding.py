"""Folding ranges: rules that span lines, and runs of comment lines."""

from __future__ import annotations

import re

from lsprotocol import types

from gaitgram_lsp.documents import Snapshot

_COMMENT_LINE = re.compile(r"^[^\S\n]*#", re.MULTILINE)


def folding_ranges(snapshot: Snapshot) -> list[types.FoldingRange]:
    source = snapshot.source
    found = []
    for rule in snapshot.result.grammar.rules:
        first, last = source.location(rule.span.start).line - 1, source.location(rule.span.end).line - 1
        if last > first:
            found.append(
                types.FoldingRange(start_line=first, end_line=last, kind=types.FoldingRangeKind.Region)
            )
    run_start = previous = -2
    for match in _COMMENT_LINE.finditer(source.text):
        line = source.location(match.start()).line - 1
        if line != previous + 1:
            if previous > run_start >= 0:
                found.append(_comments(run_start, previous))
            run_start = line
        previous = line
    if previous > run_start >= 0:
        found.append(_comments(run_start, previous))
    return sorted(found, key=lambda f: f.start_line)


def _comments(first: int, last: int) -> types.FoldingRange:
    return types.FoldingRange(start_line=first, end_line=last, kind=types.FoldingRangeKind.Comment)
