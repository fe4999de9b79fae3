"""Studies on Dask: a real deployment (a ``dask scheduler`` and two ``dask worker`` processes on
this machine, started with the venv's ``dask`` command), a worker killed mid-study, a scheduler
that is not there. Each result is compared byte for byte with the same study run locally."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
from study.test_study import gaitgram, write_study

pytest.importorskip("distributed", reason="Dask is an optional extra; the dev extra installs it")

DASK = Path(sys.executable).parent / "dask"
#: Long enough that runs are in flight for seconds, short enough for a test.
GENERATIONS = "100"


@dataclass
class Deployment:
    address: str
    scheduler: subprocess.Popen[bytes]
    workers: dict[str, subprocess.Popen[bytes]]

    def processing(self) -> dict[str, int]:
        """Tasks each worker (by name) is running now, as the scheduler says."""
        from distributed import Client

        with Client(self.address, timeout=10) as client:
            names = {a: w["name"] for a, w in client.scheduler_info()["workers"].items()}
            return {names[a]: len(keys) for a, keys in client.processing().items() if a in names}

    def kill(self, name: str) -> None:
        """kill -9 a worker: its nanny and its worker process (one process group)."""
        os.killpg(self.workers[name].pid, signal.SIGKILL)
        self.workers[name].wait()


def _start(args: list[str], log: Path) -> subprocess.Popen[bytes]:
    with log.open("wb") as out:
        return subprocess.Popen(
            args, stdout=out, stderr=subprocess.STDOUT, start_new_session=True, cwd=log.parent
        )


@pytest.fixture
def deployment(tmp_path: Path) -> Iterator[Deployment]:
    """A scheduler and two workers on free ports of this machine, torn down at the end."""
    home = tmp_path / "cluster"
    home.mkdir()
    scheduler_file = home / "scheduler.json"
    local = ["--dashboard-address", "127.0.0.1:0"]
    scheduler = _start(
        [
            str(DASK),
            "scheduler",
            "--host",
            "127.0.0.1",
            "--port",
            "0",
            "--scheduler-file",
            str(scheduler_file),
            *local,
        ],
        home / "scheduler.log",
    )
    workers: dict[str, subprocess.Popen[bytes]] = {}
    try:
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() and time.monotonic() < deadline:
            assert scheduler.poll() is None, (home / "scheduler.log").read_text()
            time.sleep(0.1)
        address = json.loads(scheduler_file.read_text())["address"]
        for name in ("w0", "w1"):
            workers[name] = _start(
                [str(DASK), "worker", address, "--name", name, "--nworkers", "1", "--nthreads", "1", *local],
                home / f"{name}.log",
            )
        found = Deployment(address, scheduler, workers)
        while len(found.processing()) < 2:
            assert time.monotonic() < deadline, "the workers did not join the scheduler in 60 s"
            time.sleep(0.2)
        yield found
    finally:
        for process in [*workers.values(), scheduler]:
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def same_runs(first: Path, second: Path) -> None:
    """Every run's statistics, best gait and checkpoint are byte-identical in two study directories."""
    compared = 0
    for path in sorted(first.glob("arms/*/run-*/*")):
        if path.name in ("stats.csv", "stats.jsonl", "best.json", "checkpoint.json"):
            twin = second / path.relative_to(first)
            assert path.read_bytes() == twin.read_bytes(), f"{twin} differs"
            compared += 1
    assert compared == 2 * 3 * 4  # 2 arms x 3 runs x 4 files


@pytest.fixture(scope="module")
def local_study(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """(the study file, the same study run locally), once for the module."""
    tmp = tmp_path_factory.mktemp("local")
    study = write_study(tmp)
    local = tmp / "local"
    result = gaitgram("study", str(study), "-o", str(local), "-q", "--generations", GENERATIONS)
    assert result.returncode == 0, result.stderr
    return study, local


@pytest.mark.slow
def test_a_study_on_a_dask_deployment_equals_the_local_study(
    local_study: tuple[Path, Path], deployment: Deployment, tmp_path: Path
) -> None:
    study, local = local_study
    out = tmp_path / "dask"
    args = ["study", str(study), "-o", str(out), "-q", "--generations", GENERATIONS]
    result = gaitgram(*args, "--scheduler", deployment.address)
    assert result.returncode == 0, result.stderr
    assert "study complete: 2 arms x 3 runs" in result.stderr
    same_runs(local, out)


@pytest.mark.slow
def test_a_worker_killed_mid_study_changes_nothing(
    local_study: tuple[Path, Path], deployment: Deployment, tmp_path: Path
) -> None:
    study, local = local_study
    out = tmp_path / "dask"
    args = ["study", str(study), "-o", str(out), "-q", "--generations", GENERATIONS]
    process = subprocess.Popen(
        [sys.executable, "-m", "gaitgram", *args, "--scheduler", deployment.address],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 120
    # Wait until w0 is running a run that has checkpointed a few generations, then kill it.
    while not (
        deployment.processing().get("w0")
        and any(len(p.read_text().splitlines()) > 5 for p in out.glob("arms/*/run-*/stats.jsonl"))
    ):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.1)
    deployment.kill("w0")
    unfinished = [
        p
        for p in out.glob("arms/*/run-*/stats.jsonl")
        if len(p.read_text().splitlines()) < int(GENERATIONS) + 1
    ]
    assert unfinished  # runs were in flight when the worker died
    _, stderr = process.communicate(timeout=300)
    assert process.returncode == 0, stderr
    assert "study complete: 2 arms x 3 runs" in stderr
    same_runs(local, out)


@pytest.mark.slow
def test_a_local_dask_cluster_runs_a_study(local_study: tuple[Path, Path], tmp_path: Path) -> None:
    """The runs take longer than the half-second poll: a poll that saw none finish was once
    reported as "cannot write"."""
    study, local = local_study
    out = tmp_path / "dask"
    result = gaitgram(
        "study", str(study), "-o", str(out), "-q", "--generations", GENERATIONS, "--dask-local", "2"
    )
    assert result.returncode == 0, result.stderr
    same_runs(local, out)


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.mark.parametrize(
    ("address", "said"),
    [
        ("notaurl", "not a scheduler address"),
        ("http://127.0.0.1:8786", "not a scheduler address"),
        ("tcp://127.0.0.1:{port}", "nothing listens at 127.0.0.1:"),
    ],
)
def test_a_scheduler_that_is_not_there_is_refused_before_anything_is_made(
    tmp_path: Path, address: str, said: str
) -> None:
    study = write_study(tmp_path)
    address = address.format(port=free_port())  # nothing listens there
    out = tmp_path / "out"
    started = time.monotonic()
    result = gaitgram("study", str(study), "-o", str(out), "-q", "--scheduler", address)
    elapsed = time.monotonic() - started
    assert result.returncode == 2, result.stderr
    assert f"--scheduler {address}: {said}" in result.stderr
    assert "Traceback" not in result.stderr
    assert elapsed < 20  # a refused connection is said at once; the timeout is 5 s (Dask's 30 s)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.gg", "tiny.toml"]  # no directory made
    evolve = gaitgram("evolve", str(tmp_path / "g.gg"), "-o", str(out), "-q", "--scheduler", address)
    assert evolve.returncode == 2
    assert f"--scheduler {address}: {said}" in evolve.stderr
    assert not out.exists()


@pytest.fixture
def web_server() -> Iterator[str]:
    """A server on a free local port that answers every connection in HTTP, not Dask."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()

    def serve() -> None:
        while True:
            try:
                connection, _ = server.accept()
            except OSError:  # closed: the test is over
                return
            with connection:
                connection.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")

    threading.Thread(target=serve, daemon=True).start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    server.shutdown(socket.SHUT_RDWR)  # wakes the accept (a close alone would not, on Linux)
    server.close()


def test_something_else_listening_there_is_refused_plainly(tmp_path: Path, web_server: str) -> None:
    study = write_study(tmp_path)
    result = gaitgram("study", str(study), "-o", str(tmp_path / "out"), "-q", "--scheduler", web_server)
    assert result.returncode == 2, result.stderr
    assert f"--scheduler {web_server}: what answered there is not a Dask scheduler" in result.stderr
    assert "MemoryError" not in result.stderr  # Dask's reading of an HTTP reply as a frame length
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists()
