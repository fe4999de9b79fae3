"""``check --fix``, ``check --diff``, ``fmt`` and ``fmt --diff`` agree byte for byte, and fixing
reaches a fixed point: the diff, applied to the file (by ``patch``, or by the strict applier
below), makes exactly what ``--fix`` or ``fmt`` writes, tabs, CRLF and byte order mark
included; and running ``--fix`` again changes nothing. Over generated grammars, as files."""

from __future__ import annotations

import functools
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
import typer.main
import typer.testing
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from gaitgram.cli import app

runner = CliRunner()


@pytest.fixture(scope="module", autouse=True)
def command_built_once() -> Iterator[None]:
    """Typer rebuilds the command from its functions' signatures on every invoke, which takes
    longer than the command itself here: build it once for the hundreds of runs below."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(typer.testing, "_get_command", functools.cache(typer.main.get_command))
        yield


_LINE = re.compile(rb"[^\n]*\n|[^\n]+\Z")
_HUNK = re.compile(rb"@@ -(\d+)(?:,(\d+))? \+(\d+)(?:,(\d+))? @@\n")


def apply_unified_diff(original: bytes, diff: bytes) -> bytes:
    """``original`` with a one-file unified diff applied, strictly (as ``patch`` with no fuzz):
    every context and removed line must be the file's, byte for byte, where the hunk says."""
    if not diff:
        return original
    old, lines = _LINE.findall(original), _LINE.findall(diff)
    assert lines[0].startswith(b"--- "), lines[0]
    assert lines[1].startswith(b"+++ "), lines[1]
    out: list[bytes] = []
    at, i = 0, 2
    while i < len(lines):
        hunk = _HUNK.fullmatch(lines[i])
        assert hunk is not None, lines[i]
        old_count = 1 if hunk[2] is None else int(hunk[2])
        new_count = 1 if hunk[4] is None else int(hunk[4])
        start = int(hunk[1]) - (1 if old_count else 0)
        assert start >= at, (start, at)
        out += old[at:start]
        at, i = start, i + 1
        kept = removed = added = 0
        while i < len(lines) and not lines[i].startswith(b"@@"):
            tag, body = lines[i][:1], lines[i][1:]
            i += 1
            if i < len(lines) and lines[i] == b"\\ No newline at end of file\n":
                assert body.endswith(b"\n")
                body, i = body[:-1], i + 1
            if tag in (b" ", b"-"):
                assert old[at : at + 1] == [body], (old[at : at + 1], body)
                at += 1
                if tag == b" ":
                    out.append(body)
                    kept += 1
                else:
                    removed += 1
            else:
                assert tag == b"+", lines[i - 1]
                out.append(body)
                added += 1
        assert (kept + removed, kept + added) == (old_count, new_count)
    return b"".join(out + old[at:])


def patch_command() -> str:
    found = shutil.which("patch")
    if found is None:
        pytest.skip("needs patch (Debian's patch package; .ci/run installs it)")
    return found


def patched(original: bytes, diff: bytes) -> bytes:
    """``original`` with ``diff`` applied by GNU patch (no fuzz, so only an exact diff applies)."""
    with tempfile.TemporaryDirectory() as folder:
        target, out = Path(folder) / "target.gg", Path(folder) / "out.gg"
        target.write_bytes(original)
        if not diff:
            return original
        run = subprocess.run(
            [patch_command(), "--fuzz=0", "--force", "--silent", "-o", str(out), str(target)],
            input=diff,
            capture_output=True,
        )
        assert run.returncode == 0, run.stdout + run.stderr
        return out.read_bytes()


# ---- grammars as files: tabs, CRLF, CR, a byte order mark, comments, no final newline ----------

PIECES = [
    "<a> ::= ",
    "<a>\t::=\t",
    "<b> ::= ",
    "<bee>  ::= ",
    "<amp> ::= ",
    "<legs> ::= ",
    "<a>",
    "<b>",
    "<be>",
    " | ",
    "\t|\t",
    "|",
    "\n",
    "\n\n",
    "  ",
    "\t",
    "# c\n",
    "\t# tab comment\n",
    "'",
    "'x'",
    "'\tx'",
    "'open ",
    "\\x4",
    "x",
    "1",
    "int[1..5",
    "int[5..1]",
    "flaot[0..1 step 0.5]",
    "float[0..1 step 0.3]",
    "int[0..1 step 0.5]",
    "]",
    "@start <a>\n",
    "  @start <b>\n",
    "@joint hip_hind\n",
    "@jont x\n",
    "<amp> ::= x # c\n",
    "<amp> ::= 1 |'open |2\n",
    "<legs> ::= y\n",
]


@st.composite
def grammar_files(draw: st.DrawFn, pieces: list[str] = PIECES) -> bytes:
    """A grammar's bytes: its line breaks LF, CRLF or CR, each its own, maybe a byte order mark."""
    text = "".join(draw(st.lists(st.sampled_from(pieces), max_size=25)))
    breaks = iter(draw(st.lists(st.sampled_from(["\n", "\n", "\r\n", "\r"]), min_size=text.count("\n"))))
    if draw(st.booleans()):  # one style for the whole file, as most files have
        style = draw(st.sampled_from(["\n", "\r\n"]))
        breaks = iter([style] * text.count("\n"))
    text = re.sub("\n", lambda _: next(breaks), text)
    bom = b"\xef\xbb\xbf" if draw(st.booleans()) else b""
    return bom + text.encode("utf-8")


@contextmanager
def files(*contents: bytes) -> Iterator[list[Path]]:
    with tempfile.TemporaryDirectory() as folder:
        paths = []
        for i, data in enumerate(contents):
            paths.append(Path(folder) / f"g{i}.gg")
            paths[-1].write_bytes(data)
        yield paths


def run(*args: str) -> bytes:
    """Standard output as bytes, after checking the command ran without an exception."""
    result = runner.invoke(app, list(args))
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    assert result.exit_code in (0, 1), result.output
    return result.stdout_bytes


FIX_OPTIONS = st.sampled_from([[], ["--unsafe-fixes"]])


@settings(max_examples=250, deadline=None)
@given(data=grammar_files(), options=FIX_OPTIONS)
def test_check_diff_applied_is_what_fix_writes_and_fixing_again_changes_nothing(
    data: bytes, options: list[str]
) -> None:
    with files(data, data) as (previewed, fixed):
        diff = run("check", "--diff", *options, str(previewed))
        assert previewed.read_bytes() == data  # --diff writes nothing
        run("check", "--fix", *options, str(fixed))
        once = fixed.read_bytes()
        assert apply_unified_diff(data, diff) == once
        second = runner.invoke(app, ["check", "--fix", *options, str(fixed)])
        assert fixed.read_bytes() == once, "a second --fix changed the file"
        assert "nothing to fix" in second.stderr
        assert run("check", "--diff", *options, str(fixed)) == b""


@settings(max_examples=80, deadline=None)
@given(data=grammar_files(), options=FIX_OPTIONS)
def test_patch_applies_the_check_diff_to_make_what_fix_writes(data: bytes, options: list[str]) -> None:
    patch_command()
    with files(data, data) as (previewed, fixed):
        diff = run("check", "--diff", *options, str(previewed))
        run("check", "--fix", *options, str(fixed))
        assert patched(data, diff) == fixed.read_bytes()


#: Layout that fmt changes, around text that parses.
LAYOUT = [
    "<a>::=x\n",
    "<a>\t::=\t'x'\t|\ty\n",
    "<b> ::=   <a>  |  'z'\n",
    "<c>::=1|2",
    "\t|\t3\n",
    "    | 4\n",
    "  @start <a>\n",
    "@start\t<a>\n",
    "# comment\t\n",
    " x  # trailing\t\n",
    "\n",
    " ",
    "\t",
]


@settings(max_examples=200, deadline=None)
@given(data=grammar_files(LAYOUT))
def test_fmt_diff_applied_is_what_fmt_writes_and_formatting_again_changes_nothing(data: bytes) -> None:
    with files(data, data) as (previewed, formatted):
        diff = run("fmt", "--diff", str(previewed))
        assert previewed.read_bytes() == data
        run("fmt", str(formatted))
        once = formatted.read_bytes()
        assert apply_unified_diff(data, diff) == once
        run("fmt", str(formatted))
        assert formatted.read_bytes() == once
        assert run("fmt", "--diff", str(formatted)) == b""


@settings(max_examples=80, deadline=None)
@given(data=grammar_files(LAYOUT))
def test_patch_applies_the_fmt_diff_to_make_what_fmt_writes(data: bytes) -> None:
    patch_command()
    with files(data, data) as (previewed, formatted):
        diff = run("fmt", "--diff", str(previewed))
        run("fmt", str(formatted))
        assert patched(data, diff) == formatted.read_bytes()
