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

from gaitgram.backends.api import Evaluation, unusable_evaluations
from gaitgram.backends.registry import BackendSpec
from gaitgram.motion.expression import MotionStatus, compile_motion, phase_grid
from gaitgram.motion.gait import MotionBatch


class CurveMatchError(ValueError):
    """Bad settings: no targets, or a target that does not compile."""


@dataclass(frozen=True)
class CurveMatch:
    """Targets are motion expressions of ``t`` in degrees, per joint name."""

    targets: Mapping[str, str]

    def __post_init__(self) -> None:
        if not self.targets:
            raise CurveMatchError('curve-match needs targets: a table joint = "expression of t"')
        for joint, text in self.targets.items():
            motion = compile_motion(text)
            if not hasattr(motion, "evaluate"):
                raise CurveMatchError(f"target for {joint}: {motion}")

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
        rms = np.sqrt(np.mean((chosen - targets[None]) ** 2, axis=2))
        names = list(self.targets)
        factors = np.array([(weights or {}).get(f"rms_{name}", 1.0) for name in names])
        total = factors.sum() or 1.0
        results = []
        for g in range(len(batch)):
            if g in unusable:
                results.append(unusable[g])
                continue
            components = {f"rms_{name}": float(value) for name, value in zip(names, rms[g], strict=True)}
            results.append(Evaluation(float((rms[g] * factors).sum() / total), components=components))
        return results

    def close(self) -> None:
        pass


def load(settings: Mapping[str, Any] | None = None) -> CurveMatch:
    targets = dict((settings or {}).get("targets", {}))
    return CurveMatch({str(k): str(v) for k, v in targets.items()})


BACKEND = BackendSpec(
    name="curve-match",
    summary="Distance of each joint curve to a target curve: analytic, for tests and sanity checks.",
    catalogue=None,
    load=load,
)
