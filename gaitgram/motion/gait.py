"""A population's joint curves as one array: what every fitness backend receives.

Each individual contributes, per joint, its phenotype's curve sampled over one
gait cycle. A joint the grammar does not drive, or one not yet free under the
joint-freedom schedule, holds its neutral angle (0). An individual whose genome
was invalid, or whose curves fail to compile or are not finite, keeps a row of
NaN and a reason, so a backend can score it as unviable without evaluating it.

A grammar with a ``@frequency`` rule gives each individual its cycle frequency
(Hz) as well: a constant expression, finite, positive and within the rule's
limits, or the individual is unusable.

A phenotype that reads a backend's sensors is a closed loop: its curve depends on what the
body senses, so ``angles`` holds its *nominal* curve (every sensor at its resting reading:
what a plot can show) and ``loops`` the loop itself, split for a backend to run
(:mod:`gaitgram.motion.feedback`). Phenotypes without sensors are sampled exactly as before.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from gaitgram.language.model import FREQUENCY
from gaitgram.motion.expression import Motion, MotionStatus, compile_motion, phase_grid
from gaitgram.motion.feedback import ClosedLoop, closed_loop
from gaitgram.motion.problems import MotionProblem

#: Samples per cycle: enough for the 10th harmonic many times over, cheap to build.
DEFAULT_SAMPLES = 256


@dataclass(frozen=True, eq=False)
class MotionBatch:
    """Joint angles of a batch of gaits over one cycle, in degrees relative to neutral.

    ``angles[g, j, k]`` is joint ``joints[j]`` of gait ``g`` at phase ``k / n_samples``.
    ``problems[g]`` is None for a usable gait; its ``details[g]`` says what went wrong.
    ``frequencies[g]`` is gait ``g``'s cycle frequency in Hz, where the grammar evolves it
    (None: the backend imposes one frequency on every gait). ``loops[g][j]`` is the closed
    loop of gait ``g``'s joint ``j`` where its phenotype reads sensors (None for an open-loop
    curve; ``loops`` None where no gait reads any), in units of ``loop_scale`` degrees.
    ``phenotypes[g]`` is gait ``g``'s whole phenotype text (None: an invalid genome), carried only
    for a backend that scores the text itself rather than curves (``BackendSpec.scores_phenotype``).
    """

    joints: tuple[str, ...]
    angles: NDArray[np.float64]
    problems: tuple[MotionProblem | None, ...]
    details: tuple[str | None, ...]
    frequencies: NDArray[np.float64] | None = None
    loops: tuple[tuple[ClosedLoop | None, ...], ...] | None = None
    loop_scale: float = 1.0
    phenotypes: tuple[str | None, ...] | None = None

    def rows(self, start: int, stop: int) -> MotionBatch:
        """Gaits ``start..stop-1`` as a batch of their own."""
        return self.take(range(start, min(stop, len(self))))

    def take(self, indices: Sequence[int]) -> MotionBatch:
        """The gaits at ``indices``, in that order, as a batch of their own."""
        rows = np.asarray(indices, dtype=np.intp)
        return MotionBatch(
            self.joints,
            self.angles[rows],
            tuple(self.problems[i] for i in rows),
            tuple(self.details[i] for i in rows),
            None if self.frequencies is None else self.frequencies[rows],
            None if self.loops is None else tuple(self.loops[i] for i in rows),
            self.loop_scale,
            None if self.phenotypes is None else tuple(self.phenotypes[i] for i in rows),
        )

    @property
    def closed_loop(self) -> bool:
        """Whether any gait reads a sensor."""
        return self.loops is not None and any(any(loop is not None for loop in row) for row in self.loops)

    def opened(self) -> MotionBatch:
        """The same gaits with their feedback cut: every curve played open loop as its nominal
        (each sensor held at its resting reading), the ablation that tells what a closed loop's
        feedback adds to the curves it came with."""
        return MotionBatch(
            self.joints,
            self.angles,
            self.problems,
            self.details,
            self.frequencies,
            None,
            1.0,
            self.phenotypes,
        )

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
    frequency: tuple[float, float] | None = None,
    sensors: Sensors | None = None,
) -> MotionBatch:
    """Sample each individual's joint phenotypes (None: an invalid genome) into a batch.

    ``frozen`` joints hold neutral whatever their phenotype says (Table 3's schedule).
    ``frequency`` is the range (Hz) of an evolved cycle frequency, read from each
    phenotype's ``"@frequency"`` text; None: the grammar does not evolve it. ``sensors``
    are what the backend lets phenotypes read (None: nothing; any name is then unknown).
    """
    scale = 180.0 / math.pi if units == "rad" else 1.0
    angles = np.zeros((len(phenotypes), len(joints), n_samples))
    frequencies = None if frequency is None else np.full(len(phenotypes), np.nan)
    problems: list[MotionProblem | None] = []
    details: list[str | None] = []
    loops: list[tuple[ClosedLoop | None, ...]] = []
    for g, texts in enumerate(phenotypes):
        row: list[ClosedLoop | None] = [None] * len(joints)
        problem, detail = _fill(angles[g], texts, joints, n_samples, scale, frozen, sensors, row)
        loops.append(tuple(row))
        if problem is None and frequencies is not None and frequency is not None:
            frequencies[g], problem, detail = cycle_frequency((texts or {}).get(FREQUENCY), frequency)
        if problem is not None:
            angles[g] = np.nan
            if frequencies is not None:
                frequencies[g] = np.nan
        problems.append(problem)
        details.append(detail)
    closed = any(any(loop is not None for loop in row) for row in loops)
    return MotionBatch(
        tuple(joints),
        angles,
        tuple(problems),
        tuple(details),
        frequencies,
        tuple(loops) if closed else None,
        scale,
    )


@dataclass(frozen=True)
class Sensors:
    """What a backend lets phenotypes read (:class:`~gaitgram.backends.sensors.SensorCatalogue`,
    as the motion layer needs it): the names, those that are phases, and each one's reading at
    rest (for the nominal curve)."""

    names: frozenset[str]
    periodic: frozenset[str] = frozenset()
    nominal: tuple[tuple[str, float], ...] = ()


def cycle_frequency(
    text: str | None, limits: tuple[float, float]
) -> tuple[float, MotionProblem | None, str | None]:
    """A ``@frequency`` phenotype's value in Hz, or why it has none: it must be a constant
    expression (no ``t``), finite, and within ``limits``."""
    if text is None:
        return math.nan, MotionProblem.INVALID_MOTION, "the @frequency rule derived nothing"
    values, problem, detail = sampled_curve(text, 4)
    if problem is not None:
        return math.nan, problem, f"@frequency: {detail}"
    if values.min() != values.max():
        return (
            math.nan,
            MotionProblem.INVALID_MOTION,
            f"@frequency: {text!r} depends on t; it must be constant",
        )
    value = float(values[0])
    low, high = limits
    if not low <= value <= high:
        return (
            math.nan,
            MotionProblem.INVALID_MOTION,
            f"@frequency: {value:g} Hz is outside the allowed {low:g}..{high:g} Hz",
        )
    return value, None, None


def _fill(
    out: NDArray[np.float64],
    texts: Mapping[str, str] | None,
    joints: Sequence[str],
    n_samples: int,
    scale: float,
    frozen: Collection[str],
    sensors: Sensors | None,
    loops: list[ClosedLoop | None],
) -> tuple[MotionProblem | None, str | None]:
    if texts is None:
        return MotionProblem.INVALID_GENOME, "the genome maps to no phenotype"
    for j, joint in enumerate(joints):
        text = texts.get(joint)
        if text is None or joint in frozen:
            continue
        if sensors is None:
            values, problem, detail = sampled_curve(text, n_samples)
        else:
            values, loops[j], problem, detail = sensed_curve(text, n_samples, sensors)
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
def sensed_curve(
    text: str, n_samples: int, sensors: Sensors
) -> tuple[NDArray[np.float64], ClosedLoop | None, MotionProblem | None, str | None]:
    """A phenotype that may read ``sensors``: its nominal curve and its closed loop, or (reading
    none) exactly :func:`sampled_curve`'s curve and no loop."""
    motion = compile_motion(text, sensors.names)
    if not isinstance(motion, Motion):
        return _EMPTY, None, MotionProblem.INVALID_MOTION, str(motion)
    if not motion.sensors:  # sampled as sampled_curve samples it, without compiling it again
        values, problem, detail = _sampled(motion, n_samples)
        return values, None, problem, detail
    loop = closed_loop(motion, sensors.periodic, n_samples)
    if not isinstance(loop, ClosedLoop):
        status = (
            MotionProblem.NON_FINITE
            if loop.status is MotionStatus.NON_FINITE
            else MotionProblem.INVALID_MOTION
        )  # type: ignore[union-attr]
        return _EMPTY, None, status, str(loop)
    values = loop.nominal(dict(sensors.nominal))
    if not np.isfinite(values).all():
        return _EMPTY, None, MotionProblem.NON_FINITE, "the curve is not finite with its sensors at rest"
    values.flags.writeable = False
    return values, loop, None, None


@lru_cache(maxsize=16_384)
def sampled_curve(text: str, n_samples: int) -> tuple[NDArray[np.float64], MotionProblem | None, str | None]:
    """A phenotype's curve on the standard grid, cached: crossover and elitism hand the same
    joint phenotypes on from generation to generation, so most are sampled only once."""
    motion = compile_motion(text)
    if not isinstance(motion, Motion):
        return _EMPTY, MotionProblem.INVALID_MOTION, str(motion)
    return _sampled(motion, n_samples)


def _sampled(motion: Motion, n_samples: int) -> tuple[NDArray[np.float64], MotionProblem | None, str | None]:
    curve = motion.evaluate(phase_grid(n_samples))
    if curve.status is not MotionStatus.OK:
        non_finite = curve.status is MotionStatus.NON_FINITE
        status = MotionProblem.NON_FINITE if non_finite else MotionProblem.INVALID_MOTION
        return _EMPTY, status, str(curve.error)
    values = curve.values.copy()
    values.flags.writeable = False
    return values, None, None


_EMPTY = np.zeros(0)
