"""Strategies as study arms: equal budgets, one report; the bundled study; GIFs of chosen gaits."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR as STRUCTURAL
from conftest import CURVE_NUMERICAL as NUMERICAL
from conftest import CURVE_TARGETS_TOML, ROOT
from gaitgram.analysis import check
from gaitgram.cli import app
from gaitgram.language import parse
from gaitgram.language.source import read_source
from gaitgram.report.records import load_study_arms
from gaitgram.strategies.registry import run_pipeline
from gaitgram.study.spec import ScaleDown, StudyError, load_study

runner = CliRunner()

STUDY = (
    """\
title = "strategies, tiny"
runs = 2
seed = 3

[settings]
generations = 3
population = 12
elite = 2
init_max_depth = 6
backend = "curve-match"

[settings.backend_settings.targets]
"""
    + CURVE_TARGETS_TOML
    + """
[[arm]]
name = "ge"
grammar = "structural.gg"

[[arm]]
name = "random"
grammar = "structural.gg"
strategy = "random"

[[arm]]
name = "cma"
grammar = "numerical.gg"
strategy = "cma-es"
[arm.settings.strategy_settings]
sigma0 = 0.2

[[arm]]
name = "front"
grammar = "structural.gg"
strategy = "nsga2"

[[arm]]
name = "repertoire"
grammar = "structural.gg"
strategy = "map-elites"
[arm.settings.strategy_settings]
descriptors = [
  { name = "rms_hip_hind", low = 0.0, high = 12.0 },
  { name = "rms_elbow_fore", low = 0.0, high = 12.0 },
]
"""
)


def gaitgram(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True)


def test_every_strategy_is_an_arm_of_one_study_and_one_report(tmp_path: Path) -> None:
    (tmp_path / "structural.gg").write_text(STRUCTURAL)
    (tmp_path / "numerical.gg").write_text(NUMERICAL)
    (tmp_path / "study.toml").write_text(STUDY)
    out = tmp_path / "study"
    result = gaitgram("study", str(tmp_path / "study.toml"), "-o", str(out), "-q", "--jobs", "2")
    assert result.returncode == 0, result.stderr
    manifest = json.loads((out / "study.json").read_text())
    assert [a["strategy"] for a in manifest["arms"]] == ["ge", "random", "cma-es", "nsga2", "map-elites"]
    arms = load_study_arms(out)
    assert [a.strategy for a in arms] == ["ge", "random", "cma-es", "nsga2", "map-elites"]
    assert {a.budget for a in arms} == {12 + 3 * 10}
    for arm in arms:  # every arm spent exactly the budget
        records = (arm.path / "run-001" / "stats.jsonl").read_text().splitlines()
        assert sum(json.loads(line)["evaluations"] for line in records) == 42
    again = gaitgram("study", str(tmp_path / "study.toml"), "-o", str(out), "-q")  # finished: nothing to do
    assert again.returncode == 0, again.stderr
    report = gaitgram("report", str(out), "-o", str(tmp_path / "report"))
    assert report.returncode == 0, report.stderr
    written = sorted(p.name for p in (tmp_path / "report").glob("*.png"))
    assert written == ["archive-repertoire.png", "convergence.png", "front-front.png"]
    summary = (tmp_path / "report" / "summary.md").read_text()
    for arm in ("ge", "random", "cma", "front", "repertoire"):
        assert f"| {arm} | 2 |" in summary


def test_a_study_arm_names_an_installed_strategy(tmp_path: Path) -> None:
    (tmp_path / "structural.gg").write_text(STRUCTURAL)
    (tmp_path / "numerical.gg").write_text(NUMERICAL)
    (tmp_path / "study.toml").write_text(STUDY.replace('strategy = "nsga2"', 'strategy = "nsgaii"'))
    with pytest.raises(StudyError, match="arm 'front': strategy: 'nsgaii' is not an installed strategy"):
        load_study(tmp_path / "study.toml")
    (tmp_path / "study.toml").write_text(
        STUDY.replace('grammar = "numerical.gg"', 'grammar = "structural.gg"')
    )
    result = gaitgram("study", str(tmp_path / "study.toml"), "-o", str(tmp_path / "out"), "-q")
    assert result.returncode == 2
    assert "arm 'cma'" in result.stderr
    assert "chooses between alternatives of different structure" in result.stderr
    assert not (tmp_path / "out").exists()


def test_the_bundled_strategies_study_compares_at_the_table_1_budget() -> None:
    study = load_study(ROOT / "studies" / "strategies.toml")
    assert [(a.name, a.strategy, a.grammar.name) for a in study.arms] == [
        ("ge-hybrid", "ge", "hybrid.gg"),
        ("cma-es-numerical", "cma-es", "numerical.gg"),
        ("random-hybrid", "random", "hybrid.gg"),
        ("ge-numerical", "ge", "numerical.gg"),
    ]
    assert study.runs == 30
    for arm in study.arms:
        assert (arm.config.generations, arm.config.population, arm.config.elite) == (50, 75, 7)
        assert arm.config.budget == 3475
        assert "weights" not in arm.config.backend_settings  # the defaults: under them GE walks
        pipeline = run_pipeline(check(parse(read_source(arm.grammar))), arm.config)
        assert pipeline.config.strategy == arm.strategy
    small = load_study(ROOT / "studies" / "strategies.toml", ScaleDown(runs=5, generations=10, population=30))
    assert {a.config.budget for a in small.arms} == {30 + 10 * 27}


def test_the_multi_objective_study_is_the_strategies_ge_arm_but_for_the_strategy() -> None:
    """Its report reads beside strategies.toml's ge-hybrid arm: run i must be the same run but for
    the search strategy (grammar, seed, budget, weights), or the comparison would not be fair."""
    ge = load_study(ROOT / "studies" / "strategies.toml").arms[0]
    study = load_study(ROOT / "studies" / "multi-objective.toml")
    assert [(a.name, a.strategy) for a in study.arms] == [
        ("nsga2-hybrid", "nsga2"),
        ("map-elites-hybrid", "map-elites"),
    ]
    assert study.runs == 30
    for arm in study.arms:
        assert arm.grammar.resolve() == ge.grammar.resolve()
        assert {**arm.config.as_dict(), "strategy": "ge"} == ge.config.as_dict()
    # Its follow-up changes NSGA-II's objectives and nothing else.
    (two,) = load_study(ROOT / "studies" / "nsga2-objectives.toml").arms
    assert two.config.strategy_settings == {"objectives": ["velocity", "duty_factor"]}
    assert {**two.config.as_dict(), "strategy_settings": {}, "runs": 30} == study.arms[0].config.as_dict()


def test_the_bump_floors_study_is_the_strategies_ge_arm_but_for_the_floors() -> None:
    """Its report reads beside strategies.toml's ge-hybrid arm (--mixed-scoring): run i must be the
    same run but for the floors it is scored on, none of them a floor its gaits are tested on."""
    ge = load_study(ROOT / "studies" / "strategies.toml").arms[0]
    (arm,) = load_study(ROOT / "studies" / "bump-floors.toml").arms
    assert arm.grammar.resolve() == ge.grammar.resolve()
    settings = dict(arm.config.backend_settings)
    assert settings.pop("bump_floors") == [0, 1, 2]
    assert {**arm.config.as_dict(), "backend_settings": settings, "runs": 30} == {
        **ge.config.as_dict(),
        "backend": "mujoco-horse",
    }
    pipeline = run_pipeline(check(parse(read_source(arm.grammar))), arm.config)
    assert pipeline.config.backend_settings["bump_floors"] == (0, 1, 2)


@pytest.mark.slow  # a study of every strategy, then GIFs of chosen gaits
def test_report_animates_chosen_trade_offs_and_cells(tmp_path: Path) -> None:
    """On the horse, briefly: two GIFs along a front, one of a chosen repertoire cell."""
    config = tmp_path / "run.toml"
    config.write_text(
        "generations = 1\npopulation = 6\nelite = 1\ninit_max_depth = 6\n\n"
        "[backend_settings]\ncycles = 1\nramp_seconds = 0.2\nthreads = 1\n"
    )
    grammar = str(ROOT / "grammars" / "sine-walk.gg")
    for strategy in ("nsga2", "map-elites"):
        result = runner.invoke(
            app,
            [
                "evolve",
                grammar,
                "-c",
                str(config),
                "--strategy",
                strategy,
                "-o",
                str(tmp_path / strategy),
                "-q",
            ],
        )
        assert result.exit_code == 0, result.stderr
    cells = json.loads((tmp_path / "map-elites" / "run-000" / "archive.json").read_text())["elites"]
    cell = ",".join(map(str, cells[0]["cell"]))
    out = tmp_path / "report"
    result = gaitgram("report", str(tmp_path / "nsga2"), "-o", str(out), "--gaits", "2")
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in out.glob("*.gif")) == ["front-nsga2-0.gif", "front-nsga2-1.gif"]
    result = gaitgram("report", str(tmp_path / "map-elites"), "-o", str(out), "--cell", cell, "--force")
    assert result.returncode == 0, result.stderr
    gif = out / f"cell-map-elites-{cell.replace(',', '-')}.gif"
    assert gif.read_bytes().startswith(b"GIF8")
    empty = gaitgram("report", str(tmp_path / "map-elites"), "-o", str(out), "--cell", "9,0", "--force")
    assert empty.returncode == 2
    assert "cell 9,0 is empty in every run" in empty.stderr
