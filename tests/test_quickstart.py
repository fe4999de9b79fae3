"""The README's quickstart, as written: its best gait stays upright over the whole horizon, and
every frame its render shows has the horse up."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.evolution.checkpoint import load_checkpoint
from gaitgram.evolution.rundir import RunDirectory

ROOT = Path(__file__).resolve().parents[1]
runner = CliRunner()


def quickstart_evolve() -> list[str]:
    """The ``gaitgram evolve`` arguments of the README's quickstart command."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    command = re.search(r"\.venv/bin/gaitgram (evolve [^&]+?) &&", readme)
    assert command, "the README's quickstart runs no `gaitgram evolve`"
    return shlex.split(command[1])


@pytest.mark.slow
def test_the_quickstarts_best_gait_stays_up_over_the_horizon(tmp_path: Path) -> None:
    args = quickstart_evolve()
    out = args.index("-o")
    args[out + 1] = str(tmp_path / "quickstart")
    result = runner.invoke(app, [*args, "-q"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    directory = RunDirectory.open(tmp_path / "quickstart")
    state = load_checkpoint(
        directory.checkpoints[0],
        directory.pipeline,
        fingerprint=directory.fingerprints,
        run=0,
        with_memory=False,
    )
    best = state.best.evaluation
    assert best.status.viable, best.detail
    assert best.components["checked_cycles"] == 20.0  # upright for the whole horizon
    # What `render` plays: the warm-up and scored cycles, through the control loop; the trunk stays up
    # (over 90 % of its standing height, within 30 degrees of level) in every step, so in every frame.
    pipeline = directory.pipeline
    evaluator = pipeline.load_evaluator()
    try:
        batch = pipeline.motion(pipeline.map([state.best.genome]), state.generation)
        states, sensors, control = evaluator.play(batch, np.array([0]))
        frequencies = evaluator.frequencies(batch, np.array([0]))
        (recording,) = evaluator.recordings(states, sensors, control, frequencies)
    finally:
        evaluator.close()
    assert recording.trunk_z.min() > 0.9 * evaluator.layout.standing_height
    assert np.abs(recording.pitch).max() < 30
