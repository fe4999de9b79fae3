"""Search strategies on the cheap curve-match backend: each one improves on its initial population,
is deterministic for a seed, and resumes after a stop or a kill to the uninterrupted result;
NSGA-II keeps a non-dominated front, MAP-Elites a repertoire with the best gait of each cell;
CMA-ES refuses a grammar with structural choices."""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from measured import summary_results, usage_results
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_NUMERICAL, CURVE_TARGETS, CURVE_TARGETS_TOML
from gaitgram.analysis import check
from gaitgram.backends.api import GaitStatus
from gaitgram.backends.curve_match import CurveMatch
from gaitgram.cli import app
from gaitgram.configuration import RunConfig, load_config
from gaitgram.evolution import checkpoint as checkpoints
from gaitgram.evolution.checkpoint import load_checkpoint
from gaitgram.evolution.engine import run_evolution
from gaitgram.language import parse
from gaitgram.pipeline import Pipeline, PipelineError
from gaitgram.strategies.api import RunState
from gaitgram.strategies.kept import non_dominated
from gaitgram.strategies.registry import run_pipeline

runner = CliRunner()

#: Structural choices (sin or cos) over ranges: GE, random, NSGA-II and MAP-Elites search it.
STRUCTURAL = CURVE_GRAMMAR
#: One expression, ranges only: a parameter vector of 7 coordinates, for CMA-ES.
NUMERICAL = CURVE_NUMERICAL
TARGETS = CURVE_TARGETS
DESCRIPTORS = [
    {"name": "rms_hip_hind", "low": 0.0, "high": 12.0, "bins": 6},
    {"name": "rms_elbow_fore", "low": 0.0, "high": 12.0, "bins": 6},
]
SETTINGS: dict[str, dict[str, Any]] = {"map-elites": {"descriptors": DESCRIPTORS}}
STRATEGIES = ("ge", "random", "cma-es", "nsga2", "map-elites")


def grammar_for(strategy: str) -> str:
    return NUMERICAL if strategy == "cma-es" else STRUCTURAL


def build(strategy: str, **changes: Any) -> Pipeline:
    config = RunConfig(
        generations=12,
        population=24,
        elite=2,
        representation_settings={"init_max_depth": 6},
        seed=1,
        backend="curve-match",
        backend_settings={"targets": TARGETS},
        strategy=strategy,
        strategy_settings=SETTINGS.get(strategy, {}),
    )
    return run_pipeline(check(parse(grammar_for(strategy))), replace(config, **changes))


def search(
    tmp_path: Path, strategy: str, name: str = "run", evaluator: Any = None, **changes: Any
) -> RunState:
    pipeline = build(strategy, **changes)
    return run_evolution(pipeline, evaluator or CurveMatch(TARGETS), 0, tmp_path / name, fingerprint="test")


def files_of(directory: Path) -> dict[str, Any]:
    """A run's records (statistics, best gait, the strategy's own) as text, by name, and its checkpoint
    but for the pickled strategy state (cma keeps wall-clock timers in it: the bytes differ, the
    results do not)."""
    found: dict[str, Any] = {
        p.name: usage_results(p.read_text()) if p.name == "backend.json" else p.read_text()
        for p in sorted(directory.iterdir())
        if p.suffix in (".csv", ".jsonl", ".json") and p.name != "checkpoint.json"
    }
    checkpoint = json.loads((directory / "checkpoint.json").read_text())["checkpoint"]
    checkpoint.pop("strategy_state", None)
    return {**found, "checkpoint": checkpoint}


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_each_strategy_improves_on_its_initial_population(tmp_path: Path, strategy: str) -> None:
    state = search(tmp_path, strategy, generations=15)
    assert len(state.history) == 16
    assert state.history[-1].best < state.history[0].best
    # GE's budget, whatever the strategy: the population, then population - elite per generation.
    assert [s.evaluations for s in state.history] == [24] + [22] * 15
    assert len(state.population) == 24


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_each_strategy_is_deterministic_for_a_seed(tmp_path: Path, strategy: str) -> None:
    a = search(tmp_path, strategy, "a", generations=6)
    b = search(tmp_path, strategy, "b", generations=6)
    c = search(tmp_path, strategy, "c", generations=6, seed=2)
    assert files_of(tmp_path / "a") == files_of(tmp_path / "b")
    assert [i.genome for i in a.population] == [i.genome for i in b.population]
    assert [i.genome for i in a.population] != [i.genome for i in c.population]


def test_random_search_starts_where_ge_starts(tmp_path: Path) -> None:
    """Genomes drawn as GE's initialisation draws them: the same seed, the same generation 0."""
    ge = search(tmp_path, "ge", "ge", generations=1)
    rnd = search(tmp_path, "random", "random", generations=1)
    assert ge.history[0] == rnd.history[0]


class Killed(Exception):
    pass


@pytest.mark.parametrize("strategy", ["random", "cma-es", "nsga2", "map-elites"])
def test_a_kill_between_the_state_and_the_checkpoint_resumes_exactly(
    tmp_path: Path, strategy: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The strategy's pickle is written, then the process dies before the checkpoint names it."""
    whole = search(tmp_path, strategy, "whole", generations=10)
    real = checkpoints.write_atomically

    def dying(path: Path, text: str | bytes, **kwargs: Any) -> None:
        if path.name == "checkpoint.json" and json.loads(text)["checkpoint"]["generation"] == 5:
            raise Killed
        real(path, text, **kwargs)

    monkeypatch.setattr(checkpoints, "write_atomically", dying)
    with pytest.raises(Killed):
        search(tmp_path, strategy, "killed", generations=10)
    monkeypatch.setattr(checkpoints, "write_atomically", real)
    killed = tmp_path / "killed"
    if strategy != "random":  # the orphan of generation 5 is there, the checkpoint is generation 4's
        assert (killed / "strategy-000005.pickle").exists()
    assert json.loads((killed / "checkpoint.json").read_text())["checkpoint"]["generation"] == 4
    pipeline = build(strategy, generations=10)
    resumed = run_evolution(pipeline, CurveMatch(TARGETS), 0, killed, fingerprint="test", resume=True)
    assert files_of(killed) == files_of(tmp_path / "whole")
    assert [i.genome for i in resumed.population] == [i.genome for i in whole.population]
    assert sorted(p.name for p in killed.glob("*.pickle")) == sorted(
        p.name for p in (tmp_path / "whole").glob("*.pickle")
    )


# ---- stopped and resumed through the command line ---------------------------------------------


def write_inputs(tmp_path: Path, strategy: str, generations: int) -> tuple[Path, Path]:
    grammar = tmp_path / "g.gg"
    grammar.write_text(grammar_for(strategy))
    lines = [
        f"generations = {generations}",
        "population = 20",
        "elite = 2",
        "init_max_depth = 6",
        'backend = "curve-match"',
        f'strategy = "{strategy}"',
    ]
    if strategy == "map-elites":
        lines += ["", "[strategy_settings]", "descriptors = ["]
        lines += [f'  {{ name = "{d["name"]}", low = 0.0, high = 12.0, bins = 6 }},' for d in DESCRIPTORS]
        lines += ["]"]
    lines += ["", "[backend_settings.targets]"]
    config = tmp_path / "run.toml"
    config.write_text("\n".join(lines) + "\n" + CURVE_TARGETS_TOML)
    return grammar, config


def load_checkpoint_generation(run_dir: Path) -> int:
    return json.loads((run_dir / "checkpoint.json").read_text())["checkpoint"]["generation"]


@pytest.mark.parametrize("strategy", ["cma-es", "nsga2", "map-elites"])
def test_finished_runs_without_their_pickled_state_still_grow(tmp_path: Path, strategy: str) -> None:
    """A committed study keeps no strategy pickle (gitignored under docs/results): asking it for
    more runs adds them, as a fresh directory of that many would hold them, and leaves the
    finished runs as they were; only an unfinished run needs its pickle."""
    grammar, config = write_inputs(tmp_path, strategy, generations=3)
    made = runner.invoke(
        app, ["evolve", str(grammar), "-c", str(config), "-o", str(tmp_path / "grown"), "-q"]
    )
    assert made.exit_code == 0, made.stderr
    pickles = list((tmp_path / "grown").rglob("strategy-*.pickle"))
    assert pickles
    for pickled in pickles:
        pickled.unlink()
    before = files_of(tmp_path / "grown" / "run-000")
    grown = runner.invoke(app, ["evolve", "--resume", str(tmp_path / "grown"), "--runs", "2", "-q"])
    assert grown.exit_code == 0, grown.stderr
    whole = runner.invoke(
        app, ["evolve", str(grammar), "-c", str(config), "--runs", "2", "-o", str(tmp_path / "whole"), "-q"]
    )
    assert whole.exit_code == 0, whole.stderr
    assert files_of(tmp_path / "grown" / "run-000") == before == files_of(tmp_path / "whole" / "run-000")
    assert files_of(tmp_path / "grown" / "run-001") == files_of(tmp_path / "whole" / "run-001")
    assert not list((tmp_path / "grown" / "run-000").glob("*.pickle"))  # nothing made up in its place


@pytest.mark.parametrize("strategy", ["random", "cma-es", "nsga2", "map-elites"])
def test_a_stopped_run_resumes_to_the_uninterrupted_result(
    tmp_path: Path, strategy: str, ctrl_c: Callable[[int], None]
) -> None:
    """Ctrl-C (a real SIGINT) to an in-process ``gaitgram evolve``, then ``--resume``: the strategy's
    state and settings come back from the run directory, and the records end as the uninterrupted
    run's. (The real kill -9 of ``evolve`` is in tests/evolution; a kill between the strategy's
    state and the checkpoint is above.)"""
    grammar, config = write_inputs(tmp_path, strategy, generations=16)
    whole = runner.invoke(
        app, ["evolve", str(grammar), "-c", str(config), "-o", str(tmp_path / "whole"), "-q"]
    )
    assert whole.exit_code == 0, whole.stderr
    interrupted = tmp_path / "interrupted"
    ctrl_c(7)
    stopped = runner.invoke(app, ["evolve", str(grammar), "-c", str(config), "-o", str(interrupted), "-q"])
    assert stopped.exit_code == 130, stopped.stderr
    assert load_checkpoint_generation(interrupted / "run-000") == 7
    assert not (interrupted / "summary.json").exists()
    resumed = runner.invoke(app, ["evolve", "--resume", str(interrupted), "-q"])
    assert resumed.exit_code == 0, resumed.stderr
    assert files_of(interrupted / "run-000") == files_of(tmp_path / "whole" / "run-000")
    assert summary_results(interrupted / "summary.json") == summary_results(
        tmp_path / "whole" / "summary.json"
    )


# ---- what each strategy keeps -------------------------------------------------------------------


def hypervolume_2d(points: np.ndarray, reference: np.ndarray) -> float:
    """The area dominated by ``points`` (minimised) up to ``reference``."""
    inside = points[np.all(points < reference, axis=1)]
    front = inside[non_dominated(inside)]
    front = front[np.argsort(front[:, 0])]
    area, ceiling = 0.0, reference[1]
    for x, y in front:
        area += (reference[0] - x) * (ceiling - y)
        ceiling = y
    return area


def objectives_of(population: list[Any], names: list[str]) -> np.ndarray:
    viable = [i for i in population if i.evaluation.status is GaitStatus.OK]
    return np.array([[i.evaluation.components[n] for n in names] for i in viable])


def test_nsga2_front_is_non_dominated_and_grows(tmp_path: Path) -> None:
    initial = search(tmp_path, "nsga2", "initial", generations=1)
    state = search(tmp_path, "nsga2", "run", generations=15)
    record = json.loads((tmp_path / "run" / "front.json").read_text())
    names = record["objectives"]
    assert set(names) == {"rms_hip_hind", "rms_elbow_fore"}  # curve-match's weighted components
    front = np.array([m["objectives"] for m in record["front"]])
    assert len(front) >= 1
    assert non_dominated(front).all()  # no member dominates another
    population = objectives_of(state.population, names)
    for member in front:  # and nothing in the population dominates a member
        assert not np.any(np.all(population <= member, axis=1) & np.any(population < member, axis=1))
    start = objectives_of(initial.population[:24], names)
    reference = start.max(axis=0) + 1.0
    assert hypervolume_2d(population, reference) > hypervolume_2d(start, reference)


class Recording:
    """Curve-match, remembering every evaluation it made."""

    def __init__(self) -> None:
        self.inner = CurveMatch(TARGETS)
        self.seen: list[Any] = []

    def evaluate(self, batch: Any, **kwargs: Any) -> list[Any]:
        results = self.inner.evaluate(batch, **kwargs)
        self.seen += results
        return results

    def close(self) -> None:
        pass


def test_map_elites_fills_cells_and_keeps_the_best_of_each(tmp_path: Path) -> None:
    recording = Recording()
    state = search(tmp_path, "map-elites", evaluator=recording, generations=15)
    archive = state.memory.archive
    record = json.loads((tmp_path / "run" / "archive.json").read_text())
    assert record["filled"] == len(archive) > 1
    viable = [e for e in recording.seen if e.status is GaitStatus.OK]
    measures = np.array([[e.components[d["name"]] for d in DESCRIPTORS] for e in viable])
    cells = archive.index_of(measures)
    best: dict[int, float] = {}
    for cell, evaluation in zip(cells, viable, strict=True):
        best[int(cell)] = min(best.get(int(cell), np.inf), evaluation.fitness)
    assert set(best) == {int(i) for i in archive.data()["index"]}  # every cell reached is kept
    for elite in record["elites"]:
        flat = int(archive.grid_to_int_index([elite["cell"]])[0])
        assert elite["fitness"] == best[flat]  # and it holds the best gait that reached it
    assert record["elites"][0]["fitness"] == min(best.values()) == state.history[-1].best


def test_cma_es_refuses_a_structural_grammar_and_says_which_grammars_it_takes(tmp_path: Path) -> None:
    config = RunConfig(backend="curve-match", backend_settings={"targets": TARGETS}, strategy="cma-es")
    with pytest.raises(PipelineError) as error:
        run_pipeline(check(parse(STRUCTURAL, name="s.gg")), config)
    message = str(error.value)
    assert "s.gg:4:1: <hip> chooses between alternatives of different structure" in message
    assert "numerical.gg" in message
    assert "ge, random, nsga2 or map-elites" in message
    _, config_path = write_inputs(tmp_path, "cma-es", generations=2)
    (tmp_path / "s.gg").write_text(STRUCTURAL)
    result = runner.invoke(
        app, ["evolve", str(tmp_path / "s.gg"), "-c", str(config_path), "-o", str(tmp_path / "o")]
    )
    assert result.exit_code == 2
    assert "different structure" in result.stderr
    assert not (tmp_path / "o").exists()


def test_cma_es_searches_the_bundled_numerical_grammar_from_its_seed() -> None:
    from gaitgram.strategies.parameters import parameter_space

    grammar = Path(__file__).resolve().parents[2] / "grammars" / "numerical.gg"
    pipeline = run_pipeline(
        check(parse(grammar.read_text(), name=str(grammar))), RunConfig(strategy="cma-es")
    )
    space = parameter_space(pipeline)
    assert space.dimension > 100
    centre = pipeline.map([space.genome(np.full(space.dimension, 0.5))])[0]
    assert centre.joints["neck_atlas"] == "-0.09+3.39*sin(2*2*PI*t+-0.31)"  # the seed's numbers
    assert pipeline.config.strategy_settings == {"sigma0": 0.3}


# ---- settings, run directories, the command line ------------------------------------------------


def test_strategy_settings_are_checked_and_recorded(tmp_path: Path) -> None:
    with pytest.raises(
        PipelineError, match=r"\[strategy_settings\] sigma: unknown setting of strategy cma-es"
    ):
        build("cma-es", strategy_settings={"sigma": 0.2})
    with pytest.raises(PipelineError, match="nsga2 needs two or more objectives"):
        build("nsga2", strategy_settings={"objectives": ["rms_hip_hind"]})
    with pytest.raises(PipelineError, match="give the range of 'rms_hip_hind'"):
        build("map-elites", strategy_settings={"descriptors": ["rms_hip_hind"]})
    with pytest.raises(PipelineError, match="no strategy named 'cmaes'; did you mean cma-es"):
        build("cmaes")
    freeing = check(parse(STRUCTURAL.replace("@joint hip_hind", "@joint hip_hind free=3..")))
    with pytest.raises(PipelineError, match="the scores change at generation 3"):
        run_pipeline(freeing, build("map-elites").config)
    grammar, config = write_inputs(tmp_path, "map-elites", generations=2)
    result = runner.invoke(
        app, ["evolve", str(grammar), "-c", str(config), "-o", str(tmp_path / "out"), "-q"]
    )
    assert result.exit_code == 0, result.stderr
    saved = load_config(tmp_path / "out" / "config.toml")
    assert saved.strategy == "map-elites"
    assert saved.strategy_settings == {"descriptors": DESCRIPTORS}
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert manifest["strategy"] == "map-elites"
    assert manifest["strategy_version"].startswith("map-elites r1; ribs ")
    resumed = runner.invoke(app, ["evolve", "--resume", str(tmp_path / "out"), "--strategy", "random"])
    assert resumed.exit_code == 2
    assert "strategy: 'map-elites' -> 'random'" in resumed.stderr


def test_a_ge_run_directory_is_what_it_always_was(tmp_path: Path) -> None:
    """No strategy line in config.toml, no pickle, no strategy in the manifest: GE's fingerprints hold."""
    state = search(tmp_path, "ge", generations=2)
    assert state.memory is None
    grammar, config = write_inputs(tmp_path, "ge", generations=2)
    result = runner.invoke(
        app, ["evolve", str(grammar), "-c", str(config), "-o", str(tmp_path / "out"), "-q"]
    )
    assert result.exit_code == 0, result.stderr
    assert "strategy" not in (tmp_path / "out" / "config.toml").read_text()
    assert "strategy" not in (tmp_path / "out" / "manifest.json").read_text()
    assert not list((tmp_path / "out").rglob("*.pickle"))
    checkpoint = json.loads((tmp_path / "out" / "run-000" / "checkpoint.json").read_text())
    assert "strategy_state" not in checkpoint["checkpoint"]


def test_a_damaged_strategy_state_is_refused(tmp_path: Path) -> None:
    search(tmp_path, "cma-es", generations=2)
    pipeline = build("cma-es", generations=2)
    (pickled,) = (tmp_path / "run").glob("strategy-*.pickle")
    pickled.write_bytes(pickled.read_bytes()[:-1] + b"\x00")
    with pytest.raises(checkpoints.CheckpointError, match="does not match its digest"):
        load_checkpoint(tmp_path / "run" / "checkpoint.json", pipeline, fingerprint="test", run=0)
    pickled.unlink()
    with pytest.raises(checkpoints.CheckpointError, match="cannot be read"):
        load_checkpoint(tmp_path / "run" / "checkpoint.json", pipeline, fingerprint="test", run=0)
    state = load_checkpoint(
        tmp_path / "run" / "checkpoint.json", pipeline, fingerprint="test", run=0, with_memory=False
    )
    assert state.generation == 2  # the population alone needs no strategy state (nor its library)


def test_a_missing_library_names_the_install_command(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "g.gg").write_text(NUMERICAL)
    for module, strategy in (("cma", "cma-es"), ("pymoo", "nsga2"), ("ribs", "map-elites")):
        monkeypatch.setitem(sys.modules, module, None)  # import cma: ModuleNotFoundError
        (tmp_path / strategy).mkdir()
        _, config = write_inputs(tmp_path / strategy, strategy, 2)
        args = ["evolve", str(tmp_path / "g.gg"), "-c", str(config), "-o", str(tmp_path / f"o-{strategy}")]
        result = runner.invoke(app, args)
        extra = strategy
        assert result.exit_code == 2, result.output
        assert f"pip install 'gaitgram[{extra}]'" in result.stderr
        assert "Traceback" not in result.stderr
        assert not (tmp_path / f"o-{strategy}").exists()


def test_every_command_starts_without_the_strategy_libraries(tmp_path: Path) -> None:
    """A plain install has no cma, pymoo or ribs: gaitgram must not import them until a run needs them."""
    grammar, config = write_inputs(tmp_path, "ge", generations=1)
    script = (
        "import sys\n"
        "for name in ('cma', 'pymoo', 'ribs'):\n"
        "    sys.modules[name] = None\n"
        "from gaitgram.cli import main\n"
        "sys.argv = ['gaitgram', *sys.argv[1:]]\n"
        "main()\n"
    )
    for args in (
        ["--help"],
        ["evolve", "--help"],
        ["study", "--help"],
        ["report", "--help"],
        ["evolve", str(grammar), "-c", str(config), "-o", str(tmp_path / "ge"), "-q"],
    ):
        result = subprocess.run([sys.executable, "-c", script, *args], capture_output=True, text=True)
        assert result.returncode == 0, (args, result.stderr)
    report = subprocess.run(
        [sys.executable, "-c", script, "report", str(tmp_path / "ge"), "-o", str(tmp_path / "rep")],
        capture_output=True,
        text=True,
    )
    assert report.returncode == 0, report.stderr


def test_reports_draw_fronts_and_repertoires(tmp_path: Path) -> None:
    runs = []
    for strategy in ("nsga2", "map-elites"):
        (tmp_path / strategy).mkdir()
        grammar, config = write_inputs(tmp_path / strategy, strategy, generations=4)
        out = tmp_path / f"{strategy}-run"
        result = runner.invoke(
            app, ["evolve", str(grammar), "-c", str(config), "-o", str(out), "--runs", "2", "-q"]
        )
        assert result.exit_code == 0, result.stderr
        runs.append(str(out))
    report = tmp_path / "report"
    result = runner.invoke(app, ["report", *runs, "-o", str(report)])
    assert result.exit_code == 0, result.stderr
    pngs = sorted(p.name for p in report.glob("*.png"))
    assert pngs == ["archive-map-elites-run.png", "convergence.png", "front-nsga2-run.png"]
    for png in pngs:
        data = (report / png).read_bytes()
        assert data.startswith(b"\x89PNG")
        assert len(data) > 10_000
    summary = (report / "summary.md").read_text()
    assert "**Fronts and repertoires**" in summary
    assert "- **map-elites-run** (archive-map-elites-run.png): rms_hip_hind, rms_elbow_fore;" in summary
    assert "- **nsga2-run** (front-nsga2-run.png): Pareto fronts of" in summary
    gifs = runner.invoke(app, ["report", runs[0], "-o", str(tmp_path / "r2"), "--gaits", "2"])
    assert gifs.exit_code == 2
    assert "drawn on the mujoco-horse backend" in gifs.stderr
