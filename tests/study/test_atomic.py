"""Kill -9 at any instant of making a run or study directory, and the same command continues.

Not killed at random times: each command runs once with every file-system step it takes in
its output's directory counted (mkdir, open, chmod, rename, replace, unlink, rmdir), then once
per step, dying at that step as under kill -9 (``os._exit``: no cleanup, no ``finally``). After
each death the same command, run again, must succeed and give exactly the uninterrupted
results, leaving no temporary directory behind. And one gaitgram at a time in a directory:
a lock that is never deleted, so two processes can never both hold it.
"""

from __future__ import annotations

import multiprocessing
import os
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR as GRAMMAR
from conftest import CURVE_STUDY as STUDY
from gaitgram.cli import app

runner = CliRunner()

#: The file-system calls counted as steps (tempfile, pathlib and shutil go through them).
STEPS = ("mkdir", "open", "chmod", "rename", "replace", "unlink", "rmdir")


def run_until(root: Path, args: list[str], limit: int | None) -> list[str]:
    """Run ``gaitgram ARGS`` in a forked child that dies at its ``limit``-th step under ``root``
    (None: never); the steps it took, as ``"name path"``."""
    log = root.parent / f"{root.name}.steps"
    log.unlink(missing_ok=True)
    pid = os.fork()
    if pid == 0:  # the child: count, and die at the limit as kill -9 would
        code = 1
        try:
            prefix = str(root.resolve()) + os.sep
            taken = 0
            record = os.open(log, os.O_WRONLY | os.O_CREAT | os.O_APPEND)

            def counted(name: str, call: Callable[..., object]) -> Callable[..., object]:
                def step(path: object, *rest: object, **options: object) -> object:
                    nonlocal taken
                    if isinstance(path, str | bytes | os.PathLike) and options.get("dir_fd") is None:
                        target = os.path.realpath(os.fsdecode(path))
                        if target.startswith(prefix):
                            taken += 1
                            os.write(record, f"{name} {target}\n".encode())
                            if taken == limit:
                                os._exit(137)
                    return call(path, *rest, **options)

                return step

            for name in STEPS:
                setattr(os, name, counted(name, getattr(os, name)))
            try:
                app(args, prog_name="gaitgram")
            except SystemExit as end:
                code = end.code if isinstance(end.code, int) else 1
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    steps = log.read_text().splitlines() if log.exists() else []
    if limit is None:
        assert os.waitstatus_to_exitcode(status) == 0, steps[-5:]
    else:
        assert os.waitstatus_to_exitcode(status) == 137, f"step {limit} of {steps}: the command ended first"
    return steps


def tree(directory: Path) -> dict[str, bytes]:
    """Every file under a directory (its lock files aside), by relative path."""
    return {
        str(p.relative_to(directory)): p.read_bytes()
        for p in sorted(directory.rglob("*"))
        if p.is_file() and p.name != ".lock"
    }


def no_temporaries(root: Path) -> None:
    assert not list(root.rglob("*.creating")), "a temporary directory was left behind"


def kill_at_every_step(
    tmp_path: Path,
    args: Callable[[Path], list[str]],
    first_run_step: str,
    again: Callable[[Path], list[str]] | None = None,
) -> int:
    """Kill the command at each of its steps before ``first_run_step`` (where its first run
    starts: creating is done), then run it ``again`` (by default the same command); the result
    must be the uninterrupted one."""
    reference = tmp_path / "reference"
    reference.mkdir()
    steps = run_until(reference, args(reference / "out"), None)
    expected = tree(reference / "out")
    creating = next(i for i, s in enumerate(steps) if first_run_step in s)
    assert creating > 5, steps
    for limit in range(1, creating + 1):
        root = tmp_path / f"killed-at-{limit}"
        root.mkdir()
        run_until(root, args(root / "out"), limit)
        result = runner.invoke(app, (again or args)(root / "out"))
        assert result.exit_code == 0, f"killed at step {limit} ({steps[limit - 1]}): {result.stderr}"
        assert tree(root / "out") == expected, f"killed at step {limit} ({steps[limit - 1]})"
        no_temporaries(root)
    return creating


@pytest.mark.slow
def test_a_study_killed_at_any_step_of_its_making_continues_to_the_same_results(tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    study = tmp_path / "s.toml"
    study.write_text(STUDY.format(generations=1).replace("runs = 3", "runs = 1"))
    args = lambda out: ["study", str(study), "-o", str(out), "-q", "--jobs", "1"]  # noqa: E731
    steps = kill_at_every_step(tmp_path, args, "/out/.stop")  # the runs start by clearing .stop
    assert steps > 20  # both arms and study.json were made, step by step


def test_an_evolve_killed_at_any_step_of_its_making_continues_to_the_same_results(tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    config = tmp_path / "run.toml"
    config.write_text(
        'generations = 1\npopulation = 8\nelite = 1\ninit_max_depth = 6\nbackend = "curve-match"\n'
        '[backend_settings.targets]\nhip_hind = "7*sin(2*PI*t)"\n'
    )

    def args(out: Path) -> list[str]:
        return ["evolve", str(tmp_path / "g.gg"), "-c", str(config), "-o", str(out), "-q"]

    def again(out: Path) -> list[str]:
        """The same command if the directory is not there; if it is, whole, that command says to
        resume it, which is what the user then runs."""
        if not out.exists():
            return args(out)
        refused = runner.invoke(app, args(out))
        assert refused.exit_code == 2
        assert f"holds a run already; continue it with --resume {out}" in " ".join(refused.stderr.split())
        return ["evolve", "--resume", str(out), "-q"]

    assert kill_at_every_step(tmp_path, args, "/out/run-000", again) > 10


@pytest.mark.parametrize("how", ["-o", "--resume"])
def test_a_run_directory_half_made_by_an_older_gaitgram_has_one_way_out(tmp_path: Path, how: str) -> None:
    """grammar.gg and config.toml written, the manifest not: each command says to delete it, and
    neither sends the user to the other."""
    (tmp_path / "g.gg").write_text(GRAMMAR)
    out = tmp_path / "out"
    out.mkdir()
    (out / "grammar.gg").write_text(GRAMMAR)
    (out / "config.toml").write_text("generations = 1\n")
    args = (
        ["evolve", str(tmp_path / "g.gg"), "-o", str(out)]
        if how == "-o"
        else ["evolve", "--resume", str(out)]
    )
    result = runner.invoke(app, [*args, "-q"])
    assert result.exit_code == 2
    assert "its creation was interrupted before manifest.json was written" in result.stderr
    assert "delete it and run the same command again" in result.stderr
    assert "pass --resume" not in result.stderr
    assert "older gaitgram that kept no manifest" not in result.stderr


def test_a_study_directory_left_with_only_its_arms_says_to_delete_it(tmp_path: Path) -> None:
    """An older gaitgram killed the moment arms/ appeared left this; it holds no run."""
    (tmp_path / "g.gg").write_text(GRAMMAR)
    study = tmp_path / "s.toml"
    study.write_text(STUDY.format(generations=1))
    (tmp_path / "out" / "arms" / "plain").mkdir(parents=True)
    (tmp_path / "out" / ".lock").touch()
    result = runner.invoke(app, ["study", str(study), "-o", str(tmp_path / "out"), "-q"])
    assert result.exit_code == 2
    assert "stopped before its study.json was written" in result.stderr
    assert "delete it and run the same command again" in result.stderr


def _hold(directory: str, barrier: multiprocessing.synchronize.Barrier, journal: str, rounds: int) -> None:
    from gaitgram.fileio import DirectoryInUse, DirectoryLock

    for _ in range(rounds):
        barrier.wait()
        try:
            with DirectoryLock(Path(directory)):
                with open(journal, "a") as out:
                    out.write(f"in {os.getpid()}\n")
                time.sleep(0.002)
                with open(journal, "a") as out:
                    out.write(f"out {os.getpid()}\n")
        except DirectoryInUse:
            pass


def test_processes_entering_the_lock_at_the_same_instant_never_both_hold_it(tmp_path: Path) -> None:
    """As a harness calling the lock directly does: four processes at a barrier, 20 times. The
    lock file is never deleted, by the holder or by a process turned away."""
    context = multiprocessing.get_context("fork")
    barrier = context.Barrier(4)
    journal = tmp_path / "journal"
    workers = [
        context.Process(target=_hold, args=(str(tmp_path), barrier, str(journal), 20)) for _ in range(4)
    ]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join(120)
        assert worker.exitcode == 0
    holder = None
    entries = journal.read_text().splitlines()
    for line in entries:
        kind, pid = line.split()
        if kind == "in":
            assert holder is None, "two processes held the lock at once"
            holder = pid
        else:
            assert holder == pid
            holder = None
    assert len(entries) >= 40  # someone held it in every round
    assert (tmp_path / ".lock").exists()
