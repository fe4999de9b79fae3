"""``gaitgram report --runs N``: a study grown since a report was made is reported as it stood, over
each arm's first N runs, and the report says so."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.report.make import HTML, kept_sets, watch_report
from gaitgram.report.records import load_arms

runner = CliRunner()
WINDOW = re.compile(r"\*\*First runs only\*\*.*?\n\n.*?\n\n", re.DOTALL)


def as_it_stood(study: Path, out: Path, runs: int) -> Path:
    """A copy of ``study`` before it grew past ``runs`` runs an arm."""
    shutil.copytree(study, out)
    for config in out.glob("arms/*/config.toml"):
        config.write_text(re.sub(r"runs = \d+", f"runs = {runs}", config.read_text()))
        for run in config.parent.glob("run-*"):
            if int(run.name[4:]) >= runs:
                shutil.rmtree(run)
    return out


def test_a_grown_study_reported_over_its_first_runs_is_the_report_it_had(tmp_path: Path) -> None:
    grown = write_hand_made_study(tmp_path / "grown")
    before = as_it_stood(grown, tmp_path / "before", 2)
    then = runner.invoke(app, ["report", str(before), "-o", str(tmp_path / "then")])
    now = runner.invoke(app, ["report", str(grown), "--runs", "2", "-o", str(tmp_path / "now")])
    assert then.exit_code == 0, then.stderr
    assert now.exit_code == 0, now.stderr
    for name in ("summary.csv", "tables.tex"):
        assert (tmp_path / "now" / name).read_bytes() == (tmp_path / "then" / name).read_bytes(), name
    now_json = json.loads((tmp_path / "now" / "summary.json").read_text())
    then_json = json.loads((tmp_path / "then" / "summary.json").read_text())
    assert [arm.pop("first_runs") for arm in now_json["arms"]] == [2, 2, 2]  # said, for a reader
    assert now_json == then_json
    said = (tmp_path / "now" / "summary.md").read_text()
    window = WINDOW.search(said)
    assert window is not None
    assert "first 2 runs alone (`gaitgram report --runs 2`)" in window.group()
    assert "alpha, beta_front, gamma hold more runs" in window.group()
    assert said.replace(window.group(), "") == (tmp_path / "then" / "summary.md").read_text()
    assert "First runs only" in (tmp_path / "now" / HTML).read_text()
    full = runner.invoke(app, ["report", str(grown), "-o", str(tmp_path / "full")])
    assert "| alpha | 3 |" in full.stdout
    assert "| alpha | 2 |" in now.stdout


def test_the_kept_sets_are_of_the_first_runs_alone(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    arms, _ = load_arms([study], runs=2)
    fronts, repertoires = kept_sets(arms)
    assert [front.run for front in fronts["beta_front"]] == [0, 1]
    repertoire = repertoires["gamma"]
    assert repertoire is not None
    assert repertoire.coverage[3, 2] == 0  # run 2's cell
    assert repertoire.coverage[3, 0] == repertoire.coverage[3, 1] == 1
    every, _ = load_arms([study])
    whole = kept_sets(every)[1]["gamma"]
    assert whole is not None
    assert whole.coverage[3, 2] == 1
    run_2 = np.zeros_like(whole.coverage)
    run_2[0, 0] = run_2[1, 2] = run_2[3, 2] = 1  # the cells run 2 fills
    assert np.array_equal(whole.coverage - repertoire.coverage, run_2)


def test_runs_as_many_as_planned_is_the_ordinary_report(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    ordinary = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "a")])
    all_runs = runner.invoke(app, ["report", str(study), "--runs", "3", "-o", str(tmp_path / "b")])
    assert all_runs.exit_code == 0, all_runs.stderr
    assert all_runs.stdout == ordinary.stdout
    assert "First runs only" not in all_runs.stdout
    assert (tmp_path / "b" / HTML).read_bytes() == (tmp_path / "a" / HTML).read_bytes()


def test_more_runs_than_an_arm_plans_is_refused_before_anything_is_written(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    result = runner.invoke(app, ["report", str(study), "--runs", "4", "-o", str(tmp_path / "r")])
    assert result.exit_code == 2
    assert "--runs 4 asks for its first 4 runs, but it plans 3" in result.stderr
    assert "give --runs from 1 to 3" in result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "r").exists()
    zero = runner.invoke(app, ["report", str(study), "--runs", "0", "-o", str(tmp_path / "r")])
    assert zero.exit_code == 2
    assert not (tmp_path / "r").exists()


def test_watching_the_first_runs_stops_once_they_have_finished(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    last = study / "arms" / "alpha" / "run-002" / "stats.jsonl"
    last.write_text(last.read_text().splitlines(keepends=True)[0])  # run 2 still running: not waited for
    messages: list[str] = []

    def never(_: float) -> None:
        raise AssertionError("waited for a run beyond --runs")

    watch_report([study], tmp_path / "watched", runs=2, sleep=never, progress=messages.append)
    assert messages == [f"6 of 6 runs finished: wrote {tmp_path / 'watched' / HTML}"]
    assert "First runs only" in (tmp_path / "watched" / "summary.md").read_text()
