"""How a check's diagnostics are shown: to people (rustc and ruff style) and to programs (JSON).

The command line prints these (``gaitgram check``, and every command that refuses a grammar with
errors); SARIF, for code scanning, is :mod:`gaitgram.analysis.sarif`. Machine output is plain
text to be written as it is, never through a console that would wrap or measure it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from json.encoder import encode_basestring  # the C one, as json.dumps(ensure_ascii=False) uses
from typing import Any

from rich.cells import cell_len

from gaitgram.collector import without_gc
from gaitgram.language.diagnostics import Diagnostic, Fix, Severity
from gaitgram.language.source import SourceError, SourceText

__all__ = [
    "CheckedFile",
    "Styled",
    "effective_severity",
    "human",
    "json_report",
    "machine_json",
    "plural",
    "source_error",
]

_STYLES = {Severity.ERROR: "bold red", Severity.WARNING: "bold yellow", Severity.INFO: "bold cyan"}


@dataclass
class Styled:
    """Text in segments, each with a rich style or none: plain data that a terminal colours
    (:mod:`gaitgram.cli.terminal`) and anything else reads as :attr:`plain`."""

    segments: list[tuple[str, str | None]] = field(default_factory=list)

    def append(self, text: str, style: str | None = None) -> None:
        self.segments.append((text, style))

    @property
    def plain(self) -> str:
        return "".join(text for text, _ in self.segments)


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


def human(diagnostic: Diagnostic, source: SourceText, *, strict: bool = False) -> Styled:
    """``file:line:col: error[GG201] message``, the source line with a caret, and the hint."""
    level = effective_severity(diagnostic, strict=strict)
    start = source.location(diagnostic.span.start)
    out = Styled()
    out.append(f"{source.name}:{start.line}:{start.column}: ", style="bold")
    out.append(f"{level.value}[{diagnostic.code.code}]", style=_STYLES[level])
    out.append(f" {diagnostic.message}\n", style="bold")

    shown, prefix, marked = _source_window(source, diagnostic.span.start, diagnostic.span.end)
    gutter = str(start.line)
    pad = " " * len(gutter)
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


#: A source line longer than this (in characters) is shown only around the problem, from
#: ``_BEFORE`` characters before it to ``SHOWN_LINE`` in all: a line of megabytes with
#: thousands of problems on it would otherwise be printed whole for each of them.
SHOWN_LINE = 160
_BEFORE = 40


def _source_window(source: SourceText, start: int, end: int) -> tuple[str, str, str]:
    """The line of ``start`` as shown (tabs expanded, a long line cut to a window with ``…`` where
    it goes on), the part of it before the problem and the part marked: from ``start`` to ``end``,
    or to the line's end."""
    text = source.text
    first = source.line_start_of(start)
    last = source.line_end_of(start)
    left, right = first, last
    if last - first > SHOWN_LINE:
        left = max(first, min(start - _BEFORE, last - SHOWN_LINE))
        right = min(last, left + SHOWN_LINE)
    opened = "…" if left > first else ""
    closed = "…" if right < last else ""
    shown = opened + text[left:right].expandtabs(4) + closed
    prefix = (opened + text[left:start]).expandtabs(4)
    marked = text[start : max(start, min(end, right))].expandtabs(4)
    return shown, prefix, marked


def source_error(error: SourceError) -> Styled:
    """``error: cannot read PATH: why``, and the hint."""
    out = Styled()
    out.append("error", style="bold red")
    out.append(f": cannot read {error.path}: {error.message}\n", style="bold")
    if error.hint:
        out.append("  = ", style="blue")
        out.append("hint: ", style="bold")
        out.append(error.hint + "\n")
    return out


@without_gc  # its fixes and records are tens of thousands of objects, none of them cyclic
def json_report(checked: Iterable[CheckedFile | SourceError], *, strict: bool = False) -> str:
    """``gaitgram check --format json``: every diagnostic of every file, in order, as one array,
    indented two spaces as ``json.dumps(indent=2, ensure_ascii=False)`` would (a property test
    holds them equal).

    Each diagnostic is an object: ``file``, ``code``, ``name``, ``severity`` (``--strict``
    applied), ``message``, ``rule``, ``line``, ``column``, ``end_line``, ``end_column`` (1-based,
    the end exclusive), ``hint``, ``data`` (the names it is about) and ``fixes``: each with
    ``title``, ``applicability`` (safe or unsafe), ``preferred`` and ``edits``, each edit
    replacing the text between its positions, in the file as read, with ``text``. A file that
    could not be read (a :class:`SourceError`) is one object of the same keys, ``code`` null and
    ``name`` ``unreadable-file``, its message saying why, as SARIF's tool notification does.

    Written record by record from templates, not built as objects and then serialised: a
    10,000-rule grammar's report holds 50,000 fix edits, most of them shared (removing a chain of
    n unreachable rules is in n fixes), and each edit's text is made once per file.
    """
    records: list[str] = []
    for found in checked:
        if isinstance(found, SourceError):
            records.append(_json_unreadable(found))
            continue
        file = f'  {{\n    "file": {encode_basestring(found.source.name)},\n'
        edits: dict[int, str] = {}  # by id: the diagnostics hold their edits while this runs
        records += [_json_record(file, d, found.source, strict, edits) for d in found.diagnostics]
    return _json_list(records, "")


def _json_record(
    file: str, diagnostic: Diagnostic, source: SourceText, strict: bool, edits: dict[int, str]
) -> str:
    """One diagnostic, at the array's depth; ``file`` is its opening, written once per file."""
    line, column, end_line, end_column = source.bounds(*diagnostic.span)
    text = encode_basestring
    code = diagnostic.code
    names = ",\n      ".join(f"{text(key)}: {text(value)}" for key, value in diagnostic.data.items())
    data = "{\n      " + names + "\n    }" if names else "{}"
    fixes = _json_list([_json_fix(fix, source, edits) for fix in diagnostic.fixes], "    ")
    return (
        f'{file}    "code": {text(code.code)},\n    "name": {text(code.name)},\n'
        f'    "severity": "{effective_severity(diagnostic, strict=strict).value}",\n'
        f'    "message": {text(diagnostic.message)},\n'
        f'    "rule": {"null" if diagnostic.rule is None else text(diagnostic.rule)},\n'
        f'    "line": {line},\n    "column": {column},\n'
        f'    "end_line": {end_line},\n    "end_column": {end_column},\n'
        f'    "hint": {"null" if diagnostic.hint is None else text(diagnostic.hint)},\n'
        f'    "data": {data},\n'
        f'    "fixes": {fixes}\n  }}'
    )


def _json_unreadable(error: SourceError) -> str:
    """A file that could not be read, as a diagnostic of no code and no place."""
    text = encode_basestring
    return (
        f'  {{\n    "file": {text(error.path)},\n    "code": null,\n    "name": "unreadable-file",\n'
        f'    "severity": "error",\n    "message": {text(f"cannot read {error.path}: {error.message}")},\n'
        '    "rule": null,\n    "line": null,\n    "column": null,\n'
        '    "end_line": null,\n    "end_column": null,\n'
        f'    "hint": {"null" if error.hint is None else text(error.hint)},\n'
        '    "data": {},\n    "fixes": []\n  }'
    )


def _json_fix(fix: Fix, source: SourceText, edits: dict[int, str]) -> str:
    written = []
    for edit in fix.edits:
        found = edits.get(id(edit))
        if found is None:
            line, column, end_line, end_column = source.bounds(*edit.span)
            found = edits[id(edit)] = (
                f'          {{\n            "line": {line},\n            "column": {column},\n'
                f'            "end_line": {end_line},\n            "end_column": {end_column},\n'
                f'            "text": {encode_basestring(edit.text)}\n          }}'
            )
        written.append(found)
    return (
        f'      {{\n        "title": {encode_basestring(fix.title)},\n'
        f'        "applicability": "{fix.applicability.value}",\n'
        f'        "preferred": {"true" if fix.preferred else "false"},\n'
        f'        "edits": {_json_list(written, "        ")}\n      }}'
    )


def _json_list(items: list[str], indent: str) -> str:
    """Items already written at their depth, as the array that holds them (at ``indent``)."""
    return "[\n" + ",\n".join(items) + "\n" + indent + "]" if items else "[]"


def machine_json(value: Any) -> str:
    """JSON text of a report, exactly as ``json.dumps(value, indent=2, ensure_ascii=False,
    allow_nan=False)`` writes it (a property test holds them equal), three times as fast: the
    standard library indents with its pure-Python encoder (``check --format sarif`` of a large
    grammar writes megabytes). A report holds text, whole numbers, flags, None, lists and
    dicts with text keys; a non-finite float is refused as ``allow_nan=False`` refuses it."""
    parts: list[str] = []
    _write_json(value, "\n", parts)
    return "".join(parts)


def _finite(value: float) -> str:
    if not math.isfinite(value):
        raise ValueError(f"Out of range float values are not JSON compliant: {value!r}")
    return float.__repr__(value)


#: How each scalar type is written, looked up by exact type so that leaves cost no call of their
#: own (subclasses, such as a StrEnum's members, take the slower way, as json.dumps does).
_SCALARS: dict[type, Callable[[Any], str]] = {
    str: encode_basestring,
    int: int.__repr__,
    bool: lambda flag: "true" if flag else "false",
    type(None): lambda _: "null",
    float: _finite,
}


def _write_json(value: Any, newline: str, parts: list[str]) -> None:
    write = _SCALARS.get(type(value))
    if write is not None:
        parts.append(write(value))
    elif isinstance(value, dict):
        if not value:
            parts.append("{}")
            return
        inner = newline + "  "
        opening = "{" + inner
        for key, item in value.items():
            if type(key) is not str and not isinstance(key, str):
                raise TypeError(f"a report's keys are text, not {type(key).__name__}")
            write = _SCALARS.get(type(item))
            if write is not None:
                parts.append(opening + encode_basestring(key) + ": " + write(item))
            else:
                parts.append(opening + encode_basestring(key) + ": ")
                _write_json(item, inner, parts)
            opening = "," + inner
        parts.append(newline + "}")
    elif isinstance(value, list | tuple):
        if not value:
            parts.append("[]")
            return
        inner = newline + "  "
        opening = "[" + inner
        for item in value:
            write = _SCALARS.get(type(item))
            if write is not None:
                parts.append(opening + write(item))
            else:
                parts.append(opening)
                _write_json(item, inner, parts)
            opening = "," + inner
        parts.append(newline + "]")
    elif isinstance(value, bool):  # before int: a bool subclass is a bool
        parts.append("true" if value else "false")
    elif isinstance(value, str):
        parts.append(encode_basestring(value))
    elif isinstance(value, int):
        parts.append(int.__repr__(value))
    elif isinstance(value, float):
        parts.append(_finite(value))
    else:
        raise TypeError(f"Object of type {type(value).__name__} is not JSON serializable")


def plural(count: int, word: str) -> str:
    return f"{count} {word}{'' if count == 1 else 's'}"
