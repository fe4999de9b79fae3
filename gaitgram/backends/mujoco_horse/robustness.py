"""Disturbances: does a gait stay upright and walking when pushed, or on uneven ground?

A walk that falls at the first disturbance is not a walk anyone can use. These trials are run on
the gaits a study hands back (``gaitgram report``), not inside the fitness. Each plays the gait
from the standing horse to the horizon (``horizon_cycles``), as the check of a kept gait does,
under one disturbance:

* **a push**: a fore-aft force on the trunk of :data:`PUSH_SHARE` of the body's weight for
  :data:`PUSH_SECONDS`, forward or backward, at phase :data:`PUSH_PHASE` of the left hind's
  first cycle after the warm-up (in its swing: it lands at 0.57-0.62 in the walks measured):
  an impulse of 0.2 x 500 kg x 9.81 m/s^2 x 0.1 s = 98 N s, a change of speed of about
  0.2 m/s (an eighth of a walk's), the size of a stumble or a bump from another horse;
* **bumps**: the floor a height field of random heights up to 2 cm (uniform, in 10 cm cells:
  :func:`~gaitgram.backends.mujoco_horse.model.bumpy_model`), flat under the standing horse and
  for a metre ahead:
  uneven turf under a 14 cm hoof. One seeded floor is one sample of such turf, and whether a gait
  crosses it is close to a coin toss for many gaits (of 71 kept walks played on ten floors, 33
  held on none, 3 on all, 35 on some), so the gait is played on each of
  :data:`BUMP_SEEDS`' floors and the trial keeps how many it held.

A gait **holds** under a disturbance when it stays upright for the whole horizon and is a walk
by criterion v2 (every term but ``steady`` and ``sustained``, per cycle) over the horizon's last
:data:`RECOVERY_CYCLES` cycles: it may stumble, but it must be walking again. Under the bumps it
must do so on every floor: a walk that falls on one turf in ten is not one a user can rely on. The sizes are
gaitgram's choice, stated here and in ``docs/fitness.md``; no published perturbation standard
for simulated horses was found.

The **graded trial** (:data:`GRADES`, :func:`graded`) gives "robust" a size: each family of
disturbance in rungs of growing size, the first rung of the bumps today's trial itself:

* bumps of 2, 4 and 6 cm on the same ten floors (each bump of the draw twice and three times as
  tall), held on every floor;
* pushes forward and backward of 20 % and 40 % of body weight, each at :data:`PUSH_PHASES`, eight
  phases of the left hind's first cycle after the warm-up, held at every phase;
* slopes up and down of 3 and 6 degrees (gravity tilted: the ground's frame is the slope's), held
  from the standing start.

Every play is a play of the gait as it is scored (a closed loop closes here too), from the
standing horse to the horizon, judged as above.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.measures import cycle_edges, measure_cycles
from gaitgram.backends.mujoco_horse.model import BUMP_HEIGHT, bumpy_model, load_model
from gaitgram.backends.mujoco_horse.reference import NOT_WALKING
from gaitgram.backends.mujoco_horse.settings import TEST_FLOORS, HorseSettings, warmup_cycles
from gaitgram.backends.mujoco_horse.task import walk_terms
from gaitgram.motion.gait import MotionBatch

PUSH_SHARE = 0.2
PUSH_SECONDS = 0.1
#: When the trial's push comes: at this phase of the left hind's cycle (in its swing: it lands at
#: 0.57-0.62 in the walks measured), the first cycle after the warm-up.
PUSH_PHASE = 0.3
#: One floor per seed; ten floors tell a gait that holds on most from one that was lucky once.
BUMP_SEEDS = TEST_FLOORS
RECOVERY_CYCLES = 5
#: The walk terms a disturbed gait must hold again; ``steady`` and ``sustained`` describe an
#: undisturbed gait.
RECOVERED_TERMS = ("speed", "duty_factor", "footfalls", "stride_length", "stride_frequency", "trunk")


@dataclass(frozen=True)
class Disturbance:
    name: str
    describe: str


DISTURBANCES: tuple[Disturbance, ...] = (
    Disturbance("push-forward", f"a forward push of {PUSH_SHARE:.0%} of body weight for {PUSH_SECONDS} s"),
    Disturbance("push-backward", f"a backward push of {PUSH_SHARE:.0%} of body weight for {PUSH_SECONDS} s"),
    Disturbance(
        "bumps",
        f"{len(BUMP_SEEDS)} floors of random bumps up to {BUMP_HEIGHT * 100:.0f} cm "
        f"(seeds {BUMP_SEEDS[0]}-{BUMP_SEEDS[-1]}), held on every one",
    ),
)


@dataclass(frozen=True)
class Trial:
    """How one gait fared under one disturbance."""

    disturbance: str
    upright: bool  # on every floor
    walking: bool  # walking again over the last cycles of the horizon, on every floor
    detail: str | None = None
    floors: int = 1  # how many floors the gait was played on
    held: int = 0  # on how many of them it held (stayed upright and walking again)

    @property
    def holds(self) -> bool:
        return self.upright and self.walking


def disturbed(
    settings: Mapping[str, object],
    batch: MotionBatch,
    disturbance: str,
    weights: Mapping[str, float] | None = None,
    *,
    bump_scale: float = 1.0,
) -> list[Trial]:
    """Every gait of ``batch`` played to the horizon under ``disturbance`` (a name in
    :data:`DISTURBANCES`), with the backend settings of the run it came from. ``bump_scale``
    sizes the bumps (:func:`~gaitgram.backends.mujoco_horse.model.bumpy_model`; the trial's, and
    every kept assessment's, are 1)."""
    names = [d.name for d in DISTURBANCES]
    if disturbance not in names:
        raise ValueError(f"no disturbance named {disturbance!r}; known: {', '.join(names)}")
    horse = HorseSettings.from_mapping(settings)
    if disturbance != "bumps":
        return _played(horse, batch, disturbance, None, weights)
    floors = [on_floor(settings, batch, seed, weights, bump_scale=bump_scale) for seed in BUMP_SEEDS]
    return [_on_every_floor(disturbance, [floor[g] for floor in floors]) for g in range(len(batch))]


def on_floor(
    settings: Mapping[str, object],
    batch: MotionBatch,
    seed: int,
    weights: Mapping[str, float] | None = None,
    *,
    bump_scale: float = 1.0,
) -> list[Trial]:
    """Every gait of ``batch`` played to the horizon on the bump floor drawn from ``seed``: one
    floor of the ``bumps`` disturbance, each trial's detail naming the walk terms it lost."""
    horse = HorseSettings.from_mapping(settings)
    return _played(horse, batch, "bumps", bumpy_model(horse.body, seed, bump_scale), weights)


def _played(
    horse: HorseSettings,
    batch: MotionBatch,
    disturbance: str,
    model: mujoco.MjModel | None,
    weights: Mapping[str, float] | None,
    pushes: Sequence[tuple[float, float]] | None = None,
) -> list[Trial]:
    """Every gait of ``batch`` played once under ``disturbance``, on ``model``'s floor (the flat
    one when None); ``pushes`` gives each gait its push (signed share of body weight, phase), by
    default the trial's for a push and none otherwise."""
    evaluator = HorseEvaluator(horse, model=model)
    try:
        rows = np.arange(len(batch))
        if pushes is None and disturbance.startswith("push"):
            sign = 1.0 if disturbance == "push-forward" else -1.0
            pushes = [(sign * PUSH_SHARE, PUSH_PHASE)] * len(batch)
        steps = int(evaluator.ends_at(batch, rows, evaluator.horizon).max())
        forces = None if pushes is None else _push(evaluator, batch, pushes, steps)
        state, sensors, control = evaluator.play(batch, rows, evaluator.horizon, forces)
        frequencies = evaluator.frequencies(batch, rows)
        scored = evaluator.score(state, sensors, control, weights or {}, frequencies, evaluator.horizon)
        recordings = evaluator.recordings(state, sensors, control, frequencies)
    finally:
        evaluator.close()
    trials = []
    for evaluation, recording in zip(scored, recordings, strict=True):
        if not evaluation.status.viable:
            trials.append(Trial(disturbance, False, False, evaluation.detail))
            continue
        last = measure_cycles(
            recording, evaluator.horizon - RECOVERY_CYCLES, evaluator.horizon, evaluator.gap_steps
        )
        terms = walk_terms(last, evaluator.targets)
        failed = [t for t in RECOVERED_TERMS if not terms[t]]
        detail = f"{NOT_WALKING}{', '.join(failed)}" if failed else None
        trials.append(Trial(disturbance, True, not failed, detail, held=int(not failed)))
    return trials


def _on_every_floor(disturbance: str, floors: list[Trial]) -> Trial:
    """One gait's trials on each bump floor as one: upright and walking on every floor; the detail
    names how many it held and the first floor it did not."""
    held = sum(t.holds for t in floors)
    failed = [(seed, t.detail) for seed, t in zip(BUMP_SEEDS, floors, strict=True) if not t.holds]
    detail = None
    if failed:
        seed, why = failed[0]
        detail = f"held on {held} of {len(floors)} floors; on seed {seed}: {why}"
    return Trial(
        disturbance,
        all(t.upright for t in floors),
        all(t.walking for t in floors),
        detail,
        len(floors),
        held,
    )


def _push(
    evaluator: HorseEvaluator, batch: MotionBatch, pushes: Sequence[tuple[float, float]], steps: int
) -> np.ndarray:
    """Applied forces [gaits, steps, nbody * 6]: per gait its push on the trunk (a signed share of
    body weight, forward positive) for :data:`PUSH_SECONDS`, at its phase of the left hind's first
    cycle after the warm-up."""
    model = evaluator.model
    forces = np.zeros((len(batch), steps, model.nbody * 6))
    weight = evaluator.layout.total_mass * -model.opt.gravity[2]
    duration = round(PUSH_SECONDS / evaluator.dt)
    trunk = evaluator.layout.trunk_body
    frequencies = evaluator.frequencies(batch, np.arange(len(batch)))
    for g, (frequency, (share, phase)) in enumerate(zip(frequencies, pushes, strict=True)):
        warmup = warmup_cycles(evaluator.settings.warmup_seconds, frequency)
        edges = cycle_edges(frequency, evaluator.dt, evaluator.ramp_steps, warmup + 1)
        start = int(edges[warmup] + round(phase / (frequency * evaluator.dt)))
        forces[g, start : start + duration, trunk * 6] = share * weight  # x of the force, world frame
    return forces


# ---- the graded trial ---------------------------------------------------------------------------

#: The phases of the cycle the graded trial pushes at (of the left hind's cycle, as the trial's).
PUSH_PHASES: tuple[float, ...] = tuple(k / 8 for k in range(8))


@dataclass(frozen=True)
class Rung:
    """One size of one family of disturbance."""

    family: str  # bumps, push-forward, push-backward, slope-up, slope-down
    size: float
    unit: str

    @property
    def name(self) -> str:
        return f"{self.family} {self.size:g} {self.unit}"

    @property
    def describe(self) -> str:
        if self.family == "bumps":
            return f"{len(BUMP_SEEDS)} floors of random bumps up to {self.size:g} cm, held on every one"
        if self.family.startswith("push"):
            way = self.family.removeprefix("push-")
            return (
                f"a {way} push of {self.size:g} % of body weight for {PUSH_SECONDS} s, "
                f"at each of {len(PUSH_PHASES)} phases of the cycle, held at every one"
            )
        way = self.family.removeprefix("slope-")
        return f"a slope {way} of {self.size:g} degrees from the standing start"


#: Each family in rungs of growing size; the first rung of the bumps is the trial's own.
GRADES: tuple[Rung, ...] = (
    *(Rung("bumps", size, "cm") for size in (2, 4, 6)),
    *(Rung(f"push-{way}", size, "%") for way in ("forward", "backward") for size in (20, 40)),
    *(Rung(f"slope-{way}", size, "deg") for way in ("up", "down") for size in (3, 6)),
)
FAMILIES: tuple[str, ...] = tuple(dict.fromkeys(rung.family for rung in GRADES))


def graded(
    settings: Mapping[str, object],
    batch: MotionBatch,
    weights: Mapping[str, float] | None = None,
    *,
    known: Mapping[str, Sequence[Trial]] | None = None,
) -> list[list[Trial]]:
    """Per gait of ``batch``, its trial on each rung of :data:`GRADES` (``Trial.disturbance`` the
    rung's name; ``floors`` the plays, ``held`` how many it held). ``known`` gives rungs already
    played (the trial's own bumps, as ``disturbed`` gave them), by rung name."""
    found: dict[str, list[Trial]] = {}
    for rung in GRADES:
        if known is not None and rung.name in known:
            found[rung.name] = [replace_name(t, rung.name) for t in known[rung.name]]
        else:
            found[rung.name] = on_rung(settings, batch, rung, weights)
    return [[found[rung.name][g] for rung in GRADES] for g in range(len(batch))]


def on_rung(
    settings: Mapping[str, object],
    batch: MotionBatch,
    rung: Rung,
    weights: Mapping[str, float] | None = None,
) -> list[Trial]:
    """Every gait of ``batch`` on one rung (of :data:`GRADES`, or any size of its families): its
    floors, phases or slope, as :func:`graded` plays them."""
    horse = HorseSettings.from_mapping(settings)
    if rung.family == "bumps":
        height = BUMP_HEIGHT * rung.size / 2
        floors = [
            _played(horse, batch, rung.name, bumpy_model(horse.body, seed, 1.0, height), weights)
            for seed in BUMP_SEEDS
        ]
        return [
            replace_name(_on_every_floor(rung.name, [floor[g] for floor in floors]), rung.name)
            for g in range(len(batch))
        ]
    if rung.family.startswith("push"):
        return _pushed(horse, batch, rung, weights)
    return _sloped(horse, batch, rung, weights)


def replace_name(trial: Trial, name: str) -> Trial:
    return Trial(name, trial.upright, trial.walking, trial.detail, trial.floors, trial.held)


def _pushed(
    horse: HorseSettings, batch: MotionBatch, rung: Rung, weights: Mapping[str, float] | None
) -> list[Trial]:
    """Every gait pushed at each of :data:`PUSH_PHASES`, all plays in one batch."""
    sign = 1.0 if rung.family == "push-forward" else -1.0
    rows = [g for g in range(len(batch)) for _ in PUSH_PHASES]
    pushes = [(sign * rung.size / 100, phase) for _ in range(len(batch)) for phase in PUSH_PHASES]
    plays = _played(horse, batch.take(rows), rung.name, None, weights, pushes)
    trials = []
    for g in range(len(batch)):
        mine = plays[g * len(PUSH_PHASES) : (g + 1) * len(PUSH_PHASES)]
        held = sum(t.holds for t in mine)
        failed = [(phase, t.detail) for phase, t in zip(PUSH_PHASES, mine, strict=True) if not t.holds]
        detail = None
        if failed:
            phase, why = failed[0]
            detail = f"held at {held} of {len(mine)} phases; at phase {phase:g}: {why}"
        trials.append(
            Trial(
                rung.name, all(t.upright for t in mine), all(t.walking for t in mine), detail, len(mine), held
            )
        )
    return trials


def sloped_model(body: str | None, degrees: float) -> mujoco.MjModel:
    """A body on a slope of ``degrees`` (up positive, the way it walks): gravity tilted about the
    lateral axis, so that the ground's frame is the slope's and heights stay heights above it."""
    model = copy.copy(load_model(body))
    g = float(np.linalg.norm(model.opt.gravity))
    angle = math.radians(degrees)
    model.opt.gravity[:] = [-g * math.sin(angle), 0.0, -g * math.cos(angle)]
    return model


def _sloped(
    horse: HorseSettings, batch: MotionBatch, rung: Rung, weights: Mapping[str, float] | None
) -> list[Trial]:
    degrees = rung.size if rung.family == "slope-up" else -rung.size
    trials = _played(horse, batch, rung.name, sloped_model(horse.body, degrees), weights)
    return [Trial(rung.name, t.upright, t.walking, t.detail, 1, int(t.holds)) for t in trials]
