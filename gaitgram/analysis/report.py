"""How a check's diagnostics are shown: to people (rustc and ruff style) and to programs (JSON).

The command line prints these (``gaitgram check``, and every command that refuses a grammar with
errors); SARIF, for code scanning, is :mod:`gaitgram.analysis.sarif`. Machine output is plain
text to be written as it is, never through a console that would wrap or measure it.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from rich.cells import cell_len
from rich.text import Text

from gaitgram.diagnostics import Diagnostic, Severity, TextEdit
from gaitgram.language.source import SourceError, SourceText

__all__ = [
    "CheckedFile",
    "as_json",
    "effective_severity",
    "human",
    "json_report",
    "machine_json",
    "plural",
    "source_error",
]

_STYLES = {Severity.ERROR: "bold red", Severity.WARNING: "bold yellow", Severity.INFO: "bold cyan"}


@dataclass(frozen=True, eq=False)
class CheckedFile:
    """One file's diagnostics, against the text they were found in."""

    path: str
    source: SourceText
    diagnostics: tuple[Diagnostic, ...]


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


def source_error(error: SourceError) -> Text:
    """``error: cannot read PATH: why``, and the hint."""
    out = Text()
    out.append("error", style="bold red")
    out.append(f": cannot read {error.path}: {error.message}\n", style="bold")
    if error.hint:
        out.append("  = ", style="blue")
        out.append("hint: ", style="bold")
        out.append(error.hint + "\n")
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


def json_report(checked: Iterable[CheckedFile], *, strict: bool = False) -> str:
    """``gaitgram check --format json``: every diagnostic of every file, in order, as one array."""
    records = [as_json(d, found.source, strict=strict) for found in checked for d in found.diagnostics]
    return machine_json(records)


def machine_json(value: Any) -> str:
    """JSON text of a report, which holds no floats (only text, whole numbers, flags and None):
    ``allow_nan=False`` would refuse a non-finite one, so :func:`gaitgram.jsonio.dumps`'s walk
    to replace them, which costs as much as the encoding, is not needed."""
    return json.dumps(value, indent=2, ensure_ascii=False, allow_nan=False)


def plural(count: int, word: str) -> str:
    return f"{count} {word}{'' if count == 1 else 's'}"
