"""How far a gait is from real walks: the DLC_Horse measures, read the same way off the model.

``seeds/dlc_walk.json`` (``gaitgram seed derive`` on 169 side-view clips of horses walked in
hand; Niknejad et al. 2023) holds, for real walks, the duty factor and the footfall phases
after the left hind (median and IQR), and four angle curves over one stride (mean and SD at 20
phases): the fetlock angles (cannon to pastern, knee-fetlock-hoof and hock-fetlock-hoof) and the
limbs' protraction (withers-knee and hip-hock against the vertical, positive forward). Here the
same landmarks are read off the model (withers: the scapula's top; knee: the carpus; hip: the
hip joint; hock: the tarsus; fetlock; hoof: the sole's centre) over the scored cycles of a gait,
each curve over each of that limb's strides, from its footfall, and averaged.

**Realism distance**, one number per gait: the mean, over eight measures, of how far the gait is
from the real walks in units of their spread:

* duty factor and the left fore's, right hind's and right fore's phases: ``|x - median| / s``,
  with ``s = IQR / 1.349`` (a normal distribution's SD from its IQR);
* each of the four curves: the mean over its 20 phases of ``|gait - mean| / SD``.

0 is the real walks' median gait; a gait at their quartiles in every measure scores about 0.67.
Speed, stride length and frequency are not in it: the real walks' speeds are unknown (pixels),
and the walk criterion judges strides against Alexander's relation at the gait's own speed.
Image-plane angles from one camera are not the model's joint angles: a curve's shape and range
compare, not its offset to the degree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.measures import HOOVES, measure_cycles, strides, touchdowns, window
from gaitgram.backends.mujoco_horse.model import STATE_SPEC
from gaitgram.backends.mujoco_horse.reference import CURVE_SAMPLES, CURVES, real_walks
from gaitgram.backends.mujoco_horse.settings import HorseSettings, warmup_cycles
from gaitgram.backends.mujoco_horse.targets import G, duty_factor_for
from gaitgram.motion.gait import MotionBatch

#: The model's landmark for each DLC keypoint of the left limbs: a body's origin, or a site.
_LANDMARKS = {
    "Withers": ("body", "scapula_fore_left"),
    "LeftKnee": ("body", "cannon_fore_left"),
    "LeftFrontFetlock": ("body", "digit_fore_left"),
    "LeftFrontHoof": ("site", "hoof_fore_left"),
    "Hip": ("body", "thigh_hind_left"),
    "LeftHock": ("body", "cannon_hind_left"),
    "LeftHindFetlock": ("body", "digit_hind_left"),
    "LeftHindHoof": ("site", "hoof_hind_left"),
}
_LIMBS = {  # curve end -> (hoof index in HOOVES, fetlock, upper, body landmark)
    "fore": (HOOVES.index("fore_left"), "LeftFrontFetlock", "LeftKnee", "Withers", "LeftFrontHoof"),
    "hind": (HOOVES.index("hind_left"), "LeftHindFetlock", "LeftHock", "Hip", "LeftHindHoof"),
}


@dataclass(frozen=True)
class Realism:
    """One gait's measures beside the real walks'."""

    measures: dict[str, float]  # duty factor, phases; curve ranges of motion (degrees)
    curves: dict[str, NDArray[np.float64]]  # each over one stride, CURVE_SAMPLES phases
    scores: dict[str, float]  # per measure of reference.MEASURES: distance from the real walks in spreads
    distance: float  # the mean of the scores
    #: The scored window's speed, stride length and frequency, and what the Froude relations
    #: predict at that speed for this body (Alexander & Jayes' duty factor, Alexander's stride).
    at_speed: dict[str, float] = field(default_factory=dict)


def _angle(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Signed angle (degrees) from direction ``a`` to ``b`` (x forward, z up), as ``seed derive``."""
    turn = np.arctan2(b[:, 1], b[:, 0]) - np.arctan2(a[:, 1], a[:, 0])
    return np.degrees((turn + np.pi) % (2 * np.pi) - np.pi)


def landmark_curves(model: mujoco.MjModel, states: NDArray[np.float64]) -> dict[str, NDArray[np.float64]]:
    """The four curves at every recorded state [steps, nstate] (``STATE_SPEC``)."""
    data = mujoco.MjData(model)
    ids = {
        name: (
            kind,
            mujoco.mj_name2id(
                model, mujoco.mjtObj.mjOBJ_BODY if kind == "body" else mujoco.mjtObj.mjOBJ_SITE, n
            ),
        )
        for name, (kind, n) in _LANDMARKS.items()
    }
    points = {name: np.empty((len(states), 2)) for name in _LANDMARKS}
    for k, state in enumerate(states):
        mujoco.mj_setState(model, data, state, STATE_SPEC)
        mujoco.mj_kinematics(model, data)
        for name, (kind, index) in ids.items():
            where = data.xpos[index] if kind == "body" else data.site_xpos[index]
            points[name][k] = where[0], where[2]
    down = np.repeat([[0.0, -1.0]], len(states), axis=0)
    found = {}
    for end, (_, fetlock, upper, body, hoof) in _LIMBS.items():
        cannon, pastern = points[fetlock] - points[upper], points[hoof] - points[fetlock]
        found[f"fetlock_{end}"] = _angle(cannon, pastern)
        found[f"protraction_{end}"] = -_angle(down, points[upper] - points[body])
    return found


def assess(settings: dict[str, Any], batch: MotionBatch) -> list[Realism | None]:
    """Each gait of ``batch`` played as its evaluation plays it (the run's backend ``settings``)
    and measured beside the real walks; None for a gait that falls or does not step."""
    evaluator = HorseEvaluator(HorseSettings.from_mapping(settings))
    try:
        rows = np.arange(len(batch))
        states, sensors, control = evaluator.play(batch, rows)  # as it is scored, closed loops closed
        frequencies = evaluator.frequencies(batch, rows)
        verdicts = evaluator.score(states, sensors, control, {"velocity": 1.0}, frequencies)
        recordings = evaluator.recordings(states, sensors, control, frequencies)
        found: list[Realism | None] = []
        for g, (verdict, recording) in enumerate(zip(verdicts, recordings, strict=True)):
            if not verdict.status.viable:
                found.append(None)
                continue
            warmup = warmup_cycles(evaluator.settings.warmup_seconds, recording.frequency)
            scored = measure_cycles(recording, warmup, warmup + evaluator.scored, evaluator.gap_steps)
            start, end = recording.cycle_edges(warmup + evaluator.scored)[[warmup, -1]]
            curves = landmark_curves(evaluator.model, states[g])
            realism = _realism(scored, recording, curves, int(start), int(end), evaluator.gap_steps)
            found.append(None if realism is None else replace(realism, at_speed=_at_speed(scored, evaluator)))
        return found
    finally:
        evaluator.close()


def _at_speed(scored: Any, evaluator: HorseEvaluator) -> dict[str, float]:
    means = window(scored)
    speed = means.velocity
    targets = evaluator.targets
    froude = speed / math.sqrt(G * targets.hip_height) if speed > 0 else math.nan
    length = float(targets.stride_at(speed)) if speed > 0 else math.nan
    return {
        "speed": speed,
        "stride_length": means.stride_length,
        "stride_frequency": means.stride_frequency,
        "froude": froude,
        "predicted_duty_factor": duty_factor_for(froude) if speed > 0 else math.nan,
        "predicted_stride_length": length,
        "predicted_stride_frequency": speed / length if speed > 0 else math.nan,
    }


def mean_phases(phases: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each hoof's mean footfall phase over the cycles (rows) that have one; NaN, quietly, for a
    hoof that never has one (a gait that drags a hoof), which makes the gait unmeasurable."""
    mean = np.full(len(HOOVES), math.nan)
    if len(phases):
        seen = np.isfinite(phases).any(axis=0)
        mean[seen] = np.nanmean(phases[:, seen], axis=0)
    return mean


def _realism(
    scored: Any, recording: Any, curves: dict[str, NDArray[np.float64]], start: int, end: int, gap: int
) -> Realism | None:
    falls = touchdowns(recording.contact, gap)
    stride_curves: dict[str, NDArray[np.float64]] = {}
    phase = np.linspace(0, 1, CURVE_SAMPLES, endpoint=False)
    for end_name, (hoof, *_rest) in _LIMBS.items():
        mine = [s for s in strides(recording, falls) if s.hoof == hoof and start <= s.start and s.end <= end]
        if not mine:
            return None
        for name in (f"fetlock_{end_name}", f"protraction_{end_name}"):
            # curve arrays are per recorded state: entry k is after step k + 1
            series = np.concatenate([[curves[name][0]], curves[name]])
            runs = [
                np.interp(
                    phase,
                    (np.arange(s.start, s.end + 1) - s.start) / (s.end - s.start),
                    series[s.start : s.end + 1],
                )
                for s in mine
            ]
            stride_curves[name] = np.mean(runs, axis=0)
    phases = mean_phases(scored.phases)
    measures = {
        "duty_factor": float(scored.duty_factor.mean()),
        "phase_fore_left": float(phases[HOOVES.index("fore_left")]),
        "phase_hind_right": float(phases[HOOVES.index("hind_right")]),
        "phase_fore_right": float(phases[HOOVES.index("fore_right")]),
        **{f"{name}_range": float(np.ptp(curve)) for name, curve in stride_curves.items()},
    }
    if not all(math.isfinite(v) for v in measures.values()):
        return None
    scores = _scores(measures, stride_curves)
    return Realism(measures, stride_curves, scores, float(np.mean(list(scores.values()))))


def _scores(measures: dict[str, float], curves: dict[str, NDArray[np.float64]]) -> dict[str, float]:
    real = real_walks()
    spread = {
        "duty_factor": real["duty_factor"],
        "phase_fore_left": real["phase_after_left_hind"]["LeftFrontHoof"],
        "phase_hind_right": real["phase_after_left_hind"]["RightHindHoof"],
        "phase_fore_right": real["phase_after_left_hind"]["RightFrontHoof"],
    }
    scores = {}
    for name, summary in spread.items():
        low, high = summary["iqr"]
        scores[name] = abs(measures[name] - summary["median"]) / ((high - low) / 1.349)
    for name in CURVES:
        reference = real["curves"][name]
        scores[name] = float(
            np.mean(np.abs(curves[name] - np.array(reference["mean"])) / np.array(reference["sd"]))
        )
    return scores
