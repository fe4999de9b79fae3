"""A plain ``pip install gaitgram``: the distributions as built for PyPI, the wheel in a fresh environment.

``python -m build`` makes the sdist and, from it, the wheel (so the sdist is complete enough to
build); ``twine check`` accepts both; the wheel carries every data file of the packages and the
sdist what builds, tests and documents them. Installed without any extra, every command must
start; the core ones (check, map, test, evaluate, seed, the language server) must work from outside
the source tree; a command that needs an extra must say so with the exact install command, never a
traceback. Building and installing take about 40 s (the package registry is the only
network).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tarfile
import venv
import zipfile
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # building and installing take about 40 s
ROOT = Path(__file__).resolve().parents[1]
GRAMMAR = ROOT / "grammars" / "sine-walk.gg"
#: A sine-walk genome that maps (with wraps) to a gait that stands without falling.
GENOME = "5,17,3,99,1000,42,7,8,9,10,11,12,13"


@pytest.fixture(scope="module")
def dists(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The sdist and the wheel, as ``python -m build`` makes them for an upload."""
    pytest.importorskip("build", reason="build is not installed (pip install -e '.[dev]')")
    out = tmp_path_factory.mktemp("dist")
    built = subprocess.run(
        [sys.executable, "-m", "build", "--outdir", str(out), str(ROOT)], capture_output=True, text=True
    )
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    (sdist,) = out.glob("gaitgram-*.tar.gz")
    (wheel,) = out.glob("gaitgram-*.whl")
    return sdist, wheel


@pytest.fixture(scope="module")
def installed(dists: tuple[Path, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The bin directory of a fresh virtual environment with only the wheel and its dependencies."""
    env = tmp_path_factory.mktemp("install") / "env"
    venv.create(env, with_pip=True)
    subprocess.run(
        [str(env / "bin" / "python"), "-m", "pip", "install", "-q", str(dists[1])],
        check=True,
        capture_output=True,
    )
    return env / "bin"


def run(bin_dir: Path, *args: str, cwd: Path, stdin: bytes | None = None) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    return subprocess.run(
        [str(bin_dir / "gaitgram"), *args], cwd=cwd, env=env, input=stdin, capture_output=True, timeout=300
    )


def test_the_wheel_carries_no_extra_and_every_command_starts(installed: Path, tmp_path: Path) -> None:
    listed = subprocess.run(
        [str(installed / "python"), "-m", "pip", "list", "--format", "json"], capture_output=True, check=True
    )
    names = {p["name"].lower() for p in json.loads(listed.stdout)}
    assert not names & {"matplotlib", "scipy", "dask", "distributed"}
    top = run(installed, "--help", cwd=tmp_path)
    assert top.returncode == 0, top.stderr
    listing = top.stdout.decode().split("Commands:", 1)[1]
    commands = [line.split()[0] for line in listing.splitlines() if line.startswith("  ")]
    assert {"check", "evolve", "study", "report", "lsp", "test"} <= set(commands)
    for command in commands:
        shown = run(installed, command, "--help", cwd=tmp_path)
        assert shown.returncode == 0, (command, shown.stderr)
        assert b"Traceback" not in shown.stderr


def test_core_commands_work_without_extras(installed: Path, tmp_path: Path) -> None:
    shutil.copy(GRAMMAR, tmp_path / "walk.gg")  # outside the source tree, named relative to it
    where = subprocess.run(
        [str(installed / "python"), "-c", "import gaitgram; print(gaitgram.__file__)"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=True,
    )
    assert not Path(where.stdout.strip()).is_relative_to(ROOT)
    checked = run(installed, "check", "walk.gg", cwd=tmp_path)
    assert checked.returncode == 0, checked.stderr
    mapped = run(installed, "map", "walk.gg", "--genome", "3,1,4,1,5,9,2,6", cwd=tmp_path)
    assert mapped.returncode in (0, 1), mapped.stderr
    assert b"Traceback" not in mapped.stderr
    tested = run(installed, "test", "walk.gg", "--examples", "20", cwd=tmp_path)
    assert tested.returncode == 0, tested.stdout + tested.stderr
    assert b"passed" in tested.stdout


def test_the_packaged_data_works_from_outside_the_source_tree(installed: Path, tmp_path: Path) -> None:
    """The seed CSV (seed grammar), the language's grammar (check), the horse model (evaluate)."""
    written = run(installed, "seed", "grammar", "--style", "hybrid", "-o", "hybrid.gg", cwd=tmp_path)
    assert written.returncode == 0, written.stderr
    checked = run(installed, "check", "hybrid.gg", cwd=tmp_path)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    shutil.copy(GRAMMAR, tmp_path / "walk.gg")
    scored = run(
        installed, "evaluate", "walk.gg", "--genome", GENOME, "--max-wraps", "10", "--set", "cycles=1",
        "--json", cwd=tmp_path,
    )  # fmt: skip
    assert scored.returncode == 0, scored.stderr
    result = json.loads(scored.stdout)
    assert result["backend"] == "mujoco-horse"
    assert result["status"] == "ok"
    assert result["components"]["measured_work"] > 0  # the horse was simulated


def test_twine_accepts_the_sdist_and_the_wheel(dists: tuple[Path, Path]) -> None:
    pytest.importorskip("twine", reason="twine is not installed (pip install -e '.[dev]')")
    checked = subprocess.run(
        [sys.executable, "-m", "twine", "check", "--strict", *map(str, dists)], capture_output=True, text=True
    )
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert checked.stdout.count("PASSED") == 2


def tracked(*folders: str) -> list[str]:
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "--", *folders],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    if listed.returncode != 0:
        pytest.skip("not a git checkout: the files to expect are not known")
    return [name for name in listed.stdout.splitlines() if (ROOT / name).is_file()]


def test_the_wheel_carries_every_data_file_of_the_packages(dists: tuple[Path, Path]) -> None:
    names = set(zipfile.ZipFile(dists[1]).namelist())
    expected = {name for name in tracked("gaitgram") if not name.endswith(".py")}
    expected |= {
        name.removeprefix("lsp/") for name in tracked("lsp/gaitgram_lsp") if not name.endswith(".py")
    }
    assert expected >= {
        "gaitgram/language/gaitgram.lark",
        "gaitgram/motion/expression.lark",
        "gaitgram/backends/mujoco_horse/horse.xml",
        "gaitgram/backends/mujoco_horse/joints.toml",
        "gaitgram/motion/horse_walk.csv",
    }
    assert expected <= names, sorted(expected - names)
    assert not [name for name in names if name.startswith(("tests/", "docs/", "grammars/"))]
    entry_points = zipfile.ZipFile(dists[1]).read("gaitgram-0.1.0.dist-info/entry_points.txt").decode()
    assert "gaitgram = gaitgram.__main__:main" in entry_points
    assert "mujoco-horse = gaitgram.backends.mujoco_horse:BACKEND" in entry_points
    assert "gaitgram-0.1.0.dist-info/licenses/LICENSE" in names
    metadata = zipfile.ZipFile(dists[1]).read("gaitgram-0.1.0.dist-info/METADATA").decode()
    assert "License-Expression: MIT" in metadata


def test_the_sdist_carries_what_builds_tests_and_documents_the_package(dists: tuple[Path, Path]) -> None:
    with tarfile.open(dists[0]) as sdist:
        names = {name.split("/", 1)[1] for name in sdist.getnames() if "/" in name}
    expected = set(tracked("gaitgram", "lsp", "grammars", "seeds", "studies", "tests", "benchmarks"))
    expected |= {name for name in tracked("docs") if "/runs/" not in name}
    expected |= {
        "pyproject.toml",
        "README.md",
        "LICENSE",
        "MANIFEST.in",
        ".pre-commit-hooks.yaml",
        "mkdocs.yml",
    }
    expected = {name for name in expected if "__pycache__" not in name}
    assert expected <= names, sorted(expected - names)[:20]
    assert not [name for name in names if "/runs/" in name]  # study outputs stay in the repository


def test_a_missing_extra_names_the_install_command(installed: Path, tmp_path: Path) -> None:
    reported = run(installed, "report", str(tmp_path), cwd=tmp_path)
    assert reported.returncode == 2
    assert b"pip install 'gaitgram[plot]'" in reported.stderr  # the brackets survive the console
    assert b"Traceback" not in reported.stderr
    shutil.copy(GRAMMAR, tmp_path / "walk.gg")
    video = run(installed, "render", "walk.gg", "--genome", GENOME, "-o", "walk.mp4", cwd=tmp_path)
    assert video.returncode == 2
    assert b"MP4 videos need imageio, which is not installed: pip install 'gaitgram[video]'" in video.stderr
    assert not (tmp_path / "walk.mp4").exists()


def message(payload: dict) -> bytes:
    body = json.dumps(payload).encode()
    return f"Content-Length: {len(body)}\r\n\r\n".encode() + body


def test_the_language_server_answers_initialize_over_stdio(installed: Path, tmp_path: Path) -> None:
    requests = b"".join(
        [
            message({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}),
            message({"jsonrpc": "2.0", "method": "initialized", "params": {}}),
            message({"jsonrpc": "2.0", "id": 2, "method": "shutdown"}),
            message({"jsonrpc": "2.0", "method": "exit"}),
        ]
    )
    served = run(installed, "lsp", cwd=tmp_path, stdin=requests)
    assert served.returncode == 0, served.stderr
    first = served.stdout.split(b"\r\n\r\n", 1)[1]
    length = int(served.stdout.split(b"\r\n", 1)[0].split(b":")[1])
    reply = json.loads(first[:length])
    assert reply["id"] == 1
    assert reply["result"]["serverInfo"]["name"] == "gaitgram-lsp"
    assert "completionProvider" in reply["result"]["capabilities"]
