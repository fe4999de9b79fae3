"""``check --format json`` is written record by record from templates (issue 28: within 1.2x of
the text format); these tests hold it to the plain reading of the format: each diagnostic as a
JSON object, the array serialised by ``json.dumps(indent=2, ensure_ascii=False)``."""

from __future__ import annotations

import json
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from gaitgram.analysis import check
from gaitgram.analysis.report import CheckedFile, effective_severity, json_report
from gaitgram.language import parse
from gaitgram.language.diagnostics import Diagnostic
from gaitgram.language.source import SourceText

PIECES = [
    "<a> ::= ",
    "<b>\t::=\t",
    "<é> ::= ",
    "<c> ::= ",
    "<a>",
    "<b>",
    "<c>",
    "<é>",
    "<undefined>",
    " | ",
    "\n",
    "# c\n",
    "'\"q\"'",
    "'ü\\\\'",
    "x",
    "1",
    "int[5..1]",
    "float[0..1 step 0.3]",
    "@start <a>\n",
    "@joint hip_hind\n",
    "<d> ::= <e>\n<e> ::= <d> | y\n",
    "<a> ::= <a> | x\n",
]


def plain_reading(diagnostic: Diagnostic, source: SourceText, strict: bool) -> dict[str, Any]:
    """The format as docs/cli.md describes it, built as objects."""

    def position(start: int, end: int) -> dict[str, int]:
        first, last = source.location(start), source.location(end)
        return {"line": first.line, "column": first.column, "end_line": last.line, "end_column": last.column}

    where = position(diagnostic.span.start, diagnostic.span.end)
    return {
        "file": source.name,
        "code": diagnostic.code.code,
        "name": diagnostic.code.name,
        "severity": effective_severity(diagnostic, strict=strict).value,
        "message": diagnostic.message,
        "rule": diagnostic.rule,
        **where,
        "hint": diagnostic.hint,
        "data": dict(diagnostic.data),
        "fixes": [
            {
                "title": fix.title,
                "applicability": fix.applicability.value,
                "preferred": fix.preferred,
                "edits": [{**position(e.span.start, e.span.end), "text": e.text} for e in fix.edits],
            }
            for fix in diagnostic.fixes
        ],
    }


def checked_file(text: str, name: str) -> CheckedFile:
    result = check(parse(text, name=name))
    return CheckedFile(name, result.grammar.source, result.diagnostics)


@settings(max_examples=300, deadline=None)
@given(
    texts=st.lists(st.lists(st.sampled_from(PIECES), max_size=20).map("".join), max_size=3),
    strict=st.booleans(),
)
def test_the_json_report_is_the_plain_reading_of_the_format(texts: list[str], strict: bool) -> None:
    files = [checked_file(text, f'dir/g{i}\t"ü".gg') for i, text in enumerate(texts)]
    expected = [plain_reading(d, f.source, strict) for f in files for d in f.diagnostics]
    assert json_report(files, strict=strict) == json.dumps(expected, indent=2, ensure_ascii=False)


def test_a_report_with_fixes_data_and_nulls_is_written_as_json_writes_it() -> None:
    text = "@start <a>\n<a> ::= x | <b>\n<b> ::= <b>\n<c> ::= <d>\n<d> ::= 'ü'\n<e> ::= y\n<a> ::= z\n"
    found = checked_file(text, "g.gg")
    codes = {d.code.code for d in found.diagnostics}
    assert {"GG204"} <= codes  # unreachable rules, with fixes and data
    assert any(d.fixes and len(d.fixes[0].edits) for d in found.diagnostics)
    expected = [plain_reading(d, found.source, False) for d in found.diagnostics]
    assert json_report([found]) == json.dumps(expected, indent=2, ensure_ascii=False)


def test_nothing_found_is_an_empty_array() -> None:
    assert json_report([checked_file("@start <a>\n<a> ::= x\n", "g.gg")]) == "[]"
    assert json_report([]) == "[]"
