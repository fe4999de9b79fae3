"""A third-party search strategy, found through its entry point, checked and run.

The example package in tests/data/plugin_example is made importable with a ``.dist-info`` beside
it, as ``pip install`` would leave it, so the real entry-point discovery runs in a fresh process.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

EXAMPLE = ROOT / "tests" / "data" / "plugin_example"

GRAMMAR = """\
<gait> ::= <hip>
@joint hip_hind
<hip> ::= <amp>*sin(2*PI*t+<phase>)
<amp> ::= int[0..20]
<phase> ::= float[0..3 step 0.5]
"""
CONFIG = """\
generations = {generations}
population = 16
elite = 2
init_max_depth = 5
backend = "curve-match"
strategy = "hill-climb"

[backend_settings.targets]
hip_hind = "7*sin(2*PI*t+1.5)"

[strategy_settings]
rate = 0.2
"""


@pytest.fixture
def plugin_env(tmp_path: Path) -> dict[str, str]:
    info = tmp_path / "site" / "gaitgram_example_backend-0.1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: gaitgram-example-backend\nVersion: 0.1.0\n")
    (info / "entry_points.txt").write_text(
        "[gaitgram.strategies]\nhill-climb = gaitgram_example_backend.hill_climb:STRATEGY\n"
    )
    path = os.pathsep.join([str(tmp_path / "site"), str(EXAMPLE), os.environ.get("PYTHONPATH", "")])
    return {**os.environ, "PYTHONPATH": path}


def gaitgram(env: dict[str, str], *args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True, env=env, cwd=cwd
    )


def test_a_plugin_strategy_is_found_and_runs(plugin_env: dict[str, str], tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    (tmp_path / "run.toml").write_text(CONFIG.format(generations=12))
    whole = gaitgram(plugin_env, "evolve", "g.gg", "-c", "run.toml", "-o", "whole", "-q", cwd=tmp_path)
    assert whole.returncode == 0, whole.stderr
    stats = [json.loads(line) for line in (tmp_path / "whole/run-000/stats.jsonl").read_text().splitlines()]
    assert stats[-1]["best"] < stats[0]["best"]
    assert [s["evaluations"] for s in stats[:2]] == [16, 14]
    assert "hill-climb r1" in (tmp_path / "whole" / "manifest.json").read_text()
    assert "rate = 0.2" in (tmp_path / "whole" / "config.toml").read_text()


def test_a_plugin_strategys_settings_are_checked(plugin_env: dict[str, str], tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    (tmp_path / "run.toml").write_text(CONFIG.format(generations=2).replace("rate = 0.2", "rate = 2"))
    bad = gaitgram(plugin_env, "evolve", "g.gg", "-c", "run.toml", "-o", "out", "-q", cwd=tmp_path)
    assert bad.returncode == 2
    assert "[strategy_settings] rate: must be a number in (0, 1], not 2" in bad.stderr
    assert not (tmp_path / "out").exists()
    unknown = gaitgram(dict(os.environ), "evolve", "g.gg", "-c", "run.toml", "-o", "out", "-q", cwd=tmp_path)
    assert unknown.returncode == 2
    assert "no strategy named 'hill-climb'" in unknown.stderr
    assert "Traceback" not in unknown.stderr
