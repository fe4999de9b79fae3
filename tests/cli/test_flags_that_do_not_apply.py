"""Flags that do not apply are refused or said, never silently ignored: a report of curve-match runs
asked to assess or animate their gaits, a cell of a repertoire no arm keeps (or given with the
wrong number of indices), ``--interval`` without ``--watch``, ``retarget --each-run`` to a body the
backend lacks, a scaling asked for twice; and ``render --set``, which docs/bodies.md promises.

Each refusal is exit 2, one line naming the flag, before anything is written or simulated.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_TARGETS_TOML, GRAMMARS
from gaitgram.cli import app

runner = CliRunner()
SINE_WALK = GRAMMARS / "sine-walk.gg"
GENOME = ["--genome", "5,17,3,99,1000,42,7,8,9,10,11,12,13", "--max-wraps", "10"]
CURVE = 'generations = 1\npopulation = 8\nelite = 1\nbackend = "curve-match"\n[backend_settings.targets]\n'
REPERTOIRE = """
[strategy_settings]
descriptors = [
  { name = "rms_hip_hind", low = 0.0, high = 12.0, bins = 3 },
  { name = "rms_elbow_fore", low = 0.0, high = 12.0, bins = 3 },
]
"""
#: A run on the horse small enough to take a second: four gaits, one generation, no walk among them.
TINY_HORSE = "generations = 1\npopulation = 4\nelite = 1\nruns = 1\n"


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def evolve(where: Path, name: str, grammar: Path, config: str, *flags: str) -> Path:
    (where / f"{name}.toml").write_text(config)
    done = runner.invoke(app, ["evolve", str(grammar), "-c", f"{name}.toml", *flags, "-o", name, "-q"])
    assert done.exit_code == 0, done.stderr
    return where / name


def refused(args: list[str], message: str) -> None:
    done = runner.invoke(app, args)
    assert done.exit_code == 2, (args, done.stderr)
    assert done.stderr == f"error: {message}\n", args


def test_report_refuses_what_curve_match_runs_give_nothing_to(here: Path) -> None:
    """Today each of these printed the report as without the flag, exit 0."""
    (here / "curve.gg").write_text(CURVE_GRAMMAR)
    evolve(here, "plain", here / "curve.gg", CURVE + CURVE_TARGETS_TOML)
    evolve(
        here, "cells", here / "curve.gg", CURVE + CURVE_TARGETS_TOML + REPERTOIRE, "--strategy", "map-elites"
    )
    scored = "plain: curve-match"
    done = runner.invoke(app, ["report", "plain", "-o", "out", "--assess"])
    assert done.exit_code == 2
    assert done.stderr.startswith("error: --assess measures the best gaits of mujoco-horse runs")
    assert f"these arms were scored otherwise ({scored}" in done.stderr
    assert done.stderr.endswith("): drop --assess\n")
    done = runner.invoke(app, ["report", "plain", "-o", "out", "--gaits", "2"])
    assert done.exit_code == 2
    assert done.stderr.startswith("error: --gaits 2: gaits are drawn on the mujoco-horse backend; these arms")
    assert done.stderr.endswith("): drop --gaits\n")
    refused(
        ["report", "plain", "-o", "out", "--cell", "0,0"],
        "--cell picks a cell of a map-elites arm's repertoire; no arm here keeps one (plain: ge): "
        "drop --cell",
    )
    refused(
        ["report", "cells", "-o", "out", "--cell", "1"],
        "--cell 1: the repertoire of arm cells has 2 descriptor(s) (rms_hip_hind, rms_elbow_fore); give a "
        "cell as I,J",
    )
    done = runner.invoke(app, ["report", "cells", "-o", "out", "--cell", "0,0"])
    assert done.exit_code == 2
    assert done.stderr.startswith("error: --cell 0,0: gaits are drawn on the mujoco-horse backend")
    refused(
        ["report", "plain", "-o", "out", "--interval", "5"],
        "--interval is how often --watch looks for finished runs; add --watch, or drop --interval",
    )
    assert not (here / "out").exists()


def test_report_says_when_gaits_finds_nothing_to_animate(here: Path) -> None:
    """A horse run whose gaits hold no walk: --gaits applies (the backend draws) but finds nothing,
    and says so rather than print the same report in silence."""
    evolve(here, "horse", SINE_WALK, TINY_HORSE)
    plain = runner.invoke(app, ["report", "horse", "-o", "plain"])
    asked = runner.invoke(app, ["report", "horse", "-o", "asked", "--gaits", "1"])
    assert asked.exit_code == 0, asked.stderr
    assert asked.stdout == plain.stdout
    assert "--gaits 1: no arm hands back a walk, a Pareto front or a repertoire; nothing to animate" in (
        asked.stderr
    )
    assert not list((here / "asked").glob("*.gif"))


def test_retarget_refuses_bodies_and_scalings_before_playing(here: Path) -> None:
    """--each-run checks the body as the single-gait path does (today it printed JSON of zero
    playings, exit 0); a scaling asked for twice is refused rather than simulated twice."""
    (here / "curve.gg").write_text(CURVE_GRAMMAR)
    evolve(here, "plain", here / "curve.gg", CURVE + CURVE_TARGETS_TOML)
    for body in ("nosuchbody", "pony"):
        refused(
            ["retarget", "--run", "plain", "--to", body, "--each-run", "--json"],
            "backend 'curve-match' has one body: its gaits cannot be retargeted",
        )
    evolve(here, "horse", SINE_WALK, TINY_HORSE)
    refused(
        ["retarget", "--run", "horse", "--to", "nosuchbody", "--each-run"],
        "backend 'mujoco-horse': no body is called 'nosuchbody'; the bodies are horse, shetland, pony, draft",
    )
    refused(
        ["retarget", "--run", "horse", "--to", "pony", "--each-run", "--scaling", "nosuch"],
        "no frequency scaling 'nosuch'; 'mujoco-horse' knows froude, unscaled",
    )
    for each in ([], ["--each-run"]):
        refused(
            [
                "retarget",
                "--run",
                "horse",
                "--to",
                "pony",
                *each,
                "--scaling",
                "froude",
                "--scaling",
                "froude",
            ],
            "--scaling froude is given twice; each scaling is played once, give it once",
        )


def gaitgram(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    """In a process of its own: rendering needs MuJoCo's offscreen OpenGL chosen before it loads."""
    env = {**os.environ, "MUJOCO_GL": "egl", "NO_COLOR": "1", "COLUMNS": "300"}
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )


def test_render_takes_set_as_evaluate_does(here: Path) -> None:
    """docs/bodies.md: ``render --set body=pony`` plays the gait on the pony (another animation
    than the horse's); an unknown setting value is refused naming it; with --run, --set is refused
    as evaluate refuses it (the run's own settings are its pipeline)."""
    render = ["render", str(SINE_WALK), *GENOME, "--fps", "2"]
    horse = gaitgram(*render, "-o", "horse.gif", cwd=here)
    pony = gaitgram(*render, "-o", "pony.gif", "--set", "body=pony", cwd=here)
    assert horse.returncode == 0, horse.stderr
    assert pony.returncode == 0, pony.stderr
    assert (here / "pony.gif").read_bytes()[:6] == b"GIF89a"
    assert (here / "pony.gif").read_bytes() != (here / "horse.gif").read_bytes()
    wrong = gaitgram(*render, "-o", "none.gif", "--set", "body=nosuchbody", cwd=here)
    assert wrong.returncode == 2
    assert "body" in wrong.stderr
    assert "nosuchbody" in wrong.stderr
    assert not (here / "none.gif").exists()
    evolve(here, "run", SINE_WALK, TINY_HORSE)
    refused(
        ["render", "--run", "run", "-o", "run.gif", "--set", "body=pony"],
        "--run run uses the run's own grammar, configuration and backend settings; drop --set (or evaluate "
        "the grammar on its own, without --run)",
    )
