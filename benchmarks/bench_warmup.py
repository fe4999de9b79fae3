"""The measurement behind the default warm-up: from rest, when does a gait's speed stop changing?

Plays the bundled seed and the best gaits of the committed strategies study (runs 0, 3, ..., 27
of its four arms; their genomes and grammars only, re-played on today's model) from the standing
horse for 30 of their own cycles after the ramp, and reports per gait the first cycle after which
every cycle's speed is within 2 % of the cruising speed (the median of the last 10), in cycles and
in seconds after the ramp, and whether the default warm-up (whole cycles of at least 1.5 s, at
least 2) starts the scored cycles after it. Not a speed benchmark: a reproducible measurement
(docs/fitness.md, "Warm-up, from measurement").
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, HorseSettings
from gaitgram.backends.mujoco_horse.measures import measure_cycles
from gaitgram.backends.mujoco_horse.settings import DEFAULT_WARMUP_SECONDS, warmup_cycles
from gaitgram.configuration import config_from_mapping, read_toml
from gaitgram.evolution.rundir import build_pipeline
from gaitgram.language.source import decode_source
from gaitgram.motion.gait import MotionBatch
from gaitgram.seed import load_seed

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "docs" / "results" / "revision-3" / "strategies" / "runs" / "arms"
CYCLES = 30
WITHIN = 0.02


def best_gaits() -> list[tuple[str, MotionBatch]]:
    """The seed, then the committed study's best gaits, each as a one-gait batch (the runs'
    grammars and codons through today's pipeline)."""
    found = [("walk seed", load_seed().motion_batch())]
    if not STUDY.is_dir():
        return found
    for arm in sorted(STUDY.iterdir()):
        config = read_toml(arm / "config.toml")
        config["backend_settings"] = {}  # today's settings: the gaits, not the old fitness
        pipeline = build_pipeline(
            decode_source((arm / "grammar.gg").read_bytes(), str(arm / "grammar.gg")),
            json.loads((arm / "manifest.json").read_text())["defines"],
            config_from_mapping(config, str(arm / "config.toml")),
        )
        for run in range(0, 30, 3):
            path = arm / f"run-{run:03d}" / "checkpoint.json"
            if not path.exists():
                continue
            checkpoint = json.loads(path.read_text())["checkpoint"]
            best = min(checkpoint["population"], key=lambda p: p["evaluation"]["fitness"])
            batch = pipeline.motion(pipeline.map([best["genome"]]), checkpoint["generation"])
            if batch.problems[0] is None:
                found.append((f"{arm.name} run {run}", batch))
    return found


def main() -> None:
    evaluator = HorseEvaluator(HorseSettings(threads=os.cpu_count() or 1, horizon_cycles=CYCLES + 1))
    print(
        f"per gait: the first cycle after which every speed is within {WITHIN:.0%} of the cruising speed "
        f"(median of the last 10 of {CYCLES} cycles), counted after the 0.5 s ramp; the warm-up "
        f"(whole cycles of at least {DEFAULT_WARMUP_SECONDS} s, at least 2) covers it or not"
    )
    print(f"{'gait':<28} {'Hz':>5} {'cruise m/s':>10} {'settled':>8} {'s':>6} {'warm-up':>8} {'covered':>8}")
    covered = total = 0
    try:
        for label, batch in best_gaits():
            frequency = float(evaluator.frequencies(batch, np.array([0]))[0])
            control = evaluator.controls(batch, np.array([0]), CYCLES)
            state, sensors = evaluator.simulate(control)
            (evaluation,) = evaluator.score(
                state, sensors, control, {"velocity": 1.0}, np.array([frequency]), CYCLES
            )
            if not evaluation.status.viable:
                print(f"{label:<28} {frequency:5.2f} {evaluation.status.value}: {evaluation.detail}")
                continue
            (recording,) = evaluator.recordings(state, sensors, control, np.array([frequency]))
            speeds = measure_cycles(recording, 0, CYCLES, evaluator.gap_steps).speed
            cruise = float(np.median(speeds[-10:]))
            off = np.abs(speeds / cruise - 1) > WITHIN
            settled = int(np.flatnonzero(off)[-1] + 1) if off.any() else 0
            warmup = warmup_cycles(DEFAULT_WARMUP_SECONDS, frequency)
            total += 1
            covered += warmup >= settled
            print(
                f"{label:<28} {frequency:5.2f} {cruise:10.3f} {settled:8d} {settled / frequency:6.2f} "
                f"{warmup:8d} {'yes' if warmup >= settled else 'no':>8}"
            )
    finally:
        evaluator.close()
    print(f"the default warm-up covers {covered} of {total} gaits")
