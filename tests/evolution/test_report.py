"""``gaitgram report``: figures and tables from real run directories."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from evolution.test_evolution import config_file
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.report.records import load_arm

runner = CliRunner()


@pytest.fixture(scope="module")
def run_dirs(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    tmp = tmp_path_factory.mktemp("runs")
    config = config_file(tmp, generations=5)
    dirs = []
    for name, seed in (("first", "1"), ("second", "2")):
        out = tmp / name
        result = runner.invoke(
            app,
            [
                "evolve",
                str(tmp / "g.gg"),
                "-c",
                str(config),
                "-o",
                str(out),
                "--runs",
                "3",
                "--seed",
                seed,
                "-q",
            ],
        )
        assert result.exit_code == 0, result.stderr
        dirs.append(out)
    return dirs


def test_report_writes_figures_and_tables(run_dirs: list[Path], tmp_path: Path) -> None:
    out = tmp_path / "report"
    result = runner.invoke(app, ["report", *map(str, run_dirs), "-o", str(out)])
    assert result.exit_code == 0, result.stderr
    assert (out / "convergence.png").read_bytes().startswith(b"\x89PNG")
    assert "<svg" in (out / "convergence.svg").read_text()
    rows = list(csv.DictReader((out / "summary.csv").open()))
    assert [r["arm"] for r in rows] == ["first", "second"]
    first = load_arm(run_dirs[0])
    assert len(first.runs) == first.generations // 5 * 3 == 3
    assert float(rows[0]["mean_best"]) == pytest.approx(first.final_best.mean())
    assert float(rows[0]["sd_best"]) == pytest.approx(first.final_best.std(ddof=1))
    summary = (out / "summary.md").read_text()
    assert summary.startswith("Final generation")
    assert "| first | 3 |" in summary
    assert "first vs second" in summary  # the difference is tested
    assert "\\begin{tabular}" in (out / "tables.tex").read_text()


def test_report_refuses_to_overwrite_and_explains_bad_directories(
    run_dirs: list[Path], tmp_path: Path
) -> None:
    out = tmp_path / "report"
    assert runner.invoke(app, ["report", str(run_dirs[0]), "-o", str(out)]).exit_code == 0
    again = runner.invoke(app, ["report", str(run_dirs[0]), "-o", str(out)])
    assert again.exit_code == 2
    assert "--force" in again.stderr
    assert runner.invoke(app, ["report", str(run_dirs[0]), "-o", str(out), "--force"]).exit_code == 0
    bad = runner.invoke(app, ["report", str(tmp_path), "-o", str(tmp_path / "r2")])
    assert bad.exit_code == 2
    assert "not a `gaitgram evolve` run directory" in bad.stderr
