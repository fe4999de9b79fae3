"""Run files are untrusted input wherever they are read: ``study.json``, an arm's ``config.toml``,
``stats.jsonl``, ``best.json``, a front; the same directory given twice; a generation the run
never reached. Each is a clear error naming the file (and line, or key) and what to do, exit 2,
never a traceback or a number computed from garbage; records that a finished run lost are
rewritten from its checkpoint by the command that made them."""

from __future__ import annotations

import json
import math
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
from study.test_study import write_arm, write_study
from typer.testing import CliRunner

from gaitgram.cli import app

runner = CliRunner()


@pytest.fixture(scope="module")
def finished(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished study (2 arms x 3 runs), made once: tests work on copies."""
    tmp = tmp_path_factory.mktemp("finished")
    study = write_study(tmp)
    result = runner.invoke(app, ["study", str(study), "-o", str(tmp / "s"), "-q", "--jobs", "2"])
    assert result.exit_code == 0, result.stderr
    return tmp


@pytest.fixture
def copy(finished: Path, tmp_path: Path) -> Path:
    """The finished study's directory, the study file and grammar beside it, to damage."""
    for name in ("g.gg", "tiny.toml"):
        shutil.copy(finished / name, tmp_path / name)
    shutil.copytree(finished / "s", tmp_path / "s")
    return tmp_path


def study_again(tmp: Path) -> object:
    return runner.invoke(app, ["study", str(tmp / "tiny.toml"), "-o", str(tmp / "s"), "-q"])


def report(*directories: Path) -> object:
    out = directories[0].parent / "report"
    return runner.invoke(app, ["report", *map(str, directories), "-o", str(out)])


def refused(result: object, *said: str) -> str:
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.stderr
    message = " ".join(result.stderr.split())  # as one line, whatever the console's width
    for text in said:
        assert text in message
    return message


def edit_json(path: Path, change: Callable[[dict], object]) -> None:
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))


@pytest.mark.parametrize(
    ("change", "said"),
    [
        (lambda d: d.update(runs=0), "study.json: runs: must be a whole number in [1, 10000], not 0"),
        (lambda d: d.update(runs="3"), "study.json: runs: '3' is not a whole number"),
        (lambda d: d.pop("runs"), "study.json: runs: missing"),
        (lambda d: d.update(arms={}), "study.json: arms: {} is not a list"),
        (lambda d: d["arms"][0].pop("name"), "study.json: arms[0].name: missing"),
        (
            lambda d: d["arms"][1].update(name="../../x"),
            "arms[1].name: '../../x' cannot name an arm directory",
        ),
        (lambda d: d.update(title=5), "study.json: title: 5 is not text"),
        (lambda d: d.update(format=9), "study.json: format 9 is not 1"),
    ],
)
def test_an_edited_study_manifest_is_named_by_study_and_report(
    copy: Path, change: Callable, said: str
) -> None:
    edit_json(copy / "s" / "study.json", change)
    refused(study_again(copy), said)
    refused(report(copy / "s"), said)


def test_a_study_manifest_that_is_not_json_is_named(copy: Path) -> None:
    (copy / "s" / "study.json").write_text('{"format": 1, "runs": ')
    refused(study_again(copy), "study.json: not JSON")
    refused(report(copy / "s"), "study.json: not JSON")


@pytest.mark.parametrize(
    ("name", "command", "remedy"),
    [
        ("best.json", report, "the file was edited or damaged: rewrite the run's records"),
        ("backend.json", report, "delete it to go on without the run's backend time and steps"),
        ("checkpoint.json", study_again, "it cannot be resumed (restore it from a backup"),
    ],
)
@pytest.mark.parametrize("content", ['{"generation": ', "[1, 2]"])
def test_a_run_record_that_holds_no_object_is_named_with_what_to_do(
    copy: Path, name: str, command: Callable, remedy: str, content: str
) -> None:
    """Every record a run keeps is read back as one JSON object: one that is not JSON, or holds
    something else, names the file, says what it holds and what to do, as every other does."""
    path = copy / "s" / "arms" / "plain" / "run-001" / name
    path.write_text(content)
    said = "not JSON: " if content.startswith("{") else "not a"
    message = refused(command(copy if command is study_again else copy / "s"), remedy)
    assert f"{path}: " in message
    assert said in message.split(f"{path}: ", 1)[1]


def test_an_edited_arm_config_is_refused_by_study_and_report(copy: Path) -> None:
    config = copy / "s" / "arms" / "plain" / "config.toml"
    config.write_text(config.read_text().replace("runs = 3", "runs = 0"))
    said = "arms/plain/config.toml was edited after the run started; restore it"
    refused(study_again(copy), said)
    refused(report(copy / "s"), said)


@pytest.mark.parametrize(
    ("line", "said"),
    [
        ("runs = 0", "config.toml: runs: must be in [1, 10_000], not 0"),
        ('tournament = "2"', "config.toml: tournament: must be an int, not '2'"),
        ("populaton = 3", "config.toml: unknown key 'populaton'; did you mean population?"),
    ],
)
def test_a_config_without_a_manifest_is_checked_key_by_key(tmp_path: Path, line: str, said: str) -> None:
    arm = write_arm(tmp_path / "arm", [{"best_walk": 0.0}])
    (arm / "config.toml").write_text(f"generations = 1\npopulation = 4\nelite = 1\n{line}\n")
    refused(report(arm), said, "restore it")


@pytest.mark.parametrize("value", ["NaN", "Infinity", "-Infinity", '"0.5"', "null"])
@pytest.mark.parametrize("line", [2, 3])
def test_a_best_that_is_no_number_is_refused_with_its_file_and_line(
    copy: Path, value: str, line: int
) -> None:
    stats = copy / "s" / "arms" / "mutant" / "run-001" / "stats.jsonl"
    lines = stats.read_text().splitlines()
    record = json.loads(lines[line - 1])
    lines[line - 1] = json.dumps(record).replace(f'"best": {json.dumps(record["best"])}', f'"best": {value}')
    stats.write_text("\n\n".join(lines) + "\n")  # blank lines between: harmless, and counted
    line = 2 * line - 1
    message = refused(
        report(copy / "s"), f"arms/mutant/run-001/stats.jsonl:{line}: best:", "not a finite number"
    )
    assert f"tiny.toml -o {copy / 's'}" in message  # the study command, with the study file it ran
    assert not (copy / "report" / "summary.json").exists()
    assert study_again(copy).exit_code == 0  # the study rewrites it from the checkpoint
    assert report(copy / "s").exit_code == 0


@pytest.mark.parametrize("where", ["fitness", "objectives"])
def test_a_non_finite_front_is_refused(tmp_path: Path, where: str) -> None:
    arm = write_arm(tmp_path / "arm", [{"best_walk": 0.0}])
    member = {"fitness": 1.0, "components": {"walk": 0.0}, "genome": [1, 2], "objectives": [0.5, 0.25]}
    if where == "fitness":
        member["fitness"] = math.nan
    else:
        member["objectives"] = [0.5, math.inf]
    front = {"generation": 1, "objectives": ["a", "b"], "front": [member]}
    (arm / "run-000" / "front.json").write_text(json.dumps(front))
    refused(report(arm), "run-000/front.json: malformed")
    assert not (tmp_path / "report" / "summary.json").exists()


def test_the_same_run_directory_under_two_spellings_is_refused(copy: Path) -> None:
    arm = copy / "s" / "arms" / "plain"
    (copy / "link").symlink_to(copy / "s")
    for second in (copy / "link" / "arms" / "plain", arm / ".." / "plain", arm):
        refused(report(arm, second), f"{second} is", f"({arm.resolve()})", "give each run directory once")
    refused(report(copy / "s", arm), "give each run directory once")  # a study and one of its arms


@pytest.mark.parametrize("lost", ["best.json", "stats.jsonl", "stats.csv"])
def test_records_a_finished_run_lost_are_rewritten_by_the_study(copy: Path, lost: str) -> None:
    path = copy / "s" / "arms" / "plain" / "run-002" / lost
    original = path.read_bytes()
    path.unlink()
    if lost != "stats.csv":  # the report reads the other two
        refused(report(copy / "s"), f"{path} is missing", f"tiny.toml -o {copy / 's'}")
    again = study_again(copy)
    assert again.exit_code == 0, again.stderr
    assert f"rewrote 1 record file(s) that disagreed with their runs' checkpoints: {path}" in " ".join(
        again.stderr.split()
    )
    assert path.read_bytes() == original
    assert report(copy / "s").exit_code == 0


def test_records_a_finished_run_lost_are_rewritten_by_evolve_resume(copy: Path) -> None:
    arm = copy / "s" / "arms" / "mutant"
    original = (arm / "run-000" / "best.json").read_bytes()
    (arm / "run-000" / "best.json").unlink()
    (arm / "run-001" / "stats.jsonl").write_text("{}\n")
    refused(report(arm), f"{arm / 'run-000' / 'best.json'} is missing", f"gaitgram evolve --resume {arm}")
    resumed = runner.invoke(app, ["evolve", "--resume", str(arm), "-q"])
    assert resumed.exit_code == 0, resumed.stderr
    assert (arm / "run-000" / "best.json").read_bytes() == original
    assert report(arm).exit_code == 0


@pytest.mark.parametrize("flags", [[], ["--genome", "1,2,3"]])
def test_evaluate_refuses_a_generation_the_run_never_reached(copy: Path, flags: list[str]) -> None:
    arm = copy / "s" / "arms" / "plain"  # 2 generations
    result = runner.invoke(app, ["evaluate", "--run", str(arm), "--generation", "999", *flags])
    refused(result, "--generation 999:", "generations 0..2 only")
    assert runner.invoke(app, ["evaluate", "--run", str(arm), "--generation", "2", *flags]).exit_code == 0
