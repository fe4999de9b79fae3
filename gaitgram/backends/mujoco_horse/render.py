"""The horse's render hook (``BackendSpec.render``): gaits drawn as they are scored.

Each gait is played through the evaluator's control loop (:meth:`HorseEvaluator.play`, closed
loops closed), to the end of its own play, and drawn from the states it recorded by the generic
MuJoCo layer (:mod:`gaitgram.backends.mujoco.render`), a side view following the trunk. An open
loop's frames are the same, to the byte, as when it was stepped in Python from its control array.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gaitgram.backends.mujoco.render import Camera, draw_plays, frame_every
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.motion.gait import MotionBatch


def render(
    settings: Mapping[str, Any],
    motion: MotionBatch,
    *,
    cycles: int | None = None,
    fps: int = 25,
    width: int = 480,
    height: int = 360,
) -> list[list[NDArray[np.uint8]]]:
    """RGB frames of each gait of ``motion`` (every one playable) under the backend ``settings``,
    ``fps`` a second, for ``cycles`` cycles after the ramp (None: its warm-up and scored ones)."""
    evaluator = HorseEvaluator(HorseSettings.from_mapping({**settings, "threads": 1}))
    try:
        rows = np.arange(len(motion))
        states, _, _ = evaluator.play(motion, rows, cycles)
        ends = evaluator.ends_at(motion, rows, cycles)  # each gait to its own end, not the longest's
        return draw_plays(
            evaluator.model,
            evaluator.initial_state,
            [states[g, : ends[g]] for g in rows],
            Camera(evaluator.layout.trunk_body),
            every=frame_every(evaluator.model, fps),
            width=width,
            height=height,
        )
    finally:
        evaluator.close()
