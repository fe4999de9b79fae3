"""Kill -9 at any instant of making a run or study directory, and the same command continues;
a report or a render cut short leaves the old files or the new ones, never some of each.

Not killed at random times: each command runs once with every file-system step it takes in
its output's directory counted (mkdir, open, chmod, rename, replace, link, unlink, rmdir), then
once per step, dying at that step as under kill -9 (``os._exit``: no cleanup, no ``finally``),
or receiving a real SIGINT there (Ctrl-C), or failing there as on a full disk (ENOSPC). After
each death the same command, run again, must succeed and give exactly the uninterrupted
results, leaving no temporary directory behind. And one gaitgram at a time in a directory:
a lock that is never deleted, so two processes can never both hold it.
"""

from __future__ import annotations

import errno
import multiprocessing
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest
from measured import comparable
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR as GRAMMAR
from conftest import CURVE_STUDY as STUDY
from conftest import GRAMMARS
from gaitgram.cli import app

runner = CliRunner()

#: The file-system calls counted as steps (tempfile, pathlib and shutil go through them).
STEPS = ("mkdir", "open", "chmod", "rename", "replace", "link", "unlink", "rmdir")


@dataclass(frozen=True)
class Cut:
    """How a command cut short ended: its exit code, standard error and the steps it took."""

    code: int
    stderr: str
    steps: list[str]


def cut_at(root: Path, args: list[str], limit: int | None, how: str = "kill", *, fresh: bool = False) -> Cut:
    """Run ``gaitgram ARGS`` in a forked child (with ``fresh``, a new Python process: for MuJoCo's
    renderer, which a fork may not share) whose ``limit``-th file-system step under ``root``
    (None: none) is cut short ``how``: ``kill`` (it dies there as under kill -9), ``ctrl-c`` (a
    real SIGINT reaches it there, as Ctrl-C sends) or ``full`` (the step fails as on a full disk)."""
    log, errors = root.parent / f"{root.name}.steps", root.parent / f"{root.name}.stderr"
    log.unlink(missing_ok=True)
    if fresh:
        child = f"from study.test_atomic import cut_here; cut_here(*{[str(root), args, limit, how]!r})"
        env = {
            **os.environ,
            "PYTHONPATH": str(Path(__file__).parents[1]),
            "MUJOCO_GL": "egl",
            "NO_COLOR": "1",
        }
        code = subprocess.run([sys.executable, "-c", child], env=env, check=False).returncode
    else:
        pid = os.fork()
        if pid == 0:
            cut_here(str(root), args, limit, how)
        code = os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])
    stderr = errors.read_text() if errors.exists() else ""
    return Cut(code, stderr, log.read_text().splitlines() if log.exists() else [])


def cut_here(root: str, args: list[str], limit: int | None, how: str) -> None:
    """The child of :func:`cut_at`: count the steps, cut at the limit, and end (never returns)."""
    code = 1
    try:
        prefix = str(Path(root).resolve()) + os.sep
        taken = 0
        record = os.open(f"{root}.steps", os.O_WRONLY | os.O_CREAT | os.O_APPEND)
        sys.stderr = open(f"{root}.stderr", "w", buffering=1)  # noqa: SIM115 (line by line, to the end)
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115
        signal.signal(signal.SIGINT, signal.default_int_handler)

        def counted(name: str, call: Callable[..., object]) -> Callable[..., object]:
            def step(path: object, *rest: object, **options: object) -> object:
                nonlocal taken
                if isinstance(path, str | bytes | os.PathLike) and options.get("dir_fd") is None:
                    target = os.path.realpath(os.fsdecode(path))
                    if target.startswith(prefix):
                        taken += 1
                        os.write(record, f"{name} {target}\n".encode())
                        if taken == limit and how == "kill":
                            os._exit(137)
                        if taken == limit and how == "ctrl-c":
                            os.kill(os.getpid(), signal.SIGINT)
                        if taken == limit and how == "full":
                            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), target)
                return call(path, *rest, **options)

            return step

        for name in STEPS:
            setattr(os, name, counted(name, getattr(os, name)))
        try:
            app(args, prog_name="gaitgram")
            code = 0
        except SystemExit as end:
            code = end.code if isinstance(end.code, int) else 1
    finally:
        sys.stderr.flush()
        os._exit(code)


def run_until(root: Path, args: list[str], limit: int | None) -> list[str]:
    """Run ``gaitgram ARGS`` in a forked child that dies at its ``limit``-th step under ``root``
    (None: never); the steps it took, as ``"name path"``."""
    cut = cut_at(root, args, limit)
    if limit is None:
        assert cut.code == 0, (cut.stderr, cut.steps[-5:])
    else:
        assert cut.code == 137, f"step {limit} of {cut.steps}: the command ended first"
    return cut.steps


def tree(directory: Path) -> dict[str, bytes]:
    """Every file under a directory (its lock files aside), by relative path; a run's records of
    its time in the backend without the seconds (the machine's, no result)."""
    return {
        str(p.relative_to(directory)): comparable(p)
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


# ---- a report replaced, cut short ---------------------------------------------------------------


@dataclass(frozen=True)
class Reports:
    """A hand-made study, its report over each arm's first two runs (the old report a directory
    holds) and the report of all three (the new one), as trees of files."""

    study: Path
    old: Path
    old_tree: dict[str, bytes]
    new_tree: dict[str, bytes]
    moments: dict[str, int]

    def args(self, out: Path, *more: str) -> list[str]:
        return ["report", str(self.study), "-o", str(out), *more]

    def cut(
        self, root: Path, limit: int | None, how: str = "kill", *, fresh: bool = False
    ) -> tuple[Path, Cut]:
        """``report --force`` into ``root/out``, holding the old report (none if ``fresh``), cut at
        step ``limit``."""
        root.mkdir()
        if not fresh:
            shutil.copytree(self.old, root / "out")
        return root / "out", cut_at(root, self.args(root / "out", "--force"), limit, how)

    def steps(self, tmp_path: Path) -> list[str]:
        """The steps of replacing the old report by the new."""
        return self.cut(tmp_path / "reference", None)[1].steps


def moments(steps: list[str]) -> dict[str, int]:
    """The steps of replacing a report that matter, by name (1-based, as ``cut_at`` counts)."""

    def at(*parts: str) -> list[int]:
        return [i for i, s in enumerate(steps, 1) if all(part in s for part in parts)]

    moved = [i for i in at("replace ", ".staging.") if not steps[i - 1].endswith(".tmp")]
    commit = at("unlink ", "moving-in")[0]
    return {
        "first file made": at(".staging.", ".tmp")[0],
        "page made": at("replace ", "report.html.")[0],
        "first set aside": at("link ")[0],
        "halfway through the swap": moved[len(moved) // 2],
        "last moved in": moved[-1],
        "swap done": commit,
        "cleaning up": commit + 1,
    }


@pytest.fixture(scope="module")
def reports(tmp_path_factory: pytest.TempPathFactory) -> Reports:
    """Made once for the tests of this module that cut reports short."""
    where = tmp_path_factory.mktemp("reports")
    study = write_hand_made_study(where / "study")
    for name, more in (("old", ["--runs", "2"]), ("new", [])):
        made = runner.invoke(app, ["report", str(study), "-o", str(where / name), *more])
        assert made.exit_code == 0, made.stderr
    made = Reports(study, where / "old", tree(where / "old"), tree(where / "new"), {})
    assert made.old_tree.keys() == made.new_tree.keys()
    assert made.old_tree != made.new_tree
    made.moments.update(moments(made.steps(where)))
    return made


def check_mended(reports: Reports, out: Path, moment: str) -> str:
    """After a kill: the next report into ``out`` mends it first, says so, and leaves the old report
    or the new one (it is refused: no --force); then the new one is made over it. Which was left."""
    again = runner.invoke(app, reports.args(out))
    assert again.exit_code == 2, (moment, again.stderr)
    assert "summary.md exists; pass --force to overwrite it" in again.stderr
    assert "interrupted gaitgram" in again.stderr, (moment, again.stderr)
    left = tree(out)
    assert left in (reports.old_tree, reports.new_tree), f"{moment}: files of each report: {sorted(left)}"
    forced = runner.invoke(app, reports.args(out, "--force"))
    assert forced.exit_code == 0, forced.stderr
    assert "interrupted gaitgram" not in forced.stderr  # mended once
    assert tree(out) == reports.new_tree
    return "old" if left == reports.old_tree else "new"


def test_a_report_killed_while_replacing_another_leaves_one_of_them(tmp_path: Path, reports: Reports) -> None:
    """kill -9 while the new report is made and while it is swapped in: until the swap is done, the
    old report is what stays (the files already swapped are put back); after, the new one."""
    moments = reports.moments
    left = {}
    for moment in ("first file made", "halfway through the swap", "swap done", "cleaning up"):
        out, cut = reports.cut(tmp_path / moment.replace(" ", "-"), moments[moment])
        assert cut.code == 137, (moment, cut.stderr)
        if moment == "halfway through the swap":  # as the kill left it: files of both reports
            assert tree(out) not in (reports.old_tree, reports.new_tree)
        left[moment] = check_mended(reports, out, moment)
    assert left == {
        "first file made": "old",
        "halfway through the swap": "old",
        "swap done": "old",  # killed just before the swap was marked done
        "cleaning up": "new",
    }


def test_a_report_killed_while_made_afresh_leaves_nothing(tmp_path: Path, reports: Reports) -> None:
    """A directory made whole: killed before it is in place (while its files are made, or at the
    rename that puts it there), there is no report at all; the next command removes what was
    left and says so."""
    steps = reports.cut(tmp_path / "reference", None, fresh=True)[1].steps
    made = next(i for i, step in enumerate(steps, 1) if step.endswith(".tmp"))
    renamed = next(i for i, step in enumerate(steps, 1) if step.startswith("rename "))
    for limit in (made, renamed):
        out, cut = reports.cut(tmp_path / f"killed-at-{limit}", limit, fresh=True)
        assert cut.code == 137
        assert not out.exists()
        assert [p.name.endswith(".creating") for p in out.parent.iterdir()] == [True]
        done = runner.invoke(app, reports.args(out))
        assert done.exit_code == 0, done.stderr
        assert "left unfinished by an interrupted gaitgram" in done.stderr
        assert tree(out) == reports.new_tree
        assert [p.name for p in out.parent.iterdir()] == ["out"]
        assert not (out / ".lock").exists()


@pytest.mark.parametrize(
    ("moment", "kept"),
    [
        ("first file made", "the report was not written; {out} is as it was"),
        ("halfway through the swap", "the report was written whole in {out}"),  # held until it is done
        ("cleaning up", "the report was written whole in {out}"),
    ],
)
def test_ctrl_c_while_a_report_is_written_says_what_was_kept(
    tmp_path: Path, reports: Reports, moment: str, kept: str
) -> None:
    """A real SIGINT at each moment: exit 130, and stderr says what the directory holds, which is
    the old report or the new one, whole, with nothing left over."""
    out, cut = reports.cut(tmp_path / "cut", reports.moments[moment], "ctrl-c")
    assert cut.code == 130, cut.stderr
    assert cut.stderr == f"interrupted: {kept.format(out=out)}\n"
    assert tree(out) == (reports.old_tree if "not written" in kept else reports.new_tree)
    no_temporaries(tmp_path / "cut")


@pytest.mark.parametrize("moment", ["page made", "halfway through the swap"])
def test_a_full_disk_while_a_report_is_written_keeps_the_old_one(
    tmp_path: Path, reports: Reports, moment: str
) -> None:
    """ENOSPC while the files are made, or at a rename of the swap: exit 2 naming the reason, the
    old report whole (the files swapped so far are put back), nothing left over."""
    out, cut = reports.cut(tmp_path / "cut", reports.moments[moment], "full")
    assert cut.code == 2, cut.stderr
    assert cut.stderr == (
        f"error: cannot write the report in {out}: No space left on device; {out} is as it was\n"
    )
    assert tree(out) == reports.old_tree
    no_temporaries(tmp_path / "cut")


@pytest.mark.slow
def test_a_report_killed_at_any_step_leaves_the_old_report_or_the_new(
    tmp_path: Path, reports: Reports
) -> None:
    steps = reports.steps(tmp_path)
    assert len(steps) > 50
    for limit in range(1, len(steps) + 1):
        out, cut = reports.cut(tmp_path / f"killed-at-{limit}", limit)
        assert cut.code == 137, (limit, cut.stderr)
        if tree(out) not in (reports.old_tree, reports.new_tree):  # else nothing was left to mend
            check_mended(reports, out, steps[limit - 1])


# ---- an animation and its strip, replaced together ----------------------------------------------

RENDER = ["render", str(GRAMMARS / "sine-walk.gg"), "--genome", "5,17,3,99,1000,42,7,8,9,10,11,12,13"]
RENDER += ["--max-wraps", "10", "--fps", "2"]


def test_render_replaces_its_animation_and_strip_together(tmp_path: Path) -> None:
    """``render --force`` over an older GIF and strip, in a process of its own: a full disk while the
    strip is written leaves both old (not a new animation beside an old strip); a Ctrl-C then waits
    until both are new, the strip keeping its mode; a kill -9 between the two renames leaves a new
    GIF beside the old strip, which the next render puts back first, saying so, before it checks
    its outputs."""

    def cut(name: str, limit: int | None, how: str = "kill") -> tuple[Path, Cut]:
        root = tmp_path / name
        root.mkdir()
        (root / "walk.gif").write_bytes(b"old animation")
        (root / "walk.png").write_bytes(b"old strip")
        (root / "walk.png").chmod(0o640)
        return root, cut_at(root, [*RENDER, "-o", str(root / "walk.gif"), "--force"], limit, how, fresh=True)

    steps = cut("reference", None)[1].steps
    made = next(i for i, step in enumerate(steps, 1) if "walk.png." in step and step.endswith(".tmp"))
    moved = [i for i, step in enumerate(steps, 1) if step.startswith("replace ") and ".staging." in step]
    moved = [i for i in moved if not steps[i - 1].endswith(".tmp")]
    assert len(moved) == 2, steps

    root, full = cut("full", made, "full")
    assert full.code == 2, full.stderr
    assert full.stderr.splitlines()[-1] == f"error: cannot write {root / 'walk.png'}: no space left on device"
    assert (root / "walk.gif").read_bytes() == b"old animation"
    assert (root / "walk.png").read_bytes() == b"old strip"
    no_temporaries(root)

    root, stopped = cut("ctrl-c", made, "ctrl-c")
    assert stopped.code == 130, stopped.stderr
    assert stopped.stderr.splitlines()[-1] == (
        f"interrupted: {root / 'walk.gif'} and {root / 'walk.png'} were written whole before it took effect"
    )
    assert (root / "walk.gif").read_bytes()[:6] == b"GIF89a"
    assert (root / "walk.png").read_bytes()[:4] == b"\x89PNG"
    assert (root / "walk.png").stat().st_mode & 0o777 == 0o640  # the file replaced keeps its mode
    no_temporaries(root)

    root, killed = cut("killed", moved[1])
    assert killed.code == 137
    assert (root / "walk.gif").read_bytes()[:6] == b"GIF89a"  # as the kill left it: one of each
    assert (root / "walk.png").read_bytes() == b"old strip"
    again = subprocess.run(
        [sys.executable, "-m", "gaitgram", *RENDER, "-o", str(root / "walk.gif")],
        capture_output=True,
        text=True,
        env={**os.environ, "MUJOCO_GL": "egl", "NO_COLOR": "1", "COLUMNS": "400"},
        check=False,
    )
    assert again.returncode == 2
    assert f"an interrupted gaitgram left {root} half-replaced: put back the 2 file(s)" in again.stderr
    assert f"error: {root / 'walk.gif'} exists; pass --force to overwrite it" in again.stderr
    assert (root / "walk.gif").read_bytes() == b"old animation"
    assert (root / "walk.png").read_bytes() == b"old strip"
    no_temporaries(root)
