"""``gaitgram check`` and ``gaitgram fmt`` from the outside: output, JSON and exit codes."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.cli import app

runner = CliRunner()

BROKEN = "<a> ::= <b> | <nope>\n<b> ::= int[5..1]\n<c> ::= x\n"


@pytest.fixture
def broken(tmp_path: Path) -> Path:
    path = tmp_path / "broken.gg"
    path.write_text(BROKEN)
    return path


def test_human_output_has_location_code_source_caret_and_hint(broken: Path) -> None:
    result = runner.invoke(app, ["check", str(broken)])
    assert result.exit_code == 1
    out = result.stdout
    assert f"{broken}:1:15: error[GG201] <nope> is not defined" in out
    assert "1 | <a> ::= <b> | <nope>\n  |               ^^^^^^\n" in out
    assert f"{broken}:2:9: error[GG301]" in out
    assert f"{broken}:3:1: warning[GG204]" in out
    assert "= hint:" in out
    assert "2 errors, 1 warning in 1 file" in result.stderr


def test_json_output(broken: Path) -> None:
    result = runner.invoke(app, ["check", "--format", "json", str(broken)])
    assert result.exit_code == 1
    records = json.loads(result.stdout)
    undefined = next(r for r in records if r["code"] == "GG201")
    assert undefined == {
        "file": str(broken),
        "code": "GG201",
        "name": "undefined-rule",
        "severity": "error",
        "message": "<nope> is not defined",
        "rule": "a",  # the rule the problem is in
        "line": 1,
        "column": 15,
        "end_line": 1,
        "end_column": 21,
        "hint": undefined["hint"],
        "data": {"name": "nope"},
        "fixes": undefined["fixes"],  # see test_check_fix.py
    }
    assert [f["title"] for f in undefined["fixes"]] == ["Define <nope>"]
    assert {r["severity"] for r in records} == {"error", "warning"}


def test_strict_turns_warnings_into_errors(tmp_path: Path) -> None:
    path = tmp_path / "w.gg"
    path.write_text("<a> ::= x\n<b> ::= y\n")
    assert runner.invoke(app, ["check", str(path)]).exit_code == 0
    strict = runner.invoke(app, ["check", "--strict", "-f", "json", str(path)])
    assert strict.exit_code == 1
    assert [r["severity"] for r in json.loads(strict.stdout)] == ["error"]


def test_exit_code_2_for_unreadable_files_and_bad_usage(tmp_path: Path, broken: Path) -> None:
    missing = runner.invoke(app, ["check", str(tmp_path / "missing.gg"), str(broken)])
    assert missing.exit_code == 2
    assert "no such file" in missing.stderr
    assert "GG201" in missing.stdout  # the readable file is still checked
    assert runner.invoke(app, ["check"]).exit_code == 2
    assert runner.invoke(app, ["check", "--format", "xml", str(broken)]).exit_code == 2
    assert runner.invoke(app, ["check", "--define", "n", str(broken)]).exit_code == 2


def test_defines(tmp_path: Path) -> None:
    path = tmp_path / "d.gg"
    path.write_text("<a> ::= GE_RANGE:n_vars\n")
    assert runner.invoke(app, ["check", str(path)]).exit_code == 1
    assert runner.invoke(app, ["check", "-D", "n_vars=3", str(path)]).exit_code == 0


def test_a_define_of_thousands_of_digits_is_too_large_in_a_short_message(tmp_path: Path) -> None:
    path = tmp_path / "d.gg"
    path.write_text("<a> ::= GE_RANGE:n\n")
    result = runner.invoke(app, ["check", "-D", f"n={'9' * 5000}", str(path)])
    assert result.exit_code == 2
    assert "n=999999999999…: the value is too large" in result.output
    assert len(result.output) < 400
    large = runner.invoke(app, ["check", "-D", f"n={'9' * 40}", str(path)])  # int() reads it
    assert large.exit_code == 1
    assert "GE_RANGE:n is too large; its size must be between 1 and 100,000" in large.output


def test_bundled_grammars_pass_strict() -> None:
    paths = sorted(str(p) for p in GRAMMARS.glob("*.gg"))
    assert paths
    result = runner.invoke(app, ["check", "--strict", *paths])
    assert result.exit_code == 0, result.stdout


def test_fmt_in_place_check_and_diff(tmp_path: Path) -> None:
    path = tmp_path / "f.gg"
    path.write_text("<a>::=x|y\n<b> ::= z\n")
    assert runner.invoke(app, ["fmt", "--check", str(path)]).exit_code == 1
    diff = runner.invoke(app, ["fmt", "--diff", str(path)])
    assert diff.exit_code == 1
    assert "-<a>::=x|y\n+<a> ::= x | y\n" in diff.stdout
    assert path.read_text() == "<a>::=x|y\n<b> ::= z\n"  # --check and --diff write nothing
    assert runner.invoke(app, ["fmt", str(path)]).exit_code == 0
    assert path.read_text() == "<a> ::= x | y\n<b> ::= z\n"
    assert runner.invoke(app, ["fmt", "--check", str(path)]).exit_code == 0
    assert [p.name for p in tmp_path.iterdir()] == ["f.gg"]  # no temporary file left behind


def test_fmt_keeps_line_breaks_and_byte_order_mark_and_its_diff_is_exact(tmp_path: Path) -> None:
    """The diff is of the file's bytes (tabs, CRLF, no newline at the end), as fmt writes them,
    so patch makes what fmt writes; a CRLF file stays CRLF."""
    raw = b"\xef\xbb\xbf<a>\t::=x|'\ty'\r\n# keep\tme\r\n<b> ::= z  # c"
    (tmp_path / "f.gg").write_bytes(raw)
    env = {**os.environ, "NO_COLOR": "1"}
    diff = subprocess.run(
        [sys.executable, "-m", "gaitgram", "fmt", "--diff", "f.gg"],
        capture_output=True,
        env=env,
        cwd=tmp_path,
    )
    assert diff.returncode == 1, diff.stderr
    assert diff.stdout == (
        b"--- f.gg\n+++ f.gg\n@@ -1,3 +1,3 @@\n"
        b"-\xef\xbb\xbf<a>\t::=x|'\ty'\r\n+\xef\xbb\xbf<a> ::= x | '\ty'\r\n # keep\tme\r\n"
        b"-<b> ::= z  # c\n\\ No newline at end of file\n+<b> ::= z  # c\r\n"
    )
    assert (tmp_path / "f.gg").read_bytes() == raw
    assert runner.invoke(app, ["fmt", str(tmp_path / "f.gg")]).exit_code == 0
    formatted = (tmp_path / "f.gg").read_bytes()
    assert formatted == b"\xef\xbb\xbf<a> ::= x | '\ty'\r\n# keep\tme\r\n<b> ::= z  # c\r\n"
    assert runner.invoke(app, ["fmt", "--check", str(tmp_path / "f.gg")]).exit_code == 0
    if shutil.which("patch") is None:
        pytest.skip("needs patch (Debian's patch package; .ci/run installs it) to apply the diff")
    (tmp_path / "f.gg").write_bytes(raw)
    applied = subprocess.run(
        ["patch", "--fuzz=0", "f.gg"], input=diff.stdout, capture_output=True, cwd=tmp_path
    )
    assert applied.returncode == 0, applied.stdout + applied.stderr
    assert (tmp_path / "f.gg").read_bytes() == formatted


def test_fmt_leaves_files_with_syntax_errors_alone(tmp_path: Path) -> None:
    path = tmp_path / "bad.gg"
    text = "<a>::=x|'oops\n"
    path.write_text(text)
    result = runner.invoke(app, ["fmt", str(path)])
    assert result.exit_code == 1
    assert "GG102" in result.stderr
    assert path.read_text() == text


GARBAGE = st.one_of(st.binary(max_size=200), st.text(max_size=200).map(str.encode))
EVERY_READER = pytest.mark.parametrize(
    "args",
    [
        ["check"],
        ["check", "-f", "json"],
        ["check", "-f", "sarif"],
        ["check", "--fix", "--unsafe-fixes"],
        ["check", "--diff"],
        ["fmt", "--check"],
    ],
)


def garbage_never_gives_a_traceback(
    tmp_path_factory: pytest.TempPathFactory, args: list[str], data: bytes
) -> None:
    path = tmp_path_factory.mktemp("garbage") / "g.gg"
    path.write_bytes(data)
    result = runner.invoke(app, [*args, str(path)])
    assert result.exit_code in (0, 1, 2)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    if result.exit_code == 2:
        assert "error:" in result.stderr


# 25 files a command in the default run, 150 in the slow set.
test_garbage_files_never_give_a_traceback = EVERY_READER(
    settings(max_examples=25)(given(data=GARBAGE)(garbage_never_gives_a_traceback))
)
test_garbage_files_never_give_a_traceback_at_length = pytest.mark.slow(
    EVERY_READER(settings(max_examples=150)(given(data=GARBAGE)(garbage_never_gives_a_traceback)))
)


def test_directories_and_huge_files_get_clear_errors(tmp_path: Path) -> None:
    huge = tmp_path / "huge.gg"
    huge.write_bytes(b"<a> ::= x\n" * (1024 * 1024))  # 10 MB
    result = runner.invoke(app, ["check", str(huge), str(tmp_path)])
    assert result.exit_code == 2
    assert f"error: cannot read {huge}: is 10.5 MB; grammars over 8.4 MB are refused" in result.stderr
    assert f"error: cannot read {tmp_path}: is a directory" in result.stderr


def test_console_script_runs_as_a_module(broken: Path) -> None:
    env = {**os.environ, "NO_COLOR": "1"}
    run = subprocess.run(
        [sys.executable, "-m", "gaitgram", "check", str(broken)], capture_output=True, text=True, env=env
    )
    assert run.returncode == 1
    assert "error[GG201]" in run.stdout
    assert "Traceback" not in run.stderr


def test_every_diagnostic_code_is_documented() -> None:
    from gaitgram.analysis.diagnostic_codes import CODES

    documented = (GRAMMARS.parent / "docs" / "diagnostics.md").read_text()
    for code in CODES.values():
        assert f"| {code.code} | `{code.name}` |" in documented, code


def test_the_summary_counts_info_messages_in_english(tmp_path: Path) -> None:
    path = tmp_path / "chains.gg"
    path.write_text("<a> ::= <b>\n<b> ::= <c>\n<c> ::= x | y\n")
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0, result.stderr
    assert result.stdout.count("info[GG206]") == 2
    assert "2 info messages in 1 file" in result.stderr
