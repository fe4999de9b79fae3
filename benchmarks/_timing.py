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
