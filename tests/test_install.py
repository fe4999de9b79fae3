"""A plain ``pip install gaitgram``: the wheel, in a fresh environment, without any extra.

Every command must start; the core ones (check, map, test, the language server) must work; a
command that needs an extra must say so with the exact install command, never a traceback.
Building the wheel and installing it takes a minute (the package registry is the only network).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GRAMMAR = ROOT / "grammars" / "sine-walk.gg"


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The bin directory of a fresh virtual environment with only the wheel and its dependencies."""
    tmp = tmp_path_factory.mktemp("install")
    wheels = tmp / "wheels"
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(wheels), str(ROOT)],
        check=True,
        capture_output=True,
    )
    (wheel,) = wheels.glob("gaitgram-*.whl")
    env = tmp / "env"
    venv.create(env, with_pip=True)
    subprocess.run(
        [str(env / "bin" / "python"), "-m", "pip", "install", "-q", str(wheel)],
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
    checked = run(installed, "check", str(GRAMMAR), cwd=tmp_path)
    assert checked.returncode == 0, checked.stderr
    mapped = run(installed, "map", str(GRAMMAR), "--genome", "3,1,4,1,5,9,2,6", cwd=tmp_path)
    assert mapped.returncode in (0, 1), mapped.stderr
    assert b"Traceback" not in mapped.stderr
    tested = run(installed, "test", str(GRAMMAR), "--examples", "20", cwd=tmp_path)
    assert tested.returncode == 0, tested.stdout + tested.stderr
    assert b"passed" in tested.stdout


def test_a_missing_extra_names_the_install_command(installed: Path, tmp_path: Path) -> None:
    reported = run(installed, "report", str(tmp_path), cwd=tmp_path)
    assert reported.returncode == 2
    assert b"pip install 'gaitgram[plot]'" in reported.stderr  # the brackets survive the console
    assert b"Traceback" not in reported.stderr


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
