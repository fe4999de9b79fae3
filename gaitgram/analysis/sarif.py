"""``gaitgram check --format sarif``: SARIF 2.1.0, the log format of code-scanning services.

One run, with the metadata of every diagnostic code as a rule (so a viewer can explain a
result it has never seen), the results with their locations, and the fixes they carry as
SARIF ``fixes``. Lines and columns are 1-based; columns count Unicode code points
(``columnKind``) and an end column is the column after the region, as in SARIF.
"""

from __future__ import annotations

import os
from functools import cache
from pathlib import Path
from typing import Any
from urllib.parse import quote

import gaitgram
from gaitgram.analysis.diagnostic_codes import CODES
from gaitgram.analysis.report import CheckedFile, effective_severity, machine_json
from gaitgram.language.diagnostics import Code, Fix, Severity
from gaitgram.language.source import SourceError, SourceText, Span

__all__ = ["SCHEMA", "SOURCE_ROOT", "docs_url", "help_uri", "sarif_log", "sarif_report"]

SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
SOURCE_ROOT = "%SRCROOT%"

_LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def sarif_report(checked: list[CheckedFile], unreadable: list[SourceError], *, strict: bool = False) -> str:
    """``gaitgram check --format sarif``: the log as JSON text."""
    return machine_json(sarif_log(checked, unreadable, strict=strict))


def sarif_log(checked: list[CheckedFile], unreadable: list[SourceError], *, strict: bool = False) -> dict:
    """The SARIF log of one ``gaitgram check``."""
    rule_index = {code: i for i, code in enumerate(CODES)}
    artifacts = [{"location": _artifact(f.path), "sourceLanguage": "gaitgram"} for f in checked]
    results = []
    for index, found in enumerate(checked):
        for d in found.diagnostics:
            location = {**_artifact(found.path), "index": index}
            region = _region(found.source, d.span)
            result: dict[str, Any] = {
                "ruleId": d.code.code,
                "ruleIndex": rule_index[d.code.code],
                "level": _LEVELS[effective_severity(d, strict=strict)],
                "message": {"text": d.message},
                "locations": [{"physicalLocation": {"artifactLocation": location, "region": region}}],
            }
            if d.fixes:
                result["fixes"] = [_fix(fix, found.source, location) for fix in d.fixes]
            properties = {"hint": d.hint, "rule": d.rule, "data": dict(d.data) if d.data else None}
            if any(properties.values()):
                result["properties"] = {k: v for k, v in properties.items() if v}
            results.append(result)
    driver: dict[str, Any] = {
        "name": "gaitgram",
        "version": gaitgram.__version__,
        "rules": [_rule(code) for code in CODES.values()],
    }
    if docs_url().startswith(("https:", "http:", "file:")):
        driver["informationUri"] = docs_url()
    run: dict[str, Any] = {
        "tool": {"driver": driver},
        "originalUriBaseIds": {SOURCE_ROOT: {"uri": Path.cwd().as_uri() + "/"}},
        "artifacts": artifacts,
        "columnKind": "unicodeCodePoints",
        "results": results,
        "invocations": [
            {
                "executionSuccessful": not unreadable,
                "toolExecutionNotifications": [
                    {
                        "level": "error",
                        "message": {"text": f"cannot read {e.path}: {e.message}"},
                        "locations": [{"physicalLocation": {"artifactLocation": _artifact(e.path)}}],
                    }
                    for e in unreadable
                ],
            }
        ],
    }
    return {"$schema": SCHEMA, "version": "2.1.0", "runs": [run]}


def _rule(code: Code) -> dict[str, Any]:
    tags = ["syntax"] if code.syntax else []
    link = f"[{code.code} in the docs]({help_uri(code)})"
    return {
        "id": code.code,
        "name": code.name,
        "shortDescription": {"text": code.summary[:1].upper() + code.summary[1:] + "."},
        "fullDescription": {"text": code.help},
        "help": {"text": code.help, "markdown": f"{code.help}\n\n{link}"},
        "helpUri": help_uri(code),
        "defaultConfiguration": {"level": _LEVELS[code.severity]},
        "properties": {"tags": tags, "fix": code.fix.value if code.fix else "none"},
    }


def _fix(fix: Fix, source: SourceText, location: dict[str, Any]) -> dict[str, Any]:
    replacements = []
    for edit in fix.edits:
        replacement: dict[str, Any] = {"deletedRegion": _region(source, edit.span)}
        if edit.text:
            replacement["insertedContent"] = {"text": edit.text}
        replacements.append(replacement)
    return {
        "description": {"text": fix.title},
        "artifactChanges": [{"artifactLocation": location, "replacements": replacements}],
        "properties": {"applicability": fix.applicability.value, "preferred": fix.preferred},
    }


def _region(source: SourceText, span: Span) -> dict[str, int]:
    start, end = source.location(span.start), source.location(span.end)
    return {
        "startLine": start.line,
        "startColumn": start.column,
        "endLine": end.line,
        "endColumn": end.column,
    }


def _artifact(path: str) -> dict[str, str]:
    """A relative path is relative to ``%SRCROOT%`` (the working directory), as scanners expect."""
    if os.path.isabs(path):
        return {"uri": Path(path).as_uri()}
    return {"uri": quote(Path(path).as_posix()), "uriBaseId": SOURCE_ROOT}


def help_uri(code: Code) -> str:
    """The code's section of ``docs/diagnostics.md``."""
    return f"{docs_url()}#{code.anchor}"


@cache
def docs_url() -> str:
    """Where ``docs/diagnostics.md`` is: the ``Documentation`` (or ``Repository``) URL the
    installed package declares; else the file in this source tree; else the path in the
    project, relative."""
    from importlib.metadata import PackageNotFoundError, metadata  # 20 ms: only for SARIF

    try:
        urls = metadata("gaitgram").get_all("Project-URL") or []
    except PackageNotFoundError:
        urls = []
    declared = dict(url.split(", ", 1) for url in urls if ", " in url)
    if "Documentation" in declared:
        return declared["Documentation"].rstrip("/") + "/diagnostics.md"
    if "Repository" in declared:
        return declared["Repository"].rstrip("/") + "/blob/main/docs/diagnostics.md"
    here = Path(gaitgram.__file__).resolve().parent.parent / "docs" / "diagnostics.md"
    return here.as_uri() if here.is_file() else "docs/diagnostics.md"
