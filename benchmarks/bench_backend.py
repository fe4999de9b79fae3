"""mujoco-horse throughput: evaluations/s of a 75-gait batch against raw ``mujoco.rollout``.

Both run the same model and the same control arrays in the same process; the
raw figure is the rollout alone (the ceiling), the backend figure includes
building the controls and computing metrics. Target: at least 90 % of raw.
"""

from __future__ import annotations

import os
import time

import numpy as np

from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, HorseSettings
from gaitgram.motion.gait import motion_batch


def random_batch(size: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    gaits = [
        {
            j: f"{rng.uniform(-8, 8):.2f}*sin(2*PI*t+{rng.uniform(0, 6.28):.2f})+{rng.uniform(-3, 3):.2f}"
            for j in CATALOGUE.names
        }
        for _ in range(size)
    ]
    return motion_batch(gaits, CATALOGUE.names)


def best_of(work, repeats: int = 3) -> float:
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        best = min(best, time.perf_counter() - start)
    return best


def main() -> None:
    batch = random_batch(75)
    threads = os.cpu_count() or 1
    evaluator = HorseEvaluator(HorseSettings(threads=threads))
    try:
        rows = np.arange(len(batch))
        control = evaluator.controls(batch, rows)
        raw = full = float("inf")
        for _ in range(5):  # interleaved, best of each: the machine's load drifts between runs
            raw = min(raw, best_of(lambda: evaluator.simulate(control), repeats=1))
            full = min(full, best_of(lambda: evaluator.evaluate(batch), repeats=1))
        steps = len(batch) * evaluator.nstep
        print(
            f"75 gaits x {evaluator.nstep} steps ({evaluator.nstep * evaluator.dt:.2f} s simulated each), "
            f"{threads} threads"
        )
        for label, seconds in (("raw mujoco.rollout", raw), ("mujoco-horse evaluate", full)):
            line = f"{label:<28} {len(batch) / seconds:8.1f} evaluations/s   {steps / seconds:10,.0f} steps/s"
            print(line + (f"   ratio {raw / full:5.1%} of raw" if seconds is full else ""))
    finally:
        evaluator.close()
