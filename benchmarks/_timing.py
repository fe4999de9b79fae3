"""Timing helpers shared by the benchmarks."""

from __future__ import annotations

import gc
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Timing:
    median: float
    best: float
    runs: int


def measure(work: Callable[[], object], *, runs: int = 7, min_time: float = 0.2) -> Timing:
    """Median and best of ``runs`` timings; each timing repeats ``work`` for at least ``min_time``."""
    work()  # warm caches (compiled regexes, lark tables)
    loops = 1
    while True:
        start = time.perf_counter()
        for _ in range(loops):
            work()
        elapsed = time.perf_counter() - start
        if elapsed >= min_time or loops >= 1 << 20:
            break
        loops *= 2
    samples = []
    for _ in range(runs):
        gc.collect()
        start = time.perf_counter()
        for _ in range(loops):
            work()
        samples.append((time.perf_counter() - start) / loops)
    return Timing(statistics.median(samples), min(samples), runs)


def row(label: str, ours: Timing, baseline: Timing, baseline_name: str) -> str:
    ratio = baseline.median / ours.median
    return (
        f"{label:<34} gaitgram {ours.median * 1e3:9.2f} ms   {baseline_name} {baseline.median * 1e3:9.2f} ms"
        f"   ratio {ratio:5.2f}x"
    )


@dataclass
class Clock:
    """Wall and CPU seconds (the process's, all threads) of repeated work: the best of each, and
    every wall time, so a report can say how noisy they were. On a loaded machine the CPU time
    is the steadier figure; the wall time is what a user waits."""

    walls: list[float]
    cpus: list[float]

    @classmethod
    def new(cls) -> Clock:
        return cls([], [])

    def time(self, work: Callable[[], object]) -> object:
        wall, cpu = time.perf_counter(), time.process_time()
        try:
            return work()
        finally:
            self.walls.append(time.perf_counter() - wall)
            self.cpus.append(time.process_time() - cpu)

    @property
    def wall(self) -> float:
        return min(self.walls)

    @property
    def cpu(self) -> float:
        return min(self.cpus)

    @property
    def spread(self) -> float:
        """Worst over best wall time, less one: how much the machine's load moved the figure."""
        return max(self.walls) / min(self.walls) - 1.0
