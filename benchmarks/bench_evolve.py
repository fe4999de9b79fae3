"""Where a Table-1 run's time goes, under fitness revision 4 and under revision 3's window.

GE on ``grammars/hybrid.gg`` (the paper's winner) with the paper's population of 75 and
elite 7, for a few generations, twice: with revision 4's evaluation (warm-up, 3 scored cycles,
the kept gaits checked over the 20-cycle horizon) and with revision 3's window (the ramp and 3
cycles, nothing checked). For each: the wall time per generation, the steps MuJoCo simulated, and
the wall time against a raw ``mujoco.rollout`` of as many steps (its rate measured in the same
process on the run's final population), so that what is not stepping MuJoCo shows. Targets:
revision 4 at most 1.5x revision 3's wall time; a run at most 1.1x the raw rollout of the steps it
simulates; under 5 % of the wall time outside the backend.
"""

from __future__ import annotations

import os
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from benchmarks.bench_backend import REVISION_3_WINDOW, raw_rollout
from gaitgram.analysis import check
from gaitgram.backends.api import Evaluation
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.evolution.config import RunConfig
from gaitgram.evolution.engine import run_evolution
from gaitgram.language import load
from gaitgram.motion.gait import MotionBatch
from gaitgram.pipeline import Pipeline

ROOT = Path(__file__).resolve().parents[1]
GENERATIONS = 6


class Timed:
    """Wraps the evaluator and adds up the time spent inside it, and the gaits it checked."""

    def __init__(self, inner: HorseEvaluator) -> None:
        self.inner = inner
        self.seconds = 0.0
        self.checked = 0

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        start = time.perf_counter()
        try:
            return self.inner.evaluate(batch, generation=generation, weights=weights)
        finally:
            self.seconds += time.perf_counter() - start

    def close(self) -> None:
        self.inner.close()


class Verifying(Timed):
    def verify(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        start = time.perf_counter()
        self.checked += len(batch)
        try:
            return self.inner.verify(batch, generation=generation, weights=weights)
        finally:
            self.seconds += time.perf_counter() - start


def run(settings: dict, verify: bool) -> tuple[float, float, int, float, int]:
    """Wall seconds, seconds inside the backend, steps simulated, raw rollout seconds for as many
    steps, and gaits checked over the horizon, for one run (revision 3 checked none: without
    ``verify`` the run trusts the evaluation)."""
    checked = check(load(ROOT / "grammars" / "hybrid.gg"))
    threads = os.cpu_count() or 1
    config = RunConfig(
        generations=GENERATIONS, population=75, seed=1, backend_settings={**settings, "threads": threads}
    )
    pipeline = Pipeline.build(checked, config)
    inner = pipeline.load_evaluator()
    assert isinstance(inner, HorseEvaluator)
    evaluator = Verifying(inner) if verify else Timed(inner)
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        state = run_evolution(pipeline, evaluator, 0, Path(tmp), fingerprint="bench")
        wall = time.perf_counter() - start
    batch = pipeline.motion(pipeline.map([i.genome for i in state.population]), state.generation)
    rows = np.array([g for g, problem in enumerate(batch.problems) if problem is None])
    steps, seconds = raw_rollout(inner, batch, rows)
    inner.close()
    raw = inner.simulated_steps * seconds / steps
    return wall, evaluator.seconds, inner.simulated_steps, raw, evaluator.checked


def main() -> None:
    print(
        f"grammars/hybrid.gg, GE, population 75 (elite 7), generations 0..{GENERATIONS}, "
        f"{os.cpu_count()} threads"
    )
    print(
        f"{'fitness':<10} {'wall s':>7} {'s/gen':>6} {'backend':>8} {'outside':>8} {'steps':>10} "
        f"{'raw s':>7} {'wall/raw':>8} {'checked':>7}"
    )
    results = {}
    for label, settings, verify in (("r4", {}, True), ("r3 window", REVISION_3_WINDOW, False)):
        wall, backend, steps, raw, verified = run(dict(settings), verify)
        results[label] = wall
        print(
            f"{label:<10} {wall:7.1f} {wall / (GENERATIONS + 1):6.2f} {backend:8.1f} "
            f"{(wall - backend) / wall:8.1%} {steps:10d} {raw:7.1f} {wall / raw:8.2f} {verified:7d}"
        )
    print(f"revision 4 / revision 3 wall time: {results['r4'] / results['r3 window']:.2f} (target <= 1.5)")
