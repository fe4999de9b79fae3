"""What a walk should be for a body: the targets the Froude number predicts, the fitness weights,
and walk criterion v2's terms and tolerances. Sources and formulas are in ``docs/fitness.md``.

Numbers, not physics or measures (dm_control's split of task from model), and no numpy at import:
the linter and ``gaitgram check`` read the backend's declaration, which is built from these.

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
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

G = 9.81

#: Bumped whenever a gait could score differently (targets, metrics, formula): runs record it, and
#: a run scored under another revision is not resumed. 2: strides from footfalls, capped
#: components, unviable score, walk; 3: 0.2 s swing; 4: steady-state cycles after a warm-up,
#: steadiness, a horizon for the gaits a run keeps, walk criterion v2.
TASK_REVISION = 4

#: (sqrt(Fr'), duty factor) read from Alexander & Jayes (1983).
DUTY_FACTOR_POINTS = ((0.0, 0.75), (0.45, 0.65), (0.7, 0.55), (1.0, 0.45), (1.6, 0.35), (2.5, 0.27))

#: Fraction of the cycle at which each limb's footfall comes, walk (lateral sequence): the phases
#: the backend plays each limb's curve at.
WALK_PHASE_OFFSETS = {"hind_left": 0.0, "fore_left": 0.25, "hind_right": 0.5, "fore_right": 0.75}

#: A comfortable walk: about 1.6 m/s for a horse with a 1.14 m hip height.
DEFAULT_FROUDE = 0.48

#: Default fitness weights: errors relative to the prediction, energy as a cost of transport,
#: steadiness as the spread of the per-cycle speeds. ``frequency`` is measured and reported but
#: not scored by default: a gait at the target speed with the target stride has it. ``footfalls``
#: (how far the footfalls land from the real walk's phases) is measured, and not scored by
#: default either: weighting it is a choice a run makes (docs/fitness.md, "Margins").
DEFAULT_WEIGHTS = {
    "velocity": 1.0,
    "duty_factor": 1.0,
    "stride": 1.0,
    "frequency": 0.0,
    "energy": 0.1,
    "steadiness": 1.0,
    "footfalls": 0.0,
}

#: Table 2 of the paper: every component it has weighted 1 ("distance" is the velocity term); the
#: paper has no steadiness term.
PAPER_WEIGHTS = {
    "velocity": 1.0,
    "duty_factor": 1.0,
    "stride": 1.0,
    "frequency": 0.0,
    "energy": 1.0,
    "steadiness": 0.0,
    "footfalls": 0.0,
}

#: No component counts for more than this (500 % error): one absurd measure cannot swamp the rest,
#: and every viable fitness is at most COMPONENT_CAP x the sum of the weights.
COMPONENT_CAP = 5.0

#: An unviable gait scores as if every component were at twice the cap: worse than any viable
#: gait, yet finite, so that averages over a population mean something (docs/fitness.md).
UNVIABLE_COMPONENT = 2 * COMPONENT_CAP

#: The cycle frequencies (Hz) a grammar's ``@frequency`` rule may give a gait: from a slow walk
#: (a horse's is about 0.7 Hz) to a fast trot (about 1.6 Hz), with room on either side.
CYCLE_FREQUENCIES = (0.3, 3.0)


# ---- walk criterion v2 -------------------------------------------------------------------------

#: The criterion's revision, recorded by reports (v2 came with fitness revision 4: docs/fitness.md).
WALK_CRITERION = "v2"


#: Speed: every measured cycle within this share of the target speed.
WALK_SPEED_TOLERANCE = 0.10
#: Duty factor (mean over the hooves, every cycle) from the lower quartile of the DLC_Horse walks
#: (seeds/dlc_walk.json: median 0.588, IQR 0.55-0.63) to Alexander & Jayes' value at the target
#: Froude number plus this margin.
WALK_DUTY_LOW = 0.55
WALK_DUTY_MARGIN = 0.05
#: Footfalls after the left hind's, as a share of its stride: the DLC_Horse walks' medians.
WALK_FOOTFALLS = {"fore_left": 0.25, "hind_right": 0.50, "fore_right": 0.731}
#: How far a footfall may be from them: 2 SD of the real walks' left-fore phase (SD from the
#: IQR, 0.211-0.278, as IQR / 1.349). A trot lands the left fore at 0.5, a pace at 0.
WALK_FOOTFALL_TOLERANCE = 0.10
#: Stride length and frequency, every stride: within this share of what Alexander's relation
#: predicts at the gait's own speed (horses scatter 3-4 % about a common fit at equal Froude
#: number, Bullimore & Burn 2006; species follow Alexander's line within about 20-30 %).
WALK_STRIDE_TOLERANCE = 0.15
#: Trunk pitch and roll: within this many degrees of level at every step (Dunbar et al. 2008:
#: horses keep the trunk within 20 degrees in every plane and gait) ...
WALK_TILT_LIMIT = 10.0
#: ... and a pitch range within a cycle no larger than the flexion-extension of the back at the
#: walk (Faber et al. 2000: about 7 degrees), a roll range no larger than its axial rotation
#: (about 13 degrees at the tuber coxae).
WALK_PITCH_RANGE = 7.0
WALK_ROLL_RANGE = 13.0
#: Steady: the per-cycle speeds spread by no more than this share of the target speed.
STEADY_SPREAD = 0.05


@dataclass(frozen=True)
class WalkTerm:
    """One term of the walk criterion: its component name, what it asks, and where that is from."""

    name: str
    asks: str


#: The terms, in the order a report lists them; each is a 0/1 component ``walk_<name>``.
WALK_TERMS: tuple[WalkTerm, ...] = (
    WalkTerm("speed", "every cycle within 10 % of the target speed"),
    WalkTerm("duty_factor", "every cycle's duty factor between 0.55 and the target's + 0.05"),
    WalkTerm("footfalls", "four-beat lateral sequence, each footfall within 0.10 of the real walk's phase"),
    WalkTerm("stride_length", "every stride within 15 % of Alexander's length at the gait's speed"),
    WalkTerm("stride_frequency", "every stride within 15 % of the frequency that length implies"),
    WalkTerm("trunk", "pitch and roll within 10 degrees of level, per-cycle ranges within 7 and 13"),
    WalkTerm("steady", "per-cycle speeds within a spread of 5 % of the target speed"),
    WalkTerm("sustained", "upright, and every term held, over every cycle of the horizon"),
)
WALK_COMPONENTS = tuple(f"walk_{term.name}" for term in WALK_TERMS)


@dataclass(frozen=True)
class GaitTargets:
    froude: float  # the paper's Fr = v / sqrt(g h)
    hip_height: float
    velocity: float  # m/s
    stride_length: float  # m
    stride_frequency: float  # Hz
    duty_factor: float
    phase_offsets: Mapping[str, float]

    @property
    def duty_window(self) -> tuple[float, float]:
        """The walk's duty factors: from the real walks' lower quartile to the prediction + margin."""
        return WALK_DUTY_LOW, self.duty_factor + WALK_DUTY_MARGIN

    def stride_at(self, speed: float | np.ndarray) -> float | np.ndarray:
        """Alexander's stride length (m) at ``speed`` for this hip height."""
        import numpy as np  # only when gaits are scored: not at the linter's import

        return self.hip_height * 2.3 * (np.asarray(speed) ** 2 / (G * self.hip_height)) ** 0.3


def duty_factor_for(froude: float) -> float:
    import numpy as np  # only when gaits are scored: not at the linter's import

    xs, ys = zip(*DUTY_FACTOR_POINTS, strict=True)
    return float(np.interp(froude, xs, ys))


def _speed_and_stride(froude: float, hip_height: float) -> tuple[float, float]:
    """The speed (m/s) at Froude number ``froude`` and Alexander's stride (m) at that speed."""
    return froude * math.sqrt(G * hip_height), hip_height * 2.3 * (froude**2) ** 0.3


def stride_frequency(froude: float, hip_height: float) -> float:
    """The target's stride frequency (Hz), as :func:`walk_targets` gives it, without numpy: what the
    backend declares it plays a gait at (``BackendSpec.cycle_frequency``)."""
    velocity, stride = _speed_and_stride(froude, hip_height)
    return velocity / stride


def walk_targets(froude: float = DEFAULT_FROUDE, hip_height: float = 1.14) -> GaitTargets:
    if not 0 < froude <= 2.5:
        raise ValueError(f"froude must be in (0, 2.5], not {froude}")
    if hip_height <= 0:
        raise ValueError("hip_height must be positive")
    velocity, stride = _speed_and_stride(froude, hip_height)
    return GaitTargets(
        froude=froude,
        hip_height=hip_height,
        velocity=velocity,
        stride_length=stride,
        stride_frequency=velocity / stride,
        duty_factor=duty_factor_for(froude),
        phase_offsets=dict(WALK_PHASE_OFFSETS),
    )


def unviable_fitness(weights: Mapping[str, float]) -> float:
    """The score of a gait that fell, flipped, diverged or could not be built."""
    return UNVIABLE_COMPONENT * float(sum(weights.values()))
