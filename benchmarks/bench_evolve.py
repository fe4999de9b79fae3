"""Where a generation's time goes: the backend's evaluation against everything else
(mapping, motion compiling and sampling, selection, variation, checkpoints and records).

Runs a few generations of ``grammars/sine-walk.gg`` on mujoco-horse with the paper's
population of 75. Target: under 5 % of the wall time outside the backend.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Mapping
from pathlib import Path

from gaitgram.analysis import check
from gaitgram.backends.api import Evaluation, Evaluator
from gaitgram.evolution.config import RunConfig
from gaitgram.evolution.engine import run_evolution
from gaitgram.language import load
from gaitgram.motion.gait import MotionBatch
from gaitgram.pipeline import Pipeline

ROOT = Path(__file__).resolve().parents[1]


class Timed:
    """Wraps an evaluator and adds up the time spent inside it."""

    def __init__(self, inner: Evaluator) -> None:
        self.inner = inner
        self.seconds = 0.0

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


def main() -> None:
    checked = check(load(ROOT / "grammars" / "sine-walk.gg"))
    pipeline = Pipeline.build(checked, RunConfig(generations=4, population=75, seed=1))
    config = pipeline.config
    evaluator = Timed(pipeline.load_evaluator())
    marks: list[tuple[float, float]] = []  # (wall clock, backend seconds) after each generation

    def mark(run: int, stats: object) -> None:
        marks.append((time.perf_counter(), evaluator.seconds))

    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        run_evolution(pipeline, evaluator, 0, Path(tmp), fingerprint="benchmark", on_generation=mark)
    evaluator.close()
    init_wall, init_backend = marks[0][0] - start, marks[0][1]
    wall = marks[-1][0] - marks[0][0]
    backend = marks[-1][1] - marks[0][1]
    print(f"sine-walk.gg on mujoco-horse, population 75, {config.generations} generations after generation 0")
    print(
        f"{'initial population':<34} {init_wall:6.2f} s wall, "
        f"{init_wall - init_backend:5.2f} s outside the backend (once per run: RampedFullGrow)"
    )
    print(f"{'generations 1..' + str(config.generations) + ' inside the backend':<34} {backend:6.2f} s")
    print(
        f"{'generations 1..' + str(config.generations) + ' outside':<34} {wall - backend:6.2f} s   "
        f"share {(wall - backend) / wall:6.2%}  (target < 5 %)"
    )
