"""``gaitgram check --fix`` / ``--diff``: what is written, what is kept, and what is refused."""

from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.analysis import files as check_cli  # where check reads, fixes and writes files
from gaitgram.analysis import fixes
from gaitgram.cli import app

runner = CliRunner()

FIXABLE = "<a> ::= x | | y | flaot[0..1 step 0.5] | <bee>\n<b> ::= 'open\n<beef> ::= z\n"
SAFELY_FIXED = "<a> ::= x | y | float[0..1 step 0.5] | <bee>\n<b> ::= 'open'\n<beef> ::= z\n"


@pytest.fixture
def fixable(tmp_path: Path) -> Path:
    path = tmp_path / "fixable.gg"
    path.write_text(FIXABLE)
    return path


def test_fix_writes_the_safe_fixes_and_reports_what_remains(fixable: Path) -> None:
    result = runner.invoke(app, ["check", "--fix", str(fixable)])
    assert fixable.read_text() == SAFELY_FIXED
    assert f"fixed {fixable}:1:13: GG106 Delete the extra |" in result.stderr
    assert f"fixed {fixable}:1:19: GG309 Make it the range float[0..1 step 0.5]" in result.stderr
    assert f"fixed {fixable}:2:9: GG102 Close the string with '" in result.stderr
    assert (
        "fixed 3 problems in 1 file (3 more fixes with --unsafe-fixes); 1 error, 2 warnings" in result.stderr
    )
    assert f"{fixable}:1:40: error[GG201] <bee> is not defined" in result.stdout  # where it is now
    assert result.exit_code == 1  # an error remains
    assert [p.name for p in fixable.parent.iterdir()] == ["fixable.gg"]  # no temporary file left


def test_unsafe_fixes_apply_the_preferred_fix_too(fixable: Path) -> None:
    result = runner.invoke(app, ["check", "--fix", "--unsafe-fixes", str(fixable)])
    assert result.exit_code == 0, result.output
    assert fixable.read_text() == "<a> ::= x | y | float[0..1 step 0.5] | <beef>\n<beef> ::= z\n"
    assert "1 file OK" in result.stderr


def test_diff_previews_without_writing(fixable: Path) -> None:
    result = runner.invoke(app, ["check", "--diff", str(fixable)])
    assert result.exit_code == 1
    assert fixable.read_text() == FIXABLE
    assert "-<a> ::= x | | y | flaot[0..1 step 0.5] | <bee>\n-<b> ::= 'open\n" in result.stdout
    assert "+<a> ::= x | y | float[0..1 step 0.5] | <bee>\n+<b> ::= 'open'\n <beef> ::= z\n" in result.stdout
    assert "error[GG201]" not in result.stdout  # only the diff
    assert "would fix 3 problems in 1 file" in result.stderr
    both = runner.invoke(app, ["check", "--fix", "--diff", str(fixable)])
    assert both.stdout == result.stdout
    assert fixable.read_text() == FIXABLE


def test_a_clean_file_is_not_touched(tmp_path: Path) -> None:
    path = tmp_path / "clean.gg"
    path.write_text("<a> ::= x | <b>\n<b> ::= y\n")
    before = path.stat()
    for args in (["--fix"], ["--fix", "--unsafe-fixes"], ["--diff"]):
        result = runner.invoke(app, ["check", *args, str(path)])
        assert result.exit_code == 0
        assert "nothing to fix" in result.stderr
    after = path.stat()
    assert (after.st_ino, after.st_mtime_ns) == (before.st_ino, before.st_mtime_ns)


def test_the_bundled_grammars_need_no_fix(tmp_path: Path) -> None:
    copies = []
    for path in sorted(GRAMMARS.glob("*.gg")):
        copies.append(tmp_path / path.name)
        shutil.copy(path, copies[-1])
    result = runner.invoke(app, ["check", "--fix", "--unsafe-fixes", *map(str, copies)])
    assert result.exit_code == 0, result.output
    for copy in copies:
        assert copy.read_bytes() == (GRAMMARS / copy.name).read_bytes()


def test_line_breaks_and_byte_order_mark_are_kept(tmp_path: Path) -> None:
    path = tmp_path / "crlf.gg"
    path.write_bytes(b"\xef\xbb\xbf<a> ::= x | | y\r\n# keep me\r\n<b> ::= 'z\r\n<c> ::= w\n")
    runner.invoke(app, ["check", "--fix", str(path)])
    assert path.read_bytes() == b"\xef\xbb\xbf<a> ::= x | y\r\n# keep me\r\n<b> ::= 'z'\r\n<c> ::= w\n"


def gaitgram(*args: str, cwd: Path) -> subprocess.CompletedProcess[bytes]:
    """The command as a user runs it: standard output as the bytes it wrote."""
    env = {**os.environ, "NO_COLOR": "1"}
    return subprocess.run([sys.executable, "-m", "gaitgram", *args], capture_output=True, env=env, cwd=cwd)


#: Tabs, CRLF line breaks, a byte order mark and no newline at the end: all must survive a diff.
RAW = b"\xef\xbb\xbf<a> ::= x\t| | y\r\n# keep\tme\r\n<b> ::= 'z\r\n<c>\t::= w"


def test_diff_is_the_exact_bytes_so_patch_makes_what_fix_writes(tmp_path: Path) -> None:
    (tmp_path / "raw.gg").write_bytes(RAW)
    (tmp_path / "fixed.gg").write_bytes(RAW)
    diff = gaitgram("check", "--diff", "raw.gg", cwd=tmp_path)
    assert diff.returncode == 1, diff.stderr
    assert b"-\xef\xbb\xbf<a> ::= x\t| | y\r\n+\xef\xbb\xbf<a> ::= x\t| y\r\n" in diff.stdout
    assert b" # keep\tme\r\n-<b> ::= 'z\r\n+<b> ::= 'z'\r\n" in diff.stdout
    assert (tmp_path / "raw.gg").read_bytes() == RAW
    assert gaitgram("check", "--fix", "fixed.gg", cwd=tmp_path).returncode == 0
    fixed = (tmp_path / "fixed.gg").read_bytes()
    assert fixed == b"\xef\xbb\xbf<a> ::= x\t| y\r\n# keep\tme\r\n<b> ::= 'z'\r\n<c>\t::= w"
    if shutil.which("patch") is None:
        pytest.skip("needs patch (Debian's patch package; .ci/run installs it) to apply the diff")
    applied = subprocess.run(
        ["patch", "--fuzz=0", "raw.gg"], input=diff.stdout, capture_output=True, cwd=tmp_path
    )
    assert applied.returncode == 0, applied.stdout + applied.stderr
    assert (tmp_path / "raw.gg").read_bytes() == fixed


def test_a_blank_line_after_a_fixed_line_is_kept_in_a_file_of_cr_line_breaks(tmp_path: Path) -> None:
    """The fixed line gets the file's most common line break, CR; before the blank line's LF it
    would read as one CRLF break, and the blank line would be gone."""
    path = tmp_path / "cr.gg"
    path.write_bytes(b"# a\r# b\r# c\r<a> ::= p | | q\n\n<b> ::= r\r")
    runner.invoke(app, ["check", "--fix", str(path)])
    assert path.read_bytes() == b"# a\r# b\r# c\r<a> ::= p | q\r\n\n<b> ::= r\r"


def test_a_second_fix_changes_nothing(tmp_path: Path) -> None:
    """Closing the string makes the merge of the two <amp> rules possible: the first run does
    both, where it used to leave the merge for a second run."""
    path = tmp_path / "amp.gg"
    path.write_text("<amp> ::= x # c\n<amp> ::= 1 |'open |2\n<legs> ::= y\n")
    first = gaitgram("check", "--fix", "--unsafe-fixes", "amp.gg", cwd=tmp_path)
    assert first.returncode == 0, first.stdout + first.stderr
    once = path.read_bytes()
    assert once == b"<amp> ::= x | 1 |'open |2' # c\n"
    assert b"GG202 Merge its alternatives into the first <amp>" in first.stderr
    second = gaitgram("check", "--fix", "--unsafe-fixes", "amp.gg", cwd=tmp_path)
    assert second.returncode == 0
    assert b"nothing to fix" in second.stderr
    assert path.read_bytes() == once


def test_fixes_that_do_not_settle_say_so(fixable: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(fixes, "MAX_PASSES", 1)  # FIXABLE takes two rounds with --unsafe-fixes
    result = runner.invoke(app, ["check", "--fix", "--unsafe-fixes", str(fixable)])
    assert (
        f"warning: {fixable}: the fixes did not settle after 1 round, each making more to fix"
        in result.stderr
    )
    assert "run the command again for the rest" in result.stderr
    monkeypatch.undo()
    again = runner.invoke(app, ["check", "--fix", "--unsafe-fixes", str(fixable)])
    assert "did not settle" not in again.stderr
    assert fixable.read_text() == "<a> ::= x | y | float[0..1 step 0.5] | <beef>\n<beef> ::= z\n"


def test_json_lists_the_fixes_and_the_remaining_problems(fixable: Path) -> None:
    before = json.loads(runner.invoke(app, ["check", "-f", "json", str(fixable)]).stdout)
    look_alike = next(r for r in before if r["code"] == "GG309")
    assert look_alike["data"] == {"text": "flaot[0..1 step 0.5]", "kind": "float"}
    assert look_alike["fixes"] == [
        {
            "title": "Make it the range float[0..1 step 0.5]",
            "applicability": "safe",
            "preferred": True,
            "edits": [{"line": 1, "column": 19, "end_line": 1, "end_column": 24, "text": "float"}],
        }
    ]
    after = runner.invoke(app, ["check", "--fix", "-f", "json", str(fixable)])
    assert sorted(r["code"] for r in json.loads(after.stdout)) == ["GG201", "GG204", "GG204"]


def test_a_file_changed_while_it_was_fixed_is_not_written(
    fixable: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    real = check_cli.fix_source

    def meanwhile(*args: object, **kwargs: object) -> object:
        outcome = real(*args, **kwargs)  # type: ignore[arg-type]
        fixable.write_text(FIXABLE + "<new> ::= typed meanwhile\n")  # an editor saves the file
        return outcome

    monkeypatch.setattr(check_cli, "fix_source", meanwhile)
    result = runner.invoke(app, ["check", "--fix", str(fixable)])
    assert result.exit_code == 2
    assert f"error: {fixable} changed while it was being fixed; not written" in result.stderr
    assert fixable.read_text().endswith("<new> ::= typed meanwhile\n")


def test_unreadable_files_and_bad_option_combinations_are_errors(tmp_path: Path, fixable: Path) -> None:
    result = runner.invoke(app, ["check", "--fix", str(tmp_path / "missing.gg"), str(fixable)])
    assert result.exit_code == 2
    assert "no such file" in result.stderr
    assert fixable.read_text() == SAFELY_FIXED  # the readable file is still fixed
    lonely = runner.invoke(app, ["check", "--unsafe-fixes", str(fixable)])
    assert lonely.exit_code == 2
    assert "--unsafe-fixes needs --fix or --diff" in lonely.output
    assert runner.invoke(app, ["check", "--diff", "-f", "json", str(fixable)]).exit_code == 2


def test_a_failed_write_is_a_clear_error_and_leaves_the_file(
    fixable: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def full(path: Path, data: str | bytes) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(check_cli, "write_output", full)
    result = runner.invoke(app, ["check", "--fix", str(fixable)])
    assert result.exit_code == 2
    assert f"error: cannot write {fixable}: no space left on device" in result.stderr
    assert "fixed nothing (3 more fixes with --unsafe-fixes); 1 file could not be written" in result.stderr
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert fixable.read_text() == FIXABLE
    assert f"{fixable}:1:13: warning[GG106]" in result.stdout  # what is still in the file
