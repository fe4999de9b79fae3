"""On the real horse: a short run's walks stay walks when measured longer, and the best it hands
back stays upright over the horizon."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.backends.api import GaitStatus
from gaitgram.cli import app
from gaitgram.evolution.checkpoint import load_checkpoint
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.pipeline import Pipeline

runner = CliRunner()


@pytest.mark.slow  # a horse run, rescored over 30 cycles
def test_a_runs_walks_stay_walks_over_more_cycles_and_a_longer_horizon(tmp_path: Path) -> None:
    out = tmp_path / "run"
    made = runner.invoke(
        app,
        [
            "evolve",
            str(GRAMMARS / "hybrid.gg"),
            "--generations",
            "2",
            "--population",
            "16",
            "--seed",
            "2",
            "-o",
            str(out),
            "-q",
        ],
    )
    assert made.exit_code == 0, made.output
    directory = RunDirectory.open(out)
    pipeline = directory.pipeline
    verdict = pipeline.spec.verdict
    assert verdict is not None
    state = load_checkpoint(
        directory.checkpoints[0], pipeline, fingerprint=directory.fingerprints, run=0, with_memory=False
    )
    assert state.best.evaluation.components["checked_cycles"] == 20.0  # the best was checked
    walks = [i for i in state.population if verdict.holds(i.evaluation)]
    assert walks, "the hybrid grammar's seed walks, so a run keeps walks"
    settings = {**pipeline.config.backend_settings, "cycles": 6, "horizon_cycles": 30}
    longer = Pipeline.build(pipeline.checked, replace(pipeline.config, backend_settings=settings))
    evaluator = longer.load_evaluator()
    try:
        rescored = longer.verify([w.genome for w in walks], evaluator, state.generation)
    finally:
        evaluator.close()
    for before, after in zip(walks, rescored, strict=True):
        assert after.evaluation.status is GaitStatus.OK, after.evaluation.detail
        assert verdict.holds(after.evaluation), verdict.failed_terms(after.evaluation)
        assert after.evaluation.components["checked_cycles"] == 30.0
        assert len(after.evaluation.cycles["speed"]) == 6
        assert before.evaluation.components["walk"] == 1.0
