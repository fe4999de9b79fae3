"""The symbolic-regression backend: PonyGE2's regression problems, scored as PonyGE2 scores them.

The oracle is PonyGE2's own fitness function: ``tests/data/ponyge2_regression/fitness_vectors.jsonl``
holds 1,284 phenotypes of its three regression grammars scored by its
``supervised_learning.regression`` (made by ``make_fitness_vectors.py`` beside it, under PonyGE2's
numpy 1.26.4), and its data files are represented by their digests (``datasets.json``).
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import ROOT
from gaitgram.backends.api import GaitStatus
from gaitgram.backends.registry import backend_names, get_backend
from gaitgram.backends.symbolic_regression import load
from gaitgram.backends.symbolic_regression.datasets import BUILT, DatasetError, digest, read_table
from gaitgram.backends.symbolic_regression.expression import (
    ExpressionError,
    aq,
    compile_expression,
    pdiv,
    plog,
    psqrt,
)
from gaitgram.cli import app

DATA = ROOT / "tests" / "data" / "ponyge2_regression"
PONYGE2 = ROOT / "tests" / "data" / "ponyge2"
runner = CliRunner()

#: Where PonyGE2 keeps each built dataset.
PONYGE2_NAMES = {"pagie-1": "Paige1", "keijzer-6": "Keijzer6"}
#: The numpy release the vectors were made under: transcendental functions (np.exp, np.log) may
#: round a last bit differently under another release (numpy 2's vectorised loops).
VECTOR_NUMPY = "1.26.4"


def evaluators() -> dict[str, Any]:
    five = {"train": str(DATA / "five_inputs" / "Train.txt"), "test": str(DATA / "five_inputs" / "Test.txt")}
    return {
        "keijzer-6": load({"dataset": "keijzer-6"}),
        "pagie-1": load({"dataset": "pagie-1"}),
        "five-inputs": load(five),
    }


def vectors() -> list[dict[str, Any]]:
    return [json.loads(line) for line in (DATA / "fitness_vectors.jsonl").read_text().splitlines()]


def scored(evaluation: Any) -> float | None:
    """A fitness as PonyGE2 records it: None where it scores NaN."""
    ok = evaluation.status.viable and math.isfinite(evaluation.fitness)
    return evaluation.fitness if ok else None


@pytest.mark.parametrize("name", sorted(BUILT))
def test_built_datasets_are_ponyge2s_files_value_for_value(name: str) -> None:
    recorded = json.loads((DATA / "datasets.json").read_text())["files"]
    dataset = BUILT[name]()
    assert dataset.test is not None
    for split, table in (("Train", dataset.train), ("Test", dataset.test)):
        entry = recorded[f"{PONYGE2_NAMES[name]}/{split}.txt"]
        assert (len(table.rows), table.n_inputs) == (entry["rows"], entry["inputs"])
        assert digest(table) == entry["values_sha256"]


def test_fitness_is_ponyge2s_on_every_vector() -> None:
    """Every phenotype PonyGE2 scores NaN is unviable here and every other one viable; the scores are
    PonyGE2's to the bit where only arithmetic is involved, and everywhere under the numpy release
    the vectors were made with (under another, np.exp and np.log may round a last bit differently,
    and then the compiled phenotype is checked against Python's own evaluation below)."""
    found = evaluators()
    exact_everywhere = np.__version__ == VECTOR_NUMPY
    wrong, compared = [], 0
    for line in vectors():
        mine = scored(found[line["problem"]].score(line["phenotype"]))
        want = line["fitness"]
        if (mine is None) != (want is None):
            wrong.append((line, mine))
        elif mine is not None and (exact_everywhere or not re.search(r"np\.|plog", line["phenotype"])):
            compared += 1
            if mine != want:
                wrong.append((line, mine))
    assert len(vectors()) == 1284
    assert compared >= 600  # the arithmetic phenotypes alone
    assert not wrong, f"{len(wrong)} disagree, first: {wrong[:3]}"


def test_compiled_phenotypes_are_python_eval_under_ponyge2s_error_state() -> None:
    """The compiler against Python itself (the test's oracle; the backend never evals): the same
    value to the bit, or the same floating-point error, on every vector phenotype."""
    data = {name: evaluator._train for name, evaluator in evaluators().items()}
    names = {"np": np, "pdiv": pdiv, "aq": aq, "psqrt": psqrt, "plog": plog}
    errors = (FloatingPointError, ZeroDivisionError, OverflowError)
    for line in vectors():
        split = data[line["problem"]]
        with np.errstate(all="raise"):
            try:
                want = eval(line["phenotype"], {**names, "x": split.x})  # the oracle
            except errors as error:
                want = type(error)
            try:
                mine = compile_expression(line["phenotype"])(split.columns)
            except errors as error:
                mine = type(error)
        if isinstance(want, type):
            assert mine is want, line["phenotype"]
        else:
            assert np.array_equal(np.asarray(mine), np.asarray(want)), line["phenotype"]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("__import__(x[:, 0])", "__import__ is not one of PonyGE2's regression functions"),
        ("np.sin('x')", 'unexpected "\'"'),
        ("x[0]", "unexpected '['"),
        ("x[:, 0]/2.0", "unexpected '/'"),
        ("x[:, 0]**2.0", "unexpected '*'"),
        ("pdiv(x[:, 0])", "pdiv takes 2 arguments, not 1"),
        ("np.sin(x[:, 0]", "expected ')'"),
        ("x[:, 0] x[:, 0]", "unexpected 'x[:, 0]'"),
        ("01", "leading zeros"),
    ],
)
def test_text_outside_the_grammars_subset_is_refused_never_run(text: str, message: str) -> None:
    with pytest.raises(ExpressionError, match=re.escape(message)):
        compile_expression(text)
    evaluation = load({"dataset": "keijzer-6"}).score(text)
    assert evaluation.status is GaitStatus.INVALID_MOTION
    assert message in (evaluation.detail or "")


def test_a_bad_phenotype_is_a_status() -> None:
    evaluator = load({"dataset": "keijzer-6"})
    overflow = evaluator.score("np.exp(np.exp(np.exp(x[:, 0])))")
    assert overflow.status is GaitStatus.NON_FINITE
    assert "floating-point error" in (overflow.detail or "")
    beyond = evaluator.score("x[:, 0]+x[:, 3]")
    assert beyond.status is GaitStatus.INVALID_MOTION
    assert "x[:, 3]: the dataset has 1 inputs" in (beyond.detail or "")
    constant = evaluator.score("12.34")  # a constant predicts every case: PonyGE2 scores it
    assert constant.status.viable
    y = np.array(evaluator.dataset.train.rows)[:, -1]
    assert constant.fitness == float(np.sqrt(np.mean(np.square(y - 12.34))))


@pytest.mark.parametrize(
    ("metric", "formula"),
    [("mse", lambda e: np.mean(np.square(e))), ("mae", lambda e: np.mean(np.abs(e)))],
)
def test_the_metrics_ponyge2s_parameter_files_may_name(metric: str, formula: Any) -> None:
    evaluator = load({"dataset": "keijzer-6", "metric": metric})
    y = np.array(evaluator.dataset.train.rows)[:, -1]
    evaluation = evaluator.score("x[:, 0]*00.10")
    x = np.array(evaluator.dataset.train.rows)[:, 0]
    assert evaluation.fitness == float(formula(y - x * 0.1))
    assert evaluation.components == {metric: evaluation.fitness}


def test_reads_ponyge2s_file_format(tmp_path: Path) -> None:
    table = read_table(DATA / "five_inputs" / "Train.txt")
    assert (len(table.rows), table.n_inputs) == (243, 5)
    path = tmp_path / "Train.txt"
    path.write_text("a,b,y\n1,2,3\n# a comment\n\n4,5,6\n")
    assert read_table(path).rows == ((1.0, 2.0, 3.0), (4.0, 5.0, 6.0))
    path.write_text("a\tb\ty\n1\t2\t3\n4\tfive\t6\n")
    with pytest.raises(DatasetError, match=re.escape(f"{path}:3: 'five' is not a number")):
        read_table(path)
    path.write_text("a\tb\ty\n1\t2\t3\n4\t5\n")
    with pytest.raises(DatasetError, match=re.escape(f"{path}:3: 2 fields where the rows above have 3")):
        read_table(path)


def test_declared_as_a_phenotype_backend_without_joints_or_sensors() -> None:
    assert "symbolic-regression" in backend_names()
    spec = get_backend("symbolic-regression")
    assert spec.catalogue is None
    assert spec.sensors is None
    assert spec.scores_phenotype


@pytest.mark.parametrize(
    ("grammar", "defines"),
    [
        (DATA / "Keijzer6.bnf", []),
        (PONYGE2 / "Vladislavleva4.bnf", []),
        (PONYGE2 / "supervised_learning.bnf", ["--define", "dataset_n_vars=2"]),
    ],
    ids=["Keijzer6", "Vladislavleva4", "supervised_learning"],
)
def test_ponyge2s_regression_grammars_check_unchanged(grammar: Path, defines: list[str]) -> None:
    result = runner.invoke(app, ["check", str(grammar), *defines])
    assert result.exit_code == 0, result.stdout + result.stderr


def run_toml(tmp_path: Path, settings: str, **extra: object) -> Path:
    lines = [
        'backend = "symbolic-regression"',
        'codons = "eager"',
        "max_wraps = 0",
        "population = 30",
        "generations = 3",
        "elite = 2",
        "max_depth = 16",
        *(f"{key} = {value}" for key, value in extra.items()),
        "[backend_settings]",
        settings,
    ]
    path = tmp_path / "run.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_evolve_on_pagie_1_with_ponyge2s_generic_grammar(tmp_path: Path) -> None:
    config = run_toml(tmp_path, 'dataset = "pagie-1"')
    out = tmp_path / "run"
    result = runner.invoke(
        app,
        [
            "evolve",
            str(PONYGE2 / "supervised_learning.bnf"),
            "-D",
            "dataset_n_vars=2",
            "-c",
            str(config),
            "-o",
            str(out),
            "-q",
        ],
    )
    assert result.exit_code == 0, result.stderr
    best = json.loads((out / "run-000" / "best.json").read_text())
    assert best["status"] == "ok"
    assert best["joints"] == {}
    rescored = load({"dataset": "pagie-1"}).score(best["phenotype"])
    assert best["fitness"] == rescored.fitness == best["components"]["rmse"]
    evaluated = runner.invoke(app, ["evaluate", "--run", str(out)])
    assert evaluated.exit_code == 0, evaluated.stderr
    assert f"{best['fitness']:.6f}" in evaluated.stdout


def test_a_run_never_resumes_on_other_data(tmp_path: Path) -> None:
    data = tmp_path / "Train.txt"
    data.write_text((DATA / "five_inputs" / "Train.txt").read_text())
    config = run_toml(tmp_path, f'train = "{data}"')
    out = tmp_path / "run"
    grammar = str(PONYGE2 / "Vladislavleva4.bnf")
    first = runner.invoke(
        app, ["evolve", grammar, "-c", str(config), "-o", str(out), "-q", "--generations", "2"]
    )
    assert first.exit_code == 0, first.stderr
    assert "train_sha256" in (out / "config.toml").read_text()
    data.write_text(data.read_text().replace("0.2\n", "0.25\n", 1))
    resumed = runner.invoke(app, ["evolve", "--resume", str(out), "-q", "--generations", "3"])
    assert resumed.exit_code == 2
    assert "is not the file the run recorded" in resumed.stderr
    assert "Traceback" not in resumed.stderr


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        ('dataset = "pagie1"', "did you mean pagie-1?"),
        ('dataset = "vladislavleva-4"', 'is read from files: train = "PATH"'),
        ('train = "no/such/Train.txt"', "no/such/Train.txt: no such file"),
        ('dataset = "keijzer-6"\nmetric = "r2"', "metric: must be one of rmse, mse, mae"),
        (
            'dataset = "keijzer-6"\ndatset = 1',
            "datset: unknown symbolic-regression setting; did you mean dataset?",
        ),
    ],
)
def test_bad_settings_exit_2_with_the_key(tmp_path: Path, settings: str, message: str) -> None:
    config = run_toml(tmp_path, settings)
    result = runner.invoke(
        app, ["evolve", str(DATA / "Keijzer6.bnf"), "-c", str(config), "-o", str(tmp_path / "r")]
    )
    assert result.exit_code == 2
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "r").exists()


def test_a_curve_backend_still_wants_joints(tmp_path: Path) -> None:
    """Only a backend that scores the text itself spares a grammar its @joint rules."""
    config = tmp_path / "run.toml"
    config.write_text('backend = "curve-match"\n[backend_settings.targets]\nneck = "sin(2*PI*t)"\n')
    result = runner.invoke(
        app, ["evolve", str(DATA / "Keijzer6.bnf"), "-c", str(config), "-o", str(tmp_path / "r")]
    )
    assert result.exit_code == 2
    assert "declares no @joint rule" in result.stderr


def test_the_ponyge2_benchmark_refuses_clearly_without_ponyge2(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if not k.startswith("GAITGRAM_PONYGE2")}
    done = subprocess.run(
        [sys.executable, "-m", "benchmarks", "ponyge2", "--runs", "1"],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2
    assert "PonyGE2 is not given: fetch it and pass --ponyge2 DIR" in done.stderr
    missing = subprocess.run(
        [sys.executable, "-m", "benchmarks", "ponyge2", "--ponyge2", str(tmp_path)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert missing.returncode == 2
    assert f"{tmp_path} is not a PonyGE2 checkout" in missing.stderr


def test_the_benchmark_gives_both_tools_the_same_settings() -> None:
    """PonyGE2's command line and gaitgram's RunConfig carry the same numbers (depths shifted by the
    terminal level PonyGE2 counts)."""
    from benchmarks.bench_ponyge2 import PROBLEMS, gaitgram_config, ponyge2_arguments

    for problem in PROBLEMS.values():
        words = ponyge2_arguments(problem, 7)
        flags = dict(zip(words[::2], words[1::2], strict=False))
        config = gaitgram_config(problem, Path("/ponyge2"), 30)
        assert int(flags["--population_size"]) == config.population
        assert int(flags["--generations"]) == config.generations
        assert int(flags["--elite_size"]) == config.elite
        assert int(flags["--tournament_size"]) == config.tournament
        ge = config.representation_settings
        assert float(flags["--crossover_probability"]) == ge["crossover"]
        assert float(flags["--mutation_probability"]) == ge["mutation"]
        assert int(flags["--codon_size"]) == ge["codon_size"]
        assert int(flags["--max_wraps"]) == ge["max_wraps"] == 0
        assert int(flags["--max_tree_depth"]) - 1 == ge["max_depth"]
        assert int(flags["--max_init_tree_depth"]) - 1 == ge["init_max_depth"]
        assert (flags["--crossover"], ge["fixed_point"], ge["crossover_within_used"]) == (
            "variable_onepoint",
            False,
            True,
        )
        assert ge["mutation_within_used"]
        assert ge["codons"] == "eager"
        assert flags["--grammar_file"] == problem.grammar
