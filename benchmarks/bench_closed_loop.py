"""Closed loops against the open loop, side by side in one run: evaluations and whole runs.

Issue 40's targets: a closed-loop evaluation at least 0.7x the evaluations/s of an open-loop one
of the same steps, and a Table-1 run of a closed-loop grammar at most 1.5x the open-loop run's
wall time.

Evaluations: 75 gaits of each bundled grammar, as a run draws them (:mod:`benchmarks._populations`):
generation 0 from seed 0, and the seed walk mutated at the runs' rate (a converged population,
feedback gains drawn anew in each gait). The closed-loop grammars are ``hybrid-feedback.gg``
(pitch, pitch rate and hoof load on four curves) and ``hybrid-reset.gg`` (the same, the hind
fetlock on its limb's oscillator, restarted at touchdown). The populations fall differently,
so each closed-loop row is compared per simulated step with the open-loop hybrid population of
its kind, and with its own *twin*: the same gaits with their loops cut, played open loop on their
nominal curves (what ``angles`` holds), which walk and fall much as they do. Rounds are
interleaved and the best of each kept; the spread is the worst round over the best.

Runs: GE from seed 1 with Table 1's population of 75, for a scaled-down number of generations
(the ratio is what matters), revision 4 (kept gaits checked over the horizon), open-loop
``hybrid.gg`` against each closed-loop grammar.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from benchmarks import _populations as populations
from benchmarks._timing import Clock
from benchmarks.bench_evolve import RunTimes, best_of, fresh_run, spread
from gaitgram.backends.mujoco.control import ClosedLoop
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, HorseSettings
from gaitgram.motion.gait import MotionBatch

ROUNDS = 3
#: Generations of the scaled-down Table-1 runs (Table 1 runs 50), and how often each run is made.
GENERATIONS = 4
RUN_ROUNDS = 2
CLOSED = ("hybrid-feedback.gg", "hybrid-reset.gg")


class _ControlClock:
    """Times a closed loop's control computation inside an evaluation (the rest is MuJoCo and the
    records): the evaluator's closed loops are made with their ``controls`` timed."""

    def __init__(self, evaluator: HorseEvaluator) -> None:
        self.seconds = 0.0
        make = evaluator.controller

        def controller(batch: MotionBatch, rows: np.ndarray) -> object:
            made = make(batch, rows)
            if isinstance(made, ClosedLoop):
                made.controls = self._timed(made.controls)  # type: ignore[method-assign]
            return made

        evaluator.controller = controller  # type: ignore[method-assign]

    def _timed(self, controls: Callable[..., Any]) -> Callable[..., Any]:
        def timed(*args: Any) -> Any:
            start = time.perf_counter()
            try:
                return controls(*args)
            finally:
                self.seconds += time.perf_counter() - start

        return timed


def evaluations(threads: int) -> None:
    rows: list[tuple[str, str, MotionBatch]] = []  # (kind, grammar, its gaits): (kind, grammar) a key
    for kind, make in (("generation 0", populations.generation_zero), ("seed mutated", populations.mutants)):
        rows.append((kind, "hybrid.gg", make("hybrid.gg")))
        for grammar in CLOSED:
            batch = make(grammar)
            assert batch.closed_loop
            rows.append((kind, grammar, batch))
            rows.append((kind, f"{grammar} twin", replace(batch, loops=None)))
    evaluator = HorseEvaluator(HorseSettings(threads=threads))
    control = _ControlClock(evaluator)
    clocks = {(kind, label): Clock.new() for kind, label, _ in rows}
    controls = dict.fromkeys(clocks, 0.0)
    steps = {}
    try:
        for kind, label, batch in rows:  # warm-up, and the steps each simulates
            before = evaluator.simulated_steps
            evaluator.evaluate(batch)
            steps[kind, label] = evaluator.simulated_steps - before
        for _ in range(ROUNDS):
            for kind, label, batch in rows:
                control.seconds = 0.0
                clocks[kind, label].time(lambda batch=batch: evaluator.evaluate(batch))
                controls[kind, label] = control.seconds
    finally:
        evaluator.close()
    print(
        f"{populations.POPULATION} gaits per population, {threads} threads, best of {ROUNDS} rounds "
        f"interleaved; per-step ratios against the open-loop hybrid population of the same kind "
        f"(target >= 0.7) and against the gaits' own open-loop twin"
    )
    print(
        f"{'population':<14} {'grammar':<24} {'steps':>7} {'evals/s':>8} {'ksteps/s':>9} {'cpu':>6} "
        f"{'vs open':>7} {'cpu':>5} {'vs twin':>7} {'controls':>8} {'spread':>6}"
    )
    for kind, label, _ in rows:
        clock, simulated = clocks[kind, label], steps[kind, label]
        rate = simulated / clock.wall
        line = (
            f"{kind:<14} {label:<24} {simulated:7d} {populations.POPULATION / clock.wall:8.1f} "
            f"{rate / 1e3:9.1f} {simulated / clock.cpu / 1e3:6.1f}"
        )
        if label in CLOSED:
            open_clock, open_steps = clocks[kind, "hybrid.gg"], steps[kind, "hybrid.gg"]
            twin_clock, twin_steps = clocks[kind, f"{label} twin"], steps[kind, f"{label} twin"]
            line += (
                f" {rate / (open_steps / open_clock.wall):7.2f}"
                f" {(simulated / clock.cpu) / (open_steps / open_clock.cpu):5.2f}"
                f" {rate / (twin_steps / twin_clock.wall):7.2f}"
                f" {controls[kind, label] / clock.walls[-1]:8.1%}"
            )
        else:
            line += f" {'':7} {'':5} {'':7} {'':8}"
        print(line + f" {clock.spread:6.0%}")


def runs(threads: int) -> None:
    print(
        f"\nTable-1 runs scaled down: GE, population 75, generations 0..{GENERATIONS}, revision 4, seed 1, "
        f"{threads} threads, each run {RUN_ROUNDS} times interleaved and the fastest kept; seconds in "
        "the backend and steps as each run recorded them (target: a closed-loop run <= 1.5x the open "
        "loop's wall time)"
    )
    print(
        f"{'grammar':<20} {'wall s':>7} {'cpu s':>7} {'backend':>8} {'steps':>9} {'vs open':>7} "
        f"{'cpu':>5} {'per step':>8} {'spread':>6}"
    )
    made: dict[str, list[RunTimes]] = {grammar: [] for grammar in ("hybrid.gg", *CLOSED)}
    for _ in range(RUN_ROUNDS):
        for grammar, times in made.items():
            times.append(fresh_run(grammar, {"threads": threads}, verify=True, generations=GENERATIONS))
    found = {grammar: best_of(times) for grammar, times in made.items()}
    base = found["hybrid.gg"]
    for grammar, times in found.items():
        per_step = (times.wall / times.steps) / (base.wall / base.steps)
        print(
            f"{grammar:<20} {times.wall:7.1f} {times.cpu:7.1f} {times.backend:8.1f} {times.steps:9d} "
            f"{times.wall / base.wall:7.2f} {times.cpu / base.cpu:5.2f} {per_step:8.2f} "
            f"{spread(made[grammar]):6.0%}"
        )
    print("\nwhere the runs' wall time goes (seconds, share of the run's wall time):")
    print(f"{'stage':<28} " + " ".join(f"{grammar:>18}" for grammar in found))
    for stage in base.stages:
        print(
            f"{stage:<28} "
            + " ".join(f"{t.stages[stage]:9.1f} {t.stages[stage] / t.wall:8.1%}" for t in found.values())
        )


def main() -> None:
    threads = os.cpu_count() or 1
    evaluations(threads)
    runs(threads)
