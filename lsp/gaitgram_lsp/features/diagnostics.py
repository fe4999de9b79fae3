"""``gaitgram check``'s diagnostics as LSP diagnostics: the same codes, messages, spans and
severities (hints are shown by hover and used by code actions).

They are made in LSP's wire form, plain JSON values, because a grammar can have thousands
and lsprotocol's classes cost ten times as much to build and then to unstructure again:
on a 5,000-rule document that difference is most of the time from an edit to its
diagnostics on screen. The classes are made from the wire form only where pygls needs
them (pull diagnostics).
"""

from __future__ import annotations

from typing import Any

from lsprotocol import types
from pygls.protocol import default_converter

from gaitgram.analysis import CheckResult
from gaitgram.diagnostics import Diagnostic, Severity
from gaitgram_lsp.positions import PositionIndex

SOURCE = "gaitgram"

SEVERITY = {
    Severity.ERROR: types.DiagnosticSeverity.Error,
    Severity.WARNING: types.DiagnosticSeverity.Warning,
    Severity.INFO: types.DiagnosticSeverity.Information,
}

#: Rendered faded by editors: code that does nothing (``Code.unnecessary``).
_UNNECESSARY_TAGS = [types.DiagnosticTag.Unnecessary.value]
_SEVERITY_VALUE = {level: severity.value for level, severity in SEVERITY.items()}

WireDiagnostic = dict[str, Any]

_converter = default_converter()


def wire_diagnostics(result: CheckResult, positions: PositionIndex) -> list[WireDiagnostic]:
    """The diagnostics as the JSON that ``textDocument/publishDiagnostics`` carries."""
    found = result.diagnostics
    starts = positions.line_characters(d.span.start for d in found)
    ends = positions.line_characters(d.span.end for d in found)
    return [_wire(d, start, end) for d, start, end in zip(found, starts, ends, strict=True)]


def wire_diagnostic(found: Diagnostic, positions: PositionIndex) -> WireDiagnostic:
    return _wire(found, positions.line_character(found.span.start), positions.line_character(found.span.end))


def _wire(found: Diagnostic, start: tuple[int, int], end: tuple[int, int]) -> WireDiagnostic:
    wire: WireDiagnostic = {
        "range": {
            "start": {"line": start[0], "character": start[1]},
            "end": {"line": end[0], "character": end[1]},
        },
        "message": found.message,
        "severity": _SEVERITY_VALUE[found.level],
        "code": found.code.code,
        "source": SOURCE,
    }
    if found.code.unnecessary:
        wire["tags"] = _UNNECESSARY_TAGS
    return wire


def to_lsp(wire: list[WireDiagnostic]) -> list[types.Diagnostic]:
    return _converter.structure(wire, list[types.Diagnostic])
