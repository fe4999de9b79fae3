"""A third-party backend, found through its entry point, checked and evolved against.

The example package in tests/data/plugin_example is made importable with a
``.dist-info`` beside it, exactly what ``pip install`` would leave, so the real
entry-point discovery runs in a fresh process.
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
@backend neck-swing
<gait> ::= <neck>;<tail>
@joint neck limits=-40..40
<neck> ::= <a>*sin(2*PI*t)
@joint tail
<tail> ::= 0
<a> ::= int[0..40]
"""


@pytest.fixture
def plugin_env(tmp_path: Path) -> dict[str, str]:
    info = tmp_path / "gaitgram_example_backend-0.1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: gaitgram-example-backend\nVersion: 0.1.0\n")
    (info / "entry_points.txt").write_text(
        "[gaitgram.backends]\nneck-swing = gaitgram_example_backend:BACKEND\n"
        "crash-once = gaitgram_example_backend.crash_once:BACKEND\n"
    )
    path = os.pathsep.join([str(tmp_path), str(EXAMPLE), os.environ.get("PYTHONPATH", "")])
    return {**os.environ, "PYTHONPATH": path}


def gaitgram(env: dict[str, str], *args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True, env=env, cwd=cwd
    )


def test_plugin_joints_are_checked(plugin_env: dict[str, str], tmp_path: Path) -> None:
    good = tmp_path / "good.gg"
    good.write_text(GRAMMAR)
    assert gaitgram(plugin_env, "check", "--strict", str(good), cwd=tmp_path).returncode == 0
    bad = tmp_path / "bad.gg"
    bad.write_text(GRAMMAR.replace("@joint tail", "@joint tial").replace("limits=-40..40", "limits=-90..90"))
    run = gaitgram(plugin_env, "check", "-f", "json", str(bad), cwd=tmp_path)
    codes = {d["code"]: d for d in json.loads(run.stdout)}
    assert "did you mean tail?" in codes["GG502"]["hint"]
    assert "GG506" in codes  # limits wider than the backend's
    assert "GG503" in codes  # the tail now has no curve


def test_plugin_evolves(plugin_env: dict[str, str], tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    config = tmp_path / "run.toml"
    config.write_text(
        "generations = 15\npopulation = 20\nelite = 2\ninit_max_depth = 5\n\n"
        "[backend_settings]\ntarget_amplitude = 25\n"
    )
    run = gaitgram(plugin_env, "evolve", "g.gg", "-c", str(config), "-o", "out", "-q", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    best = json.loads((tmp_path / "out" / "run-000" / "best.json").read_text())
    assert best["fitness"] == pytest.approx(0.0, abs=1e-9)
    assert best["joints"]["neck"] == "25*sin(2*PI*t)"


def test_unknown_backend_is_a_clear_error(tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    run = gaitgram(dict(os.environ), "evolve", "g.gg", "-o", "out", "-q", cwd=tmp_path)
    assert run.returncode != 0
    assert "GG501" in run.stderr or "no backend named 'neck-swing'" in run.stderr
    assert "Traceback" not in run.stderr


@pytest.mark.slow  # a real Dask cluster
def test_a_lost_dask_worker_is_retried(plugin_env: dict[str, str], tmp_path: Path) -> None:
    pytest.importorskip("distributed", reason="Dask is an optional extra; the dev extra installs it")
    (tmp_path / "g.gg").write_text("<g> ::= <hip>\n@joint hip\n<hip> ::= int[0..20]*sin(2*PI*t)\n")
    marker = tmp_path / "crashed"
    settings = f'[backend_settings]\nmarker = "{marker}"\n[backend_settings.targets]\nhip = "7*sin(2*PI*t)"\n'
    config = tmp_path / "run.toml"
    config.write_text(f'generations = 3\npopulation = 12\nelite = 1\nbackend = "crash-once"\n{settings}')
    lost = gaitgram(
        plugin_env, "evolve", "g.gg", "-c", str(config), "-o", "dask", "-q", "--dask-local", "2", cwd=tmp_path
    )
    assert lost.returncode == 0, lost.stderr
    assert marker.exists()  # a worker really died
    local = gaitgram(plugin_env, "evolve", "g.gg", "-c", str(config), "-o", "local", "-q", cwd=tmp_path)
    assert local.returncode == 0, local.stderr
    assert (tmp_path / "dask/run-000/stats.csv").read_text() == (
        tmp_path / "local/run-000/stats.csv"
    ).read_text()
