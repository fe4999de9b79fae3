"""Text edits: applying a set of them at once, and the spans that fixes delete.

Fixes are made by the builder and the linter (as :class:`~gaitgram.language.diagnostics.Fix`
data) and applied by ``gaitgram check --fix``, the language server and tests alike, so
what "applying" means is defined once, here: every edit's span is an offset range of
the text the edits were made for, edits never overlap, and they are applied together.
"""

from __future__ import annotations

import difflib
import os
import re
from collections.abc import Iterable

from gaitgram.language.diagnostics import Applicability, Fix, TextEdit
from gaitgram.language.source import SourceText, Span

__all__ = [
    "EditConflict",
    "apply_edits",
    "blank_end",
    "conflicts",
    "deletion_fix",
    "line_end",
    "normalized",
    "removal",
    "smallest_edit",
    "unified_diff",
    "union",
]


class EditConflict(ValueError):
    """Two edits touch the same text, so applying both has no single meaning."""


def conflicts(a: TextEdit, b: TextEdit) -> bool:
    """Whether two different edits cannot both be applied.

    They conflict if their spans overlap, or if both insert at the same offset (the order
    of the insertions would be a guess). An insertion at the start or end of a replaced
    span does not conflict with it. Identical edits never conflict: they are one edit.
    """
    if a == b:
        return False
    if a.span.start == a.span.end == b.span.start == b.span.end:
        return True
    return a.span.start < b.span.end and b.span.start < a.span.end


def normalized(edits: Iterable[TextEdit]) -> list[TextEdit]:
    """The edits sorted, duplicates dropped; :class:`EditConflict` if two conflict."""
    unique = sorted(set(edits), key=lambda e: (e.span.start, e.span.end, e.text))
    reach: TextEdit | None = None  # the edit reaching furthest so far
    for edit in unique:
        if reach is not None and conflicts(reach, edit):
            raise EditConflict(f"edits at {reach.span} and {edit.span} overlap")
        if reach is None or edit.span.end >= reach.span.end:
            reach = edit
    return unique


def apply_edits(text: str, edits: Iterable[TextEdit]) -> str:
    """``text`` with every edit applied; spans refer to ``text`` as given (not as edited)."""
    parts: list[str] = []
    position = 0
    for edit in normalized(edits):
        start, end = edit.span.start, edit.span.end
        if not 0 <= start <= end <= len(text):
            raise EditConflict(f"edit at {edit.span} is outside the text ({len(text)} characters)")
        parts.append(text[position:start])
        parts.append(edit.text)
        position = end
    parts.append(text[position:])
    return "".join(parts)


def line_end(text: str | SourceText, offset: int) -> int:
    """The offset of the newline ending the line of ``offset`` (or the end of the text); from a
    :class:`SourceText`'s line index, without a scan of a long line."""
    if isinstance(text, SourceText):
        return text.line_end_of(offset)
    end = text.find("\n", offset)
    return len(text) if end == -1 else end


_BLANKS = re.compile(r"[^\S\n]*")


def blank_end(text: str, offset: int) -> int:
    """The offset past the blanks (whitespace but line breaks) at ``offset``."""
    return _BLANKS.match(text, offset).end()  # type: ignore[union-attr]  # the empty run matches


def removal(text: str | SourceText, start: int, end: int) -> Span:
    """The span to delete to remove ``text[start:end]`` cleanly: its whole lines if nothing else
    is on them (a comment after it goes too), else it and the spaces after it.

    Reads only the blanks around the item (and a comment after it), never its whole line: an
    item on a line of megabytes with thousands of others costs what a short line costs."""
    raw = text.text if isinstance(text, SourceText) else text
    before = start
    while before > 0 and raw[before - 1] != "\n" and raw[before - 1].isspace():
        before -= 1
    own_line = before == 0 or raw[before - 1] == "\n"
    after = blank_end(raw, end)
    if own_line and (after == len(raw) or raw[after] in "\n#"):
        stop = line_end(text, after)
        return Span(before, min(stop + 1, len(raw)))
    return Span(before if own_line else start, after)


def union(spans: Iterable[Span]) -> list[Span]:
    """Overlapping or touching spans merged: what deleting all of them deletes."""
    merged: list[Span] = []
    for span in sorted(spans):  # spans are tuples: by start, then end
        if merged and span.start <= merged[-1].end:
            merged[-1] = Span(merged[-1].start, max(merged[-1].end, span.end))
        else:
            merged.append(span)
    return merged


def deletion_fix(text: str | SourceText, span: Span, title: str) -> Fix:
    """Delete an item (an annotation, a rule) with its lines, if nothing else is on them."""
    return Fix(title, (TextEdit(removal(text, span.start, span.end), ""),), Applicability.UNSAFE, True)


def smallest_edit(old: str, new: str) -> TextEdit | None:
    """One edit turning ``old`` into ``new`` that covers only the lines that differ (an editor
    keeps the cursor and folds of the lines it does not touch); None if they are equal."""
    if old == new:
        return None
    before, after = old.splitlines(keepends=True), new.splitlines(keepends=True)
    head = 0
    while head < min(len(before), len(after)) and before[head] == after[head]:
        head += 1
    tail = 0
    while tail < min(len(before), len(after)) - head and before[-1 - tail] == after[-1 - tail]:
        tail += 1
    start = sum(len(line) for line in before[:head])
    end = len(old) - sum(len(line) for line in before[len(before) - tail :])
    return TextEdit(Span(start, end), "".join(after[head : len(after) - tail]))


_BYTE_LINE = re.compile(rb"[^\n]*\n|[^\n]+\Z")


def unified_diff(name: str, before: bytes, after: bytes) -> bytes:
    """The unified diff from ``before`` to ``after``, the bytes of file ``name``, as ``diff -u``
    writes it: lines end at ``\n`` alone (a ``\r`` and tabs stay in their line), and a last line
    without one is marked, so ``patch`` applied to the file makes ``after`` exactly."""
    label = os.fsencode(name)
    lines = difflib.diff_bytes(
        difflib.unified_diff, _BYTE_LINE.findall(before), _BYTE_LINE.findall(after), label, label
    )
    return b"".join(
        line if line.endswith(b"\n") else line + b"\n\\ No newline at end of file\n" for line in lines
    )
