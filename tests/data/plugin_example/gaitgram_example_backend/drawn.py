"""The neck-swing backend, drawn and assessed: an example of the hooks a report and ``gaitgram
render`` reach a backend through (docs/plugins.md, "Drawing and assessing gaits").

- ``verdict``: a gait *swings* when its neck's amplitude is within 5 degrees of the target;
- ``render``: each gait's neck as a dark bar across a white picture, moved from the middle by its
  angle at each frame's phase (one cycle a second), so a test can read the angle back;
- ``assess`` and ``assessment``: each gait's amplitude beside a metronome's 30 degrees, its neck
  curve on the metronome's band, and a trial under a gust that a gait swinging less than 10
  degrees does not hold.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from gaitgram.backends.api import (
    Assessment,
    Evaluation,
    ReferenceCurve,
    ReferenceMeasure,
    Verdict,
)
from gaitgram.backends.registry import BackendSpec
from gaitgram.motion.gait import MotionBatch
from gaitgram_example_backend import CATALOGUE, NeckSwing

#: What a metronome swings (degrees), the reference the gaits are assessed against.
METRONOME = 30.0
SAMPLES = 20
#: What a gust trial's detail says before the terms a gait failed.
FAILED = "not swinging again: "


class DrawnNeckSwing(NeckSwing):
    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        scored = super().evaluate(batch, generation=generation, weights=weights)
        return [
            e
            if not e.status.viable
            else Evaluation(
                e.fitness,
                components={**e.components, "swinging": float(e.fitness <= 5.0)},
            )
            for e in scored
        ]


def load(settings: Mapping[str, Any] | None = None) -> DrawnNeckSwing:
    return DrawnNeckSwing(float((settings or {}).get("target_amplitude", 30.0)))


def neck(batch: MotionBatch, g: int, phases: np.ndarray) -> np.ndarray:
    """Gait ``g``'s neck angle (degrees) at ``phases`` of its cycle."""
    curve = batch.angles[g, batch.joints.index("neck")]
    return np.interp(phases % 1.0, np.arange(len(curve)) / len(curve), curve, period=1.0)


def render(
    settings: Mapping[str, Any],
    motion: MotionBatch,
    *,
    cycles: int | None = None,
    fps: int = 25,
    width: int = 480,
    height: int = 360,
) -> list[list[np.ndarray]]:
    """Per gait, ``fps`` frames a cycle, for ``cycles`` cycles (default 2): the bar's middle is
    ``width / 2 + angle / 40 * width / 2`` pixels from the left."""
    count = fps * (cycles or 2)
    drawn = []
    for g in range(len(motion)):
        frames = []
        for angle in neck(motion, g, np.arange(count) / fps):
            frame = np.full((height, width, 3), 255, np.uint8)
            middle = round(width / 2 + angle / 40 * width / 2)
            frame[:, max(0, middle - 4) : middle + 4] = 20
            frames.append(frame)
        drawn.append(frames)
    return drawn


def assess(settings: Mapping[str, Any], motion: MotionBatch) -> list[dict[str, Any]]:
    """Each gait's amplitude beside the metronome's, and its trial under a gust."""
    phases = np.arange(SAMPLES) / SAMPLES
    found = []
    for g in range(len(motion)):
        if motion.problems[g] is not None:
            found.append({"gait": "invalid", "detail": motion.details[g], "realism": None, "trials": []})
            continue
        curve = neck(motion, g, phases)
        amplitude = float((curve.max() - curve.min()) / 2)
        score = abs(amplitude - METRONOME) / 5.0
        holds = amplitude >= 10.0
        found.append(
            {
                "gait": "measured",
                "detail": None,
                "realism": {
                    "measures": {"amplitude": amplitude},
                    "scores": {"amplitude": score},
                    "distance": score,
                    "curves": {"neck": [float(v) for v in curve]},
                },
                "trials": [
                    {
                        "disturbance": "gust",
                        "describe": "a gust from the side",
                        "upright": True,
                        "walking": holds,
                        "detail": None if holds else f"{FAILED}swinging",
                        "floors": 1,
                        "held": int(holds),
                    }
                ],
                "graded": [],
            }
        )
    return found


def assessment() -> Assessment:
    phases = np.arange(SAMPLES) / SAMPLES
    return Assessment(
        title="Necks beside a metronome",
        text=f"Each run's best neck swing beside a metronome's {METRONOME:g} degrees.",
        measures=(
            ReferenceMeasure("amplitude", "neck amplitude (deg)", METRONOME, "a metronome's"),
            ReferenceMeasure("neck_max", "neck: furthest forward (deg)", METRONOME, "a metronome's"),
        ),
        scored=("amplitude",),
        curves=(
            ReferenceCurve(
                "neck",
                "neck (deg)",
                tuple(METRONOME * math.sin(2 * math.pi * p) for p in phases),
                (5.0,) * SAMPLES,
            ),
        ),
        figure="Necks beside the metronome",
        failed_terms=FAILED,
    )


BACKEND = BackendSpec(
    name="neck-drawn",
    summary="Example: neck-swing, drawn and assessed beside a metronome.",
    catalogue=CATALOGUE,
    load=load,
    verdict=Verdict("swinging", "swing", ("swinging",), None, "v1"),
    render=render,
    assess=assess,
    assessment=assessment,
)
