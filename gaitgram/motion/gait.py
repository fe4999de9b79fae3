"""A population's joint curves as one array: what every fitness backend receives.

Each individual contributes, per joint, its phenotype's curve sampled over one
gait cycle. A joint the grammar does not drive, or one not yet free under the
joint-freedom schedule, holds its neutral angle (0). An individual whose genome
was invalid, or whose curves fail to compile or are not finite, keeps a row of
NaN and a reason, so a backend can score it as unviable without evaluating it.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from gaitgram.motion.expression import Motion, MotionStatus, compile_motion, phase_grid

#: Samples per cycle: enough for the 10th harmonic many times over, cheap to build.
DEFAULT_SAMPLES = 256


class MotionProblem(StrEnum):
    """Why an individual has no usable motion."""

    INVALID_GENOME = "invalid-genome"
    INVALID_MOTION = "invalid-motion"  # a joint's phenotype does not compile, or divides by zero
    NON_FINITE = "non-finite"


@dataclass(frozen=True, eq=False)
class MotionBatch:
    """Joint angles of a batch of gaits over one cycle, in degrees relative to neutral.

    ``angles[g, j, k]`` is joint ``joints[j]`` of gait ``g`` at phase ``k / n_samples``.
    ``problems[g]`` is None for a usable gait; its ``details[g]`` says what went wrong.
    """

    joints: tuple[str, ...]
    angles: NDArray[np.float64]
    problems: tuple[MotionProblem | None, ...]
    details: tuple[str | None, ...]

    def __len__(self) -> int:
        return self.angles.shape[0]

    @property
    def n_samples(self) -> int:
        return self.angles.shape[2]

    @property
    def phases(self) -> NDArray[np.float64]:
        return phase_grid(self.n_samples)

    @property
    def usable(self) -> NDArray[np.bool_]:
        return np.array([p is None for p in self.problems], dtype=bool)


def motion_batch(
    phenotypes: Sequence[Mapping[str, str] | None],
    joints: Sequence[str],
    *,
    units: str = "deg",
    n_samples: int = DEFAULT_SAMPLES,
    frozen: Collection[str] = (),
) -> MotionBatch:
    """Sample each individual's joint phenotypes (None: an invalid genome) into a batch.

    ``frozen`` joints hold neutral whatever their phenotype says (Table 3's schedule).
    """
    scale = 180.0 / math.pi if units == "rad" else 1.0
    angles = np.zeros((len(phenotypes), len(joints), n_samples))
    problems: list[MotionProblem | None] = []
    details: list[str | None] = []
    for g, texts in enumerate(phenotypes):
        problem, detail = _fill(angles[g], texts, joints, n_samples, scale, frozen)
        if problem is not None:
            angles[g] = np.nan
        problems.append(problem)
        details.append(detail)
    return MotionBatch(tuple(joints), angles, tuple(problems), tuple(details))


def _fill(
    out: NDArray[np.float64],
    texts: Mapping[str, str] | None,
    joints: Sequence[str],
    n_samples: int,
    scale: float,
    frozen: Collection[str],
) -> tuple[MotionProblem | None, str | None]:
    if texts is None:
        return MotionProblem.INVALID_GENOME, "the genome maps to no phenotype"
    for j, joint in enumerate(joints):
        text = texts.get(joint)
        if text is None or joint in frozen:
            continue
        values, problem, detail = sampled_curve(text, n_samples)
        if problem is not None:
            return problem, f"{joint}: {detail}"
        out[j] = values
        if scale != 1.0:
            with np.errstate(over="ignore"):
                out[j] *= scale
            if not np.isfinite(out[j]).all():  # finite radians can overflow as degrees
                return MotionProblem.NON_FINITE, f"{joint}: the curve is not finite in degrees"
    return None, None


@lru_cache(maxsize=16_384)
def sampled_curve(text: str, n_samples: int) -> tuple[NDArray[np.float64], MotionProblem | None, str | None]:
    """A phenotype's curve on the standard grid, cached: crossover and elitism hand the same
    joint phenotypes on from generation to generation, so most are sampled only once."""
    motion = compile_motion(text)
    if not isinstance(motion, Motion):
        return _EMPTY, MotionProblem.INVALID_MOTION, str(motion)
    curve = motion.evaluate(phase_grid(n_samples))
    if curve.status is not MotionStatus.OK:
        non_finite = curve.status is MotionStatus.NON_FINITE
        status = MotionProblem.NON_FINITE if non_finite else MotionProblem.INVALID_MOTION
        return _EMPTY, status, str(curve.error)
    values = curve.values.copy()
    values.flags.writeable = False
    return values, None, None


_EMPTY = np.zeros(0)
