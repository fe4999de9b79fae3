"""Every committed run under docs/results still opens, resumes and re-scores as it did, now that GE
is a representation plug-in (issue 41): its settings, written at the top level of each run's
config.toml, are read as GE's ``representation_settings``, and a run's fingerprint, checkpoints
and records are what they were, byte for byte.

The runs scored under an older fitness revision (``docs/results/revision-N``) are refused for that
reason alone (tests/cli/test_revisions.py), so they are left out here.
"""

from __future__ import annotations

import json
import shutil
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import ROOT
from gaitgram.cli import app
from gaitgram.evolution.checkpoint import load_checkpoint
from gaitgram.evolution.records import run_records
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.ge.registry import get_representation
from gaitgram.runlayout import CHECKPOINT, runs_in

RESULTS = ROOT / "docs" / "results"
#: Committed arms whose study was stopped before all its runs were made (their READMEs say so).
STOPPED_PART_WAY: set[str] = {"balance-stride/runs/arms/ge-hybrid-stride-margins"}
ARMS = sorted(
    path.parent
    for path in RESULTS.rglob("manifest.json")
    if not any(part.startswith("revision-") for part in path.relative_to(RESULTS).parts)
)
runner = CliRunner()
pytestmark = pytest.mark.skipif(
    not ARMS, reason="the committed study runs are not in this source tree (the sdist omits them)"
)


def test_the_committed_studies_are_all_here() -> None:
    studies = {arm.relative_to(RESULTS).parts[0] for arm in ARMS}
    assert {
        "table4",
        "table5",
        "strategies",
        "multi-objective",
        "retarget",
        "bump-floors",
        "balance-margins",
        "balance-margins-7",
        "balance-stride",
        "balance-margins-bumps",
        "balance-margins-bumps-4cm",
        "balance-cycle-stride",
    } <= studies


def _records_agree(directory: RunDirectory, runs: range) -> None:
    for run in runs:
        checkpoint = directory.checkpoints[run]
        state = load_checkpoint(
            checkpoint, directory.pipeline, fingerprint=directory.fingerprints, run=run, with_memory=False
        )
        for name, text in run_records(directory.pipeline, state).items():
            assert (checkpoint.parent / name).read_text(encoding="utf-8") == text, (
                f"{checkpoint.parent / name}"
            )


@pytest.mark.parametrize("arm", ARMS, ids=lambda arm: str(arm.relative_to(RESULTS)))
def test_a_committed_run_opens_as_its_representation_under_its_own_fingerprint(arm: Path) -> None:
    """Opened as the representation its config.toml names (GE where it names none: runs made
    before representations were plug-ins write GE's settings as top-level keys), with the
    settings it wrote, under the fingerprint its manifest holds; its first run's checkpoint read
    back and its records (``best.json`` with its derivation, statistics) derived from it to the
    byte."""
    written = tomllib.loads((arm / "config.toml").read_text(encoding="utf-8"))
    directory = RunDirectory.open(arm)
    assert json.loads((arm / "manifest.json").read_text())["fingerprint"] in directory.fingerprints
    name = written.get("representation", "ge")
    assert directory.config.representation == name
    keys = {setting.name for setting in get_representation(name).settings}
    table = written.get("representation_settings", {k: v for k, v in written.items() if k in keys})
    settings = directory.config.representation_settings
    assert {key: settings[key] for key in table} == table
    assert set(settings) == keys
    _records_agree(directory, range(1))


@pytest.mark.slow
@pytest.mark.parametrize("arm", ARMS, ids=lambda arm: str(arm.relative_to(RESULTS)))
def test_every_committed_checkpoint_and_record_reads_back_as_it_was(arm: Path) -> None:
    """Every run the arm holds, and as many as it plans unless its study was stopped part-way (as
    its README says): then its first runs and none after them."""
    directory = RunDirectory.open(arm)
    held = [run for run, path in runs_in(arm) if (path / CHECKPOINT).is_file()]
    assert held, arm
    assert held == list(range(len(held))), held
    if len(held) < directory.config.runs:
        assert arm.relative_to(RESULTS).as_posix() in STOPPED_PART_WAY, arm
    _records_agree(directory, held)


@pytest.mark.parametrize(
    ("arm", "flags"),
    [("table5/runs/arms/hybrid", []), ("multi-objective/runs/arms/map-elites-hybrid", ["--walk"])],
)
def test_evaluate_run_rescores_a_committed_best_exactly(arm: str, flags: list[str]) -> None:
    """``gaitgram evaluate --run`` maps the recorded genome through the run's own GE and plays it:
    the evaluation the run recorded, exactly (it exits 2 on any difference)."""
    result = runner.invoke(app, ["evaluate", "--run", str(RESULTS / arm), *flags, "--json"])
    assert result.exit_code == 0, result.output
    record = json.loads(result.stdout)
    assert record["fitness"] == record["recorded_fitness"]


def test_a_committed_study_arm_resumes_without_changing_a_byte(tmp_path: Path) -> None:
    """A finished committed arm, resumed: nothing to run, nothing rewritten."""
    copy = tmp_path / "none"
    shutil.copytree(RESULTS / "table4" / "runs" / "arms" / "none", copy)
    before = {p: p.read_bytes() for p in copy.rglob("run-*/*") if p.is_file()}
    result = runner.invoke(app, ["evolve", "--resume", str(copy), "-q"])
    assert result.exit_code == 0, result.output
    assert "rewrote" not in result.stderr
    assert {p: p.read_bytes() for p in before} == before
