"""The closed loop's controls, computed fast (loops of one skeleton together whatever their curve,
what the sensors do not change computed a block of steps ahead, index arrays built once per set
of gaits), are bit for bit those of the plain definition: per gait, per curve, per tick, the
open-loop curves, the slots read at the phase, the skeleton run on the held sensors, the ramp,
the neutral targets and the range, in that order."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks import _populations as populations
from gaitgram.backends.mujoco.control import ClosedLoop
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.joints import CATALOGUE
from gaitgram.backends.registry import get_backend
from gaitgram.motion.gait import MotionBatch, motion_batch
from gaitgram.motion.seed_walk import load_seed
from gaitgram.pipeline import sensors_of
from gaitgram.seed.grammars import fit_seed

HORSE_SENSORS = sensors_of(get_backend("mujoco-horse"))
STEPS = 1000  # 2 s: past the ramp, several landings of every hoof


def _interpolate(samples: np.ndarray, phases: np.ndarray) -> np.ndarray:
    """A slot's samples [n + 1] read at ``phases`` in [0, 1): the definition."""
    n = len(samples) - 1
    position = phases * n
    low = np.minimum(np.floor(position).astype(np.intp), n - 1)
    fraction = position - low
    v_low = samples[low]
    return v_low + (samples[low + 1] - v_low) * fraction


def _reference(evaluator: HorseEvaluator, batch: MotionBatch, gait: int, states, sensors, steps: int):
    """Gait ``gait``'s controls for its first ``steps`` steps, alone, tick by tick, from the records
    ``states`` and ``sensors`` [steps, ...] of its play."""
    act = evaluator.actuation
    loop = evaluator.controller(batch.take([gait]), np.arange(1))  # its sensing and oscillators
    assert isinstance(loop, ClosedLoop)
    by_joint = {name: j for j, name in enumerate(batch.joints)}
    loops = [batch.loops[gait][by_joint[curve]] for curve in act.curves]
    ids = np.arange(1)
    controls = np.empty((steps, act.nu))
    for first in range(0, steps, evaluator.tick):
        last = min(first + evaluator.tick, steps)
        if first == 0:
            state, sensed = evaluator.initial_state[None], evaluator.rollout.start_sensors[None]
        else:
            state, sensed = states[None, first - 1], sensors[None, first - 1]
        own = loop.frequencies if loop.own_frequencies else None
        values = evaluator.open_loop.values(loop.table, loop.samples, first, last, own)
        readings = (
            loop.sensing.read(state, sensed, frequencies=loop.frequencies) if loop.sensing is not None else {}
        )
        clock = act.clock(first, last, loop.frequencies)
        phases = {"t": np.mod(clock, 1.0)}
        if loop.oscillators is not None:
            loop.oscillators.tick(ids, first, sensed, loop.frequencies)
            # A limb's clock moved by its last landing, wrapped into [0, 1) (none for a limbless actuator).
            limb = act.limb_index
            shift = np.where(limb >= 0, loop.oscillators.shift[0][np.maximum(limb, 0)], 0.0)
            phases["phase"] = np.mod(clock + shift, 1.0)
        for curve, closed in enumerate(loops):
            if closed is None:
                continue
            acts = np.flatnonzero(act.curve_index == curve)
            slots = [_interpolate(slot.samples, phases[slot.variable][0][:, acts]) for slot in closed.slots]
            held = {}
            for name in closed.sensors:  # a limb's sensor: its actuators' limbs; the body's: one value
                reading = readings[name][0]
                held[name] = reading[act.limb_index[acts]] if reading.ndim == 1 else reading
            result = np.broadcast_to(closed.run(slots, held), (last - first, len(acts)))
            if loop.scale != 1.0:
                result = result * loop.scale
            values[0][:, acts] = np.radians(np.where(np.isfinite(result), result, 0.0))
        controls[first:last] = act.finish(values, first, last)[0]
    return controls


def _seed_loops() -> MotionBatch:
    """The seed's curves with loops of several shapes, one curve's differing from gait to gait
    (sensors alone, sensors on a slot, a slot of the oscillator's phase, an averaged sensor),
    played at the target's frequency."""
    texts = {joint: fit.text for joint, fit in fit_seed(load_seed()).items()}
    gaits = []
    for k in range(6):
        gait = dict(texts)
        gait["hip_hind"] = f"{texts['hip_hind']}+{0.1 * k}*pitch-{0.02 * k}*pitch_rate"
        gait["fetlock_fore"] = f"{texts['fetlock_fore']}+{k}*(load-1)"
        gait["fetlock_hind"] = texts["fetlock_hind"].replace("*t", "*(phase+0.05)")
        if k % 2:
            gait["shoulder_fore"] = f"{k}*pitch"
        else:  # the pace averaged tick by tick: a tick cut by a chunk's end must not move it twice
            gait["shoulder_fore"] = f"({texts['shoulder_fore']})*(1+{0.2 * k}*(1-cycle_pace))"
        gaits.append(gait)
    return motion_batch(gaits, CATALOGUE.names, sensors=HORSE_SENSORS)


@pytest.mark.parametrize("grammar", ["hybrid-feedback.gg", "hybrid-reset.gg", "seed"])
def test_controls_are_the_definitions_bit_for_bit_as_gaits_drop_out(grammar: str) -> None:
    """Chunks of 33 steps cut ticks in two; one gait drops out after each chunk, so the loop is
    asked for fewer gaits as it goes; the grammars' gaits evolve their frequencies (several in
    play), the seed's play the target's."""
    if grammar == "seed":
        batch = _seed_loops()
        assert batch.frequencies is None
    else:
        batch = populations.generation_zero(grammar, size=8, seed=3)
        usable = [g for g in range(len(batch)) if batch.problems[g] is None]
        batch = batch.take(usable[:6])
        assert len(np.unique(batch.frequencies)) > 1
    assert batch.closed_loop
    evaluator = HorseEvaluator(chunk_steps=33)
    gaits = len(batch)
    nstate = evaluator.rollout.nstate
    states = np.zeros((gaits, STEPS, nstate))
    sensors = np.zeros((gaits, STEPS, evaluator.model.nsensordata))
    controls = np.zeros((gaits, STEPS, evaluator.model.nu))
    played = np.zeros(gaits, dtype=int)

    def keep(ids, first, state, sensordata, control, *_):
        span = slice(first, first + state.shape[1])
        states[ids, span], sensors[ids, span], controls[ids, span] = state, sensordata, control
        played[ids] = first + state.shape[1]
        dropped = np.zeros(len(ids), dtype=bool)
        dropped[-1] = first // 33 in (2, 5, 9)  # the last gait still played drops out
        return dropped

    controller = evaluator.controller(batch, np.arange(gaits))
    evaluator.rollout.run(np.full(gaits, STEPS), controller, keep)
    assert sorted(played) == [99, 198, 330] + [STEPS] * 3
    if controller.oscillators is not None:  # hooves landed: phases restarted mid-play
        assert (controller.oscillators.shift != 0).sum() >= 4
    for g in range(gaits):
        expected = _reference(evaluator, batch, g, states[g], sensors[g], played[g])
        assert np.array_equal(controls[g, : played[g]], expected), g
    evaluator.close()


def test_a_gait_whose_loops_of_two_curves_fail_together_names_the_first_curve() -> None:
    """Loops of one skeleton run together whatever their curve; the curve a failure names is still
    the first in the walker's order (the shoulder before the hip)."""
    bad = "1e300*pitch*1e300"
    batch = motion_batch([{"hip_hind": bad, "shoulder_fore": bad}], CATALOGUE.names, sensors=HORSE_SENSORS)
    (evaluation,) = HorseEvaluator().evaluate(batch)
    assert evaluation.status.value == "non-finite"
    assert "the closed loop of shoulder_fore is not finite at" in evaluation.detail
