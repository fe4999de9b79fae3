"""``gaitgram report`` names each arm's representation where a study's arms are not all GE: a real
study of a GE, an SGE and a CFG-GP arm, reported; a GE-only report reads as it always did (the
committed reports, byte for byte, are tests/study/test_committed_results.py's)."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_TARGETS_TOML
from gaitgram.cli import app

STUDY = (
    """\
title = "representations"
runs = 2
seed = 7

[settings]
generations = 3
population = 12
elite = 1
backend = "curve-match"

[settings.backend_settings.targets]
"""
    + CURVE_TARGETS_TOML
    + """
[[arm]]
name = "plain"
grammar = "g.gg"

[[arm]]
name = "structured"
grammar = "g.gg"
representation = "sge"

[[arm]]
name = "trees"
grammar = "g.gg"
representation = "cfg-gp"
[arm.settings.representation_settings]
max_depth = 8
"""
)


def gaitgram(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True, cwd=cwd)


def test_a_report_names_each_arms_representation(tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(CURVE_GRAMMAR)
    (tmp_path / "s.toml").write_text(STUDY)
    study = gaitgram("study", "s.toml", "-o", "out", "-q", cwd=tmp_path)
    assert study.returncode == 0, study.stderr
    runner = CliRunner()
    report = runner.invoke(app, ["report", str(tmp_path / "out"), "-o", str(tmp_path / "rep")])
    assert report.exit_code == 0, report.stderr
    assert "| arm | representation | runs |" in report.stdout  # the screen's table too
    summary = (tmp_path / "rep" / "summary.md").read_text()
    assert "| arm | representation | runs | avg. best |" in summary
    for arm, representation in (("plain", "ge"), ("structured", "sge"), ("trees", "cfg-gp")):
        assert f"| {arm} | {representation} | 2 |" in summary
    arms = json.loads((tmp_path / "rep" / "summary.json").read_text())["arms"]
    assert [(a["name"], a["representation"]) for a in arms] == [
        ("plain", "ge"),
        ("structured", "sge"),
        ("trees", "cfg-gp"),
    ]
    html = (tmp_path / "rep" / "report.html").read_text()
    assert ">representation</th>" in html
    assert "<td>trees</td><td>cfg-gp</td>" in html
    rows = list(csv.DictReader((tmp_path / "rep" / "summary.csv").open(newline="")))
    assert [(r["arm"], r["strategy"], r["representation"]) for r in rows] == [
        ("plain", "ge", "ge"),
        ("structured", "ge", "sge"),
        ("trees", "ge", "cfg-gp"),
    ]
    assert list(rows[0])[:4] == ["arm", "strategy", "representation", "runs"]
    tex = (tmp_path / "rep" / "tables.tex").read_text()
    assert "\\begin{tabular}{llrrrrrrr}" in tex
    assert "Arm & Representation & Runs &" in tex
    assert "structured & sge & 2 &" in tex
    assert "trees & cfg-gp & 2 &" in tex

    ge_only = runner.invoke(app, ["report", str(tmp_path / "out/arms/plain"), "-o", str(tmp_path / "ge")])
    assert ge_only.exit_code == 0, ge_only.stderr
    assert "representation" not in (tmp_path / "ge" / "summary.md").read_text()
    for name in ("summary.md", "summary.json", "summary.csv"):
        assert "representation" not in (tmp_path / "ge" / name).read_text()
    assert "Representation" not in (tmp_path / "ge" / "tables.tex").read_text()
