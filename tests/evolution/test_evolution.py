"""The GE loop: it optimises, it is deterministic, and it survives being stopped and killed."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import pytest
from measured import summary_results
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_TARGETS, CURVE_TARGETS_TOML
from gaitgram.analysis import check
from gaitgram.backends.curve_match import CurveMatch
from gaitgram.cli import app
from gaitgram.configuration import ConfigError, RunConfig, WeightStage, load_config
from gaitgram.evolution.engine import run_evolution
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.evolution.session import run_session
from gaitgram.language import parse
from gaitgram.pipeline import Pipeline
from gaitgram.strategies.registry import run_pipeline

runner = CliRunner()

#: A reachable target (amplitude 7 and phase 1.5 are on the grammar's grids); the hip is frozen
#: until generation 3.
GRAMMAR = CURVE_GRAMMAR.replace("@joint hip_hind\n", "@joint hip_hind free=3..\n")
TARGETS = CURVE_TARGETS


def config_file(tmp_path: Path, generations: int = 25, **extra: object) -> Path:
    lines = [
        f"generations = {generations}",
        "population = 40",
        "elite = 4",
        "init_max_depth = 6",
        'backend = "curve-match"',
        *(f"{k} = {v}" for k, v in extra.items()),
        "",
        "[backend_settings.targets]",
    ]
    path = tmp_path / "run.toml"
    path.write_text("\n".join(lines) + "\n" + CURVE_TARGETS_TOML)
    (tmp_path / "g.gg").write_text(GRAMMAR)
    return path


def pipeline(config: RunConfig) -> Pipeline:
    config = replace(config, backend="curve-match", backend_settings={"targets": TARGETS})
    return run_pipeline(check(parse(GRAMMAR)), config)


def evolve(tmp_path: Path, config: RunConfig, run_dir: str = "run"):
    return run_evolution(pipeline(config), CurveMatch(TARGETS), 0, tmp_path / run_dir, fingerprint="test")


def test_evolution_finds_a_reachable_target(tmp_path: Path) -> None:
    state = evolve(
        tmp_path,
        RunConfig(
            generations=100, population=60, elite=4, representation_settings={"init_max_depth": 6}, seed=3
        ),
    )
    first, last = state.history[0], state.history[-1]
    assert first.best > 1.0
    assert last.best < 1e-9  # found exactly
    assert [s.best for s in state.history] == sorted((s.best for s in state.history), reverse=True)  # elitism


def test_same_seed_same_run_different_seed_different_run(tmp_path: Path) -> None:
    config = RunConfig(
        generations=6, population=20, elite=2, representation_settings={"init_max_depth": 6}, seed=5
    )
    a = evolve(tmp_path, config, "a")
    b = evolve(tmp_path, config, "b")
    c = evolve(
        tmp_path,
        RunConfig(
            generations=6, population=20, elite=2, representation_settings={"init_max_depth": 6}, seed=6
        ),
        "c",
    )
    assert (tmp_path / "a" / "stats.csv").read_text() == (tmp_path / "b" / "stats.csv").read_text()
    assert [i.genome for i in a.population] == [i.genome for i in b.population]
    assert [i.genome for i in a.population] != [i.genome for i in c.population]


def test_frozen_joints_hold_neutral_until_free(tmp_path: Path) -> None:
    problem = pipeline(RunConfig())
    assert problem.frozen_at(2) == {"hip_hind"}
    assert problem.frozen_at(3) == frozenset()
    genome = (7, 0, 3) * 5
    at_2 = problem.evaluate([genome], CurveMatch(TARGETS), 2)[0].evaluation.components["rms_hip_hind"]
    neutral = CurveMatch({"hip_hind": "0"}).evaluate  # distance of the target from a neutral joint
    assert at_2 == pytest.approx(7 / 2**0.5)
    assert neutral is not None


def test_run_directory_records(tmp_path: Path) -> None:
    config = config_file(tmp_path, generations=3)
    result = runner.invoke(
        app,
        [
            "evolve",
            str(tmp_path / "g.gg"),
            "-c",
            str(config),
            "-o",
            str(tmp_path / "out"),
            "--runs",
            "2",
            "-q",
        ],
    )
    assert result.exit_code == 0, result.stderr
    out = tmp_path / "out"
    assert sorted(p.name for p in out.iterdir()) == [
        ".lock",  # held while a gaitgram works in it
        "config.toml",
        "grammar.gg",
        "manifest.json",
        "run-000",
        "run-001",
        "summary.json",
    ]
    stats = (out / "run-000" / "stats.csv").read_text().splitlines()
    assert stats[0].startswith("generation,best,average_all,average,std,invalid,evaluations,mean_rms_elbow")
    assert len(stats) == 1 + 4
    lines = [json.loads(x) for x in (out / "run-000" / "stats.jsonl").read_text().splitlines()]
    assert [x["generation"] for x in lines] == [0, 1, 2, 3]
    best = json.loads((out / "run-000" / "best.json").read_text())
    assert {"genome", "phenotype", "joints", "fitness", "components", "derivation", "status"} <= best.keys()
    assert best["fitness"] == min(x["best"] for x in lines)
    assert set(best["curves"]) == {"hip_hind", "elbow_fore"}
    assert len(best["curves"]["elbow_fore"]) == 64
    summary = json.loads((out / "summary.json").read_text())
    assert len(summary["runs"]) == 2
    assert summary["runs"][0]["best_fitness"] != summary["runs"][1]["best_fitness"]  # derived seeds differ
    assert load_config(out / "config.toml").runs == 2


def test_existing_run_directory_is_never_overwritten(tmp_path: Path) -> None:
    config = config_file(tmp_path, generations=1)
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    result = runner.invoke(app, ["evolve", str(tmp_path / "g.gg"), "-c", str(config), "-o", str(out), "-q"])
    assert result.exit_code == 2
    assert "choose another --out" in result.stderr
    assert "--resume" not in result.stderr  # it holds no run to resume
    assert (out / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.gg", "out", "run.toml"]  # nothing left beside it


def test_config_errors_are_clear(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text("generatoins = 5\n")
    with pytest.raises(ConfigError, match="unknown key 'generatoins'"):
        load_config(path)
    path.write_text("population = 'many'\n")
    with pytest.raises(ConfigError, match="population: must be an int"):
        load_config(path)
    path.write_text("elite = 80\n")
    with pytest.raises(ConfigError, match="elite: 80 elites leave no room"):
        load_config(path)
    path.write_text("[[weight_schedule]]\nstart = 0\nweights = { energy = -1 }\n")
    with pytest.raises(ConfigError, match="must be a finite number >= 0"):
        load_config(path)
    path.write_text("generations = \n")
    result = runner.invoke(app, ["evolve", "grammars/sine-walk.gg", "-c", str(path)])
    assert result.exit_code == 2
    assert "not valid TOML" in result.stderr


def test_weight_schedule_by_generation() -> None:
    config = RunConfig(weight_schedule=(WeightStage(10, {"energy": 0.5}), WeightStage(0, {"energy": 0.0})))
    assert config.weights_at(0) == {"energy": 0.0}
    assert config.weights_at(10) == {"energy": 0.5}


def _cli(*args: str) -> list[str]:
    return [sys.executable, "-m", "gaitgram", *args]


def _wait_for_generation(path: Path, generation: int, process: subprocess.Popen, timeout: float = 60) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if path.exists():
            try:
                if json.loads(path.read_text())["checkpoint"]["generation"] >= generation:
                    return
            except (json.JSONDecodeError, KeyError):
                pass
        assert process.poll() is None, "the run ended before it could be interrupted"
        time.sleep(0.02)
    raise TimeoutError


def session(tmp_path: Path, name: str, *, resume: bool = False, stop_after: tuple[int, int] | None = None):
    """The runs of the run directory ``name`` (made unless resuming), in-process; ``stop_after``
    (run, generation): asked to stop once that generation of that run is recorded."""
    path = tmp_path / name
    if resume:
        directory = RunDirectory.open(path)
    else:
        config = RunConfig(
            generations=12,
            population=20,
            elite=2,
            representation_settings={"init_max_depth": 6},
            seed=4,
            runs=2,
        )
        directory = RunDirectory.create(path, pipeline(config), defines={}, origin="g.gg")
    recorded: list[tuple[int, int]] = []
    states = run_session(
        directory,
        CurveMatch(TARGETS),
        resume=resume,
        on_generation=lambda run, stats: recorded.append((run, stats.generation)),
        should_stop=lambda: stop_after in recorded,
    )
    return states, recorded


@pytest.mark.parametrize(
    "stop_after", [(0, 5), (0, 12), (1, 7)], ids=["mid-run-0", "between-runs", "mid-run-1"]
)
def test_a_stopped_session_resumes_to_the_uninterrupted_result(
    tmp_path: Path, stop_after: tuple[int, int]
) -> None:
    """``should_stop`` between generations, as Ctrl-C asks, then ``resume``: every record as if
    the runs had never stopped (the in-process twin of the kill -9 test below)."""
    whole, _ = session(tmp_path, "whole")
    stopped, recorded = session(tmp_path, "stopped", stop_after=stop_after)
    assert recorded[-1] == stop_after  # it stopped right after the generation it was asked to
    assert [s.generation for s in stopped] == [12] * stop_after[0] + [stop_after[1]]
    assert not (tmp_path / "stopped" / "summary.json").exists()  # an unfinished session has no summary
    resumed, recorded = session(tmp_path, "stopped", resume=True)
    run, generation = stop_after
    if generation == 12:  # run 0 had finished: the resume starts run 1 from its generation 0
        assert recorded[0] == (run + 1, 0)
    else:
        assert recorded[0] == (run, generation + 1)
    assert [s.generation for s in resumed] == [12, 12]
    for r in (0, 1):
        assert [i.genome for i in resumed[r].population] == [i.genome for i in whole[r].population]
        for name in ("stats.csv", "stats.jsonl", "best.json", "checkpoint.json"):
            assert (tmp_path / "stopped" / f"run-{r:03d}" / name).read_bytes() == (
                tmp_path / "whole" / f"run-{r:03d}" / name
            ).read_bytes(), name
    assert summary_results(tmp_path / "stopped" / "summary.json") == summary_results(
        tmp_path / "whole" / "summary.json"
    )


def test_ctrl_c_stops_after_the_generation_and_the_resume_gives_the_uninterrupted_result(
    tmp_path: Path, ctrl_c: Callable[[int], None]
) -> None:
    """A real SIGINT to an in-process ``gaitgram evolve``: it finishes the generation, says how to
    continue, exits 130; ``--resume`` ends where the uninterrupted run ends."""
    config = config_file(tmp_path, generations=30)
    grammar = str(tmp_path / "g.gg")
    whole = runner.invoke(app, ["evolve", grammar, "-c", str(config), "-o", str(tmp_path / "whole"), "-q"])
    assert whole.exit_code == 0, whole.stderr
    interrupted = tmp_path / "interrupted"
    ctrl_c(12)
    stopped = runner.invoke(app, ["evolve", grammar, "-c", str(config), "-o", str(interrupted), "-q"])
    assert stopped.exit_code == 130, stopped.stderr
    assert f"--resume {interrupted}" in stopped.stderr
    assert (
        json.loads((interrupted / "run-000" / "checkpoint.json").read_text())["checkpoint"]["generation"]
        == 12
    )
    assert not (interrupted / "summary.json").exists()
    resumed = runner.invoke(app, ["evolve", "--resume", str(interrupted), "-q"])
    assert resumed.exit_code == 0, resumed.stderr
    for name in ("stats.csv", "stats.jsonl", "best.json"):
        assert (interrupted / "run-000" / name).read_text() == (
            tmp_path / "whole" / "run-000" / name
        ).read_text()
    assert summary_results(interrupted / "summary.json") == summary_results(
        tmp_path / "whole" / "summary.json"
    )


@pytest.mark.slow
def test_a_run_killed_with_kill_9_resumes_to_the_uninterrupted_result(tmp_path: Path) -> None:
    """The one real kill -9 of ``gaitgram evolve`` (a process, killed at whatever it was doing)."""
    config = config_file(tmp_path, generations=200)
    grammar = str(tmp_path / "g.gg")
    whole = subprocess.run(
        _cli("evolve", grammar, "-c", str(config), "-o", str(tmp_path / "whole"), "-q"),
        capture_output=True,
        text=True,
    )
    assert whole.returncode == 0, whole.stderr
    interrupted = tmp_path / "interrupted"
    process = subprocess.Popen(
        _cli("evolve", grammar, "-c", str(config), "-o", str(interrupted), "-q"),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    _wait_for_generation(interrupted / "run-000" / "checkpoint.json", 30, process)
    os.kill(process.pid, signal.SIGKILL)
    process.communicate(timeout=60)
    assert process.returncode == -signal.SIGKILL
    assert not (interrupted / "summary.json").exists()
    resumed = subprocess.run(
        _cli("evolve", "--resume", str(interrupted), "-q"), capture_output=True, text=True
    )
    assert resumed.returncode == 0, resumed.stderr
    for name in ("stats.csv", "stats.jsonl", "best.json"):
        assert (interrupted / "run-000" / name).read_text() == (
            tmp_path / "whole" / "run-000" / name
        ).read_text()
    assert summary_results(interrupted / "summary.json") == summary_results(
        tmp_path / "whole" / "summary.json"
    )


def test_dask_local_cluster_gives_the_local_result(tmp_path: Path) -> None:
    pytest.importorskip("distributed", reason="Dask is an optional extra; the dev extra installs it")
    config = config_file(tmp_path, generations=4)
    grammar = str(tmp_path / "g.gg")
    local = runner.invoke(app, ["evolve", grammar, "-c", str(config), "-o", str(tmp_path / "local"), "-q"])
    dask = runner.invoke(
        app, ["evolve", grammar, "-c", str(config), "-o", str(tmp_path / "dask"), "-q", "--dask-local", "2"]
    )
    assert local.exit_code == dask.exit_code == 0, dask.stderr
    assert (tmp_path / "local/run-000/stats.csv").read_text() == (
        tmp_path / "dask/run-000/stats.csv"
    ).read_text()


def test_mujoco_runs_give_the_same_statistics_with_one_and_two_threads(tmp_path: Path) -> None:
    grammar = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
    config = tmp_path / "run.toml"
    config.write_text(
        "generations = 2\npopulation = 8\nelite = 1\ninit_max_depth = 6\n\n"
        "[backend_settings]\ncycles = 1\nramp_seconds = 0.2\n"
    )
    stats = []
    for threads in ("1", "2"):
        out = tmp_path / f"t{threads}"
        result = runner.invoke(
            app, ["evolve", str(grammar), "-c", str(config), "--threads", threads, "-o", str(out), "-q"]
        )
        assert result.exit_code == 0, result.stderr
        stats.append((out / "run-000" / "stats.csv").read_text())
    assert stats[0] == stats[1]
