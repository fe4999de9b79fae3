"""The committed studies under docs/results (issue 26): each current report has its README and
its page, and its summary.json says what scored the runs and which walk criterion counted them,
both this code's. Superseded revisions live under docs/results/revision-N, marked so."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import ROOT
from gaitgram.backends.mujoco_horse.targets import TASK_REVISION, WALK_CRITERION
from gaitgram.report.assess import FORMAT
from gaitgram.runlayout import ASSESSMENT, BEST_WALK

RESULTS = ROOT / "docs" / "results"
CURRENT = sorted(
    path.parent for path in RESULTS.glob("*/summary.json") if not path.parent.name.startswith("revision-")
)


def test_the_current_studies_are_there() -> None:
    assert {"strategies", "table4", "table5"} <= {study.name for study in CURRENT}


@pytest.mark.parametrize("study", CURRENT, ids=lambda study: study.name)
def test_a_current_report_says_what_scored_it_and_how_walks_were_counted(study: Path) -> None:
    assert (study / "README.md").is_file()
    assert (study / "report.html").is_file()
    summary = json.loads((study / "summary.json").read_text(encoding="utf-8"))
    assert summary["backend"] == "mujoco-horse"
    assert f"fitness r{TASK_REVISION}," in summary["backend_version"]
    assert summary["verdict"]["version"] == WALK_CRITERION


@pytest.mark.parametrize("study", CURRENT, ids=lambda study: study.name)
def test_a_current_report_measured_its_gaits_as_this_code_does(study: Path) -> None:
    kept = list(study.rglob(ASSESSMENT)) + list(study.rglob(BEST_WALK))
    assert kept, "no kept assessments: made without --assess"
    stale = [str(p.relative_to(study)) for p in kept if json.loads(p.read_text())["format"] != FORMAT]
    assert not stale, f"assessed by another code: {stale[:3]}; gaitgram report --assess"
    header = (study / "robustness-shares.csv").read_text(encoding="utf-8").splitlines()[0]
    assert "floors_held_bumps" in header.split(",")  # the bumps are ten floors


@pytest.mark.parametrize("study", CURRENT, ids=lambda study: study.name)
def test_a_readme_s_longer_check_of_its_best_walks_is_kept_and_holds(study: Path) -> None:
    """Where a README re-scores each arm's best walk over 40 cycles into best-walks-40-cycles.jsonl
    (``evaluate --walk --horizon 40 --json``), the file is there, one record per arm, each still a
    walk over the 40 cycles with the fitness its run recorded (issue 26: a longer horizon keeps a
    committed best walk a walk)."""
    kept = study / "best-walks-40-cycles.jsonl"
    if "best-walks-40-cycles.jsonl" not in (study / "README.md").read_text(encoding="utf-8"):
        assert not kept.exists()
        return
    records = [json.loads(line) for line in kept.read_text(encoding="utf-8").splitlines()]
    arms = {record["gait"].split(" run ")[0] for record in records}
    assert len(arms) == len(records) >= 1
    reported = {arm["name"] for arm in json.loads((study / "summary.json").read_text())["arms"]}
    assert {Path(arm).name for arm in arms} <= reported, "a record of an arm the report does not show"
    for record in records:
        assert record["horizon"] == 40
        assert record["status"] == "ok", record["gait"]
        assert record["components"]["walk"] == 1.0, record["gait"]
        assert record["components"]["checked_cycles"] == 40.0
        assert record["fitness"] == record["recorded_fitness"]
