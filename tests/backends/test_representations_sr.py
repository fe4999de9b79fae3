"""``python -m benchmarks representations_sr`` (issue 41, 5b): the five representations on PonyGE2's
regression problems. Its machinery runs here on a tiny budget (2 runs, 3 generations, 20
individuals) over a stand-in PonyGE2 checkout (PonyGE2's grammars, as tests/data keeps them, and our
own five-input data for Vladislavleva-4's grammar), and what it writes is checked against what
scipy.stats computes from runs.jsonl alone. The record's own figures are in
docs/results/representations-sr/."""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from scipy import stats

from benchmarks.bench_ponyge2 import PROBLEMS, Refused
from benchmarks.bench_representations_sr import (
    REPRESENTATIONS,
    census,
    execute,
    summary,
    write,
)
from conftest import ROOT

DATA = ROOT / "tests" / "data"
RUNS, GENERATIONS, POPULATION = 2, 3, 20


@pytest.fixture(scope="module")
def checkout(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A directory laid out as PonyGE2's: its three regression grammars and data for the one
    problem gaitgram does not build (Vladislavleva-4)."""
    root = tmp_path_factory.mktemp("ponyge2")
    grammars = root / "grammars" / "supervised_learning"
    grammars.mkdir(parents=True)
    for source in (
        DATA / "ponyge2" / "supervised_learning.bnf",
        DATA / "ponyge2_regression" / "Keijzer6.bnf",
        DATA / "ponyge2" / "Vladislavleva4.bnf",
    ):
        shutil.copy(source, grammars / source.name)
    shutil.copytree(DATA / "ponyge2_regression" / "five_inputs", root / "datasets" / "Vladislavleva4")
    return root


@pytest.fixture(scope="module")
def record(checkout: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[dict[str, Any]]]:
    """Every problem and representation, run and written as the benchmark writes its record."""
    out = tmp_path_factory.mktemp("record")
    found = execute(
        list(PROBLEMS), list(REPRESENTATIONS), RUNS, checkout, out / "runs.jsonl", GENERATIONS, POPULATION
    )
    write(out, summary(found, list(PROBLEMS), list(REPRESENTATIONS)), found)
    return out, found


def lines(path: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in path.read_text().splitlines()]


def test_census_counts_distinct_genotypes_sharing_a_phenotype() -> None:
    """Genotypes 1 and 2 map to one phenotype (both redundant), 3 maps alone (its copy counts once),
    4 is invalid (out of the share)."""
    population = [
        SimpleNamespace(genome=g, phenotype=p)
        for g, p in [((1,), "x"), ((2,), "x"), ((3,), "y"), ((3,), "y"), ((4,), None)]
    ]
    assert census(population) == (4, 3, 2, 2)


def test_every_run_is_recorded_with_its_generations(record: tuple[Path, list[dict[str, Any]]]) -> None:
    out, _ = record
    runs = lines(out / "runs.jsonl")
    assert sorted((r["problem"], r["representation"], r["run"]) for r in runs) == sorted(
        (p, rep, i) for p in PROBLEMS for rep in REPRESENTATIONS for i in range(RUNS)
    )
    for run in runs:
        assert (run["generations"], run["population"]) == (GENERATIONS, POPULATION)
        for column in ("best", "genotypes", "mapped", "redundant", "phenotypes"):
            assert len(run[column]) == GENERATIONS + 1, column
        for genotypes, mapped, redundant, phenotypes in zip(
            run["genotypes"], run["mapped"], run["redundant"], run["phenotypes"], strict=True
        ):
            assert 0 < genotypes <= POPULATION
            assert redundant <= mapped <= genotypes
            assert redundant != 1  # a shared phenotype has two genotypes at least
            assert mapped - redundant <= phenotypes <= mapped  # lone genotypes, and groups of several
        best = [math.inf if b is None else b for b in run["best"]]
        assert best == sorted(best, reverse=True)  # elites keep the best
        assert run["fitness"] == run["best"][-1]


def _a12(x: Sequence[float], y: Sequence[float]) -> float:
    return sum((a < b) + 0.5 * (a == b) for a in x for b in y) / (len(x) * len(y))


def _holm(p: Sequence[float]) -> list[float]:
    order = sorted(range(len(p)), key=lambda i: p[i])
    adjusted, running = [0.0] * len(p), 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (len(p) - rank) * p[i]))
        adjusted[i] = running
    return adjusted


def test_the_statistics_are_recomputed_from_the_runs(record: tuple[Path, list[dict[str, Any]]]) -> None:
    """comparison.json holds what scipy.stats gives on runs.jsonl's final bests and censuses."""
    out, _ = record
    runs = lines(out / "runs.jsonl")
    comparison = json.loads((out / "comparison.json").read_text())
    assert comparison["budget"]["early_generations"] == [0, 0]
    assert comparison["budget"]["late_generations"] == [GENERATIONS, GENERATIONS]
    claim_p: list[float] = []
    claim_entries: list[dict[str, Any]] = []
    wilcoxon_p: list[float] = []
    wilcoxon_entries: list[dict[str, Any]] = []
    early_p: list[float] = []
    early_entries: list[dict[str, Any]] = []
    for problem in PROBLEMS:
        entry = comparison["problems"][problem]
        final = {
            rep: [
                r["fitness"]
                for r in sorted(runs, key=lambda r: r["run"])
                if (r["problem"], r["representation"]) == (problem, rep)
            ]
            for rep in REPRESENTATIONS
        }
        for rep, values in final.items():
            q1, median, q3 = np.percentile(values, [25, 50, 75])
            assert entry["final"][rep]["median"] == pytest.approx(median, rel=1e-12)
            assert (entry["final"][rep]["q1"], entry["final"][rep]["q3"]) == pytest.approx(
                (q1, q3), rel=1e-12
            )
            assert entry["final"][rep]["best"] == min(values)
            common = entry["final"][rep]["most_common"]
            assert common["runs"] == values.count(common["fitness"]) == max(map(values.count, values))
        h, p = stats.kruskal(*final.values())
        assert (entry["kruskal_wallis"]["h"], entry["kruskal_wallis"]["p"]) == pytest.approx((h, p))
        for test, (first, second) in zip(entry["claim_pairs"], [("sge", "ge"), ("dsge", "sge")], strict=True):
            assert (test["first"], test["second"]) == (first, second)
            u, p = stats.mannwhitneyu(final[first], final[second], alternative="two-sided")
            assert (test["u"], test["p"]) == pytest.approx((u, p))
            assert test["a12_first_lower"] == pytest.approx(_a12(final[first], final[second]))
            claim_p.append(p)
            claim_entries.append(test)
        early_of: dict[str, list[float]] = {}
        for rep in REPRESENTATIONS:
            mine = sorted(
                (r for r in runs if (r["problem"], r["representation"]) == (problem, rep)),
                key=lambda r: r["run"],
            )
            early = [r["redundant"][0] / r["mapped"][0] for r in mine]
            late = [r["redundant"][-1] / r["mapped"][-1] for r in mine]
            red = entry["redundancy"][rep]
            assert red["early_median"] == pytest.approx(float(np.median(early)))
            assert red["late_median"] == pytest.approx(float(np.median(late)))
            assert red["late_higher"] == sum(b > a for a, b in zip(early, late, strict=True))
            p = 1.0 if early == late else float(stats.wilcoxon(early, late).pvalue)
            assert red["p"] == pytest.approx(p)
            wilcoxon_p.append(p)
            wilcoxon_entries.append(red)
            early_of[rep] = early
        for test, second in zip(entry["early_redundancy_pairs"], ["ge", "pige"], strict=True):
            assert (test["first"], test["second"]) == ("sge", second)
            x, y = early_of["sge"], early_of[second]
            u, p = (
                (len(x) * len(y) / 2, 1.0)
                if len(set(x + y)) == 1
                else stats.mannwhitneyu(x, y, alternative="two-sided")
            )
            assert (test["u"], test["p"], test["a12_first_lower"]) == pytest.approx((u, p, _a12(x, y)))
            early_p.append(p)
            early_entries.append(test)
    for test, adjusted in zip(claim_entries, _holm(claim_p), strict=True):
        assert test["p_holm"] == pytest.approx(adjusted)
    for red, adjusted in zip(wilcoxon_entries, _holm(wilcoxon_p), strict=True):
        assert red["p_holm"] == pytest.approx(adjusted)
    for test, adjusted in zip(early_entries, _holm(early_p), strict=True):
        assert test["p_holm"] == pytest.approx(adjusted)


def test_the_readme_shows_the_figures_and_a_verdict_on_each_claim(
    record: tuple[Path, list[dict[str, Any]]],
) -> None:
    out, _ = record
    text = (out / "README.md").read_text()
    comparison = json.loads((out / "comparison.json").read_text())
    keijzer = comparison["problems"]["keijzer-6"]
    assert f"| Keijzer-6 | SGE | {keijzer['final']['sge']['median']:.4g} (" in text
    pair = keijzer["claim_pairs"][0]
    assert f"| Keijzer-6 | SGE vs GE | {pair['u']:.1f} |" in text
    assert "## What it shows, and what it does not" in text
    for claim, verdict in comparison["claims"].items():
        assert isinstance(verdict["supported"], bool), claim
    assert text.count("**supported**") + text.count("**not supported**") == 3
    assert "Refused: none" in text
    assert "scaled down from PonyGE2's `regression.txt` budget" in text


def test_a_record_resumes_and_refuses_another_budget(
    checkout: Path, record: tuple[Path, list[dict[str, Any]]]
) -> None:
    """Runs already in runs.jsonl are not run again; a record of one budget takes no other."""
    out, _ = record
    before = (out / "runs.jsonl").read_text()
    again = execute(
        list(PROBLEMS), list(REPRESENTATIONS), RUNS, checkout, out / "runs.jsonl", GENERATIONS, POPULATION
    )
    assert (out / "runs.jsonl").read_text() == before
    assert len(again) == len(PROBLEMS) * len(REPRESENTATIONS) * RUNS
    with pytest.raises(Refused, match="holds runs of another budget"):
        execute(["keijzer-6"], ["ge"], RUNS, checkout, out / "runs.jsonl", GENERATIONS + 1, POPULATION)
    assert (out / "runs.jsonl").read_text() == before


def test_a_grammar_a_representation_refuses_is_recorded_not_worked_around(
    checkout: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """SGE at a recursion level whose genome would pass its million values is refused: the record
    says so, no run is made, and the README names it."""
    import benchmarks.bench_representations_sr as bench

    monkeypatch.setitem(bench.REPRESENTATIONS, "sge", {"recursion": 40})
    found = execute(["keijzer-6"], ["ge", "sge"], RUNS, checkout, tmp_path / "runs.jsonl", 1, POPULATION)
    refused = [r for r in found if "refused" in r]
    assert [(r["problem"], r["representation"]) for r in refused] == [("keijzer-6", "sge")]
    assert not [r for r in found if r["representation"] == "sge" and "refused" not in r]
    write(tmp_path, summary(found, ["keijzer-6"], ["ge", "sge"]), found)
    text = (tmp_path / "README.md").read_text()
    assert "- SGE on Keijzer-6: " + refused[0]["refused"] in text


def test_the_command_refuses_clearly_without_ponyge2(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if not k.startswith("GAITGRAM_PONYGE2")}

    def run(*words: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "benchmarks", "representations_sr", *words],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            check=False,
        )

    missing = run("--runs", "2")
    assert missing.returncode == 2
    assert "PonyGE2 is not given: fetch it and pass --ponyge2 DIR" in missing.stderr
    elsewhere = run("--ponyge2", str(tmp_path))
    assert elsewhere.returncode == 2
    assert f"{tmp_path} is not a PonyGE2 checkout" in elsewhere.stderr
    misspelt = run("--representations", "ge,sgee")
    assert misspelt.returncode == 2
    assert "--representations: unknown sgee" in misspelt.stderr
    for result in (missing, elsewhere, misspelt):
        assert "Traceback" not in result.stderr
