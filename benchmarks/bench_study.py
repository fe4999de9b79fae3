"""Whole runs in parallel against one run at a time with every thread: the study's default.

The same small study (the hybrid grammar on mujoco-horse, two arms of two runs, a few
generations of the paper's population) runs twice from scratch: with one run per core and one
simulation thread each (``--jobs N --threads 1``, the default), and with one run at a time using
all N threads (``--jobs 1 --threads N``). Same work, same results (the test suite checks that a
study's results do not depend on its parallelism); the ratio is the speed-up of the default.
"""

from __future__ import annotations

import json
import os
import tempfile
import time
from pathlib import Path

from gaitgram.study.runner import open_study, run_study
from gaitgram.study.spec import ScaleDown, load_study

ROOT = Path(__file__).resolve().parents[1]
STUDY = """\
title = "benchmark"
runs = 2
seed = 0

[[arm]]
name = "a"
grammar = "{grammar}"

[[arm]]
name = "b"
grammar = "{grammar}"
"""


def _time_study(folder: Path, jobs: int, threads: int) -> tuple[float, list[float]]:
    study_file = folder / "study.toml"
    study_file.write_text(STUDY.format(grammar=ROOT / "grammars" / "hybrid.gg"))
    study = load_study(study_file, ScaleDown(generations=3, population=40))
    out = folder / f"jobs{jobs}"
    with open_study(study, out) as directory:
        start = time.perf_counter()
        run_study(directory, jobs=jobs, threads=threads)
        seconds = time.perf_counter() - start
    bests = [json.loads(path.read_text())["fitness"] for path in sorted(out.glob("arms/*/run-*/best.json"))]
    return seconds, bests


def main() -> None:
    cores = os.cpu_count() or 1
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        threaded, bests_threaded = _time_study(folder, jobs=1, threads=cores)
        parallel, bests_parallel = _time_study(folder, jobs=cores, threads=1)
    runs = len(bests_parallel)
    print(f"{runs} runs of 4 generations x 40 (hybrid.gg, mujoco-horse) on {cores} cores")
    print(f"one run at a time, {cores} threads each : {threaded:7.1f} s")
    print(f"{cores} runs at a time, 1 thread each   : {parallel:7.1f} s")
    print(f"speed-up of runs in parallel            : {threaded / parallel:7.2f}x")
    print(f"same results                            : {bests_parallel == bests_threaded}")
