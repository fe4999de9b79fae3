"""Where a Table-1 run's time goes, under fitness revision 4 and under revision 3's window.

GE on ``grammars/hybrid.gg`` (the paper's winner) with the paper's population of 75 and
elite 7, for a few generations, twice: with revision 4's evaluation (warm-up, 3 scored cycles,
the kept gaits checked over the 20-cycle horizon) and with revision 3's window (the ramp and 3
cycles, nothing checked). Each run is made ``ROUNDS`` times, interleaved, and the fastest kept.

For each: the wall time per generation; the seconds inside the backend and the steps MuJoCo
simulated, as the run recorded them itself (``backend.json``); the wall time against a raw
``mujoco.rollout`` of as many steps (its rate measured in the same process on the run's final
population, best of three); the CPU time against the raw rollout's (steadier than the wall time
on a loaded machine); and the wall time against the run's own time in ``Batch.rollout``
(MuJoCo stepping, measured within the run, so that the machine's load moves both alike). Last,
the wall time of each stage (:mod:`benchmarks._stages`): what is not stepping MuJoCo.

Targets (issue 40): revision 4 at most 1.5x revision 3's wall time; a run at most 1.1x the raw
rollout of the steps it simulates. Revision 4 simulates more steps than revision 3 (the warm-up
and the horizon's checks): the ratio of steps is printed beside the wall time's, and the wall time
per step says what each step costs.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import tempfile
import time
from collections.abc import Mapping
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from benchmarks._stages import stage_times
from benchmarks.bench_backend import REVISION_3_WINDOW, raw_rollout
from gaitgram.analysis import check
from gaitgram.backends.api import Evaluation
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.configuration import RunConfig
from gaitgram.evolution.engine import run_evolution
from gaitgram.evolution.usage import read_usage
from gaitgram.language import load
from gaitgram.motion.gait import MotionBatch
from gaitgram.pipeline import Pipeline

ROOT = Path(__file__).resolve().parents[1]
GENERATIONS = 6
#: Each run is made this many times, interleaved, and the best kept (the machine's load moves them).
ROUNDS = 2


class Trusting:
    """The evaluator without its ``verify``: revision 3 checked nothing, so the run trusts each
    evaluation (the engine checks only what an evaluator can verify)."""

    def __init__(self, inner: HorseEvaluator) -> None:
        self.inner = inner

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        return self.inner.evaluate(batch, generation=generation, weights=weights)

    @property
    def simulated_steps(self) -> int:
        return self.inner.simulated_steps

    def close(self) -> None:
        self.inner.close()


@dataclass(frozen=True)
class RunTimes:
    """One run timed: wall and CPU seconds (the process's, every thread); what the run recorded
    of itself (``backend.json``: seconds inside the backend and steps simulated); the raw
    rollout's wall and CPU seconds for as many steps (NaN for a closed loop, whose controls exist
    only as it is played); and the wall seconds of each stage (:mod:`benchmarks._stages`)."""

    wall: float
    cpu: float
    backend: float
    steps: int
    raw: float
    raw_cpu: float
    stages: dict[str, float]

    @property
    def mujoco(self) -> float:
        return self.stages["MuJoCo (Batch.rollout)"]


def timed_run(
    grammar: str, settings: Mapping[str, object], *, verify: bool, generations: int = GENERATIONS
) -> RunTimes:
    """One GE run of ``grammars/<grammar>`` (population 75, seed 1) from scratch, timed; without
    ``verify`` the run trusts the evaluation (revision 3 checked nothing)."""
    checked = check(load(ROOT / "grammars" / grammar))
    config = RunConfig(generations=generations, population=75, seed=1, backend_settings=dict(settings))
    pipeline = Pipeline.build(checked, config)
    inner = pipeline.load_evaluator()
    assert isinstance(inner, HorseEvaluator)
    evaluator = inner if verify else Trusting(inner)
    with tempfile.TemporaryDirectory() as tmp, stage_times() as stages:
        start, cpu = time.perf_counter(), time.process_time()
        state = run_evolution(pipeline, evaluator, 0, Path(tmp), fingerprint="bench")
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        usage = read_usage(Path(tmp))  # what the run recorded of itself
    assert usage is not None
    assert usage.steps == inner.simulated_steps  # it counted every step
    raw = raw_cpu = math.nan
    batch = pipeline.motion(pipeline.map([i.genome for i in state.population]), state.generation)
    if not batch.closed_loop:
        rows = np.array([g for g, problem in enumerate(batch.problems) if problem is None])
        # Best of three, wall and CPU (the machine's load moves them): the rollout's rate on the
        # run's final population, for as many steps as the run simulated.
        rates = [raw_rollout(inner, batch, rows) for _ in range(3)]
        steps = rates[0][0]
        raw = usage.steps * min(r[1] for r in rates) / steps
        raw_cpu = usage.steps * min(r[2] for r in rates) / steps
    inner.close()
    return RunTimes(wall, cpu, usage.seconds, usage.steps, raw, raw_cpu, dict(stages))


def fresh_run(
    grammar: str, settings: Mapping[str, object], *, verify: bool, generations: int = GENERATIONS
) -> RunTimes:
    """:func:`timed_run` in a process of its own, as ``gaitgram evolve`` runs: nothing compiled or
    sampled by an earlier run in the same process (the curves' caches) makes it look cheaper."""
    with ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn")) as pool:
        return pool.submit(
            timed_run, grammar, dict(settings), verify=verify, generations=generations
        ).result()


def best_of(runs: list[RunTimes]) -> RunTimes:
    """The run of least wall time among repeats of one run (the same steps: runs are deterministic)."""
    assert len({r.steps for r in runs}) == 1
    return min(runs, key=lambda r: r.wall)


def spread(runs: list[RunTimes]) -> float:
    walls = [r.wall for r in runs]
    return max(walls) / min(walls) - 1


def main() -> None:
    threads = os.cpu_count() or 1
    print(
        f"grammars/hybrid.gg, GE, population 75 (elite 7), generations 0..{GENERATIONS}, {threads} threads; "
        f"each run {ROUNDS} times, interleaved, the best kept; backend seconds and steps as the run "
        "recorded them (backend.json); raw: mujoco.rollout of as many steps at its rate on the run's "
        "final population (best of 3)"
    )
    print(
        f"{'fitness':<10} {'wall s':>7} {'s/gen':>6} {'backend':>8} {'outside':>8} {'steps':>10} "
        f"{'raw s':>7} {'wall/raw':>8} {'backend/raw':>11} {'cpu/raw':>8} {'wall/MuJoCo':>11} {'spread':>6}"
    )
    rounds: dict[str, list[RunTimes]] = {"r4": [], "r3 window": []}
    for _ in range(ROUNDS):
        rounds["r4"].append(fresh_run("hybrid.gg", {"threads": threads}, verify=True))
        rounds["r3 window"].append(
            fresh_run("hybrid.gg", {**REVISION_3_WINDOW, "threads": threads}, verify=False)
        )
    results = {label: best_of(runs) for label, runs in rounds.items()}
    for label, times in results.items():
        print(
            f"{label:<10} {times.wall:7.1f} {times.wall / (GENERATIONS + 1):6.2f} {times.backend:8.1f} "
            f"{(times.wall - times.backend) / times.wall:8.1%} {times.steps:10d} {times.raw:7.1f} "
            f"{times.wall / times.raw:8.2f} {times.backend / times.raw:11.2f} "
            f"{times.cpu / times.raw_cpu:8.2f} {times.wall / times.mujoco:11.2f} {spread(rounds[label]):6.0%}"
        )
    r4, r3 = results["r4"], results["r3 window"]
    print(
        f"revision 4 / revision 3: wall time {r4.wall / r3.wall:.2f} (target <= 1.5), CPU time "
        f"{r4.cpu / r3.cpu:.2f}, steps {r4.steps / r3.steps:.2f}, wall per step "
        f"{(r4.wall / r4.steps) / (r3.wall / r3.steps):.2f}"
    )
    print("\nwhere the wall time goes (seconds, share of the run's wall time):")
    print(f"{'stage':<28} " + " ".join(f"{label:>16}" for label in results))
    for stage in r4.stages:
        print(
            f"{stage:<28} "
            + " ".join(f"{t.stages[stage]:8.1f} {t.stages[stage] / t.wall:7.1%}" for t in results.values())
        )
    print(
        f"{'other':<28} "
        + " ".join(
            f"{t.wall - sum(t.stages.values()):8.1f} {(t.wall - sum(t.stages.values())) / t.wall:7.1%}"
            for t in results.values()
        )
    )
