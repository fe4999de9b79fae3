"""A number a gaitgram file holds is finite or null, never NaN or infinity: gaitgram writes none
(``jsonio.dumps``), so one is an edit or damage, refused alike in every file a report reads,
naming the file and the key (issue 39, class 8: an assessment's ``Infinity`` was shown as n/a).

The arm is a copy of a committed one (docs/results/table4, arm ``none``: ten runs, each with its
kept assessment), without its checkpoints, which a report does not read."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from conftest import ROOT
from gaitgram.cli import app

runner = CliRunner()
ARM = ROOT / "docs" / "results" / "table4" / "runs" / "arms" / "none"


@pytest.fixture
def arm(tmp_path: Path) -> Path:
    copy = tmp_path / "none"
    shutil.copytree(ARM, copy, ignore=shutil.ignore_patterns("checkpoint.json", "stats.csv"))
    return copy


def damage(path: Path, place: Callable[[dict[str, Any]], tuple[Any, Any]], literal: str) -> None:
    """Write ``literal`` (a JSON token Python's json reads as a float) at a place in a JSON file."""
    data = json.loads(path.read_text())
    container, key = place(data)
    container[key] = "@@damaged@@"
    path.write_text(json.dumps(data, indent=1).replace('"@@damaged@@"', literal))


PLACES = {
    "realism.scores.phase_hind_right": lambda d: (d["realism"]["scores"], "phase_hind_right"),
    "realism.measures.speed": lambda d: (d["realism"]["measures"], "speed"),
    "realism.curves.fetlock_fore[2]": lambda d: (d["realism"]["curves"]["fetlock_fore"], 2),
}


@pytest.mark.parametrize("literal", ["Infinity", "-Infinity", "NaN", "1e999"])
@pytest.mark.parametrize("key", list(PLACES))
@pytest.mark.parametrize("file", ["run-003/assessment.json", "best-walk-assessment.json"])
def test_a_non_finite_number_in_an_assessment_is_refused_naming_file_and_key(
    arm: Path, tmp_path: Path, file: str, key: str, literal: str
) -> None:
    damage(arm / file, PLACES[key], literal)
    result = runner.invoke(app, ["report", str(arm), "-o", str(tmp_path / "report")])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.stderr
    message = " ".join(result.stderr.split())
    assert f"{arm / file}: {key}: {literal} is not a finite number" in message
    assert f"measure it again with: gaitgram report --assess {arm}" in message
    assert not (tmp_path / "report").exists()


def test_the_undamaged_copy_reports(arm: Path, tmp_path: Path) -> None:
    """The copy itself reads: what the tests above refuse is the one damaged number."""
    result = runner.invoke(app, ["report", str(arm), "-o", str(tmp_path / "report")])
    assert result.exit_code == 0, result.stderr
    assert "| none | 10 |" in (tmp_path / "report" / "summary.md").read_text()
