"""What the bump measurements share: a committed arm's runs' best gaits and the floors they held."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from gaitgram.evolution.rundir import RunDirectory
from gaitgram.motion.gait import MotionBatch


def kept_best_gaits(arm: Path) -> tuple[dict[str, Any], list[float], MotionBatch]:
    """The arm's backend settings, the share of the trial's bump floors each run's
    best gait held (its kept ``assessment.json``), and those gaits as one batch, in run order."""
    pipeline = RunDirectory.open(arm).pipeline
    kept, genomes = [], []
    for run in range(pipeline.config.runs):
        best = json.loads((arm / f"run-{run:03d}" / "best.json").read_text())
        trials = json.loads((arm / f"run-{run:03d}" / "assessment.json").read_text())["trials"]
        bumps = next(t for t in trials if t["disturbance"] == "bumps")
        kept.append(bumps["held"] / bumps["floors"])
        genomes.append(tuple(best["genome"]))
    batch = pipeline.motion(pipeline.map(genomes), pipeline.config.generations)
    return dict(pipeline.config.backend_settings), kept, batch
