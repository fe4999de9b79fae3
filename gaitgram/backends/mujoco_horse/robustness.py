"""Disturbances: does a gait stay upright and walking when pushed, or on uneven ground?

A walk that falls at the first disturbance is not a walk anyone can use. These trials are run on
the gaits a study hands back (``gaitgram report``), not inside the fitness. Each plays the gait
from the standing horse to the horizon (``horizon_cycles``), as the check of a kept gait does,
under one disturbance:

* **a push**: a fore-aft force on the trunk of :data:`PUSH_SHARE` of the body's weight for
  :data:`PUSH_SECONDS`, forward or backward, at the left hind's mid-stance of the first cycle
  after the warm-up: an impulse of 0.2 x 500 kg x 9.81 m/s^2 x 0.1 s = 98 N s, a change of speed
  of about 0.2 m/s (an eighth of a walk's), the size of a stumble or a bump from another horse;
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
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.measures import cycle_edges, measure_cycles
from gaitgram.backends.mujoco_horse.model import BUMP_HEIGHT, bumpy_model
from gaitgram.backends.mujoco_horse.settings import TEST_FLOORS, HorseSettings, warmup_cycles
from gaitgram.backends.mujoco_horse.task import walk_terms
from gaitgram.motion.gait import MotionBatch

PUSH_SHARE = 0.2
PUSH_SECONDS = 0.1
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
    models = [bumpy_model(horse.body, seed, bump_scale) for seed in BUMP_SEEDS]
    floors = [_played(horse, batch, disturbance, model, weights) for model in models]
    return [_on_every_floor(disturbance, [floor[g] for floor in floors]) for g in range(len(batch))]


def _played(
    horse: HorseSettings,
    batch: MotionBatch,
    disturbance: str,
    model: mujoco.MjModel | None,
    weights: Mapping[str, float] | None,
) -> list[Trial]:
    """Every gait of ``batch`` played once under ``disturbance``, on ``model``'s floor (the flat
    one when None)."""
    evaluator = HorseEvaluator(horse, model=model)
    try:
        rows = np.arange(len(batch))
        control = evaluator.controls(batch, rows, evaluator.horizon)
        forces = (
            _push(evaluator, batch, disturbance, control.shape[1]) if disturbance.startswith("push") else None
        )
        state, sensors = evaluator.simulate(control, forces)
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
        detail = f"not walking again: {', '.join(failed)}" if failed else None
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


def _push(evaluator: HorseEvaluator, batch: MotionBatch, disturbance: str, steps: int) -> np.ndarray:
    """Applied forces [gaits, steps, nbody * 6]: the push on the trunk, per gait at the left hind's
    mid-stance (phase 0.3) of its first cycle after the warm-up."""
    model = evaluator.model
    forces = np.zeros((len(batch), steps, model.nbody * 6))
    size = PUSH_SHARE * evaluator.layout.total_mass * -model.opt.gravity[2]
    sign = 1.0 if disturbance == "push-forward" else -1.0
    duration = round(PUSH_SECONDS / evaluator.dt)
    trunk = evaluator.layout.trunk_body
    for g, frequency in enumerate(evaluator.frequencies(batch, np.arange(len(batch)))):
        warmup = warmup_cycles(evaluator.settings.warmup_seconds, frequency)
        edges = cycle_edges(frequency, evaluator.dt, evaluator.ramp_steps, warmup + 1)
        start = int(edges[warmup] + round(0.3 / (frequency * evaluator.dt)))
        forces[g, start : start + duration, trunk * 6] = sign * size  # x of the force, world frame
    return forces
