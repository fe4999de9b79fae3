"""What the trial's turf breaks in the open loop's best gaits: which walk terms fail on each bump
floor, and how far their footfalls sit from the real walk's, flat and on turf.

The measurements behind docs/fitness.md's "Margins" and the balance README's reading of it. On the
committed strategies study's 30 best GE-hybrid gaits (docs/results/strategies/runs, open loop):

1. **Footfalls**: each gait played over the horizon on the flat floor and on the trial's first
   three test floors, its last five cycles measured: the largest |footfall phase - the real
   walk's| (walk criterion v2 allows 0.10), and each hoof's mean offset, medians over gaits.
2. **Terms lost on the ten floors**: each gait, as evolved and with its hip and shoulder curves
   scaled by 1.03 and 1.05 (a longer stride everywhere, as ``speed_feedback`` plays them), on each
   of the trial's ten bump floors: of the 300 plays, how many lose the walk, on which terms (a
   play may lose several), and how many on the speed term alone.

``--arm DIR`` measures another arm's best gaits instead (the balance-margins study's, say).
Not a speed benchmark: a reproducible measurement. About 10 minutes on 2 cores.
"""

from __future__ import annotations

import collections
import json
from pathlib import Path

import numpy as np

from benchmarks.bench_speed_feedback import ARM, FLOORS, PLACED, turf_table
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.measures import HOOVES, measure_cycles
from gaitgram.backends.mujoco_horse.model import bumpy_model
from gaitgram.backends.mujoco_horse.reference import NOT_WALKING
from gaitgram.backends.mujoco_horse.robustness import BUMP_SEEDS, RECOVERY_CYCLES, on_floor
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.backends.mujoco_horse.targets import WALK_FOOTFALLS
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.motion.gait import MotionBatch

SCALES = (1.0, 1.03, 1.05)


def main(argv: list[str] | None = None) -> None:
    arm = Path(argv[argv.index("--arm") + 1]) if argv and "--arm" in argv else ARM
    pipeline = RunDirectory.open(arm).pipeline
    genomes = [
        tuple(json.loads((arm / f"run-{run:03d}" / "best.json").read_text())["genome"])
        for run in range(pipeline.config.runs)
    ]
    mapped = pipeline.map(genomes)
    generation = pipeline.config.generations
    settings = dict(pipeline.config.backend_settings)
    horse = HorseSettings.from_mapping(settings)
    batches = {}
    for scale in SCALES:
        joints = [
            {j: f"({text})*{scale}" if j in PLACED and scale != 1.0 else text for j, text in m.joints.items()}
            for m in mapped
        ]
        batches[scale] = pipeline.motion(
            [m._replace(joints=j) for m, j in zip(mapped, joints, strict=True)], generation
        )
    print(f"the best gaits of {arm}")
    _footfalls(horse, batches[1.0])
    print()
    turf_table(settings, batches[1.0])
    print()
    print(
        f"GE-hybrid's {len(genomes)} best gaits on the trial's {len(BUMP_SEEDS)} bump floors: "
        "plays that lose the walk"
    )
    print(f"{'curves':22} {'lost':>8} {'speed alone':>11}  terms failed (a play may fail several)")
    for scale, batch in batches.items():
        terms: collections.Counter[str] = collections.Counter()
        lost = alone = 0
        for seed in BUMP_SEEDS:
            for trial in on_floor(settings, batch, seed):
                if trial.holds:
                    continue
                lost += 1
                failed = _failed_terms(trial.detail)
                terms.update(failed)
                alone += failed == ["speed"]
        label = "as evolved" if scale == 1.0 else f"hip, shoulder x {scale}"
        plays = len(batch) * len(BUMP_SEEDS)
        shown = ", ".join(f"{name} {count}" for name, count in terms.most_common())
        print(f"{label:22} {lost:>4}/{plays} {alone:>11}  {shown}")


def _failed_terms(detail: str | None) -> list[str]:
    """The walk terms a play failed, from its detail ("not walking again: speed, footfalls"); a
    gait that fell is "fell"."""
    if detail is None or not detail.startswith(NOT_WALKING):
        return ["fell"]
    return [term.strip() for term in detail.removeprefix(NOT_WALKING).split(",")]


def _footfalls(horse: HorseSettings, batch: MotionBatch) -> None:
    expected = np.array([0.0, *(WALK_FOOTFALLS[hoof] for hoof in HOOVES[1:])])
    rows = np.arange(len(batch))
    print(
        f"GE-hybrid's {len(batch)} best gaits: footfalls over the last {RECOVERY_CYCLES} cycles "
        "(medians over gaits)"
    )
    offsets = " ".join(f"{hoof:>10}" for hoof in HOOVES[1:])
    print(f"{'floor':10} {'worst |error|':>13} {'over 0.10':>9}   mean offset: {offsets}")
    for label, model in [("flat", None), *((f"bumps {s}", bumpy_model(horse.body, s, 1.0)) for s in FLOORS)]:
        evaluator = HorseEvaluator(horse, model=model)
        try:
            horizon = evaluator.horizon
            state, sensors, control = evaluator.play(batch, rows, horizon)
            frequencies = evaluator.frequencies(batch, rows)
            scored = evaluator.score(state, sensors, control, {}, frequencies, horizon)
            recordings = evaluator.recordings(state, sensors, control, frequencies)
            phases = [
                measure_cycles(r, horizon - RECOVERY_CYCLES, horizon, evaluator.gap_steps).phases - expected
                for e, r in zip(scored, recordings, strict=True)
                if e.status.viable
            ]
        finally:
            evaluator.close()
        worst = np.array([np.nanmax(np.abs(p)) for p in phases])
        mean = np.median([np.nanmean(p, axis=0) for p in phases], axis=0)
        shown = " ".join(f"{m:>+10.3f}" for m in mean[1:])
        print(
            f"{label:10} {np.median(worst):13.3f} {int((worst > 0.10).sum()):>4} of {len(worst)}"
            f"   {'':13}{shown}"
        )
