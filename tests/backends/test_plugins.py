"""A third-party backend, found through its entry point, checked and evolved against.

The example package in tests/data/plugin_example is made importable with a
``.dist-info`` beside it, exactly what ``pip install`` would leave, so the real
entry-point discovery runs in a fresh process.
"""

from __future__ import annotations

import json
import math
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
        "neck-drawn = gaitgram_example_backend.drawn:BACKEND\n"
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


def test_a_plugin_s_gaits_are_drawn_and_assessed_through_its_hooks(
    plugin_env: dict[str, str], tmp_path: Path
) -> None:
    """``neck-drawn`` (tests/data/plugin_example/.../drawn.py) declares render, assess and assessment
    hooks and a verdict: ``gaitgram render`` draws its gait with its frames, ``report --assess
    --gaits 1`` keeps its assessments, shows its realism and robustness sections as it declares
    them and animates its best "walk" (a swinging neck). Nothing above the backends knows it."""
    from PIL import Image

    (tmp_path / "g.gg").write_text(GRAMMAR.replace("@backend neck-swing", "@backend neck-drawn"))
    config = tmp_path / "run.toml"
    config.write_text(
        "generations = 15\npopulation = 20\nelite = 2\ninit_max_depth = 5\nruns = 2\n\n"
        "[backend_settings]\ntarget_amplitude = 25\n"
    )
    run = gaitgram(plugin_env, "evolve", "g.gg", "-c", str(config), "-o", "out", "-q", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    best = json.loads((tmp_path / "out" / "run-000" / "best.json").read_text())
    assert best["joints"]["neck"] == "25*sin(2*PI*t)"

    drawn = gaitgram(plugin_env, "render", "--run", "out", "-o", "neck.gif", "--fps", "7", cwd=tmp_path)
    assert drawn.returncode == 0, drawn.stderr
    gif = Image.open(tmp_path / "neck.gif")
    assert "wrote neck.gif (14 frames)" in drawn.stderr  # the hook's: 7 a second, over 2 cycles
    assert (gif.n_frames, gif.size) == (14, (480, 360))  # no two alike in a row, so GIF keeps each
    for k in range(gif.n_frames):  # the bar sits where the best gait's neck is at that frame
        gif.seek(k)
        dark = [x for x in range(480) if gif.convert("L").getpixel((x, 180)) < 128]
        expected = 240 + 25 * math.sin(2 * math.pi * k / 7) / 40 * 240
        assert abs((dark[0] + dark[-1] + 1) / 2 - expected) <= 1.5, (k, dark)

    seed = gaitgram(plugin_env, "render", "--run", "out", "--compare", "seed", "-o", "x.gif", cwd=tmp_path)
    assert seed.returncode == 2
    assert "--compare seed: the walk seed drives scapula_fore" in seed.stderr
    assert "which backend 'neck-drawn' lacks" in seed.stderr
    assert not (tmp_path / "x.gif").exists()

    report = gaitgram(plugin_env, "report", "out", "-o", "report", "--assess", "--gaits", "1", cwd=tmp_path)
    assert report.returncode == 0, report.stderr
    kept = json.loads((tmp_path / "out" / "run-000" / "assessment.json").read_text())
    assert (kept["backend"], kept["genome"]) == ("neck-drawn", best["genome"])
    assert kept["realism"]["measures"]["amplitude"] == pytest.approx(25.0, abs=0.2)
    summary = (tmp_path / "report" / "summary.md").read_text()
    assert "**Necks beside a metronome** (each run's best gait)" in summary
    assert "| neck amplitude (deg) | 30 | a metronome's |" in summary
    assert "| neck: furthest forward (deg) | 30 | a metronome's |" in summary
    assert "holds: gust" in summary
    assert Image.open(tmp_path / "report" / "walk-out.gif").n_frames == 24  # the gallery's 12 fps, 2 cycles
    assert (tmp_path / "report" / "realism.png").read_bytes()[:4] == b"\x89PNG"  # one curve, one panel
