"""Runs scored under another fitness revision: never re-scored, resumed or mixed with today's.

The committed studies under docs/results were scored under fitness revision 3 (and 2); this
gaitgram scores revision 4. Re-scoring one of their runs would score it differently, so
``evaluate`` refuses, saying which revisions; ``report`` refuses to put arms scored differently
in one table.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from gaitgram.backends.mujoco_horse.targets import TASK_REVISION
from gaitgram.cli import app

ROOT = Path(__file__).resolve().parents[2]
OLD_ARM = ROOT / "docs/results/revision-3/strategies/runs/arms/ge-hybrid"
runner = CliRunner()
pytestmark = pytest.mark.skipif(
    not OLD_ARM.is_dir(), reason="the committed study runs are not in this source tree (the sdist omits them)"
)


def test_the_committed_runs_are_revision_3_and_this_gaitgram_scores_4() -> None:
    manifest = json.loads((OLD_ARM / "manifest.json").read_text())
    assert "fitness r3," in manifest["backend_version"]
    assert TASK_REVISION == 4


def test_a_revision_3_run_is_not_rescored(tmp_path: Path) -> None:
    result = runner.invoke(app, ["evaluate", "--run", str(OLD_ARM)])
    assert result.exit_code == 2
    message = " ".join(result.stderr.split())
    assert "fitness r3" in message
    assert f"fitness r{TASK_REVISION}" in message
    assert "could score differently" in message
    assert "Traceback" not in result.output


def test_a_report_refuses_arms_scored_under_different_revisions(tmp_path: Path) -> None:
    new = tmp_path / "new"
    made = runner.invoke(
        app,
        [
            "evolve",
            str(ROOT / "grammars/hybrid.gg"),
            "--generations",
            "1",
            "--population",
            "10",
            "-o",
            str(new),
            "-q",
        ],
    )
    assert made.exit_code == 0, made.output
    # The committed arm as it is (another budget too: the scoring is refused first, and named).
    result = runner.invoke(app, ["report", str(new), str(OLD_ARM), "-o", str(tmp_path / "report")])
    assert result.exit_code == 2, result.output
    message = " ".join(result.stderr.split())
    assert "scored differently" in message
    assert "fitness r3" in message
    assert f"fitness r{TASK_REVISION}" in message
    assert not (tmp_path / "report").exists()
