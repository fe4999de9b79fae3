"""A run records what it spent in its backend: per generation the steps simulated and the seconds
inside the backend (``backend.json`` beside its checkpoint), summed in its ``summary.json`` and in
a report of it, so that its cost against the raw simulation comes from the run itself."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_TARGETS
from gaitgram.analysis import check
from gaitgram.backends.curve_match import CurveMatch
from gaitgram.cli import app
from gaitgram.configuration import RunConfig
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.evolution.session import run_session
from gaitgram.language import load, parse
from gaitgram.strategies.registry import run_pipeline

runner = CliRunner()
SINE_WALK = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
MUJOCO = RunConfig(
    generations=2,
    population=8,
    elite=1,
    representation_settings={"init_max_depth": 6},
    backend_settings={"cycles": 1, "threads": 1},
)


def _directory(path: Path, config: RunConfig, grammar: str | None = None) -> RunDirectory:
    if grammar is None:
        built = run_pipeline(check(load(SINE_WALK)), config)
    else:
        built = run_pipeline(check(parse(grammar)), config)
    return RunDirectory.create(path, built, defines={}, origin="g.gg")


def _copy(directory: Path, to: Path, leaving_out: str = "") -> Path:
    shutil.copytree(directory, to, ignore=shutil.ignore_patterns(leaving_out) if leaving_out else None)
    return to


def _generations(run_dir: Path) -> list[dict]:
    return json.loads((run_dir / "backend.json").read_text())["generations"]


@pytest.fixture(scope="module")
def mujoco_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int]:
    """A mujoco-horse run, and the steps its evaluator counted."""
    path = tmp_path_factory.mktemp("mujoco") / "out"
    directory = _directory(path, MUJOCO)
    evaluator = directory.pipeline.load_evaluator()
    run_session(directory, evaluator, resume=False)
    evaluator.close()
    return path, evaluator.simulated_steps


def test_a_mujoco_run_records_the_steps_it_simulated_and_its_time_in_the_backend(
    mujoco_run: tuple[Path, int],
) -> None:
    path, counted = mujoco_run
    generations = _generations(path / "run-000")
    assert [g["generation"] for g in generations] == [0, 1, 2]
    assert all(g["simulated_steps"] > 0 and g["backend_seconds"] > 0 for g in generations)
    usage = json.loads((path / "summary.json").read_text())["runs"][0]["backend_usage"]
    assert usage["generations_counted"] == 3
    assert usage["simulated_steps"] == sum(g["simulated_steps"] for g in generations) == counted
    assert usage["backend_seconds"] == pytest.approx(math.fsum(g["backend_seconds"] for g in generations))
    # Generation 0 scores 8 gaits over at least the ramp and 3 cycles of at most 1.3 Hz each.
    assert generations[0]["simulated_steps"] >= 8 * (0.5 + 3 / 1.3) / 0.002 * 0.5  # half: some fall


def test_a_stopped_run_resumed_records_the_uninterrupted_run_s_steps(
    tmp_path: Path, mujoco_run: tuple[Path, int]
) -> None:
    directory = _directory(tmp_path / "out", MUJOCO)
    evaluator = directory.pipeline.load_evaluator()
    done: list[int] = []
    run_session(
        directory,
        evaluator,
        resume=False,
        on_generation=lambda _, s: done.append(s.generation),
        should_stop=lambda: 1 in done,
    )
    assert [g["generation"] for g in _generations(tmp_path / "out" / "run-000")] == [0, 1]
    run_session(directory, evaluator, resume=True)
    evaluator.close()
    steps = [g["simulated_steps"] for g in _generations(tmp_path / "out" / "run-000")]
    assert steps == [g["simulated_steps"] for g in _generations(mujoco_run[0] / "run-000")]


def test_a_report_shows_the_runs_time_in_the_backend(tmp_path: Path, mujoco_run: tuple[Path, int]) -> None:
    path, counted = mujoco_run
    made = runner.invoke(app, ["report", str(path), "-o", str(tmp_path / "report")])
    assert made.exit_code == 0, made.stderr
    markdown = (tmp_path / "report" / "summary.md").read_text()
    assert "**Time in the backend** (as each run recorded it):" in markdown
    report = json.loads((tmp_path / "report" / "summary.json").read_text())
    (row,) = report["sections"]["backend-usage"]["tables"]["arms"]
    assert row["runs_recorded"] == "1/1"
    assert row["generations_counted"] == "3/3"
    assert row["simulated_steps"] == counted
    seconds = json.loads((path / "summary.json").read_text())["runs"][0]["backend_usage"]["backend_seconds"]
    assert row["backend_seconds"] == pytest.approx(seconds)
    assert row["microseconds_per_step"] == pytest.approx(seconds / counted * 1e6)


def test_a_report_of_runs_that_recorded_nothing_has_no_such_section(
    tmp_path: Path, mujoco_run: tuple[Path, int]
) -> None:
    """Runs made before runs recorded their usage (every committed one) keep their reports."""
    copy = _copy(mujoco_run[0], tmp_path / "old", leaving_out="backend.json")
    made = runner.invoke(app, ["report", str(copy), "-o", str(tmp_path / "report")])
    assert made.exit_code == 0, made.stderr
    assert "Time in the backend" not in (tmp_path / "report" / "summary.md").read_text()
    assert "backend-usage" not in json.loads((tmp_path / "report" / "summary.json").read_text())["sections"]


def test_a_damaged_record_is_refused_by_the_report_naming_it(
    tmp_path: Path, mujoco_run: tuple[Path, int]
) -> None:
    copy = _copy(mujoco_run[0], tmp_path / "damaged")
    (copy / "run-000" / "backend.json").write_text('{"format": 1, "generations": [{"generation": 0}]}')
    made = runner.invoke(app, ["report", str(copy), "-o", str(tmp_path / "report")])
    assert made.exit_code == 2
    assert "run-000/backend.json: generations[0].backend_seconds must be a number >= 0" in made.stderr
    assert "delete it" in made.stderr
    assert "Traceback" not in made.stderr


CURVE = RunConfig(
    generations=4,
    population=10,
    elite=1,
    representation_settings={"init_max_depth": 6},
    backend="curve-match",
)


def _curve_directory(path: Path) -> RunDirectory:
    config = RunConfig(**{**CURVE.__dict__, "backend_settings": {"targets": CURVE_TARGETS}})
    return _directory(path, config, CURVE_GRAMMAR)


def test_a_backend_that_counts_no_steps_records_its_time_alone(tmp_path: Path) -> None:
    directory = _curve_directory(tmp_path / "out")
    run_session(directory, CurveMatch(CURVE_TARGETS), resume=False)
    usage = json.loads((tmp_path / "out" / "summary.json").read_text())["runs"][0]["backend_usage"]
    assert usage["simulated_steps"] is None
    assert usage["backend_seconds"] > 0
    assert usage["generations_counted"] == 5


def test_a_run_resumed_from_a_checkpoint_without_a_record_counts_the_generations_after_it(
    tmp_path: Path,
) -> None:
    """As a run started by an older gaitgram, or whose record was lost or damaged: the totals say
    how many generations they cover."""
    for damage in ("lost", "damaged"):
        directory = _curve_directory(tmp_path / damage)
        done: list[int] = []
        run_session(
            directory,
            CurveMatch(CURVE_TARGETS),
            resume=False,
            on_generation=lambda _, s, done=done: done.append(s.generation),
            should_stop=lambda done=done: 2 in done,
        )
        record = tmp_path / damage / "run-000" / "backend.json"
        if damage == "lost":
            record.unlink()
        else:
            record.write_text("{not json")
        run_session(directory, CurveMatch(CURVE_TARGETS), resume=True)
        assert [g["generation"] for g in _generations(tmp_path / damage / "run-000")] == [3, 4]
        usage = json.loads((tmp_path / damage / "summary.json").read_text())["runs"][0]["backend_usage"]
        assert usage["generations_counted"] == 2
