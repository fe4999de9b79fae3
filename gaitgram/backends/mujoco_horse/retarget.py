"""A gait played on another body: the same joint curves, the cycle frequency scaled by dynamic
similarity.

Bodies that differ only in size move alike at equal Froude number (Alexander & Jayes 1983): the
same angles, the same phase offsets and duty factor, the same relative stride length, and a cycle
frequency that scales as ``sqrt(g / h)`` with the hip height ``h``. So a gait evolved on one
body is played on another at its frequency times ``sqrt(h_from / h_to)`` (``froude``), or, to
compare, at the frequency it was evolved at (``unscaled``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from gaitgram.backends.mujoco_horse.bodies import SCALINGS
from gaitgram.backends.mujoco_horse.model import horse_layout
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.backends.mujoco_horse.targets import CYCLE_FREQUENCIES, walk_targets
from gaitgram.motion.gait import MotionBatch


def frequency_ratio(source: str | None, target: str | None) -> float:
    """The Froude-scaled frequency on ``target`` over the frequency on ``source``: sqrt(h_s / h_t),
    with each body's standing hip height (exactly 1 for one body)."""
    if (source or "horse") == (target or "horse"):
        return 1.0
    return math.sqrt(horse_layout(source).hip_height / horse_layout(target).hip_height)


def retarget(
    settings: Mapping[str, Any], motion: MotionBatch, body: str, scaling: str
) -> tuple[dict[str, Any], MotionBatch]:
    """The settings and motion that play ``motion``, evolved under ``settings``, on ``body`` (one of
    ``bodies.toml``'s: the caller checked it, as the ``body`` setting).

    A gait without its own frequency is played at the target frequency of the body it is on,
    which already scales as ``sqrt(g / h)``; ``unscaled`` plays it at its source body's instead.
    """
    if scaling not in SCALINGS:
        raise ValueError(f"no frequency scaling called {scaling!r}; known: {', '.join(SCALINGS)}")
    source = HorseSettings.from_mapping(settings)
    # The frequencies are given as played on the target body, so its own scaling is dropped.
    target = {key: value for key, value in settings.items() if key != "frequencies_of"} | {"body": body}
    played = motion.frequencies
    if played is not None and source.frequencies_of is not None:  # as the source run played them
        played = played * frequency_ratio(source.frequencies_of, source.body)
    if scaling == "froude":
        ratio = frequency_ratio(source.body, body)
        frequencies = None if played is None else played * ratio
    else:
        own = walk_targets(source.froude, horse_layout(source.body).hip_height).stride_frequency
        chosen = np.full(len(motion.angles), np.nan) if played is None else played
        frequencies = np.where(np.isfinite(chosen), chosen, own)
    if frequencies is not None:
        low, high = CYCLE_FREQUENCIES
        played = frequencies[np.isfinite(frequencies)]
        if played.size and not (played.min() >= low and played.max() <= high):
            raise ValueError(
                f"on {body} the gaits would be played at {played.min():.3g}-{played.max():.3g} Hz, outside "
                f"the {low}-{high} Hz the backend plays"
            )
    return target, replace(motion, frequencies=frequencies)
