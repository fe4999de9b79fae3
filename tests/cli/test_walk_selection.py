"""``evaluate``/``render --run DIR --walk``: the best walk a run hands back, which the weighted
fitness may rank below its best gait, re-scored through the run's own pipeline.

The runs are made here, short, on the horse: GE on the hybrid grammar under the paper's weights
(seed 0: its best gait is no walk, its final population holds one), MAP-Elites and NSGA-II (seed 2:
their repertoire and front hold walks).
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

runner = CliRunner()
#: Every test here reads the three horse runs the module's fixture makes.
pytestmark = pytest.mark.slow
PAPER_WEIGHTS = (
    'backend = "mujoco-horse"\n[backend_settings]\n'
    "weights = { velocity = 1.0, duty_factor = 1.0, stride = 1.0, frequency = 0.0, energy = 1.0 }\n"
)


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    base = tmp_path_factory.mktemp("walks")
    (base / "paper.toml").write_text(PAPER_WEIGHTS)
    made = {
        "ge": ("ge", 0, ["-c", str(base / "paper.toml")]),
        "map-elites": ("map-elites", 2, []),
        "nsga2": ("nsga2", 2, []),
    }
    for name, (strategy, seed, extra) in made.items():
        result = runner.invoke(
            app,
            [
                "evolve",
                str(GRAMMARS / "hybrid.gg"),
                *extra,
                "--generations",
                "2",
                "--population",
                "16",
                "--seed",
                str(seed),
                "--strategy",
                strategy,
                "-o",
                str(base / name),
                "-q",
            ],
        )
        assert result.exit_code == 0, result.output
    return base


@pytest.fixture
def arm(runs: Path, tmp_path: Path) -> Path:
    """A copy of the GE run, free to edit."""
    return Path(shutil.copytree(runs / "ge", tmp_path / "arm"))


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
    assert record["components"]["checked_cycles"] == 20.0
    assert record["fitness"] == record["recorded_fitness"]
    assert (record["run"], record["gait"]) == (0, f"{arm} run 0, best walk, generation 2")
    assert "horizon" not in record
    assert record["fitness"] > json.loads(best.stdout)["fitness"]  # ranked below the best gait
    walkers = [g for g in population(arm, 0) if g["evaluation"]["components"]["walk"] == 1.0]
    assert [record["genome"]] == [g["genome"] for g in walkers]
    table = runner.invoke(app, ["evaluate", "--run", str(arm), "--walk"])
    assert "run 0, best walk, generation 2" in table.stderr
    longer = evaluate("--run", str(arm), "--walk", "--horizon", "40")  # does it stay a walk?
    held = json.loads(longer.stdout)
    assert (held["run"], held["horizon"]) == (0, 40)  # which gait, checked over what
    assert longer.exit_code == (0 if held["status"] == "ok" else 1), longer.stderr
    if held["status"] == "ok":
        assert (held["fitness"], held["components"]["checked_cycles"]) == (record["fitness"], 40.0)


def test_a_kept_front_is_what_the_run_hands_back(arm: Path) -> None:
    gaits = population(arm, 0)
    walker = next(g for g in gaits if g["evaluation"]["components"]["walk"] == 1.0)
    others = [g for g in gaits if g["evaluation"]["components"]["walk"] == 0.0]

    def keep(members: list[dict]) -> None:
        front = [{"genome": g["genome"], **g["evaluation"]} for g in members]
        (arm / "run-000" / "front.json").write_text(json.dumps({"objectives": [], "front": front}))

    keep(others[:3])  # the population holds a walk, but this front does not
    refused = evaluate("--run", str(arm), "--walk")
    assert refused.exit_code == 2
    assert "hands back a walk" in refused.stderr
    recorded = walker["evaluation"]["fitness"]
    walker["evaluation"]["fitness"] = recorded / 2  # a record edited by hand is caught by re-scoring
    keep([walker])
    tampered = evaluate("--run", str(arm), "--walk")
    assert tampered.exit_code == 2
    assert f"re-scoring gives fitness {recorded!r}" in tampered.stderr
    (arm / "run-000" / "front.json").write_text(json.dumps({"front": [{"components": {}, "genome": "x"}]}))
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
    assert "run 0, best walk" in walk.stderr
    best = subprocess.run([*command, "-o", "best.gif"], cwd=tmp_path, capture_output=True, text=True, env=env)
    assert best.returncode == 0, best.stderr
    assert (tmp_path / "walk.gif").read_bytes() != (tmp_path / "best.gif").read_bytes()  # another gait


@pytest.mark.parametrize(
    ("name", "file", "key"), [("map-elites", "archive.json", "elites"), ("nsga2", "front.json", "front")]
)
def test_walk_reads_a_real_repertoire_and_front(runs: Path, name: str, file: str, key: str) -> None:
    """MAP-Elites hands back its repertoire and NSGA-II its front: the best walk in them, re-scored,
    reproduces the recorded evaluation; every member was checked over the horizon."""
    kept = json.loads((runs / name / "run-000" / file).read_text())[key]
    assert all(member["components"]["checked_cycles"] == 20.0 for member in kept)
    walks = [member for member in kept if member["components"]["walk"] == 1.0]
    assert walks
    result = evaluate("--run", str(runs / name), "--walk")
    assert result.exit_code == 0, result.stderr
    record = json.loads(result.stdout)
    assert record["components"]["walk"] == 1.0
    assert record["fitness"] == record["recorded_fitness"] == min(member["fitness"] for member in walks)
    assert record["genome"] == min(walks, key=lambda member: member["fitness"])["genome"]
