"""Rendering diagnostics for people (rustc/ruff style) and for programs (JSON)."""

from __future__ import annotations

import difflib
import os
import re
from typing import Any

from rich.cells import cell_len
from rich.console import Console
from rich.text import Text

from gaitgram.diagnostics import Diagnostic, Severity, TextEdit
from gaitgram.language.source import SourceError, SourceText

_STYLES = {Severity.ERROR: "bold red", Severity.WARNING: "bold yellow", Severity.INFO: "bold cyan"}


def effective_severity(diagnostic: Diagnostic, *, strict: bool) -> Severity:
    """``--strict`` makes warnings errors; infos stay infos."""
    level = diagnostic.level
    return Severity.ERROR if strict and level is Severity.WARNING else level


def human(diagnostic: Diagnostic, source: SourceText, *, strict: bool = False) -> Text:
    """``file:line:col: error[GG201] message``, the source line with a caret, and the hint."""
    level = effective_severity(diagnostic, strict=strict)
    start = source.location(diagnostic.span.start)
    end = source.location(diagnostic.span.end)
    out = Text()
    out.append(f"{source.name}:{start.line}:{start.column}: ", style="bold")
    out.append(f"{level.value}[{diagnostic.code.code}]", style=_STYLES[level])
    out.append(f" {diagnostic.message}\n", style="bold")

    line_text = source.line_text(start.line)
    gutter = str(start.line)
    pad = " " * len(gutter)
    shown = line_text.expandtabs(4)
    prefix = line_text[: start.column - 1].expandtabs(4)
    last_column = end.column if end.line == start.line else len(line_text) + 1
    marked = line_text[start.column - 1 : last_column - 1].expandtabs(4)
    out.append(f"{pad} |\n", style="blue")
    out.append(f"{gutter} | ", style="blue")
    out.append(shown + "\n")
    out.append(f"{pad} | ", style="blue")
    out.append(" " * cell_len(prefix) + "^" * max(1, cell_len(marked)), style=_STYLES[level])
    out.append("\n")
    if diagnostic.hint:
        out.append(f"{pad} = ", style="blue")
        out.append("hint: ", style="bold")
        out.append(diagnostic.hint + "\n")
    return out


def as_json(diagnostic: Diagnostic, source: SourceText, *, strict: bool = False) -> dict[str, Any]:
    """One diagnostic as JSON; lines and columns are 1-based, ``end_column`` is exclusive.

    ``fixes`` lists its fixes (``applicability`` safe or unsafe), each edit replacing the text
    between its positions, in the file as read, with ``text``; ``data`` names what it is about.
    """
    start = source.location(diagnostic.span.start)
    end = source.location(diagnostic.span.end)
    return {
        "file": source.name,
        "code": diagnostic.code.code,
        "name": diagnostic.code.name,
        "severity": effective_severity(diagnostic, strict=strict).value,
        "message": diagnostic.message,
        "rule": diagnostic.rule,
        "line": start.line,
        "column": start.column,
        "end_line": end.line,
        "end_column": end.column,
        "hint": diagnostic.hint,
        "data": dict(diagnostic.data),
        "fixes": [
            {
                "title": fix.title,
                "applicability": fix.applicability.value,
                "preferred": fix.preferred,
                "edits": [_json_edit(edit, source) for edit in fix.edits],
            }
            for fix in diagnostic.fixes
        ],
    }


def _json_edit(edit: TextEdit, source: SourceText) -> dict[str, Any]:
    start, end = source.location(edit.span.start), source.location(edit.span.end)
    return {
        "line": start.line,
        "column": start.column,
        "end_line": end.line,
        "end_column": end.column,
        "text": edit.text,
    }


def print_source_error(console: Console, error: SourceError) -> None:
    """``error: cannot read PATH: why``, and the hint."""
    out = Text()
    out.append("error", style="bold red")
    out.append(f": cannot read {error.path}: {error.message}\n", style="bold")
    if error.hint:
        out.append("  = ", style="blue")
        out.append("hint: ", style="bold")
        out.append(error.hint + "\n")
    console.print(out, end="", soft_wrap=True, highlight=False)


def plural(count: int, word: str) -> str:
    return f"{count} {word}{'' if count == 1 else 's'}"


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
