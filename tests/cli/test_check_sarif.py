"""``gaitgram check --format sarif``: valid SARIF 2.1.0, with every code's rule metadata.

The schema is vendored from the OASIS SARIF TC's repository (oasis-tcs/sarif-spec,
``sarif-2.1/schema/sarif-schema-2.1.0.json``, the 2.1.0 errata 01 schema), so the test runs
offline.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from typer.testing import CliRunner

from conftest import ROOT
from gaitgram.analysis.diagnostic_codes import CODES
from gaitgram.cli import app

runner = CliRunner()

SCHEMA = json.loads((ROOT / "tests" / "data" / "sarif-schema-2.1.0.json").read_text())
DOCS = (ROOT / "docs" / "diagnostics.md").read_text()

TEXT = "<a> ::= <b> | <nope> | x | | flaot[0..1 step 0.5]\n<b> ::= int[5..1] | <c>\n<c> ::= é 😀 <nah>\n"


def sarif(*args: str) -> tuple[dict[str, Any], int]:
    result = runner.invoke(app, ["check", "--format", "sarif", *args])
    log = json.loads(result.stdout)
    jsonschema.Draft4Validator(SCHEMA).validate(log)
    return log, result.exit_code


@pytest.fixture
def grammar(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "g.gg"
    path.write_text(TEXT)
    return path


def test_the_log_is_valid_sarif_with_a_rule_for_every_code(grammar: Path) -> None:
    log, status = sarif("g.gg")
    assert status == 1
    assert log["version"] == "2.1.0"
    (run,) = log["runs"]
    driver = run["tool"]["driver"]
    assert driver["name"] == "gaitgram"
    rules = driver["rules"]
    assert [r["id"] for r in rules] == list(CODES)
    for rule, code in zip(rules, CODES.values(), strict=True):
        assert rule["name"] == code.name
        assert rule["shortDescription"]["text"]
        assert rule["help"]["text"] == code.help
        level = {"error": "error", "warning": "warning", "info": "note"}[code.severity.value]
        assert rule["defaultConfiguration"]["level"] == level
        assert rule["helpUri"].endswith(f"docs/diagnostics.md#{code.anchor}")
        assert rule["properties"]["fix"] == (code.fix.value if code.fix else "none")


def test_every_help_link_lands_on_a_heading_in_the_docs() -> None:
    anchors = {_slug(h) for h in re.findall(r"^#+ (.+)$", DOCS, flags=re.MULTILINE)}
    shown = re.sub(r"\\([\\<])", r"\1", DOCS)  # as Markdown shows it: \\ is \ and \< is <
    for code in CODES.values():
        assert code.anchor in anchors, code
        assert code.help in shown, f"docs/diagnostics.md lacks the help text of {code}"


def _slug(heading: str) -> str:
    """The anchor GitHub gives a Markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def test_results_have_locations_and_fixes(grammar: Path) -> None:
    log, _ = sarif("g.gg")
    (run,) = log["runs"]
    assert run["columnKind"] == "unicodeCodePoints"
    assert run["artifacts"][0]["location"] == {"uri": "g.gg", "uriBaseId": "%SRCROOT%"}
    results = {r["ruleId"]: r for r in reversed(run["results"])}  # the first of each
    assert sorted(r["ruleId"] for r in run["results"]) == ["GG106", "GG201", "GG201", "GG301", "GG309"]
    undefined = results["GG201"]
    assert undefined["level"] == "error"
    assert undefined["message"]["text"] == "<nope> is not defined"
    assert undefined["ruleIndex"] == list(CODES).index("GG201")
    (location,) = undefined["locations"]
    assert location["physicalLocation"]["artifactLocation"]["uri"] == "g.gg"
    assert location["physicalLocation"]["region"] == {
        "startLine": 1,
        "startColumn": 15,
        "endLine": 1,
        "endColumn": 21,
    }
    (fix,) = results["GG309"]["fixes"]
    assert fix["description"]["text"] == "Make it the range float[0..1 step 0.5]"
    (change,) = fix["artifactChanges"]
    assert change["replacements"] == [
        {
            "deletedRegion": {"startLine": 1, "startColumn": 30, "endLine": 1, "endColumn": 35},
            "insertedContent": {"text": "float"},
        }
    ]
    (delete,) = results["GG106"]["fixes"]
    assert "insertedContent" not in delete["artifactChanges"][0]["replacements"][0]
    assert [f["description"]["text"] for f in results["GG201"]["fixes"]] == ["Define <nope>"]
    after_emoji = run["results"][-1]["locations"][0]["physicalLocation"]["region"]
    assert (after_emoji["startLine"], after_emoji["startColumn"]) == (3, 13)  # code points: é and 😀 are one


def test_strict_unreadable_files_and_fixed_files(grammar: Path) -> None:
    log, status = sarif("--strict", "g.gg", "missing.gg")
    assert status == 2
    (run,) = log["runs"]
    assert {r["level"] for r in run["results"]} == {"error"}  # warnings count as errors
    (invocation,) = run["invocations"]
    assert invocation["executionSuccessful"] is False
    (note,) = invocation["toolExecutionNotifications"]
    assert note["message"]["text"] == "cannot read missing.gg: no such file"
    log, _ = sarif("--fix", str(grammar))  # an absolute path is a file URI
    (run,) = log["runs"]
    assert run["artifacts"][0]["location"] == {"uri": grammar.as_uri()}
    assert {r["ruleId"] for r in run["results"]} == {"GG201", "GG301"}  # the rest was fixed


def test_an_empty_check_is_a_valid_log(tmp_path: Path) -> None:
    path = tmp_path / "clean.gg"
    path.write_text("<a> ::= x\n")
    log, status = sarif(str(path))
    assert status == 0
    assert log["runs"][0]["results"] == []
