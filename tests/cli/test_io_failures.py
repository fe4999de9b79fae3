"""Input and output failures from the outside: each one an ``error:`` line and the right exit code.

A full disk, a closed pipe, a directory where a file was meant, a device or an endless pipe
where a grammar was meant, a tree too large to draw: none may end in a traceback, a
half-written file or a machine out of memory. Whatever can only be seen in a real process
(standard output's last flush, a closed pipe) runs ``python -m gaitgram``, with its memory
capped so that a regression fails the test instead of exhausting the machine.
"""

from __future__ import annotations

import errno
import json
import os
import resource
import stat
import subprocess
import sys
import threading
from pathlib import Path
from types import SimpleNamespace

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram import fileio
from gaitgram.cli import app
from gaitgram.language.source import SourceError, read_source

runner = CliRunner()
SINE_WALK = GRAMMARS / "sine-walk.gg"
ROOT = GRAMMARS.parent
#: Address space for a child process: plenty for any command, far below the machine's memory.
MEMORY_CAP = 2 << 30
IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0
needs_dev_full = pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs Linux's /dev/full")


def _cap_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP, MEMORY_CAP))


def gaitgram(*args: str, stdout: object = subprocess.PIPE, stdin: object = None, **kwargs: object):
    """``python -m gaitgram ARGS`` in a fresh process with its memory capped."""
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args],
        stdout=stdout,
        stdin=stdin,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "NO_COLOR": "1"},
        preexec_fn=_cap_memory,
        timeout=300,
        check=False,
        **kwargs,
    )


def assert_clean(stderr: str) -> None:
    assert "Traceback" not in stderr, stderr
    assert "Exception ignored" not in stderr, stderr


# ---- output: standard output, files, directories ---------------------------------------------


@needs_dev_full
@pytest.mark.parametrize(
    "args",
    [
        ["compile", str(SINE_WALK), "-o", "-"],
        ["map", str(SINE_WALK), "--genome", "3,1,4,1,5"],
        ["map", str(SINE_WALK), "--genome", "3,1,4,1,5", "--json"],
        ["check", "-f", "json", str(SINE_WALK)],
        ["sample", str(SINE_WALK), "-n", "3"],
    ],
    ids=["compile", "map", "map-json", "check-json", "sample"],
)
def test_standard_output_on_a_full_disk_is_one_error_line(args: list[str]) -> None:
    with open("/dev/full", "w") as full:
        result = gaitgram(*args, stdout=full)
    assert result.returncode == 2, result.stderr
    assert "error: cannot write <stdout>: no space left on device\n" in result.stderr
    assert_clean(result.stderr)


@needs_dev_full
def test_an_output_file_on_a_full_disk_is_reported_and_the_device_left_alone() -> None:
    result = gaitgram("compile", str(SINE_WALK), "-o", "/dev/full")
    assert result.returncode == 2
    assert result.stderr == "error: cannot write /dev/full: no space left on device\n"
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)  # written to, never replaced by a rename


def test_an_output_that_is_a_directory_or_under_a_file_is_refused(tmp_path: Path) -> None:
    directory = tmp_path / "out"
    directory.mkdir()
    plain = tmp_path / "plain.txt"
    plain.write_text("not a directory")
    for extra in ([], ["--force"]):
        result = runner.invoke(app, ["compile", str(SINE_WALK), "-o", str(directory), *extra])
        assert result.exit_code == 2
        assert result.stderr == f"error: cannot write {directory}: is a directory; choose another -o\n"
    result = runner.invoke(app, ["compile", str(SINE_WALK), "-o", str(plain / "x.json")])
    assert result.exit_code == 2
    assert (
        result.stderr
        == f"error: cannot write {plain / 'x.json'}: {plain} is not a directory; choose another -o\n"
    )
    result = runner.invoke(app, ["seed", "grammar", "--style", "free", "-o", str(directory)])
    assert result.exit_code == 2
    assert result.stderr == f"error: cannot write {directory}: is a directory; choose another -o\n"
    assert plain.read_text() == "not a directory"


@pytest.mark.skipif(IS_ROOT, reason="root writes into any directory")
def test_an_unwritable_directory_is_reported(tmp_path: Path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        result = runner.invoke(app, ["compile", str(SINE_WALK), "-o", str(locked / "t.json")])
    finally:
        locked.chmod(0o700)
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: cannot write {locked / 't.json'}: permission denied (cannot create files in {locked}); "
        "choose another -o\n"
    )


def test_a_refused_temporary_file_is_reported_with_the_output_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """What an unwritable directory does, also for root: the message names the output, not the
    temporary file, and nothing is left behind."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise PermissionError(errno.EACCES, "Permission denied", str(tmp_path / ".t.json.x.tmp"))

    monkeypatch.setattr(fileio.tempfile, "mkstemp", refuse)
    result = runner.invoke(app, ["compile", str(SINE_WALK), "-o", str(tmp_path / "t.json")])
    assert result.exit_code == 2
    assert result.stderr == f"error: cannot write {tmp_path / 't.json'}: permission denied\n"
    assert list(tmp_path.iterdir()) == []


def test_a_closed_pipe_ends_quietly() -> None:
    """``gaitgram sample G -n 100000 | head -1``: as ``yes | head -1``, no traceback, no
    "Exception ignored", the exit status of a process killed by SIGPIPE."""
    process = subprocess.Popen(
        [sys.executable, "-m", "gaitgram", "sample", str(SINE_WALK), "-n", "100000"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        preexec_fn=_cap_memory,
    )
    assert process.stdout is not None
    assert process.stderr is not None
    assert process.stdout.readline().strip()
    process.stdout.close()
    stderr = process.stderr.read().decode()
    assert process.wait(timeout=300) in (0, 141)
    assert_clean(stderr)
    assert stderr == ""


def test_new_output_files_follow_the_umask(tmp_path: Path) -> None:
    out = tmp_path / "tables.json"
    result = subprocess.run(
        [sys.executable, "-m", "gaitgram", "compile", str(SINE_WALK), "-o", str(out)],
        capture_output=True,
        text=True,
        preexec_fn=lambda: os.umask(0o027),
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert stat.S_IMODE(out.stat().st_mode) == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["tables.json"]


# ---- input: missing files, devices, endless pipes ----------------------------------------------


def test_check_reads_what_it_can_and_unreadable_outranks_lint_errors(tmp_path: Path) -> None:
    good = tmp_path / "a.gg"
    good.write_text("<a> ::= x\n")
    missing = tmp_path / "missing.gg"
    bad = tmp_path / "b.gg"
    bad.write_text("<b> ::= y | <c>\n")
    result = runner.invoke(app, ["check", str(good), str(missing), str(bad)])
    assert result.exit_code == 2
    assert f"error: cannot read {missing}: no such file\n" in result.stderr
    assert f"{bad}:1:13: error[GG201]" in result.stdout  # the files after it are still checked
    assert result.stderr.endswith("1 error in 2 files; 1 file could not be read\n")


@pytest.mark.parametrize(
    ("texts", "summary", "code"),
    [
        (["<a> ::= x\n"], "1 file OK", 0),
        (["<a> ::= x\n", "<a> ::= x\n"], "2 files OK", 0),
        (["<a> ::= x\n<b> ::= y\n", None], "1 warning in 1 file; 1 file could not be read", 2),
        ([None, None], "2 files could not be read", 2),
        (["<a> ::= <b> | <c>\n", "<a> ::= x\n<b> ::= y\n<c> ::= z\n"], "2 errors, 2 warnings in 2 files", 1),
    ],
)
def test_check_summary_counts_and_plurals(
    tmp_path: Path, texts: list[str | None], summary: str, code: int
) -> None:
    paths = []
    for i, text in enumerate(texts):
        path = tmp_path / f"g{i}.gg"
        if text is not None:
            path.write_text(text)
        paths.append(str(path))
    result = runner.invoke(app, ["check", *paths])
    assert result.exit_code == code
    assert result.stderr.splitlines()[-1] == summary


def _feed_forever(fifo: Path) -> threading.Thread:
    """A writer that never stops on its own: it ends when the reader closes the FIFO."""

    def feed() -> None:
        try:
            with open(fifo, "wb") as handle:
                while True:
                    handle.write(b"<a> ::= x\n" * 10_000)
        except OSError:  # BrokenPipeError: the reader has stopped
            pass

    thread = threading.Thread(target=feed, daemon=True)
    thread.start()
    return thread


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_an_endless_fifo_stops_at_the_size_limit(tmp_path: Path) -> None:
    fifo = tmp_path / "grammar.gg"
    os.mkfifo(fifo)
    writer = _feed_forever(fifo)
    with pytest.raises(SourceError, match=r"is over 0.0 MB; grammars over 0.0 MB are refused"):
        read_source(fifo, max_bytes=1000)
    writer.join(timeout=30)
    writer = _feed_forever(fifo)
    result = gaitgram("check", str(fifo))
    writer.join(timeout=30)
    assert result.returncode == 2
    assert f"error: cannot read {fifo}: is over 8.4 MB; grammars over 8.4 MB are refused" in result.stderr
    assert_clean(result.stderr)


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
def test_devices_are_refused_and_standard_input_is_bounded() -> None:
    checked = gaitgram("check", "/dev/zero")
    assert checked.returncode == 2
    assert "error: cannot read /dev/zero: is a character device, not a file" in checked.stderr
    mapped = gaitgram("map", str(SINE_WALK), "--genome-file", "/dev/zero")
    assert mapped.returncode == 2
    assert "error: cannot read /dev/zero: is a character device, not a file" in mapped.stderr
    with open("/dev/zero", "rb") as zeros:
        piped = gaitgram("map", str(SINE_WALK), "--genome-file", "-", stdin=zeros)
    assert piped.returncode == 2
    assert "error: cannot read <stdin>: is over 8.4 MB; genomes over 8.4 MB are refused" in piped.stderr
    for result in (checked, mapped, piped):
        assert_clean(result.stderr)


def test_a_missing_genome_file_is_an_error_line(tmp_path: Path) -> None:
    result = runner.invoke(app, ["map", str(SINE_WALK), "--genome-file", str(tmp_path / "none.txt")])
    assert result.exit_code == 2
    assert result.stderr == f"error: cannot read {tmp_path / 'none.txt'}: no such file\n"


# ---- fmt: links, permissions, owners, counts ----------------------------------------------------

UNFORMATTED = "<a>::=x|y\n"
FORMATTED = "<a> ::= x | y\n"


def test_fmt_follows_symlinks_and_keeps_mode_owner_and_hard_links(tmp_path: Path) -> None:
    target = tmp_path / "target.gg"
    target.write_text(UNFORMATTED)
    target.chmod(0o640)
    owner = (1234, 2345) if IS_ROOT else (target.stat().st_uid, target.stat().st_gid)
    if IS_ROOT:
        os.chown(target, *owner)
    link = tmp_path / "link.gg"
    link.symlink_to(target.name)
    linked = tmp_path / "linked.gg"
    linked.write_text(UNFORMATTED)
    other_name = tmp_path / "other-name.gg"
    os.link(linked, other_name)
    inode = linked.stat().st_ino

    result = runner.invoke(app, ["fmt", str(link), str(linked)])
    assert result.exit_code == 0, result.stderr
    assert link.is_symlink()  # the link stays a link
    assert os.readlink(link) == "target.gg"
    assert target.read_text() == FORMATTED
    info = target.stat()
    assert stat.S_IMODE(info.st_mode) == 0o640
    assert (info.st_uid, info.st_gid) == owner
    assert linked.stat().st_ino == other_name.stat().st_ino == inode  # still one file, two names
    assert other_name.read_text() == FORMATTED
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "link.gg",
        "linked.gg",
        "other-name.gg",
        "target.gg",
    ]


def test_fmt_counts_every_file_once_and_never_says_minus_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A failed write is a failure, not a change minus one."""
    real_replace = os.replace

    def replace(src: str, dst: str | os.PathLike[str]) -> None:
        if Path(dst).name == "full.gg":
            raise OSError(errno.ENOSPC, "No space left on device")
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    full = tmp_path / "full.gg"
    full.write_text(UNFORMATTED)
    alone = runner.invoke(app, ["fmt", str(full)])
    assert alone.exit_code == 2
    assert f"error: cannot write {full}: no space left on device\n" in alone.stderr
    assert alone.stderr.splitlines()[-1] == "0 files reformatted, 0 files unchanged, 1 file failed"
    assert full.read_text() == UNFORMATTED

    files = {"changed.gg": UNFORMATTED, "same.gg": FORMATTED, "broken.gg": "<a>::=x|'oops\n"}
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    paths = [str(tmp_path / n) for n in ("changed.gg", "same.gg", "full.gg", "missing.gg", "broken.gg")]
    mixed = runner.invoke(app, ["fmt", *paths])
    assert mixed.exit_code == 2
    assert mixed.stderr.splitlines()[-1] == (
        "1 file reformatted, 1 file unchanged, 1 file with syntax errors, 2 files failed"
    )
    checked = runner.invoke(app, ["fmt", "--check", *paths[1:3]])
    assert checked.exit_code == 1
    assert checked.stderr.splitlines()[-1] == "1 file would be reformatted, 1 file unchanged"


def test_an_in_place_write_that_fails_puts_the_old_text_back(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "g.gg"
    path.write_text(UNFORMATTED)
    os.link(path, tmp_path / "h.gg")
    real = fileio._overwrite
    calls = []

    def overwrite(handle: object, payload: bytes) -> None:
        calls.append(payload)
        if len(calls) == 1:
            handle.write(payload[:3])  # type: ignore[attr-defined]  # half written, then the disk fills
            raise OSError(errno.ENOSPC, "No space left on device")
        real(handle, payload)  # type: ignore[arg-type]

    monkeypatch.setattr(fileio, "_overwrite", overwrite)
    result = runner.invoke(app, ["fmt", str(path)])
    assert result.exit_code == 2
    assert path.read_text() == UNFORMATTED
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.gg", "h.gg"]  # the copy is gone too


def test_fmt_rewrites_a_writable_file_in_a_directory_it_may_not_create_files_in(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """As an editor would: no temporary file can be made beside it, so it is written in place."""
    path = tmp_path / "g.gg"
    path.write_text(UNFORMATTED)
    inode = path.stat().st_ino

    def refuse(*args: object, **kwargs: object) -> None:
        raise PermissionError(errno.EACCES, "Permission denied")

    real_access = os.access
    monkeypatch.setattr(fileio.tempfile, "mkstemp", refuse)
    monkeypatch.setattr(os, "access", lambda p, mode: Path(p) != tmp_path and real_access(p, mode))
    result = runner.invoke(app, ["fmt", str(path)])
    assert result.exit_code == 0, result.stderr
    assert path.read_text() == FORMATTED
    assert path.stat().st_ino == inode


# ---- sizes: trees, samples -------------------------------------------------------------------------


def test_map_refuses_trees_too_large_to_draw_before_building_them(tmp_path: Path) -> None:
    bushy = tmp_path / "bushy.gg"
    bushy.write_text("<e> ::= <e><e> | x\n")
    chain = tmp_path / "chain.gg"
    chain.write_text("<e> ::= <e>x | x\n")
    zeros = tmp_path / "zeros.txt"
    zeros.write_text(",".join(["0"] * 30_000))

    wide = gaitgram("map", str(bushy), "--genome-file", str(zeros), "--tree", "ascii")
    assert wide.returncode == 2
    assert "error: the derivation tree has more than 100,000 nodes" in wide.stderr
    assert wide.stdout == ""

    deep = gaitgram("map", str(chain), "--genome-file", str(zeros), "--max-wraps", "0", "--tree", "ascii")
    assert deep.returncode == 2
    assert "error: the derivation tree is 30,001 levels deep" in deep.stderr
    dot = gaitgram("map", str(chain), "--genome-file", str(zeros), "--max-wraps", "0", "--tree", "dot")
    assert dot.returncode == 1  # invalid (the codons ran out), and drawn: DOT does not indent
    assert dot.stdout.count("\n  n") == 30_001 + 30_001 + 30_000 + 30_000  # nodes, then edges

    zeros.write_text(",".join(["0"] * 300_000))
    huge = gaitgram("map", str(bushy), "--genome-file", str(zeros))
    assert huge.returncode == 2
    assert "error: the derivation reads 1,200,000 codons" in huge.stderr
    for result in (wide, deep, dot, huge):
        assert_clean(result.stderr)


def test_sample_prints_each_derivation_as_it_is_made(monkeypatch: pytest.MonkeyPatch) -> None:
    """The first samples are out before the fourth is even made (here: fails to be)."""
    from gaitgram.cli import sample  # noqa: F401 (imported before the patch: it keeps the real random_tree)
    from gaitgram.ge import initialisation

    real = initialisation.random_tree
    made = []

    def random_tree(*args: object, **kwargs: object) -> initialisation.GeneratedTree:
        if len(made) == 3:
            raise initialisation.InitialisationError("stop here")
        made.append(1)
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(initialisation, "random_tree", random_tree)
    result = runner.invoke(app, ["sample", str(SINE_WALK), "-n", "1000"])
    assert result.exit_code == 1
    assert len(result.stdout.splitlines()) == 3
    assert "error: stop here" in result.stderr


@pytest.mark.parametrize("method", ["ramped", "grow", "full"])
def test_streamed_samples_are_the_population_the_library_makes(method: str) -> None:
    import numpy as np

    from gaitgram.analysis import check
    from gaitgram.ge import compile_mapper
    from gaitgram.ge.initialisation import Method, ramped_population, random_tree
    from gaitgram.language import load

    result = runner.invoke(
        app, ["sample", str(SINE_WALK), "-n", "25", "--max-depth", "9", "--seed", "7", "--method", method]
    )
    assert result.exit_code == 0
    checked = check(load(SINE_WALK))
    rng = np.random.default_rng(7)
    if method == "ramped":
        trees = ramped_population(checked.facts, rng, 25, max_depth=9, tail=0)
    else:
        trees = [
            random_tree(checked.facts, rng, max_depth=9, method=Method(method), tail=0) for _ in range(25)
        ]
    mapper = compile_mapper(checked.grammar, max_wraps=0)
    assert result.stdout.splitlines() == [mapper.phenotype(t.genome) for t in trees]


# ---- JSON ---------------------------------------------------------------------------------------


def test_json_output_is_strict(monkeypatch: pytest.MonkeyPatch) -> None:
    """A non-finite number is written as null, never as a bare NaN that strict parsers reject."""
    from gaitgram.cli import seed

    fit = SimpleNamespace(text="0", terms=[], dropped=[], rms_error=float("nan"), max_error=float("inf"))
    monkeypatch.setattr(seed, "fit_seed", lambda data, threshold: {"hip": fit})
    result = runner.invoke(app, ["seed", "fit", "--json"])
    assert result.exit_code == 0

    def reject(token: str) -> None:
        raise ValueError(f"not strict JSON: {token}")

    record = json.loads(result.stdout, parse_constant=reject)
    assert record["rms_error"] is None
    assert record["max_error"] is None


def test_no_json_bypasses_the_strict_writer() -> None:
    for folder in ("gaitgram/cli", "gaitgram/ge"):
        for path in sorted((ROOT / folder).glob("*.py")):
            assert "json.dumps(" not in path.read_text(), f"{path}: use gaitgram.jsonio.dumps"
