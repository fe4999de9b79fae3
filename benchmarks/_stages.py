"""Where a run's time goes: wall seconds spent in each stage, by timers put around the functions
that do it for the length of a ``with`` block (no profiler, whose overhead would swell the Python
stages against MuJoCo's)."""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from mujoco import batch as mjbatch

from gaitgram.backends.mujoco import control
from gaitgram.backends.mujoco_horse import evaluator
from gaitgram.evolution import engine
from gaitgram.pipeline import Pipeline

#: Stage -> the functions whose time is its own (owner, attribute), in the order a report lists them.
STAGES: dict[str, tuple[tuple[Any, str], ...]] = {
    "MuJoCo (Batch.rollout)": ((mjbatch.Batch, "rollout"),),
    "controls": ((evaluator._OpenController, "controls"), (control.ClosedLoop, "controls")),
    "records (_observe)": ((evaluator.HorseEvaluator, "_observe"),),
    "verdicts (_verdicts)": ((evaluator.HorseEvaluator, "_verdicts"),),
    "mapping (Pipeline.map)": ((Pipeline, "map"),),
    "motion (Pipeline.motion)": ((Pipeline, "motion"),),
    "checkpoints, records": ((engine, "save_checkpoint"), (engine, "run_files")),
}


@contextmanager
def stage_times() -> Iterator[dict[str, float]]:
    """Seconds per stage of :data:`STAGES` spent within the block (filled in as it runs)."""
    seconds = dict.fromkeys(STAGES, 0.0)
    saved: list[tuple[Any, str, Callable[..., Any]]] = []

    def timer(stage: str, function: Callable[..., Any]) -> Callable[..., Any]:
        @functools.wraps(function)
        def timed(*args: Any, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                seconds[stage] += time.perf_counter() - start

        return timed

    try:
        for stage, places in STAGES.items():
            for owner, name in places:
                function = owner.__dict__[name]  # the plain function, not a bound method
                saved.append((owner, name, function))
                setattr(owner, name, timer(stage, function))
        yield seconds
    finally:
        for owner, name, function in reversed(saved):
            setattr(owner, name, function)
