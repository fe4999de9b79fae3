"""What ``gaitgram report`` prints, and what a report of one arm leaves out: the terminal gets a
screen at most (the summary's main columns, the pairs that differ, what the other sections are),
the files every table; the rank tests, which compare arms, are left out of a one-arm report with
one sentence rather than printed as tables of "n/a"."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from study import report_fixtures
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.report.sections import ONE_ARM_NOTE

runner = CliRunner()
SCREEN = 40


def test_a_one_arm_report_leaves_the_rank_tests_out_with_one_sentence(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    result = runner.invoke(app, ["report", str(study / "arms" / "alpha"), "-o", str(tmp_path / "r")])
    assert result.exit_code == 0, result.stderr
    summary = (tmp_path / "r" / "summary.md").read_text()
    assert "Kruskal-Wallis H" not in summary
    assert "| pair |" not in summary
    assert summary.count(ONE_ARM_NOTE) == 1
    assert "Where the runs started" in summary  # the sections' own tables stay
    assert "Pairwise" not in (tmp_path / "r" / "tables.tex").read_text()  # no empty pairs table
    assert ONE_ARM_NOTE in result.stdout
    assert "Kruskal-Wallis H" not in result.stdout
    assert len(result.stdout.splitlines()) <= SCREEN
    assert f"wrote {len(list((tmp_path / 'r').iterdir()))} files in {tmp_path / 'r'}" in result.stderr


def test_the_terminal_gets_a_screen_and_the_files_every_table(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "r")])
    assert result.exit_code == 0, result.stderr
    printed = result.stdout
    assert len(printed.splitlines()) <= SCREEN
    assert printed.startswith("# Hand-made: three arms & a title\n")
    assert "| alpha | 3 |" in printed  # each arm's row, its main columns
    assert "**final best**: Kruskal-Wallis H = " in printed
    assert "0 of 3 pairs differ" in printed  # three runs an arm separate none
    summary = (tmp_path / "r" / "summary.md").read_text()
    assert "| alpha vs beta_front |" in summary  # every pair's test is in the file
    assert "Further sections: Where the runs started; " in printed
    assert "Every table is in summary.md" in printed


def test_a_study_of_many_arms_still_fits_a_screen(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Fourteen arms of ten runs, far enough apart that pairs differ: the terminal lists ten arms
    and five pairs, and says how many more are in summary.md."""
    arms = {
        (f"arm{k:02d}", "ge"): [(k + run / 100, 2.0 + k, 1.5 + k, 0, 1.0, 0.5) for run in range(10)]
        for k in range(14)
    }
    monkeypatch.setattr(report_fixtures, "ARMS", arms)
    study = write_hand_made_study(tmp_path / "study")
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "r")])
    assert result.exit_code == 0, result.stderr
    printed = result.stdout.splitlines()
    assert len(printed) <= SCREEN, result.stdout
    assert "| arm09 | 10 |" in result.stdout
    assert "arm10" not in result.stdout
    assert "... and 4 more arms (summary.md)" in printed
    assert "- ... and " in result.stdout  # more pairs differ than are listed
    assert len([line for line in printed if " vs " in line]) == 5
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert len(summary["arms"]) == 14
    assert len(summary["pairs"]) == 91
