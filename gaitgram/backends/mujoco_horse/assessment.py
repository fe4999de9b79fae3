"""A kept gait measured beyond its score, as ``gaitgram report --assess`` keeps it
(``run-NNN/assessment.json``): its realism beside the DLC_Horse walks
(:mod:`~gaitgram.backends.mujoco_horse.realism`), its trials under each disturbance
(:mod:`~gaitgram.backends.mujoco_horse.robustness`) and its graded trial (``graded``: each family of
disturbance in rungs of growing size). The backend declares it (``BackendSpec.assess``) so that
the study layer asks for it without knowing the horse."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from gaitgram.backends.mujoco_horse.realism import assess
from gaitgram.backends.mujoco_horse.robustness import DISTURBANCES, GRADES, Rung, Trial, disturbed, graded
from gaitgram.motion.gait import MotionBatch


def assess_gaits(settings: Mapping[str, Any], batch: MotionBatch) -> list[dict[str, Any]]:
    """Each gait of ``batch`` (a :class:`~gaitgram.motion.gait.MotionBatch`) with the run's backend
    ``settings``: its realism (``None`` where it falls, does not step or cannot be built) and its
    disturbance trials, as kept in ``assessment.json``."""
    playable = [g for g in range(len(batch)) if batch.problems[g] is None]
    found: list[dict[str, Any]] = [
        {"gait": "invalid", "detail": batch.details[g], "realism": None, "trials": [], "graded": []}
        for g in range(len(batch))
    ]
    if not playable:
        return found
    sub = batch.take(playable)
    realism = _realism(settings, sub)
    trials = {d.name: disturbed(settings, sub, d.name) for d in DISTURBANCES}
    rungs = graded(settings, sub, known={GRADES[0].name: trials["bumps"]})  # the trial's bumps: rung 1
    for k, g in enumerate(playable):
        found[g] = {
            "gait": "measured" if realism[k] is not None else "falls",
            "detail": None,
            "realism": realism[k],
            "trials": [
                {
                    "disturbance": d.name,
                    "describe": d.describe,
                    "upright": trials[d.name][k].upright,
                    "walking": trials[d.name][k].walking,
                    "detail": trials[d.name][k].detail,
                    "floors": trials[d.name][k].floors,
                    "held": trials[d.name][k].held,
                }
                for d in DISTURBANCES
            ],
            "graded": [_rung(rung, trial) for rung, trial in zip(GRADES, rungs[k], strict=True)],
        }
    return found


def _rung(rung: Rung, trial: Trial) -> dict[str, Any]:
    return {
        "family": rung.family,
        "size": rung.size,
        "unit": rung.unit,
        "describe": rung.describe,
        "upright": trial.upright,
        "walking": trial.walking,
        "detail": trial.detail,
        "plays": trial.floors,
        "held": trial.held,
    }


def _realism(settings: Mapping[str, Any], batch: MotionBatch) -> list[dict[str, Any] | None]:
    """:func:`~gaitgram.backends.mujoco_horse.realism.assess` as ``assessment.json`` keeps it:
    the measures with the window's speed and strides and their predictions, the scores, the
    distance and the curves (one simulation)."""
    return [
        None
        if realism is None
        else {
            "measures": {**realism.measures, **realism.at_speed},
            "scores": realism.scores,
            "distance": realism.distance,
            "curves": {name: [float(v) for v in curve] for name, curve in realism.curves.items()},
        }
        for realism in assess(settings, batch)
    ]
