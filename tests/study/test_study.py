"""Studies: a tiny study runs, survives Ctrl-C and kill -9, resumes to identical results, and its
statistics are scipy's on the same numbers."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from measured import summary_results
from scipy import stats
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_STUDY
from gaitgram.cli import app
from gaitgram.report.records import load_study_arms
from gaitgram.report.sections import build_report
from gaitgram.report.stats import (
    a12,
    compare_rates,
    compare_spreads,
    holm,
    mcnemar_exact,
    paired_summary,
    wilson_interval,
)
from gaitgram.study.spec import ScaleDown, StudyError, load_study

runner = CliRunner()

#: Three runs of two arms of the tiny curve-match problem; ``{generations}`` to fill in.
GRAMMAR, STUDY = CURVE_GRAMMAR, CURVE_STUDY


def write_study(tmp_path: Path, generations: int = 2) -> Path:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    path = tmp_path / "tiny.toml"
    path.write_text(STUDY.format(generations=generations))
    return path


def gaitgram(*args: str, **kwargs) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True, **kwargs)


def same_study_results(out: Path, whole: Path) -> None:
    """Every arm's summary and every run's statistics as the uninterrupted study's."""
    for arm in ("plain", "mutant"):
        assert summary_results(out / "arms" / arm / "summary.json") == summary_results(
            whole / "arms" / arm / "summary.json"
        )
        for run in range(3):
            name = f"arms/{arm}/run-{run:03d}/stats.csv"
            assert (out / name).read_text() == (whole / name).read_text()


def checkpointed(out: Path, generation: int) -> bool:
    """Whether any run of the study in ``out`` has checkpointed ``generation``."""
    for path in out.glob("arms/*/run-*/checkpoint.json"):
        try:
            if json.loads(path.read_text())["checkpoint"]["generation"] >= generation:
                return True
        except (OSError, ValueError, KeyError):  # replaced while read: the next poll reads it
            pass
    return False


def test_a_study_stopped_with_ctrl_c_and_run_again_gives_the_uninterrupted_results(
    tmp_path: Path, ctrl_c_when: Callable[[Callable[[], bool]], None]
) -> None:
    """A real SIGINT to an in-process ``gaitgram study`` (its runs in worker processes): the runs
    stop after their generation, it says how to continue, exits 130; the same command again ends
    where the uninterrupted study ends. (The real kill -9 of ``study`` is the slow test below.)"""
    study = write_study(tmp_path, generations=40)
    whole = runner.invoke(app, ["study", str(study), "-o", str(tmp_path / "whole"), "-q", "--jobs", "2"])
    assert whole.exit_code == 0, whole.stderr
    out = tmp_path / "stopped"
    ctrl_c_when(lambda: checkpointed(out, 3))
    stopped = runner.invoke(app, ["study", str(study), "-o", str(out), "-q", "--jobs", "2"])
    assert stopped.exit_code == 130, stopped.stderr
    assert "continue with the same command" in stopped.stderr
    # Runs are taken run by run across the arms: the last runs had not started, no arm is whole.
    assert not list(out.glob("arms/*/summary.json"))
    assert not (out / "arms" / "mutant" / "run-002" / "checkpoint.json").exists()
    resumed = runner.invoke(app, ["study", str(study), "-o", str(out), "-q", "--jobs", "1"])
    assert resumed.exit_code == 0, resumed.stderr
    same_study_results(out, tmp_path / "whole")


@pytest.mark.slow
def test_a_study_killed_and_resumed_gives_the_uninterrupted_results(tmp_path: Path) -> None:
    """The one real kill -9 of ``gaitgram study``: the study process only, whose workers must die
    with it and leave every run resumable."""
    study = write_study(tmp_path, generations=150)
    whole = gaitgram("study", str(study), "-o", str(tmp_path / "whole"), "-q", "--jobs", "2")
    assert whole.returncode == 0, whole.stderr
    out = tmp_path / "killed"
    process = subprocess.Popen(
        [sys.executable, "-m", "gaitgram", "study", str(study), "-o", str(out), "-q", "--jobs", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    deadline = time.monotonic() + 60
    while not list(out.glob("arms/*/run-000/stats.jsonl")) and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(0.3)
    os.kill(process.pid, signal.SIGKILL)  # the study process only: its workers must die with it
    process.wait()
    assert not (out / "arms" / "plain" / "summary.json").exists()
    time.sleep(0.5)
    resumed = gaitgram("study", str(study), "-o", str(out), "-q", "--jobs", "1")
    assert resumed.returncode == 0, resumed.stderr
    same_study_results(out, tmp_path / "whole")


def test_the_report_statistics_are_scipys(tmp_path: Path) -> None:
    study = write_study(tmp_path)
    result = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q")
    assert result.returncode == 0, result.stderr
    arms = load_study_arms(tmp_path / "s")
    report = build_report(arms)
    plain, mutant = (a.final_best for a in arms)
    assert report.best.kruskal_p == pytest.approx(stats.kruskal(plain, mutant).pvalue)
    (pair,) = report.best.pairs
    assert pair.p_value == pytest.approx(stats.mannwhitneyu(plain, mutant, alternative="two-sided").pvalue)
    assert pair.a12 == pytest.approx(np.mean([(x < y) + 0.5 * (x == y) for x in plain for y in mutant]))
    reported = gaitgram("report", str(tmp_path / "s"), "-o", str(tmp_path / "report"))
    assert reported.returncode == 0, reported.stderr
    assert "**final best**: Kruskal-Wallis H = " in reported.stdout
    assert "| plain vs mutant |" in (tmp_path / "report" / "summary.md").read_text()
    summary = json.loads((tmp_path / "report" / "summary.json").read_text())
    assert [a["final_best"] for a in summary["arms"]] == [list(plain), list(mutant)]
    assert summary["pairs"][0]["best"]["p_holm"] == pytest.approx(pair.p_holm)
    assert (tmp_path / "report" / "convergence.png").read_bytes().startswith(b"\x89PNG")
    assert "\\toprule" in (tmp_path / "report" / "tables.tex").read_text()
    again = gaitgram("report", str(tmp_path / "s"), "-o", str(tmp_path / "again"))
    assert again.returncode == 0, again.stderr
    for name in ("summary.md", "summary.json", "convergence.svg"):  # committed reports do not churn
        assert (tmp_path / "again" / name).read_bytes() == (tmp_path / "report" / name).read_bytes()


def test_a_different_study_in_the_same_directory_is_refused(tmp_path: Path) -> None:
    study = write_study(tmp_path)
    assert gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q").returncode == 0
    more = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q", "--generations", "3")
    assert more.returncode == 2
    assert "arm 'plain' differs" in more.stderr
    assert "generations: 2 -> 3" in more.stderr


def test_runs_of_different_budgets_are_not_reported_together(tmp_path: Path) -> None:
    study = write_study(tmp_path)
    assert gaitgram("study", str(study), "-o", str(tmp_path / "a"), "-q").returncode == 0
    assert (
        gaitgram("study", str(study), "-o", str(tmp_path / "b"), "-q", "--generations", "3").returncode == 0
    )
    from gaitgram.report.records import ReportError, load_arm

    arms = [
        load_arm(tmp_path / "a" / "arms" / "plain", "two"),
        load_arm(tmp_path / "b" / "arms" / "plain", "three"),
    ]
    with pytest.raises(ReportError, match="different budgets"):
        build_report(arms)


def test_study_files_are_checked_with_the_arm_named(tmp_path: Path) -> None:
    study = write_study(tmp_path)
    study.write_text(study.read_text().replace("mutation = 0.2", "mutaton = 0.2"))
    with pytest.raises(StudyError, match=r"arm 'mutant'.*did you mean mutation"):
        load_study(study)
    study.write_text(STUDY.format(generations=2).replace('name = "mutant"', 'name = "plain"'))
    with pytest.raises(StudyError, match="two arms are named 'plain'"):
        load_study(study)


def test_scaling_down_keeps_the_elites_share(tmp_path: Path) -> None:
    study = write_study(tmp_path)
    study.write_text(study.read_text().replace("population = 12\nelite = 1", "population = 75\nelite = 7"))
    scaled = load_study(study, ScaleDown(runs=2, generations=5, population=20))
    config = scaled.arms[0].config
    assert (scaled.runs, config.generations, config.population, config.elite) == (2, 5, 20, 2)


def test_holm_and_a12_on_known_values() -> None:
    assert holm([0.01, 0.04, 0.03]) == pytest.approx([0.03, 0.06, 0.06])
    adjusted = holm([0.01, float("nan"), 0.04, 0.03])  # an untestable pair is not counted
    assert np.isnan(adjusted[1])
    assert [adjusted[i] for i in (0, 2, 3)] == pytest.approx([0.03, 0.06, 0.06])
    assert a12([1, 2], [3, 4]) == 1.0
    assert a12([1, 2], [1, 2]) == 0.5


@pytest.mark.parametrize(("walks", "runs"), [(0, 3), (2, 3), (27, 30), (30, 30), (5, 10)])
def test_the_walk_rate_interval_is_wilsons_score_interval(walks: int, runs: int) -> None:
    z = stats.norm.ppf(0.975)
    share = walks / runs
    centre = (share + z * z / (2 * runs)) / (1 + z * z / runs)
    half = z / (1 + z * z / runs) * np.sqrt(share * (1 - share) / runs + z * z / (4 * runs * runs))
    low, high = wilson_interval(walks, runs)
    assert (low, high) == pytest.approx((centre - half, centre + half), abs=1e-12)
    assert 0 <= low <= share <= high <= 1


def test_walk_rates_are_compared_by_fishers_exact_test_with_holm() -> None:
    counts = {"a": (9, 10), "b": (5, 10), "c": (0, 10)}
    pairs = compare_rates(counts)
    assert [(p.first, p.second) for p in pairs] == [("a", "b"), ("a", "c"), ("b", "c")]
    raw = [stats.fisher_exact([[k, n - k], [j, m - j]]).pvalue for (k, n), (j, m) in
           [(counts["a"], counts["b"]), (counts["a"], counts["c"]), (counts["b"], counts["c"])]]  # fmt: skip
    assert [p.p_value for p in pairs] == pytest.approx(raw)
    assert [p.p_holm for p in pairs] == pytest.approx(holm(raw))
    assert pairs[0].p_value == pytest.approx(0.1409, abs=1e-4)  # as the report's text says


def test_spreads_are_compared_by_brown_forsythe_with_holm() -> None:
    rng = np.random.default_rng(3)
    groups = {"tight": rng.normal(0, 0.01, 12), "wide": rng.normal(0, 1.0, 12), "mid": rng.normal(0, 0.3, 12)}
    tested = compare_spreads(groups)
    overall = stats.levene(*groups.values(), center="median")
    assert (tested.statistic, tested.p_value) == pytest.approx((overall.statistic, overall.pvalue))
    raw = [stats.levene(groups[p.first], groups[p.second], center="median").pvalue for p in tested.pairs]
    assert [p.p_value for p in tested.pairs] == pytest.approx(raw)
    assert [p.p_holm for p in tested.pairs] == pytest.approx(holm(raw))
    assert tested.pairs[0].p_holm < 0.05  # tight against wide
    flat = compare_spreads({"a": [1.0, 1.0, 1.0], "b": [2.0, 2.0, 2.0]})  # no spread to test
    assert np.isnan(flat.p_value)
    assert np.isnan(flat.pairs[0].p_holm)
    # Two runs an arm, or runs on two plateaus: deviations equal but for rounding, not a finding.
    for pair in ({"a": [0.1, 0.4], "b": [0.3, 0.7]}, {"a": [0.1, 0.1, 0.4, 0.4], "b": [0.3, 0.3, 0.7, 0.7]}):
        assert np.isnan(compare_spreads(pair).p_value)


def test_paired_playings_are_compared_run_by_run() -> None:
    values = {"scaled": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6], "unscaled": [0.2, 0.3, 0.5, 0.6, 0.9, 1.0]}
    walks = {"scaled": [True] * 5 + [False], "unscaled": [False] * 6}
    summary = paired_summary(values, walks)
    assert summary["runs"] == 6
    assert summary["playings"]["scaled"]["walks"] == 5
    assert summary["playings"]["scaled"]["wilson95"] == pytest.approx(list(wilson_interval(5, 6)))
    (pair,) = summary["paired"]
    assert (pair["first_lower"], pair["walks_first_only"], pair["walks_second_only"]) == (6, 5, 0)
    assert pair["p_value"] == pytest.approx(stats.wilcoxon(values["scaled"], values["unscaled"]).pvalue)
    assert pair["mcnemar_p"] == pytest.approx(2 * 0.5**5) == mcnemar_exact(5, 0)
    assert mcnemar_exact(0, 0) == 1.0
    assert "walks" not in paired_summary(values)["playings"]["scaled"]


def test_the_bundled_paper_studies_load_at_the_table_1_budget_and_scale_down() -> None:
    studies = Path(__file__).resolve().parents[2] / "studies"
    table5 = load_study(studies / "table5.toml")
    assert [a.name for a in table5.arms] == ["numerical", "concatenating", "hybrid", "free", "sinusoidal"]
    assert table5.runs == 30
    assert {(a.config.generations, a.config.population) for a in table5.arms} == {(50, 75)}
    paper = {"velocity": 1.0, "duty_factor": 1.0, "stride": 1.0, "frequency": 0.0, "energy": 1.0}
    assert all(a.config.backend_settings["weights"] == paper for a in table5.arms)
    table4 = load_study(studies / "table4.toml", ScaleDown(generations=10))
    varying = next(a for a in table4.arms if a.name == "varying-weights")
    assert [stage.start for stage in varying.config.weight_schedule] == [0, 2, 4, 6, 8]  # 0, 11, ... of 50
    assert load_study(studies / "table4.toml").arms[1].config.weight_schedule[1].start == 11


def test_a_small_share_never_reads_as_none() -> None:
    from gaitgram.report.sections import share_text as _rate

    assert [_rate(v) for v in (0.0, 0.0004, 0.004, 0.9, None)] == ["0%", "< 0.1%", "0.4%", "90%", "n/a"]


def test_a_study_grows_more_runs_and_never_drops_any(tmp_path: Path) -> None:
    study = write_study(tmp_path)
    small = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q", "--runs", "2")
    assert small.returncode == 0, small.stderr
    grown = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q")  # the file's 3 runs
    assert grown.returncode == 0, grown.stderr
    whole = gaitgram("study", str(study), "-o", str(tmp_path / "whole"), "-q")
    assert whole.returncode == 0, whole.stderr
    for arm in ("plain", "mutant"):
        for name in (f"run-{run:03d}/stats.csv" for run in range(3)):
            assert (tmp_path / "s" / "arms" / arm / name).read_text() == (
                tmp_path / "whole" / "arms" / arm / name
            ).read_text()
        assert summary_results(tmp_path / "s" / "arms" / arm / "summary.json") == summary_results(
            tmp_path / "whole" / "arms" / arm / "summary.json"
        )
    assert json.loads((tmp_path / "s" / "study.json").read_text())["runs"] == 3
    fewer = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q", "--runs", "2")
    assert fewer.returncode == 2
    assert "holds 3 runs per arm" in fewer.stderr


def test_a_growth_that_did_not_finish_is_finished_by_asking_for_its_runs(tmp_path: Path) -> None:
    """A growth stopped after some arms grew (killed, or one arm's checkpoint refused) leaves the
    study at its old count and those arms at the new one: the study says which count finishes it."""
    from gaitgram.evolution.rundir import RunDirectory

    study = write_study(tmp_path)
    small = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q", "--runs", "2")
    assert small.returncode == 0, small.stderr
    RunDirectory.open(tmp_path / "s" / "arms" / "plain").grow(3)  # as far as a stopped growth got
    again = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q", "--runs", "2")
    assert again.returncode == 2
    assert "arm 'plain' already has 3, from a growth that did not finish; give --runs 3" in again.stderr
    finished = gaitgram("study", str(study), "-o", str(tmp_path / "s"), "-q", "--runs", "3")
    assert finished.returncode == 0, finished.stderr
    assert json.loads((tmp_path / "s" / "study.json").read_text())["runs"] == 3


def write_arm(path: Path, runs: list[dict]) -> Path:
    """A finished two-generation arm written by hand: each run gives its best's walk component, the
    final population's mean walk and, optionally, a Pareto front or repertoire."""
    path.mkdir(parents=True)
    (path / "config.toml").write_text(f"generations = 1\npopulation = 4\nelite = 1\nruns = {len(runs)}\n")
    for index, run in enumerate(runs):
        directory = path / f"run-{index:03d}"
        directory.mkdir()
        row = {"best": 1.0, "average": 1.0, "invalid": 0, "evaluations": 4, **run.get("stats", {})}
        rows = [{"generation": generation, **row} for generation in range(2)]
        for generation, share in enumerate(run.get("walk_shares", ())):
            rows[generation]["mean_walk"] = share
        for generation, best in enumerate(run.get("bests", ())):
            rows[generation]["best"] = best
        (directory / "stats.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
        best = {"fitness": rows[-1]["best"], "status": "ok", "components": {"walk": run["best_walk"]}}
        (directory / "best.json").write_text(json.dumps(best))
        for name, key in (("front.json", "front"), ("archive.json", "elites")):
            if name in run:
                members = [{"fitness": 1.0, "components": {"walk": w}, "genome": [1, 2]} for w in run[name]]
                (directory / name).write_text(json.dumps({key: members}))
    return path


def test_walk_held_counts_what_each_strategy_hands_back(tmp_path: Path) -> None:
    from gaitgram.report.formats import csv_text, markdown
    from gaitgram.report.records import load_arm

    # A walk in the final population although the best is not one (as CMA-ES's runs end).
    population = write_arm(
        tmp_path / "population",
        [
            {"best_walk": 0.0, "stats": {"mean_walk": 0.25}},
            {"best_walk": 1.0, "stats": {"mean_walk": 0.5}},
            {"best_walk": 0.0, "stats": {"mean_walk": 0.0}},
        ],
    )
    # A front or repertoire decides, not the population beside it.
    front = write_arm(
        tmp_path / "front",
        [
            {"best_walk": 0.0, "stats": {"mean_walk": 0.0}, "front.json": [0.0, 1.0]},
            {"best_walk": 0.0, "stats": {"mean_walk": 0.5}, "front.json": [0.0, 0.0]},
        ],
    )
    archive = write_arm(
        tmp_path / "archive",
        [{"best_walk": 0.0, "stats": {"mean_walk": 0.0}, "archive.json": [0.0, 1.0, 0.0]}] * 2,
    )
    # Records that do not say (an older run, a backend without the walk criterion) read n/a, not 0.
    silent = write_arm(tmp_path / "silent", [{"best_walk": 1.0}])
    arms = {path.name: load_arm(path) for path in (population, front, archive, silent)}
    assert arms["population"].walk_rate == pytest.approx(1 / 3)
    assert arms["population"].walk_held_rate == pytest.approx(2 / 3)
    assert (arms["front"].walk_rate, arms["front"].walk_held_rate) == (0.0, 0.5)
    assert (arms["archive"].walk_rate, arms["archive"].walk_held_rate) == (0.0, 1.0)
    assert (arms["silent"].walk_rate, arms["silent"].walk_held_rate) == (1.0, None)
    report = build_report(list(arms.values()))
    table = markdown(report)
    assert "| walk rate [95 % CI] | walk held |" in table
    assert "| 33% [6%, 79%] | 67% |" in table
    assert "| 100% [21%, 100%] | n/a |" in table
    rows = csv_text(report).splitlines()
    assert rows[0].endswith("walk_rate,walk_rate_ci_low,walk_rate_ci_high,walk_held_rate")
    assert rows[-1].endswith(",1.0,0.20654931437723745,1.0,")
    assert [a["walk_held_rate"] for a in report.as_json()["arms"]] == [pytest.approx(2 / 3), 0.5, 1.0, None]


def test_the_first_walk_is_the_first_generation_whose_population_holds_one(tmp_path: Path) -> None:
    from gaitgram.report.records import load_arm
    from gaitgram.report.sections import first_walk_section

    early = write_arm(
        tmp_path / "early",
        [{"best_walk": 1.0, "walk_shares": [0.25, 0.5]}, {"best_walk": 1.0, "walk_shares": [0.0, 0.25]}],
    )
    late = write_arm(tmp_path / "late", [{"best_walk": 0.0, "walk_shares": [0.0, 0.0]}] * 2)
    arms = [load_arm(early), load_arm(late)]
    assert [r.first_walk for r in arms[0].runs] == [0, 1]
    assert [r.first_walk for r in arms[1].runs] == [None, None]
    section = first_walk_section(arms)
    assert section is not None
    (table,) = section.tables
    assert table.rows == (("early", 2, 2, 0.5, 0, 1), ("late", 2, 0, None, None, None))
    (pair,) = section.tests[0].comparison.pairs
    assert pair.a12 == 1.0  # every early run found one sooner than every late run (which never did)
    # Records that do not say (a backend without a walk criterion): no section, not "never".
    silent = write_arm(tmp_path / "silent", [{"best_walk": 1.0}])
    assert first_walk_section([arms[0], load_arm(silent)]) is None


def test_a_generation_with_no_viable_gait_holds_no_walk(tmp_path: Path) -> None:
    """A generation whose every gait is unviable records no means (none could be measured): it
    holds no walk, so the run's first walk is still known; a generation that lacks the mean with
    viable gaits in it does not say, and the section is left out."""
    from gaitgram.report.records import load_arm
    from gaitgram.report.sections import first_walk_section

    path = write_arm(
        tmp_path / "a",
        [{"best_walk": 1.0, "walk_shares": [0.0, 0.5]}, {"best_walk": 1.0, "walk_shares": [0.25, 0.5]}],
    )
    stats = path / "run-000" / "stats.jsonl"
    rows = [json.loads(line) for line in stats.read_text().splitlines()]
    del rows[0]["mean_walk"]

    def write(invalid: int) -> None:
        rows[0]["invalid"] = invalid
        stats.write_text("".join(json.dumps(r) + "\n" for r in rows))

    write(invalid=rows[0]["evaluations"])
    # A later generation evaluates only its new gaits (population less the elite), all unviable.
    later = path / "run-001" / "stats.jsonl"
    second = [json.loads(line) for line in later.read_text().splitlines()]
    del second[1]["mean_walk"]
    second[1].update(evaluations=3, invalid=4)
    later.write_text("".join(json.dumps(r) + "\n" for r in second))
    arm = load_arm(path)
    assert [r.first_walk for r in arm.runs] == [1, 0]
    assert arm.runs[1].walk_share.tolist() == [0.25, 0.0]
    assert first_walk_section([arm]) is not None
    write(invalid=1)
    arm = load_arm(path)
    assert arm.runs[0].walk_share is None
    assert first_walk_section([arm]) is None


def test_where_the_runs_started_is_each_runs_first_generation_best(tmp_path: Path) -> None:
    from gaitgram.report.records import load_arm
    from gaitgram.report.sections import start_section

    def runs(*bests: list[float]) -> list[dict]:
        return [{"best_walk": 1.0, "bests": b} for b in bests]

    started = write_arm(tmp_path / "started", runs([0.3, 0.2], [0.5, 0.4]))
    scratch = write_arm(tmp_path / "scratch", runs([0.9, 0.6], [0.7, 0.5]))
    section = start_section([load_arm(started), load_arm(scratch)])
    (table,) = section.tables
    assert [row[0] for row in table.rows] == ["started", "scratch"]
    assert [row[2][0] for row in table.rows] == pytest.approx([0.4, 0.8])  # the first generation's medians
    assert [row[3][0] for row in table.rows] == pytest.approx([0.3, 0.55])  # and the last's
    (pair,) = section.tests[0].comparison.pairs
    assert pair.a12 == 1.0  # every started run began below every scratch run


def test_an_unreadable_front_is_a_report_error(tmp_path: Path) -> None:
    from gaitgram.report.records import ReportError, load_arm

    arm = write_arm(tmp_path / "arm", [{"best_walk": 0.0, "front.json": [1.0]}])
    for broken, problem in [
        ('{"front": 3}', "malformed"),
        ('{"front": [3]}', "malformed"),
        ("[]", "not a record"),
        ("{", "malformed \\(not JSON"),
        ('{"front": [{"fitness": 1, "components": {"walk": "yes"}, "genome": [1]}]}', "malformed"),
    ]:
        (arm / "run-000" / "front.json").write_text(broken)
        with pytest.raises(ReportError, match=rf"run-000.*{problem}"):
            load_arm(arm)


def test_a_front_that_is_the_whole_population_is_called_out() -> None:
    from gaitgram.report.sections import saturation as _saturation

    assert _saturation([70, 74], 75) == ""
    note = _saturation([75, 60, 75], 75)
    assert note.startswith(". In 2 of 3 runs the final front is the whole population (75)")
    assert "fewer objectives" in note
