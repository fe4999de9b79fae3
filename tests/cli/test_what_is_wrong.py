"""Messages name what is wrong (issue 39, class 9): a path that does not exist, a study given where
a run is wanted, a run that lost its checkpoint or its manifest, a misspelt descriptor, a directory
where a file is wanted, a file that cannot be read in JSON output, a loop of symbolic links. Each
is exit 2 with one line that says it and what to do, never a traceback and never another fault's
message."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_STUDY
from gaitgram.cli import app

runner = CliRunner()


@pytest.fixture(scope="module")
def finished(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished study of the tiny curve-match problem (two arms, one run each)."""
    tmp = tmp_path_factory.mktemp("finished")
    (tmp / "g.gg").write_text(CURVE_GRAMMAR)
    (tmp / "tiny.toml").write_text(CURVE_STUDY.format(generations=1))
    result = runner.invoke(app, ["study", str(tmp / "tiny.toml"), "-o", str(tmp / "s"), "--runs", "1", "-q"])
    assert result.exit_code == 0, result.output
    return tmp


def said(*args: str) -> str:
    """The command's one-line error, exit 2 (as one line, whatever the console's width)."""
    result = runner.invoke(app, list(args))
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.stderr
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return " ".join(result.stderr.split())


def arm_copy(finished: Path, tmp_path: Path) -> Path:
    arm = tmp_path / "plain"
    shutil.copytree(finished / "s" / "arms" / "plain", arm)
    return arm


def test_watching_a_directory_that_does_not_exist_yet_says_so(tmp_path: Path) -> None:
    message = said("report", str(tmp_path / "later"), "--watch", "-o", str(tmp_path / "out"))
    assert f"{tmp_path / 'later'}: no such directory yet" in message
    assert f"gaitgram study STUDY.toml -o {tmp_path / 'later'}" in message
    assert "not a `gaitgram evolve` run directory" not in message
    message = said("report", str(tmp_path / "later"), "-o", str(tmp_path / "out"))
    assert message == f"error: {tmp_path / 'later'}: no such directory"


def test_a_study_directory_given_for_a_run_names_its_arms(finished: Path) -> None:
    study = finished / "s"
    for command in (["retarget", "--run", str(study), "--to", "pony"], ["evaluate", "--run", str(study)]):
        message = said(*command)
        assert f"{study} is a study directory, not a run directory: give one of its arms" in message
        assert f"{study / 'arms' / 'mutant'} (its arms: mutant, plain)" in message


def test_a_finished_run_whose_checkpoint_was_deleted_says_so(finished: Path, tmp_path: Path) -> None:
    arm = arm_copy(finished, tmp_path)
    (arm / "run-000" / "checkpoint.json").unlink()
    message = said("evaluate", "--run", str(arm))
    assert (
        f"{arm / 'run-000' / 'checkpoint.json'} is missing, though the run recorded its generations"
        in message
    )
    assert f"gaitgram evolve --resume {arm}" in message
    assert "no run has finished a generation" not in message


def test_a_run_whose_manifest_was_deleted_is_not_called_older(finished: Path, tmp_path: Path) -> None:
    arm = arm_copy(finished, tmp_path)
    (arm / "manifest.json").unlink()
    message = said("evaluate", "--run", str(arm))
    assert f"{arm} cannot be used: its manifest.json is missing, deleted or lost" in message
    assert "older gaitgram" not in message
    message = said("evolve", "--resume", str(arm), "-q")
    assert "its manifest.json is missing" in message


def test_a_misspelt_descriptor_without_a_range_gets_a_did_you_mean(tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(CURVE_GRAMMAR)
    (tmp_path / "run.toml").write_text(
        'backend = "curve-match"\nstrategy = "map-elites"\n'
        '[backend_settings.targets]\nhip_hind = "sin(2*PI*t)"\nelbow_fore = "sin(2*PI*t)"\n'
        '[strategy_settings]\ndescriptors = ["rms_elbow_for"]\n'
    )
    message = said(
        "evolve", str(tmp_path / "g.gg"), "-c", str(tmp_path / "run.toml"), "-o", str(tmp_path / "o")
    )
    assert "descriptors[0].name: backend 'curve-match' reports no component 'rms_elbow_for'" in message
    assert "did you mean rms_elbow_fore?" in message
    assert "give the range" not in message


def test_a_directory_named_like_a_file_is_a_directory(tmp_path: Path) -> None:
    (tmp_path / "x.csv").mkdir()
    assert (
        said("seed", "fit", str(tmp_path / "x.csv"))
        == f"error: {tmp_path / 'x.csv'}: cannot read it: is a directory"
    )
    (tmp_path / "tracks" / "y.csv").mkdir(parents=True)
    message = said("seed", "derive", str(tmp_path / "tracks"), "-o", str(tmp_path / "o.json"))
    assert f"cannot read {tmp_path / 'tracks' / 'y.csv'}: is a directory, not a file" in message
    assert "no such file" not in message


def test_check_json_lists_a_file_it_cannot_read(tmp_path: Path) -> None:
    """As SARIF says it in a notification: the JSON array has the file, never ``[]``."""
    (tmp_path / "nul.gg").write_bytes(b"<a> ::= x\x00\n")
    (tmp_path / "ok.gg").write_text("<a> ::= x\n")
    result = runner.invoke(
        app,
        [
            "check",
            "--format",
            "json",
            str(tmp_path / "nul.gg"),
            str(tmp_path / "gone.gg"),
            str(tmp_path / "ok.gg"),
        ],
    )
    assert result.exit_code == 2
    records = json.loads(result.stdout)
    assert result.stdout == json.dumps(records, indent=2, ensure_ascii=False) + "\n"
    unreadable = [r for r in records if r["name"] == "unreadable-file"]
    assert [(r["file"], r["code"], r["severity"]) for r in unreadable] == [
        (str(tmp_path / "nul.gg"), None, "error"),
        (str(tmp_path / "gone.gg"), None, "error"),
    ]
    assert "contains a NUL byte" in unreadable[0]["message"]
    assert unreadable[1]["message"] == f"cannot read {tmp_path / 'gone.gg'}: no such file"
    assert set(unreadable[0]) == set(records[-1])  # the fields of every diagnostic


def test_a_loop_of_symbolic_links_is_named(finished: Path, tmp_path: Path) -> None:
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    loop = str(tmp_path / "a")
    arm = str(finished / "s" / "arms" / "plain")
    grammar = str(finished / "g.gg")
    for command in (
        ["evolve", grammar, "--start-from", loop, "-o", str(tmp_path / "o")],
        ["evaluate", "--run", loop],
        ["report", loop, "-o", str(tmp_path / "r")],
        ["evolve", grammar, "-c", loop, "-o", str(tmp_path / "o")],
        ["seed", "derive", loop, "-o", str(tmp_path / "d.json")],
        ["evolve", "--resume", arm, "-o", loop, "-q"],
    ):
        message = said(*command)
        assert "too many levels of symbolic links" in message or "a resumed run stays in" in message, command
