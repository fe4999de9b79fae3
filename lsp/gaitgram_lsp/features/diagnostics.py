"""``gaitgram check``'s diagnostics as LSP diagnostics: the same codes, messages, spans and
severities (hints are shown by hover and used by code actions).

They are made in LSP's wire form, plain JSON values, because a grammar can have thousands
and lsprotocol's classes cost ten times as much to build and then to unstructure again:
on a 5,000-rule document that difference is most of the time from an edit to its
diagnostics on screen. The classes are made from the wire form only where pygls needs
them (pull diagnostics).
"""

from __future__ import annotations

import json
from typing import Any

from lsprotocol import types
from pygls.protocol import default_converter

from gaitgram.analysis import CheckResult
from gaitgram.language.diagnostics import Diagnostic, Severity
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
    return WireCache().encode(result, positions)[0]


class WireCache:
    """One document's diagnostics in wire form and as JSON text, kept from one analysis to the
    next: an edit changes a few of thousands, and making the rest again (their values, then
    their JSON) cost a third of the time from a change to its diagnostics on screen. Each is
    found by what it says and where; only those of the last analysis are kept."""

    def __init__(self) -> None:
        self._kept: dict[tuple[object, ...], tuple[WireDiagnostic, str]] = {}

    def encode(self, result: CheckResult, positions: PositionIndex) -> tuple[list[WireDiagnostic], list[str]]:
        """The diagnostics in wire form, and each as JSON (``json.dumps`` of it, compact)."""
        found = result.diagnostics
        starts = positions.line_characters(d.span.start for d in found)
        ends = positions.line_characters(d.span.end for d in found)
        kept, made = self._kept, {}
        wire, encoded = [], []
        for d, start, end in zip(found, starts, ends, strict=True):
            key = (d.code, d.message, d.level, start, end)
            pair = kept.get(key) or made.get(key)
            if pair is None:
                value = _wire(d, start, end)
                pair = (value, json.dumps(value, separators=(",", ":")))
            made[key] = pair
            wire.append(pair[0])
            encoded.append(pair[1])
        self._kept = made
        return wire, encoded


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
