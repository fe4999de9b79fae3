"""The walking task: what a gait should achieve, from the Froude number (the paper's Sec. 3.2).

Physics-free (dm_control's split of task from model): targets and the fitness
formula only. Sources and formulas are in ``docs/fitness.md``.

The paper writes Fr = v / sqrt(g h), with h the hip height; Alexander & Jayes
(1983) use Fr' = v^2 / (g h) = Fr^2. Predictions:

* speed v = Fr sqrt(g h);
* relative stride length lambda / h = 2.3 (Fr')^0.3 (Alexander 1976);
* stride frequency f = v / lambda;
* duty factor from Alexander & Jayes' figure, interpolated against sqrt(Fr') = Fr;
* walk footfalls in lateral sequence: hind left 0, fore left 0.25, hind right 0.5, fore right 0.75.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

G = 9.81

#: Bumped whenever a gait could score differently (targets, metrics, formula): runs record it, and
#: a run scored under another revision is not resumed.
TASK_REVISION = 3  # 2: strides from footfalls, capped components, unviable score, walk; 3: 0.2 s swing

#: (sqrt(Fr'), duty factor) read from Alexander & Jayes (1983).
DUTY_FACTOR_POINTS = ((0.0, 0.75), (0.45, 0.65), (0.7, 0.55), (1.0, 0.45), (1.6, 0.35), (2.5, 0.27))

#: Fraction of the cycle at which each limb's footfall comes, walk (lateral sequence).
WALK_PHASE_OFFSETS = {"hind_left": 0.0, "fore_left": 0.25, "hind_right": 0.5, "fore_right": 0.75}

#: A comfortable walk: about 1.6 m/s for a horse with a 1.14 m hip height.
DEFAULT_FROUDE = 0.48

#: Default fitness weights: errors relative to the prediction, energy as a cost of transport.
#: ``frequency`` is measured and reported but not scored by default: the paper imposes it.
DEFAULT_WEIGHTS = {"velocity": 1.0, "duty_factor": 1.0, "stride": 1.0, "frequency": 0.0, "energy": 0.1}

#: Table 2 of the paper: every component weighted 1 ("distance" is the velocity term).
PAPER_WEIGHTS = {"velocity": 1.0, "duty_factor": 1.0, "stride": 1.0, "frequency": 0.0, "energy": 1.0}

#: No component counts for more than this (500 % error): one absurd measure cannot swamp the rest,
#: and every viable fitness is at most COMPONENT_CAP x the sum of the weights.
COMPONENT_CAP = 5.0

#: An unviable gait scores as if every component were at twice the cap: worse than any viable
#: gait, yet finite, so that averages over a population mean something (docs/fitness.md).
UNVIABLE_COMPONENT = 2 * COMPONENT_CAP

#: The cycle frequencies (Hz) a grammar's ``@frequency`` rule may give a gait: from a slow walk
#: (a horse's is about 0.7 Hz) to a fast trot (about 1.6 Hz), with room on either side.
CYCLE_FREQUENCIES = (0.3, 3.0)

#: A walk, for the walk rate: speed within 10 % of the target and duty factor within 0.05.
WALK_SPEED_TOLERANCE = 0.10
WALK_DUTY_TOLERANCE = 0.05


@dataclass(frozen=True)
class GaitTargets:
    froude: float  # the paper's Fr = v / sqrt(g h)
    hip_height: float
    velocity: float  # m/s
    stride_length: float  # m
    stride_frequency: float  # Hz
    duty_factor: float
    phase_offsets: Mapping[str, float]


def duty_factor_for(froude: float) -> float:
    xs, ys = zip(*DUTY_FACTOR_POINTS, strict=True)
    return float(np.interp(froude, xs, ys))


def walk_targets(froude: float = DEFAULT_FROUDE, hip_height: float = 1.14) -> GaitTargets:
    if not 0 < froude <= 2.5:
        raise ValueError(f"froude must be in (0, 2.5], not {froude}")
    if hip_height <= 0:
        raise ValueError("hip_height must be positive")
    velocity = froude * math.sqrt(G * hip_height)
    stride = hip_height * 2.3 * (froude**2) ** 0.3
    return GaitTargets(
        froude=froude,
        hip_height=hip_height,
        velocity=velocity,
        stride_length=stride,
        stride_frequency=velocity / stride,
        duty_factor=duty_factor_for(froude),
        phase_offsets=dict(WALK_PHASE_OFFSETS),
    )


@dataclass(frozen=True)
class GaitMetrics:
    """What the simulation measured over the scored cycles."""

    velocity: float  # mean forward speed of the trunk, m/s
    duty_factor: float  # mean over hooves of the share of time on the ground
    stride_length: float  # mean over hooves of the forward distance between successive touchdowns, m
    stride_frequency: float  # mean over hooves of 1 / the time between successive touchdowns, Hz
    work_per_cycle: float  # actuator work per cycle, J (positive and negative work both cost)


def fitness_components(metrics: GaitMetrics, targets: GaitTargets, mass: float) -> dict[str, float]:
    """Each component is dimensionless, so weights compare like with like; each is capped at
    :data:`COMPONENT_CAP`."""
    raw = {
        "velocity": abs(metrics.velocity - targets.velocity) / targets.velocity,
        "duty_factor": abs(metrics.duty_factor - targets.duty_factor) / targets.duty_factor,
        "stride": abs(metrics.stride_length - targets.stride_length) / targets.stride_length,
        "frequency": abs(metrics.stride_frequency - targets.stride_frequency) / targets.stride_frequency,
        # Cost of transport: work per cycle over the work of lifting the body one stride.
        "energy": metrics.work_per_cycle / (mass * G * targets.stride_length),
    }
    return {name: min(value, COMPONENT_CAP) for name, value in raw.items()}


def is_walk(metrics: GaitMetrics, targets: GaitTargets) -> bool:
    """The walk-rate criterion: near the target speed and the target duty factor."""
    return (
        abs(metrics.velocity - targets.velocity) <= WALK_SPEED_TOLERANCE * targets.velocity
        and abs(metrics.duty_factor - targets.duty_factor) <= WALK_DUTY_TOLERANCE
    )


def weighted_fitness(components: Mapping[str, float], weights: Mapping[str, float]) -> float:
    return float(sum(weights.get(name, 0.0) * value for name, value in components.items()))


def unviable_fitness(weights: Mapping[str, float]) -> float:
    """The score of a gait that fell, flipped, diverged or could not be built."""
    return UNVIABLE_COMPONENT * float(sum(weights.values()))
