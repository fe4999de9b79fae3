"""The README's quickstart, run as written: its three gaitgram commands in a fresh directory (the
two set-up commands before them are what a clone needs, and CI runs them). It hands back a best gait
that is a walk by the backend's criterion and goes on walking over 40 cycles; ``evolve`` and
``render`` say so, and ``report`` prints no more than a screen."""

from __future__ import annotations

import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import ROOT
from gaitgram.backends.mujoco_horse.targets import WALK_CRITERION
from gaitgram.cli import app

SETUP = ("python3 -m venv .venv", ".venv/bin/pip install -q -e '.[dev]'")
GAITGRAM = ".venv/bin/gaitgram "


def readme_commands() -> list[str]:
    """Each ``sh`` block of the README, as one line."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    return [block.strip() for block in re.findall(r"```sh\n(.*?)```", readme, flags=re.DOTALL)]


def quickstart() -> list[list[str]]:
    """The arguments of each gaitgram command of the README's quickstart, in order."""
    line = readme_commands()[0]
    steps = line.split(" && ")
    assert tuple(steps[:2]) == SETUP, line
    assert all(step.startswith(GAITGRAM) for step in steps[2:]), line
    return [shlex.split(step.removeprefix(GAITGRAM)) for step in steps[2:]]


def test_the_readme_has_two_set_up_commands_the_quickstart_and_the_tests() -> None:
    commands = readme_commands()
    assert [c for c in commands if c.startswith(" && ".join(SETUP))] == commands[:2]
    assert commands[1] == " && ".join(SETUP) + " && .venv/bin/python -m pytest"
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert commands[1] in ci.splitlines()  # CI runs the README's test command, verbatim


@pytest.fixture(scope="module")
def ran(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[subprocess.CompletedProcess[str]]]:
    """The quickstart's gaitgram commands run in a directory of their own, as from a clone (the
    bundled grammars where the README's paths say)."""
    here = tmp_path_factory.mktemp("clone")
    (here / "grammars").symlink_to(ROOT / "grammars")
    done = []
    for args in quickstart():
        result = subprocess.run(
            [sys.executable, "-m", "gaitgram", *args], cwd=here, capture_output=True, text=True, check=False
        )
        assert result.returncode == 0, f"gaitgram {shlex.join(args)}:\n{result.stderr}"
        done.append(result)
    return here, done


def run_directory(here: Path) -> Path:
    evolve = quickstart()[0]
    assert evolve[0] == "evolve"
    return here / evolve[evolve.index("-o") + 1]


def test_the_quickstart_evolves_a_walk_and_says_so(ran) -> None:
    _, (evolve, _, render) = ran
    said = f"a walk by criterion {WALK_CRITERION}"
    assert evolve.stderr.splitlines()[-1] == f"the best gait is {said}"
    assert render.stderr.splitlines()[-1] == f"the gait shown is {said}"


def test_the_quickstarts_best_gait_walks_on_over_40_cycles(ran) -> None:
    here, _ = ran
    result = CliRunner().invoke(
        app, ["evaluate", "--run", str(run_directory(here)), "--horizon", "40", "--json"]
    )
    assert result.exit_code == 0, result.output
    scored = json.loads(result.stdout)
    assert scored["status"] == "ok"
    assert scored["components"]["checked_cycles"] == 40.0
    assert scored["components"]["walk"] == 1.0  # every term, in every cycle of the 40
    assert scored["fitness"] == scored["recorded_fitness"]


def test_the_quickstarts_report_fits_a_screen_and_writes_the_rest(ran) -> None:
    here, (_, report, _) = ran
    printed = report.stdout.splitlines()
    assert 0 < len(printed) <= 40, report.stdout
    assert "n/a" not in report.stdout  # no rank test of one arm printed empty
    assert "| avg. average |" not in report.stdout
    assert "| avg. average |" in (run_directory(here) / "report" / "summary.md").read_text()
    assert (run_directory(here) / "best.gif").read_bytes().startswith(b"GIF8")
