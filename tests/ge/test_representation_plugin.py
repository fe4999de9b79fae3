"""A third-party representation, found through its entry point, evolved and mapped; and the built-in
ones declared as entry points as the built-in backends and strategies are.

The example package in tests/data/plugin_example is made importable with a ``.dist-info`` beside
it, as ``pip install`` would leave it, so the real entry-point discovery runs in a fresh process.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from conftest import ROOT
from gaitgram.backends.registry import BUILTIN as BACKENDS
from gaitgram.ge.registry import BUILTIN as REPRESENTATIONS
from gaitgram.ge.registry import get_representation
from gaitgram.strategies.registry import BUILTIN as STRATEGIES

EXAMPLE = ROOT / "tests" / "data" / "plugin_example"

GRAMMAR = """\
<gait> ::= <hip>
@joint hip_hind
<hip> ::= <amp>*sin(2*PI*t+<phase>)
<amp> ::= int[0..20]
<phase> ::= float[0..3 step 0.5]
"""
CONFIG = """\
generations = 10
population = 16
elite = 2
backend = "curve-match"

[backend_settings.targets]
hip_hind = "13*sin(2*PI*t+2.5)"

[representation_settings]
length = 8
"""


def test_the_builtin_representations_are_declared_entry_points() -> None:
    """pyproject.toml declares every built-in plug-in (what an installed gaitgram lists), and the
    registries' built-ins, found without scanning entry points, are the same ones."""
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["entry-points"]
    assert declared["gaitgram.representations"] == REPRESENTATIONS
    assert declared["gaitgram.strategies"] == STRATEGIES
    assert declared["gaitgram.backends"] == BACKENDS


@pytest.fixture
def plugin_env(tmp_path: Path) -> dict[str, str]:
    info = tmp_path / "site" / "gaitgram_example_backend-0.1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: gaitgram-example-backend\nVersion: 0.1.0\n")
    (info / "entry_points.txt").write_text(
        "[gaitgram.representations]\nfixed-ge = gaitgram_example_backend.fixed_ge:REPRESENTATION\n"
    )
    path = os.pathsep.join([str(tmp_path / "site"), str(EXAMPLE), os.environ.get("PYTHONPATH", "")])
    return {**os.environ, "PYTHONPATH": path}


def gaitgram(env: dict[str, str], *args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True, env=env, cwd=cwd
    )


def test_a_plugin_representation_evolves_and_maps(plugin_env: dict[str, str], tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    (tmp_path / "run.toml").write_text(CONFIG)
    run = gaitgram(
        plugin_env, "evolve", "g.gg", "-c", "run.toml", "--representation", "fixed-ge", "-o", "out", "-q",
        cwd=tmp_path,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    out = tmp_path / "out"
    stats = [json.loads(line) for line in (out / "run-000/stats.jsonl").read_text().splitlines()]
    assert stats[0]["best"] > 0
    assert stats[-1]["best"] == 0  # the target found
    best = json.loads((out / "run-000/best.json").read_text())
    assert len(best["genome"]) == 8  # the plug-in's genomes: exactly `length` codons
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["representation_version"] == "gaitgram-example-backend 0.1.0; fixed-ge r1"
    config = (out / "config.toml").read_text()
    assert 'representation = "fixed-ge"' in config
    assert "length = 8\nmutation = 0.05" in config  # the plug-in's defaults spelt out

    genome = ",".join(map(str, best["genome"]))
    mapping = ("map", "g.gg", "--representation", "fixed-ge", "--genome", genome)
    mapped = gaitgram(plugin_env, *mapping, "--setting", "length=8", cwd=tmp_path)
    assert mapped.returncode == 0, mapped.stderr
    assert mapped.stdout.splitlines()[0] == best["phenotype"] == "13*sin(2*PI*t+2.5)"
    short = gaitgram(plugin_env, *mapping, cwd=tmp_path)
    assert short.returncode == 2
    assert "a fixed-ge genome is a list of exactly 60 codons (setting length)" in short.stderr


def test_a_plugin_representations_settings_are_checked(plugin_env: dict[str, str], tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    (tmp_path / "run.toml").write_text(CONFIG.replace("length", "lenght"))
    args = ("evolve", "g.gg", "-c", "run.toml", "--representation", "fixed-ge", "-o", "out", "-q")
    bad = gaitgram(plugin_env, *args, cwd=tmp_path)
    assert bad.returncode == 2
    wrong = (
        "[representation_settings] lenght: unknown setting of representation fixed-ge; did you mean length?"
    )
    assert wrong in bad.stderr
    assert not (tmp_path / "out").exists()
    (tmp_path / "run.toml").write_text(CONFIG)
    unknown = gaitgram(dict(os.environ), *args, cwd=tmp_path)
    assert unknown.returncode == 2
    assert "no representation named 'fixed-ge'" in unknown.stderr
    assert "Traceback" not in unknown.stderr


def _toml(value: object) -> str:
    return (
        str(value).lower()
        if isinstance(value, bool)
        else f'"{value}"'
        if isinstance(value, str)
        else str(value)
    )


def test_the_docs_give_every_builtin_setting_with_its_default() -> None:
    """docs/ge.md's Representations section lists each built-in representation's settings as the
    code declares them (`name = default`, or the name alone for one left out), so they cannot drift."""
    text = (ROOT / "docs" / "ge.md").read_text()
    section = text[text.index("## Representations") : text.index("## Compiled formats")]
    for name in REPRESENTATIONS:
        start = section.index(f"- **`{name}`**")
        end = section.find("\n- **", start + 1)
        entry = " ".join(section[start : end if end > 0 else None].split())
        for setting in get_representation(name).settings:
            shown = (
                f"`{setting.name}`"
                if setting.default is None
                else f"`{setting.name} = {_toml(setting.default)}`"
            )
            assert shown in entry, (name, shown)
