"""The realism and robustness sections of a report on the horse, from real runs: ``gaitgram report
--assess`` measures each run's best gait once (kept in the run directory), every report reads it.

Two short arms are run here (GE and random search on the hybrid grammar under the paper's weights;
GE's seed 0 hands back a walk, so its best walk is animated), reported with ``--assess --gaits 1``
and opened in Debian's Chromium.
"""

from __future__ import annotations

import csv
import io
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image
from study.browser import Opened, chromium
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.cli import app
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError, best_walk_of_runs
from gaitgram.report import assess as assess_module
from gaitgram.report.assess import assess_arm, best_walk_path
from gaitgram.runlayout import ASSESSMENT, BEST_WALK

runner = CliRunner()
PAPER_WEIGHTS = (
    'backend = "mujoco-horse"\n[backend_settings]\n'
    "weights = { velocity = 1.0, duty_factor = 1.0, stride = 1.0, frequency = 0.0, energy = 1.0 }\n"
)
ARMS = {"ge": ("ge", 0), "random": ("random", 4)}
TEXT = ("summary.md", "summary.csv", "tables.tex", "summary.json", "realism-measures.csv")


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two arms of two runs each, reported with --assess --gaits 1 (in ``made / "report"``)."""
    base = tmp_path_factory.mktemp("realism")
    (base / "paper.toml").write_text(PAPER_WEIGHTS)
    for name, (strategy, seed) in ARMS.items():
        result = runner.invoke(
            app,
            [
                "evolve",
                str(GRAMMARS / "hybrid.gg"),
                "-c",
                str(base / "paper.toml"),
                *("--generations", "2", "--population", "16", "--runs", "2", "--seed", str(seed)),
                *("--strategy", strategy, "-o", str(base / name), "-q"),
            ],
        )
        assert result.exit_code == 0, result.output
    # in a process of its own: the GIF needs MuJoCo's offscreen OpenGL chosen before MuJoCo loads
    report = [*(str(base / n) for n in ARMS), "-o", str(base / "report"), "--assess", "--gaits", "1"]
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    done = subprocess.run(
        [sys.executable, "-m", "gaitgram", "report", *report], capture_output=True, text=True, env=env
    )
    assert done.returncode == 0, done.stderr
    assert "measuring the best gaits of 2 run(s)" in done.stderr
    return base


def kept(arm: Path) -> list[dict[str, Any]]:
    return [json.loads((arm / f"run-{r:03d}" / ASSESSMENT).read_text()) for r in range(2)]


def rows(path: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(path.read_text())))


@pytest.mark.slow
def test_each_run_s_best_gait_is_measured_as_the_backend_measures_it(made: Path) -> None:
    from gaitgram.backends.mujoco_horse.realism import assess
    from gaitgram.backends.mujoco_horse.robustness import BUMP_SEEDS, disturbed

    for name in ARMS:
        for run, record in enumerate(kept(made / name)):
            best = json.loads((made / name / f"run-{run:03d}" / "best.json").read_text())
            assert record["genome"] == best["genome"]
            assert record["fitness"] == best["fitness"]
            assert record["gait"] in ("measured", "falls")
            assert [t["disturbance"] for t in record["trials"]] == ["push-forward", "push-backward", "bumps"]
            assert [t["floors"] for t in record["trials"]] == [1, 1, len(BUMP_SEEDS)]
            for t in record["trials"]:
                assert 0 <= t["held"] <= t["floors"]
                assert (t["held"] == t["floors"]) == (t["upright"] and t["walking"])
    # the walk the report animates is measured too, from wherever in the runs it comes
    directory = RunDirectory.open(made / "ge")
    walk = json.loads((made / "ge" / BEST_WALK).read_text())
    assert walk["genome"] == list(best_walk_of_runs(directory).genome)
    assert walk["gait"] == "measured"
    # recomputed independently through the backend's own functions, for one gait
    pipeline = directory.pipeline
    record = kept(made / "ge")[0]
    batch = pipeline.motion(pipeline.map([tuple(record["genome"])]), pipeline.config.generations)
    settings = dict(pipeline.config.backend_settings)
    (realism,) = assess(settings, batch)
    assert realism is not None
    assert record["realism"]["distance"] == pytest.approx(realism.distance, rel=1e-12)
    assert record["realism"]["scores"] == pytest.approx(realism.scores, rel=1e-12)
    assert record["realism"]["measures"]["duty_factor"] == pytest.approx(realism.measures["duty_factor"])
    for name in ("push-backward", "bumps"):
        (trial,) = disturbed(settings, batch, name)
        kept_trial = next(t for t in record["trials"] if t["disturbance"] == name)
        assert (kept_trial["upright"], kept_trial["walking"], kept_trial["detail"], kept_trial["held"]) == (
            trial.upright,
            trial.walking,
            trial.detail,
            trial.held,
        )


@pytest.mark.slow
def test_a_report_animates_and_measures_a_walk_of_a_finished_run_only(made: Path, tmp_path: Path) -> None:
    """A study still running is reported over its finished runs: its best walk is one of theirs,
    not a walk an unfinished run holds at the moment (``report --watch``)."""
    from dataclasses import replace

    from gaitgram.evolution.checkpoint import load_checkpoint, save_checkpoint

    arm = Path(shutil.copytree(made / "ge", tmp_path / "ge"))
    directory = RunDirectory.open(arm)
    walk = best_walk_of_runs(directory)
    assert best_walk_of_runs(directory, finished_only=True) == walk  # every run has finished
    checkpoint = arm / f"run-{walk.run:03d}" / "checkpoint.json"
    state = load_checkpoint(checkpoint, directory.pipeline, fingerprint=directory.fingerprint, run=walk.run)
    unfinished = replace(state, generation=state.generation - 1, history=state.history[:-1])
    save_checkpoint(checkpoint, unfinished, fingerprint=directory.fingerprint, run=walk.run)
    assert best_walk_of_runs(directory).run == walk.run  # what the run holds now, finished or not
    try:
        other: int | None = best_walk_of_runs(directory, finished_only=True).run
    except RunDirectoryError:  # the other run holds no walk
        other = None
    assert other != walk.run


@pytest.mark.slow
def test_the_sections_show_what_the_runs_keep(made: Path) -> None:
    out = made / "report"
    summary = (out / "summary.md").read_text()
    assert "**Gaits held against real horses** (each run's best gait):" in summary
    assert "**Robust, not only sustained** (each run's best gait):" in summary
    assert " 0 fell" not in summary  # a note names only the failures there were
    assert " 0 stayed up" not in summary
    assert "**realism distance**: Kruskal-Wallis H =" in summary
    distances = {
        name: [r["realism"]["distance"] for r in kept(made / name) if r["gait"] == "measured"]
        for name in ARMS
    }
    for row in rows(out / "realism-distance.csv"):
        values = distances[row["arm"]]
        assert int(row["measured"]) == len(values)
        assert float(row["median_distance"]) == pytest.approx(np.median(values))
        assert float(row["best_distance"]) == pytest.approx(min(values))
    for row in rows(out / "robustness-shares.csv"):
        records = kept(made / row["arm"])
        holds = [all(t["upright"] and t["walking"] for t in r["trials"]) for r in records]
        assert float(row["holds_all"]) == pytest.approx(sum(holds) / len(records))
        bumps = [next(t for t in r["trials"] if t["disturbance"] == "bumps") for r in records]
        assert float(row["holds_bumps"]) == pytest.approx(
            sum(t["upright"] and t["walking"] for t in bumps) / 2
        )
        assert float(row["floors_held_bumps"]) == pytest.approx(
            sum(t["held"] / t["floors"] for t in bumps) / 2
        )
    measures = {r["measure"]: r for r in rows(out / "realism-measures.csv")}
    assert float(measures["duty factor"]["real"]) == 0.588  # DLC_Horse's median
    assert measures["duty factor"]["real_spread"] == "IQR 0.55 to 0.632"
    ge = [r["realism"]["measures"]["stride_frequency"] for r in kept(made / "ge") if r["gait"] == "measured"]
    assert float(measures["stride frequency (Hz)"]["ge"]) == pytest.approx(np.median(ge))
    data = json.loads((out / "summary.json").read_text())
    assert set(data["sections"]) == {
        *("start", "first-walk", "walk-rates", "spread", "realism", "robustness", "graded", "backend-usage")
    }
    for row in data["sections"]["graded"]["tables"]["graded-shares"]:  # recomputed from the assessments
        records = kept(made / row["arm"])
        assert row["measured"] == len(records)
        for trial in records[0]["graded"]:
            key = f"holds_{trial['family']}_{trial['size']}"
            held = [
                next(t for t in r["graded"] if (t["family"], t["size"]) == (trial["family"], trial["size"]))
                for r in records
            ]
            best = [
                json.loads((made / row["arm"] / f"run-{r:03d}" / "best.json").read_text()) for r in range(2)
            ]
            walks = [
                b["status"] == "ok" and b["components"]["walk"] == 1.0 for b in best
            ]  # handed back a walk
            share = sum(w and t["upright"] and t["walking"] for w, t in zip(walks, held, strict=True)) / 2
            assert row[key][0] == pytest.approx(share)
    for name in ARMS:  # why a gait that stayed up was not walking again, as its detail says
        stopped = [
            t["detail"]
            for r in kept(made / name)
            for t in r["trials"]
            if t["disturbance"] == "bumps" and t["upright"] and not t["walking"]
        ]
        if stopped:
            speed = sum("not walking again: " in d and "speed" in d.split("again: ")[1] for d in stopped)
            note = next(line for line in summary.splitlines() if line.startswith(f"- **{name}**"))
            assert "walk terms failing on the first floor not held: " in note
            assert (f"speed {speed}" in note) == (speed > 0)
    assert list(data["sections"]["realism"]["tests"]) == ["realism distance"]
    assert list(data["sections"]["robustness"]["tests"]) == ["bumps: share of floors not held"]
    assert (out / "realism.svg").read_text().count("<svg") == 1
    assert (out / "walk-ge.gif").exists()  # GE's seed 0 hands back a walk: animated, its curves beside
    assert (out / "curves-ge.png").read_bytes().startswith(b"\x89PNG")


@pytest.mark.slow
def test_a_report_reads_what_was_kept_and_simulates_nothing(
    made: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def never(*_: object) -> None:
        raise AssertionError("simulated again")

    monkeypatch.setattr(assess_module, "measure", never)
    assert assess_arm(made / "ge") == []  # every run's best gait is measured already
    result = runner.invoke(
        app, ["report", *(str(made / n) for n in ARMS), "-o", str(tmp_path / "again"), "--assess"]
    )
    assert result.exit_code == 0, result.stderr
    for name in (*TEXT, "realism.svg"):
        assert (tmp_path / "again" / name).read_bytes() == (made / "report" / name).read_bytes(), name


@pytest.mark.slow
def test_a_stale_or_missing_assessment_is_said_and_a_damaged_one_refused(made: Path, tmp_path: Path) -> None:
    arm = Path(shutil.copytree(made / "ge", tmp_path / "ge"))
    record = json.loads((arm / "run-001" / ASSESSMENT).read_text())
    record["genome"] = [*record["genome"], 1]  # another gait's
    (arm / "run-001" / ASSESSMENT).write_text(json.dumps(record))
    result = runner.invoke(app, ["report", str(arm), "-o", str(tmp_path / "stale")])
    assert result.exit_code == 0, result.stderr
    summary = (tmp_path / "stale" / "summary.md").read_text()
    assert "of 2 runs' best gaits, 1 measured on another gait or scoring (stale)" in summary
    (row,) = rows(tmp_path / "stale" / "realism-distance.csv")
    assert int(row["measured"]) == (kept(made / "ge")[0]["gait"] == "measured")

    for run in range(2):
        (arm / f"run-{run:03d}" / ASSESSMENT).unlink()
    result = runner.invoke(app, ["report", str(arm), "-o", str(tmp_path / "none")])
    assert result.exit_code == 0, result.stderr
    summary = (tmp_path / "none" / "summary.md").read_text()
    assert "**Gaits held against real horses** (each run's best gait):\n\nNot measured yet." in summary
    assert "of 2 runs' best gaits, 2 not measured yet" in summary
    assert not list((tmp_path / "none").glob("realism*"))

    record = json.loads((made / "ge" / "run-000" / ASSESSMENT).read_text())
    bumps = next(t for t in record["trials"] if t["disturbance"] == "bumps")
    bumps["held"] = bumps["floors"] + 1  # held on more floors than it was played on
    (arm / "run-000" / ASSESSMENT).write_text(json.dumps(record))
    result = runner.invoke(app, ["report", str(arm), "-o", str(tmp_path / "overheld")])
    assert result.exit_code == 2
    assert "floors and held" in result.stderr
    assert not (tmp_path / "overheld").exists()

    (arm / "run-000" / ASSESSMENT).write_text('{"format": 1')
    result = runner.invoke(app, ["report", str(arm), "-o", str(tmp_path / "damaged")])
    assert result.exit_code == 2
    assert str(arm / "run-000" / ASSESSMENT) in result.stderr
    assert f"gaitgram report --assess {arm}" in result.stderr
    assert not (tmp_path / "damaged").exists()


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    with chromium() as launched:
        yield launched


@pytest.mark.slow
def test_chromium_shows_the_sections_and_the_animated_walk_beside_the_real_walks(
    browser: Any, made: Path, tmp_path: Path
) -> None:
    opened = Opened(browser, made / "report" / "report.html")
    page = opened.page
    assert opened.errors == []
    assert opened.requests == [(made / "report" / "report.html").as_uri()]
    (tmp_path / "report.png").write_bytes(page.screenshot(full_page=True))
    assert opened.column("realism-distance", 0) == ["ge", "random"]
    assert len(opened.column("realism-measures", 0)) == 19
    assert opened.column("robustness-shares", 0) == ["ge", "random"]
    assert page.locator("#realism h3", has_text="Rank tests: realism distance").count() == 1
    images = {i["id"]: i for i in opened.images()}
    assert images["realism"]["kind"] == "image/svg+xml"
    assert images["walk-ge"]["kind"] == "image/gif"
    assert images["curves-ge"]["kind"] == "image/png"
    assert all(i["complete"] and i["width"] > 0 for i in images.values()), images
    gif = page.eval_on_selector("#walk-ge img", "i => i.src")
    import base64

    animation = Image.open(io.BytesIO(base64.b64decode(gif.split(",", 1)[1])))
    assert animation.n_frames > 10  # it moves
    walk, curves = (page.locator(f"#{name}").bounding_box() for name in ("walk-ge", "curves-ge"))
    assert walk is not None
    assert curves is not None
    assert curves["x"] >= walk["x"] + walk["width"]  # side by side
    assert abs(curves["y"] - walk["y"]) < 1
    caption = page.locator("#curves-ge figcaption").text_content()
    assert caption is not None
    assert "thick: the walk beside" in caption  # the animated walk's own curves, measured
    header = page.locator("#realism-distance th", has_text="median distance")
    header.click()
    medians = [float(v.split(" ")[0]) for v in opened.column("realism-distance", 4)]
    assert medians == sorted(medians)
    assert opened.errors == []


@pytest.mark.slow
def test_a_report_over_the_first_runs_measures_their_best_walk_apart(
    made: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``report --assess --runs 1``: run 1 is not measured, and the best walk of run 0 alone is kept
    beside, not over, the arm's best walk."""
    arm = Path(shutil.copytree(made / "ge", tmp_path / "ge"))
    (arm / "run-001" / ASSESSMENT).unlink()
    whole = (arm / BEST_WALK).read_bytes()
    asked: list[int] = []

    def recorded(settings: dict[str, Any], batch: Any, *_: object) -> list[dict[str, Any]]:
        asked.append(len(batch))
        return [{"gait": "falls", "detail": None, "realism": None, "trials": []}] * len(batch)

    monkeypatch.setattr(assess_module, "measure", recorded)
    directory = RunDirectory.open(arm)
    try:
        first = best_walk_of_runs(directory, runs=[0])
    except RunDirectoryError:  # run 0 hands back no walk: nothing to measure
        first = None
    written = assess_arm(arm, window=1)
    assert not (arm / "run-001" / ASSESSMENT).exists()
    assert (arm / BEST_WALK).read_bytes() == whole
    if first is None:
        assert written == []
        assert asked == []
        return
    assert written == [best_walk_path(arm, 1)] == [arm / "best-walk-assessment-first-1.json"]
    assert asked == [1]
    kept_walk = json.loads(written[0].read_text())
    assert (kept_walk["run"], kept_walk["genome"]) == (0, list(first.genome))


def test_the_terms_a_disturbed_gait_failed_are_counted_from_its_detail() -> None:
    from gaitgram.backends.registry import get_backend
    from gaitgram.report.realism_robustness import Trial, _failing_terms

    declared = get_backend("mujoco-horse").assessment
    assert declared is not None
    words = declared().failed_terms  # the words the horse's trials write before the failed terms

    def trial(detail: str | None) -> Trial:
        return Trial("bumps", "", True, False, detail, 10, 3)

    trials = [
        trial("held on 3 of 10 floors; on seed 26: not walking again: speed, footfalls"),
        trial("held on 0 of 10 floors; on seed 26: not walking again: speed"),
        trial("held on 9 of 10 floors; on seed 31: not walking again: stride_length, speed"),
        trial("something else entirely"),
        trial(None),
    ]
    assert _failing_terms(trials, words) == "speed 3, footfalls 1, stride_length 1"
    assert _failing_terms(trials, "") == ""  # a backend that declares no such words: nothing counted
    assert _failing_terms([], words) == ""
