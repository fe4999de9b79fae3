"""``evaluate``/``render --run DIR --walk``: the best walk a run hands back, which the weighted
fitness may rank below its best gait, re-scored through the run's own pipeline.

The runs are the committed CMA-ES arm of docs/results/strategies: none of its best gaits is a walk,
yet most of its final populations hold one.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.cli import app

ARM = Path(__file__).resolve().parents[2] / "docs/results/strategies/runs/arms/cma-es-numerical"
runner = CliRunner()
pytestmark = pytest.mark.skipif(
    not ARM.is_dir(), reason="the committed study runs are not in this source tree (the sdist omits them)"
)


@pytest.fixture
def arm(tmp_path: Path) -> Path:
    """Runs 5-7 of the arm: 5 has the best gait and no walk, 6 the best walk (0.3093)."""
    copy = tmp_path / "arm"
    copy.mkdir()
    for name in ("config.toml", "grammar.gg", "manifest.json"):
        shutil.copy(ARM / name, copy / name)
    for run in (5, 6, 7):
        shutil.copytree(ARM / f"run-{run:03d}", copy / f"run-{run:03d}")
    return copy


def evaluate(*args: str):
    return runner.invoke(app, ["evaluate", *args, "--json"])


def population(arm: Path, run: int) -> list[dict]:
    return json.loads((arm / f"run-{run:03d}" / "checkpoint.json").read_text())["checkpoint"]["population"]


def test_walk_picks_the_best_walk_where_the_best_gait_is_none(arm: Path) -> None:
    best = evaluate("--run", str(arm))
    assert best.exit_code == 0, best.stderr
    assert json.loads(best.stdout)["components"]["walk"] == 0.0
    walk = evaluate("--run", str(arm), "--walk")
    assert walk.exit_code == 0, walk.stderr
    record = json.loads(walk.stdout)
    assert record["components"]["walk"] == 1.0
    assert record["fitness"] == record["recorded_fitness"] == pytest.approx(0.309275, abs=1e-6)
    assert record["fitness"] > json.loads(best.stdout)["fitness"]  # ranked below the best gait
    walkers = [g for g in population(arm, 6) if g["evaluation"]["components"]["walk"] == 1.0]
    assert [record["genome"]] == [g["genome"] for g in walkers]
    table = runner.invoke(app, ["evaluate", "--run", str(arm), "--walk"])
    assert "run 6, best walk, generation 50" in table.stderr


def test_a_kept_front_is_what_the_run_hands_back(arm: Path) -> None:
    gaits = population(arm, 6)
    walker = next(g for g in gaits if g["evaluation"]["components"]["walk"] == 1.0)
    others = [g for g in gaits if g["evaluation"]["components"]["walk"] == 0.0]

    def keep(members: list[dict]) -> None:
        front = [{"genome": g["genome"], **g["evaluation"]} for g in members]
        (arm / "run-006" / "front.json").write_text(json.dumps({"objectives": [], "front": front}))

    keep(others[:3])  # run 6's population holds a walk, but its front does not
    refused = evaluate("--run", str(arm), "--walk")
    assert refused.exit_code == 2
    assert "hands back a walk" in refused.stderr
    walker["evaluation"]["fitness"] = 0.25  # a record edited by hand is caught by re-scoring
    keep([walker])
    tampered = evaluate("--run", str(arm), "--walk")
    assert tampered.exit_code == 2
    assert "re-scoring gives fitness 0.309" in tampered.stderr
    (arm / "run-006" / "front.json").write_text(json.dumps({"front": [{"components": {}, "genome": "x"}]}))
    malformed = evaluate("--run", str(arm), "--walk")
    assert malformed.exit_code == 2
    assert "front.json" in malformed.stderr
    assert "Traceback" not in malformed.stderr


def test_walk_needs_a_run_and_no_genome(arm: Path) -> None:
    alone = evaluate(str(GRAMMARS / "numerical.gg"), "--genome", "1,2,3", "--walk")
    assert alone.exit_code == 2
    assert "give --run DIR" in alone.stderr
    both = evaluate("--run", str(arm), "--walk", "--genome", "1,2,3")
    assert both.exit_code == 2
    assert "drop --genome" in both.stderr


def test_render_shows_the_best_walk(arm: Path, tmp_path: Path) -> None:
    pytest.importorskip("PIL", reason="Pillow is not installed (pip install 'gaitgram[plot]')")
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    command = [sys.executable, "-m", "gaitgram", "render", "--run", str(arm), "--fps", "4"]
    walk = subprocess.run(
        [*command, "--walk", "-o", "walk.gif"], cwd=tmp_path, capture_output=True, text=True, env=env
    )
    assert walk.returncode == 0, walk.stderr
    assert "run 6, best walk" in walk.stderr
    best = subprocess.run([*command, "-o", "best.gif"], cwd=tmp_path, capture_output=True, text=True, env=env)
    assert best.returncode == 0, best.stderr
    assert (tmp_path / "walk.gif").read_bytes() != (tmp_path / "best.gif").read_bytes()  # another gait


def test_walk_reads_a_real_repertoire(tmp_path: Path) -> None:
    """MAP-Elites hands back its repertoire: run 12 of the committed arm holds the best walk in its
    archive.json, and re-scoring it reproduces the recorded evaluation."""
    source = ARM.parents[3] / "multi-objective/runs/arms/map-elites-hybrid"
    copy = tmp_path / "arm"
    copy.mkdir()
    for name in ("config.toml", "grammar.gg", "manifest.json"):
        shutil.copy(source / name, copy / name)
    shutil.copytree(source / "run-012", copy / "run-012")
    archive = json.loads((copy / "run-012" / "archive.json").read_text())["elites"]
    walks = [cell for cell in archive if cell["components"]["walk"] == 1.0]
    result = evaluate("--run", str(copy), "--walk")
    assert result.exit_code == 0, result.stderr
    record = json.loads(result.stdout)
    assert record["components"]["walk"] == 1.0
    assert record["fitness"] == record["recorded_fitness"] == min(cell["fitness"] for cell in walks)
    assert record["genome"] == min(walks, key=lambda cell: cell["fitness"])["genome"]
