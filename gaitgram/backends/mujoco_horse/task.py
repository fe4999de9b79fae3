"""The walking task's scoring: the fitness formula and walk criterion v2, as plain functions of
the measures of :mod:`~gaitgram.backends.mujoco_horse.measures` and the targets of
:mod:`~gaitgram.backends.mujoco_horse.targets` (physics-free, as dm_control splits task from model).
Sources and formulas are in ``docs/fitness.md``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from gaitgram.backends.mujoco_horse.measures import HOOVES, CycleMeasures, WindowMeasures
from gaitgram.backends.mujoco_horse.targets import (
    COMPONENT_CAP,
    STEADY_SPREAD,
    WALK_FOOTFALL_TOLERANCE,
    WALK_FOOTFALLS,
    WALK_PITCH_RANGE,
    WALK_ROLL_RANGE,
    WALK_SPEED_TOLERANCE,
    WALK_STRIDE_TOLERANCE,
    WALK_TERMS,
    WALK_TILT_LIMIT,
    G,
    GaitTargets,
)


def walk_terms(measures: CycleMeasures, targets: GaitTargets) -> dict[str, bool]:
    """Each term of walk criterion v2 but ``sustained``, judged on every cycle of ``measures``.

    A term holds only if it holds in each cycle and for each stride, so that measuring more of
    the same cycles cannot turn a walk into something else: window means lie within the bounds
    that every cycle meets."""
    cycles = set(range(len(measures)))
    if not cycles:
        return {term.name: False for term in WALK_TERMS if term.name != "sustained"}
    low, high = targets.duty_window
    duty = measures.duty_factor.mean(axis=1)
    # Every stride of every hoof, at the speed of the cycle it closes in; in each cycle every hoof
    # must close one.
    cycle_of, length, frequency = measures.all_strides.T
    at_speed = measures.speed[cycle_of.astype(int)]
    predicted = np.asarray(targets.stride_at(at_speed))
    stepping = not np.isnan(measures.stride_length).any()
    expected = np.array([0.0, *(WALK_FOOTFALLS[hoof] for hoof in HOOVES[1:])])
    return {
        "speed": bool(np.all(np.abs(measures.speed / targets.velocity - 1) <= WALK_SPEED_TOLERANCE)),
        "duty_factor": bool(np.all((duty >= low) & (duty <= high))),
        "footfalls": set(measures.stride_cycles.tolist()) == cycles
        and bool(np.all(np.abs(measures.phases - expected) <= WALK_FOOTFALL_TOLERANCE)),
        "stride_length": stepping and bool(np.all(np.abs(length / predicted - 1) <= WALK_STRIDE_TOLERANCE)),
        "stride_frequency": stepping
        and bool(np.all(np.abs(frequency * predicted / at_speed - 1) <= WALK_STRIDE_TOLERANCE)),
        "trunk": bool(
            np.all(np.abs(measures.pitch) <= WALK_TILT_LIMIT)
            and np.all(np.abs(measures.roll) <= WALK_TILT_LIMIT)
            and np.all(np.ptp(measures.pitch, axis=1) <= WALK_PITCH_RANGE)
            and np.all(np.ptp(measures.roll, axis=1) <= WALK_ROLL_RANGE)
        ),
        "steady": bool(np.ptp(measures.speed) <= STEADY_SPREAD * targets.velocity),
    }


# ---- fitness -----------------------------------------------------------------------------------


def footfall_error(measures: CycleMeasures) -> float:
    """How far the footfalls land from the real walk's phases (criterion v2's footfalls term, which
    allows 0.10): the mean over the lead hoof's strides and the three other hooves of
    |phase - walk's phase|, in cycles. A hoof that does not land in a stride counts 1 (a whole
    cycle off), as does a window with no stride of the lead hoof."""
    if not len(measures.phases):
        return 1.0
    expected = np.array([WALK_FOOTFALLS[hoof] for hoof in HOOVES[1:]])
    error = np.abs(measures.phases[:, 1:] - expected)
    return float(np.mean(np.where(np.isnan(error), 1.0, error)))


def fitness_components(
    measured: WindowMeasures,
    targets: GaitTargets,
    mass: float,
    footfalls: float,
    speed_margin: float = 0.0,
) -> dict[str, float]:
    """Each component is dimensionless, so weights compare like with like; each is capped at
    :data:`COMPONENT_CAP`. ``footfalls`` is :func:`footfall_error` of the scored cycles.
    ``speed_margin`` aims the speed and stride terms that share above the walk's targets (the
    criterion keeps its own): a gait tuned exactly to the target on the flat has no room left for
    what turf costs it (docs/fitness.md, "Margins")."""
    aimed = 1.0 + speed_margin
    raw = {
        "velocity": abs(measured.velocity - aimed * targets.velocity) / (aimed * targets.velocity),
        "duty_factor": abs(measured.duty_factor - targets.duty_factor) / targets.duty_factor,
        "stride": abs(measured.stride_length - aimed * targets.stride_length)
        / (aimed * targets.stride_length),
        "frequency": abs(measured.stride_frequency - targets.stride_frequency) / targets.stride_frequency,
        # Cost of transport at the target speed: mean power over the weight times that speed
        # (revision 3's work per target cycle over m g lambda*, the same quantity).
        "energy": measured.power / (mass * G * targets.velocity),
        "steadiness": measured.speed_spread / targets.velocity,
        "footfalls": footfalls,
    }
    return {name: min(value, COMPONENT_CAP) for name, value in raw.items()}


def weighted_fitness(components: Mapping[str, float], weights: Mapping[str, float]) -> float:
    return float(sum(weights.get(name, 0.0) * value for name, value in components.items()))
