"""Each bundled backend declares the components its evaluations report (``BackendSpec.components``),
which is what a strategy's objectives and descriptors are checked against before a run: the
declaration must be exactly what a viable gait's evaluation holds."""

from __future__ import annotations

from gaitgram.backends.api import GaitStatus
from gaitgram.backends.registry import get_backend
from gaitgram.motion.gait import motion_batch


def test_mujoco_horse_reports_what_it_declares() -> None:
    spec = get_backend("mujoco-horse")
    settings = spec.checked_settings({"cycles": 1, "ramp_seconds": 0.2})
    evaluator = spec.load(settings)
    try:
        (standing,) = evaluator.evaluate(motion_batch([{}], spec.catalogue.names))
    finally:
        evaluator.close()
    assert standing.status is GaitStatus.OK
    assert set(standing.components) == spec.components(settings)


def test_curve_match_reports_what_it_declares() -> None:
    spec = get_backend("curve-match")
    settings = spec.checked_settings({"targets": {"hip_hind": "7*sin(2*PI*t)", "elbow_fore": "3"}})
    (gait,) = spec.load(settings).evaluate(motion_batch([{"hip_hind": "sin(2*PI*t)"}], ("hip_hind",)))
    assert gait.status is GaitStatus.OK
    assert set(gait.components) == spec.components(settings)
