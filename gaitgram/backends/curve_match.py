"""The ``curve-match`` backend: how far each joint curve is from a target curve.

Analytic and fast, for tests, teaching and checking that the GE loop works
before paying for physics. Fitness is the mean over target joints of the RMS
difference in degrees; each joint's RMS is a component. A joint without a
target is ignored; a target joint the gait does not drive counts as neutral (0).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitgram.backends.api import Evaluation, GaitStatus, SettingsError, unusable_evaluations
from gaitgram.backends.registry import BackendSpec
from gaitgram.motion.expression import Motion, MotionStatus, compile_motion, phase_grid
from gaitgram.motion.gait import MotionBatch

#: Grids a target is checked on before a run: the run's own sample count is among them by default.
CHECK_SAMPLES = (64, 256, 1024)


class CurveMatchError(SettingsError):
    """Bad settings: no targets, or a target that does not compile."""

    def __init__(self, message: str) -> None:
        super().__init__("targets", message)


@dataclass(frozen=True)
class CurveMatch:
    """Targets are motion expressions of ``t`` in degrees, per joint name."""

    targets: Mapping[str, str]

    def __post_init__(self) -> None:
        check_targets(self.targets)

    def _target_angles(self, joints: tuple[str, ...], n_samples: int) -> tuple[list[int], np.ndarray]:
        phases = phase_grid(n_samples)
        rows, curves = [], []
        for joint, text in self.targets.items():
            curve = compile_motion(text).evaluate(phases)  # type: ignore[union-attr]
            if curve.status is not MotionStatus.OK:
                raise CurveMatchError(f"target for {joint}: {curve.error}")
            rows.append(joints.index(joint) if joint in joints else -1)
            curves.append(curve.values)
        return rows, np.array(curves)

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        """``weights`` may weight joints by name (``rms_<joint>``); unweighted joints count 1."""
        rows, targets = self._target_angles(batch.joints, batch.n_samples)
        unusable = unusable_evaluations(batch)
        # Gait angles for the target joints; joints the batch lacks hold neutral.
        padded = np.concatenate([batch.angles, np.zeros((len(batch), 1, batch.n_samples))], axis=1)
        chosen = padded[:, rows, :]  # [gaits, targets, samples]; index -1 picks the zeros
        with np.errstate(over="ignore", invalid="ignore"):
            rms = np.sqrt(np.mean((chosen - targets[None]) ** 2, axis=2))
        names = list(self.targets)
        factors = np.array([(weights or {}).get(f"rms_{name}", 1.0) for name in names])
        total = factors.sum() or 1.0
        results = []
        for g in range(len(batch)):
            if g in unusable:
                results.append(unusable[g])
                continue
            if not np.isfinite(rms[g]).all():  # curves so large that their distance overflows
                results.append(Evaluation.unviable(GaitStatus.NON_FINITE, "the RMS distance overflows"))
                continue
            components = {f"rms_{name}": float(value) for name, value in zip(names, rms[g], strict=True)}
            results.append(Evaluation(float((rms[g] * factors).sum() / total), components=components))
        return results

    def close(self) -> None:
        pass


def check_targets(targets: Mapping[str, str]) -> None:
    """Every target compiles and is finite on the usual grids, so a run never fails mid-way."""
    if not targets:
        raise CurveMatchError('curve-match needs targets: a table joint = "expression of t"')
    for joint, text in targets.items():
        motion = compile_motion(text)
        if not isinstance(motion, Motion):
            raise SettingsError(f"targets.{joint}", str(motion))
        for samples in CHECK_SAMPLES:
            curve = motion.evaluate(phase_grid(samples))
            if curve.status is not MotionStatus.OK:
                raise SettingsError(f"targets.{joint}", f"{text!r}: {curve.error}")


def check_settings(settings: Mapping[str, Any]) -> dict[str, Any]:
    for key in settings:
        if key != "targets":
            raise SettingsError(str(key), "unknown curve-match setting; its only setting is targets")
    targets = settings.get("targets")
    if not isinstance(targets, Mapping) or not targets:
        raise SettingsError("targets", 'curve-match needs a table of targets: joint = "expression of t"')
    for joint, text in targets.items():
        if not isinstance(text, str):
            raise SettingsError(f"targets.{joint}", f"must be an expression of t in quotes, not {text!r}")
    check_targets(targets)
    return {"targets": {str(k): v for k, v in targets.items()}}


def load(settings: Mapping[str, Any] | None = None) -> CurveMatch:
    targets = dict((settings or {}).get("targets", {}))
    return CurveMatch({str(k): str(v) for k, v in targets.items()})


BACKEND = BackendSpec(
    name="curve-match",
    summary="Distance of each joint curve to a target curve: analytic, for tests and sanity checks.",
    catalogue=None,
    load=load,
    check_settings=check_settings,
    weight_names=lambda settings: frozenset(f"rms_{joint}" for joint in settings.get("targets", {})),
    components=lambda settings: frozenset(f"rms_{joint}" for joint in settings.get("targets", {})),
    version="rms r1",
)
