"""Closed loops: sensors read from MuJoCo's state as declared, controls computed from them at the
control rate and held in between, and a loop without sensors the open loop to the bit."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from types import MappingProxyType

import mujoco
import numpy as np
import pytest

from gaitgram.backends.mujoco.control import Actuation, ClosedLoop, Oscillators
from gaitgram.backends.mujoco.rollout import STATE_SPEC
from gaitgram.backends.mujoco.sensing import Sensing, SensingError
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.joints import CATALOGUE, SENSORS
from gaitgram.backends.mujoco_horse.model import LIMBS
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.backends.registry import get_backend
from gaitgram.backends.sensors import SensorCatalogue
from gaitgram.motion.gait import motion_batch
from gaitgram.motion.seed_walk import load_seed
from gaitgram.pipeline import sensors_of
from gaitgram.seed.grammars import SEED_TOUCHDOWN, fit_seed

HORSE_SENSORS = sensors_of(get_backend("mujoco-horse"))

#: A trunk on three degrees of freedom (as the horse's) with one foot below it.
SLAB = """
<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="trunk" pos="0 0 0.6">
      <joint name="root_x" type="slide" axis="1 0 0"/>
      <joint name="root_z" type="slide" axis="0 0 1"/>
      <joint name="root_pitch" type="hinge" axis="0 1 0"/>
      <geom type="box" size="0.3 0.1 0.05" mass="40"/>
      <site name="trunk"/>
      <body name="leg" pos="0 0 -0.3">
        <geom name="foot" type="box" size="0.05 0.05 0.25" mass="10"/>
        <site name="foot" type="box" pos="0 0 -0.25" size="0.06 0.06 0.02"/>
      </body>
    </body>
  </worldbody>
  <sensor>
    <framequat name="trunk_quat" objtype="site" objname="trunk"/>
    <framepos name="trunk_pos" objtype="site" objname="trunk"/>
    <framelinvel name="trunk_linvel" objtype="site" objname="trunk"/>
    <touch name="hoof_only" site="foot"/>
  </sensor>
</mujoco>
"""


def _slab_sensors() -> SensorCatalogue:
    by_name = {sensor.name: sensor for sensor in SENSORS}
    return SensorCatalogue(
        (
            by_name["pitch"],
            by_name["pitch_rate"],
            by_name["speed"],
            by_name["pace"],
            replace(by_name["height"], read=MappingProxyType({**by_name["height"].read})),
            by_name["load"],
            by_name["contact"],
        )
    )


def _record(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
    state = np.empty(mujoco.mj_stateSize(model, STATE_SPEC))
    mujoco.mj_getState(model, data, state, STATE_SPEC)
    return state[None, :], data.sensordata.copy()[None, :]


def test_a_known_pitch_rate_height_and_speed_are_read_as_declared() -> None:
    model = mujoco.MjModel.from_xml_string(SLAB)
    data = mujoco.MjData(model)
    data.qpos[:] = [0.4, 0.1, 0.2]  # x, z, pitch (about +y: nose down)
    data.qvel[:] = [1.25, 0.0, -0.3]
    mujoco.mj_forward(model, data)
    facts = {"standing_height": 0.6, "quarter_weight": 50 * 9.81 / 4}
    sensing = Sensing(
        model, _slab_sensors(), {"pitch", "pitch_rate", "height", "speed"}, limbs=("only",), facts=facts
    )
    readings = sensing.read(*_record(model, data))
    assert readings["pitch"][0] == pytest.approx(-math.degrees(0.2), abs=1e-9)  # nose down is negative
    assert readings["pitch_rate"][0] == pytest.approx(math.degrees(0.3), abs=1e-9)  # rising nose
    assert readings["height"][0] == pytest.approx(0.1, abs=1e-9)  # 0.7 m against 0.6 standing
    assert readings["speed"][0] == pytest.approx(1.25, abs=1e-9)


def test_pace_is_the_speed_as_a_share_of_the_walkers_target() -> None:
    model = mujoco.MjModel.from_xml_string(SLAB)
    data = mujoco.MjData(model)
    data.qvel[:] = [1.25, 0.0, 0.0]
    mujoco.mj_forward(model, data)
    facts = {"standing_height": 0.6, "quarter_weight": 50 * 9.81 / 4, "target_speed": 0.5}
    sensing = Sensing(model, _slab_sensors(), {"speed", "pace"}, limbs=("only",), facts=facts)
    readings = sensing.read(*_record(model, data))
    assert readings["pace"][0] == pytest.approx(2.5, abs=1e-9)  # 1.25 m/s against 0.5
    assert readings["speed"][0] == pytest.approx(1.25, abs=1e-9)  # the same velocity, unscaled
    with pytest.raises(SensingError, match="per names 'target_speed', which the walker does not give"):
        Sensing(model, _slab_sensors(), {"pace"}, limbs=("only",), facts={"standing_height": 0.6})


def test_cycle_pace_is_the_pace_averaged_tick_by_tick_over_each_gait_s_own_cycle() -> None:
    """An exponential average from the nominal 1, its time constant one cycle of the gait: after
    n ticks at a steady pace p, p + (1 - p) exp(-n tick f); a tick's second part (cut by a chunk's
    end) does not move it; only the gaits read are updated, each at its own frequency."""
    model = mujoco.MjModel.from_xml_string(SLAB)
    data = mujoco.MjData(model)
    data.qvel[:] = [0.4, 0.0, 0.0]
    mujoco.mj_forward(model, data)
    facts = {"standing_height": 0.6, "quarter_weight": 50 * 9.81 / 4, "target_speed": 0.5}
    by_name = {sensor.name: sensor for sensor in SENSORS}
    catalogue = SensorCatalogue((by_name["pace"], by_name["cycle_pace"]))
    tick = 0.01
    sensing = Sensing(
        model, catalogue, {"pace", "cycle_pace"}, limbs=("only",), facts=facts, gaits=3, tick_seconds=tick
    )
    state, sensed = _record(model, data)
    frequencies = np.array([0.5, 1.0, 2.0])
    for _ in range(50):
        readings = sensing.read(np.repeat(state, 3, 0), np.repeat(sensed, 3, 0), frequencies=frequencies)
    assert readings["pace"] == pytest.approx([0.8] * 3, abs=1e-12)  # raw: 0.4 m/s against 0.5
    expected = 0.8 + 0.2 * np.exp(-50 * tick * frequencies)
    assert readings["cycle_pace"] == pytest.approx(expected, rel=1e-12)
    held = sensing.read(np.repeat(state, 3, 0), np.repeat(sensed, 3, 0), frequencies=frequencies, tick=False)
    assert np.array_equal(held["cycle_pace"], readings["cycle_pace"])
    ids = np.array([2])  # the others dropped out
    (later,) = sensing.read(state, sensed, ids=ids, frequencies=frequencies[ids])["cycle_pace"]
    assert later == pytest.approx(0.8 + 0.2 * np.exp(-51 * tick * 2.0), rel=1e-12)
    assert sensing.averages["cycle_pace"][:2] == pytest.approx(expected[:2], rel=1e-12)
    with pytest.raises(ValueError, match="averaged over the cycle: give the frequencies"):
        sensing.read(state, sensed, ids=ids)
    bad = replace(
        by_name["cycle_pace"], read=MappingProxyType({**by_name["cycle_pace"].read, "average_cycles": 0})
    )
    with pytest.raises(SensingError, match="average_cycles must be a number of cycles in"):
        Sensing(model, SensorCatalogue((bad,)), {"cycle_pace"}, limbs=("only",), facts=facts)


def test_the_horse_paces_at_one_when_it_walks_at_its_target_on_any_body() -> None:
    """``pace`` divides by the task's own target, which scales with the body (retargeting)."""
    for body in (None, "pony"):
        evaluator = HorseEvaluator(HorseSettings(body=body))
        target = evaluator.targets.velocity
        assert evaluator._facts["target_speed"] == target
        model, data = evaluator.model, mujoco.MjData(evaluator.model)
        data.qvel[0] = target  # the root's forward slide
        mujoco.mj_forward(model, data)
        sensing = Sensing(model, SENSORS, {"speed", "pace"}, limbs=LIMBS, facts=evaluator._facts)
        readings = sensing.read(*_record(model, data))
        assert readings["pace"][0] == pytest.approx(1.0, abs=1e-6)
        assert readings["speed"][0] == pytest.approx(target, abs=1e-6)


def test_a_known_contact_and_load_are_read_as_declared() -> None:
    model = mujoco.MjModel.from_xml_string(SLAB)
    data = mujoco.MjData(model)
    facts = {"standing_height": 0.6, "quarter_weight": 50 * 9.81 / 4}
    sensing = Sensing(model, _slab_sensors(), {"load", "contact"}, limbs=("only",), facts=facts)
    mujoco.mj_forward(model, data)
    up = sensing.read(*_record(model, data))  # 5 cm above the floor
    assert up["contact"].tolist() == [[0.0]]
    assert up["load"].tolist() == [[0.0]]
    data.qpos[2] = 0.0
    for _ in range(1500):  # dropped, settled: the foot carries the whole body
        mujoco.mj_step(model, data)
    down = sensing.read(*_record(model, data))
    assert down["contact"].tolist() == [[1.0]]
    assert down["load"][0, 0] == pytest.approx(4.0, rel=0.02)  # the whole weight: four quarters


def _seed_texts() -> dict[str, str]:
    return {joint: fit.text for joint, fit in fit_seed(load_seed()).items()}


def _keep_everything(evaluator: HorseEvaluator, steps: int, gaits: int):
    nstate = mujoco.mj_stateSize(evaluator.model, STATE_SPEC)
    states = np.empty((gaits, steps, nstate))
    controls = np.empty((gaits, steps, evaluator.model.nu))

    def keep(ids, first, state, sensordata, control, *_):
        states[ids, first : first + state.shape[1]] = state
        controls[ids, first : first + state.shape[1]] = control
        return np.zeros(len(ids), dtype=bool)

    return states, controls, keep


def test_a_loop_without_sensors_is_the_open_loop_to_the_bit() -> None:
    """The closed loop's machinery (ticks of 5 steps, chunks of 7) on curves that read no sensor
    gives the open loop's controls and states, bit for bit."""
    evaluator = HorseEvaluator(chunk_steps=7)
    batch = motion_batch([_seed_texts(), {"hip_hind": "12*sin(2*PI*t)"}], CATALOGUE.names)
    rows = np.arange(2)
    steps = 400
    expected_states, _, expected_controls = evaluator.play(batch, rows, cycles=1)
    open_loop = evaluator.controller(batch, rows)
    closed = ClosedLoop(
        evaluator.open_loop,
        open_loop.table,
        batch.n_samples,
        evaluator.frequencies(batch, rows),
        False,
        [(None,) * len(CATALOGUE.names)] * 2,
        tick=evaluator.tick,
        sensing=None,
        oscillators=None,
    )
    states, controls, keep = _keep_everything(evaluator, steps, 2)
    evaluator.rollout.run(np.full(2, steps), closed, keep)
    assert np.array_equal(controls, expected_controls[:, :steps])
    assert np.array_equal(states, expected_states[:, :steps])
    evaluator.close()


def test_sensed_terms_are_read_at_each_tick_and_held() -> None:
    """A hip curve of the trunk's pitch alone: each tick's control is the pitch at the step before
    it, held for the tick's steps, blended in over the ramp."""
    evaluator = HorseEvaluator()
    batch = motion_batch([{"hip_hind": "10*pitch"}], CATALOGUE.names, sensors=HORSE_SENSORS)
    _states, sensors, controls = evaluator.play(batch, np.arange(1), cycles=1)
    hip = [a for a, curve in enumerate(evaluator.layout.actuator_curve) if curve == "hip_hind"]
    quat = evaluator.layout.sensors["trunk_quat"]
    w, x, y, z = sensors[0, :, quat].T
    pitch = -np.degrees(np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0)))
    tick = evaluator.tick
    for step in range(tick, 600):
        read = pitch[(step // tick) * tick - 1]  # the last step recorded before the tick began
        ramp = min(1.0, step * evaluator.dt / evaluator.settings.ramp_seconds)
        expected = np.clip(
            evaluator.layout.neutral_ctrl[hip] + ramp * np.radians(10 * read),
            evaluator.layout.ctrl_low[hip],
            evaluator.layout.ctrl_high[hip],
        )
        assert controls[0, step, hip] == pytest.approx(expected, abs=1e-12)
    assert np.ptp(controls[0, 300:600, hip[0]]) > 0  # it moved with the trunk
    evaluator.close()


def _feedback_batch(count: int = 6):
    texts = _seed_texts()
    gaits = []
    for k in range(count):
        gait = dict(texts)
        gait["hip_hind"] = f"{texts['hip_hind']}+{0.1 * k}*pitch-{0.02 * k}*pitch_rate"
        gait["fetlock_fore"] = f"{texts['fetlock_fore']}+{k}*(load-1)"
        gait["fetlock_hind"] = texts["fetlock_hind"].replace("*t", "*(phase+0.05)")
        gaits.append(gait)
    return motion_batch(gaits, CATALOGUE.names, sensors=HORSE_SENSORS)


def test_closed_loops_score_the_same_whatever_the_threads_chunks_and_company() -> None:
    batch = _feedback_batch()
    assert batch.closed_loop
    reference = HorseEvaluator(HorseSettings(threads=1)).evaluate(batch)
    assert all(e.status.viable for e in reference[:3]), [e.detail for e in reference]
    two = HorseEvaluator(HorseSettings(threads=2), chunk_steps=33).evaluate(batch)
    assert [e.as_record() for e in two] == [e.as_record() for e in reference]
    alone = [HorseEvaluator(HorseSettings(threads=2)).evaluate(batch.take([g]))[0] for g in (0, 4)]
    assert [e.as_record() for e in alone] == [reference[0].as_record(), reference[4].as_record()]


def test_verify_keeps_the_closed_loops_fitness() -> None:
    batch = _feedback_batch(2)
    evaluator = HorseEvaluator()
    scored, checked = evaluator.evaluate(batch), evaluator.verify(batch)
    for a, b in zip(scored, checked, strict=True):
        if b.status.viable:
            assert a.fitness == b.fitness


def test_a_closed_loop_that_computes_no_finite_control_is_unviable() -> None:
    """Finite at rest (pitch 0: the nominal curve is 0), infinite as soon as the trunk pitches."""
    batch = motion_batch([{"hip_hind": "1e300*pitch*1e300"}], CATALOGUE.names, sensors=HORSE_SENSORS)
    assert batch.problems == (None,)
    (evaluation,) = HorseEvaluator().evaluate(batch)
    assert evaluation.status.value == "non-finite"
    assert "the closed loop of hip_hind is not finite at" in evaluation.detail


def _actuation() -> Actuation:
    return Actuation(
        curves=("leg",),
        curve_index=np.array([0, 0]),
        offsets=np.array([0.0, 0.5]),
        limb_index=np.array([0, 1]),
        limbs=("left", "right"),
        neutral=np.zeros(2),
        low=-np.ones(2),
        high=np.ones(2),
        timestep=0.01,
        ramp_seconds=0.0,
    )


def test_an_oscillator_restarts_at_its_hoofs_landing_and_not_at_chatter() -> None:
    actuation = _actuation()
    oscillators = Oscillators(1, np.array([0, 1]), above=5.0, airborne=0.2, actuation=actuation)
    frequency = np.array([1.0])
    ids = np.array([0])

    def phases_at(step: int, left: float, right: float) -> np.ndarray:
        oscillators.tick(ids, step, np.array([[left, right]]), frequency)
        return oscillators.phases(ids, actuation.clock(step, step + 1, frequency))[0, 0]

    # Airborne time counts from the last tick that saw the hoof down.
    assert phases_at(0, 100, 100) == pytest.approx([0.0, 0.5])  # standing: the clock
    assert phases_at(10, 0, 100) == pytest.approx([0.1, 0.6])  # the left hoof lifts
    assert phases_at(15, 100, 100) == pytest.approx([0.15, 0.65])  # down 0.15 s after: chatter
    phases_at(20, 0, 100)
    left_lands = phases_at(50, 100, 100)  # down 0.35 s after: a landing
    assert left_lands[0] == 0.0
    assert left_lands[1] == pytest.approx(0.0)  # the right runs on its clock: 0.5 + 0.5
    assert phases_at(70, 100, 100) == pytest.approx([0.2, 0.2])  # and runs on from there


def test_the_seeds_hooves_land_where_the_reset_grammar_says() -> None:
    """hybrid-reset.gg plays the seed's limb curves at t = phase + SEED_TOUCHDOWN: the phase at
    which each limb group's hoof lands when the seed is played (a walk's landings, after its
    warm-up, ignoring contact chatter shorter than the oscillator's airborne time)."""
    evaluator = HorseEvaluator()
    _, sensors, _ = evaluator.play(load_seed().motion_batch(), np.arange(1), cycles=12)
    frequency = evaluator.targets.stride_frequency
    airborne = round(SENSORS.get("phase").read["airborne_seconds"] / evaluator.dt)
    for limb in LIMBS:
        down = sensors[0, :, evaluator.layout.sensors[f"hoof_{limb}"].start] > 5.0
        lifted = np.flatnonzero(down[:-1] & ~down[1:]) + 1
        landings = [
            step
            for step in np.flatnonzero(down[1:] & ~down[:-1]) + 1
            if step * evaluator.dt > 3.0
            and (lifted[lifted < step].size and step - lifted[lifted < step][-1] >= airborne)
        ]
        phases = np.mod(
            np.array(landings) * evaluator.dt * frequency - evaluator.targets.phase_offsets[limb], 1.0
        )
        assert len(phases) >= 8, limb
        assert np.abs(phases - SEED_TOUCHDOWN[limb.split("_")[0]]).max() < 0.01, (limb, phases)
    evaluator.close()


def test_a_curve_of_sensors_has_a_nominal_curve_and_the_open_loop_part_is_unchanged() -> None:
    texts = _seed_texts()
    plain = motion_batch([texts], CATALOGUE.names, sensors=HORSE_SENSORS)
    assert plain.loops is None  # nothing read: the open loop, as without sensors
    assert np.array_equal(plain.angles, motion_batch([texts], CATALOGUE.names).angles)
    closed = dict(texts)
    closed["hip_hind"] = texts["hip_hind"] + "+2*(load-1)+0.5*pitch"
    batch = motion_batch([closed], CATALOGUE.names, sensors=HORSE_SENSORS)
    hip = CATALOGUE.names.index("hip_hind")
    assert batch.loops[0][hip] is not None
    assert batch.loops[0][0] is None
    # At rest the load reads 1 and the pitch 0: the nominal curve is the open-loop one.
    assert np.allclose(batch.angles[0, hip], plain.angles[0, hip], atol=1e-9)


def test_a_limb_sensor_on_a_joint_without_a_limb_is_not_played() -> None:
    batch = motion_batch([{"neck_mid": "2*load"}], CATALOGUE.names, sensors=HORSE_SENSORS)
    (evaluation,) = HorseEvaluator().evaluate(batch)
    assert not evaluation.status.viable
    assert "neck_mid" in evaluation.detail
    assert "load" in evaluation.detail


def test_the_pace_grammars_seed_is_the_feedback_seed_and_its_gain_reads_the_pace() -> None:
    """hybrid-pace.gg's seed genome (every gain 0) scores as hybrid-feedback.gg's to the bit; a
    stride gain scales the hip and shoulder with the trunk's pace, and so changes the score."""
    from gaitgram.ge import compile_mapper
    from gaitgram.language import load
    from gaitgram.seed.grammars import seed_genome

    grammars = Path(__file__).resolve().parents[2] / "grammars"
    feedback, pace = (load(grammars / f"{name}.gg") for name in ("hybrid-feedback", "hybrid-pace"))
    gaits = [compile_mapper(feedback).map_fast(seed_genome(feedback)).joints]
    for gain in (20, 0):  # the middle index, 20, is gain 0; index 0 is -1
        gaits.append(compile_mapper(pace).map_fast(seed_genome(pace, {"stride_gain": gain})).joints)
    for joint, gain in (("hip_hind", "0"), ("shoulder_fore", "-1")):
        closed = gaits[0][joint].index("+0*pitch")  # the feedback terms, every gain 0
        curve, tail = gaits[0][joint][:closed], gaits[0][joint][closed:]
        assert gaits[1 if gain == "0" else 2][joint] == f"({curve})*(1+{gain}*(1-pace)){tail}"
    assert gaits[2]["fetlock_hind"] == gaits[0]["fetlock_hind"]  # the fetlocks are not scaled
    batch = motion_batch(gaits, CATALOGUE.names, sensors=HORSE_SENSORS, frequency=(0.6, 1.3))
    seed, zero, scaled = (e.as_record() for e in HorseEvaluator().evaluate(batch))
    assert zero == seed
    assert scaled["fitness"] != seed["fitness"]


def _stride_gaits(grammar: str, sensor: str) -> tuple[dict, dict, dict]:
    """The records of the hybrid seed and of the stride grammar's seed genome at gain 0 and 1, its
    hip and shoulder curves checked to be the hybrid's scaled by ``sensor``."""
    from gaitgram.ge import compile_mapper
    from gaitgram.language import load
    from gaitgram.seed.grammars import seed_genome

    grammars = Path(__file__).resolve().parents[2] / "grammars"
    hybrid, stride = (load(grammars / f"{name}.gg") for name in ("hybrid", grammar))
    gaits = [compile_mapper(hybrid).map_fast(seed_genome(hybrid)).joints]
    for gain in (20, 40):  # the middle index, 20, is gain 0; index 40 is 1
        gaits.append(compile_mapper(stride).map_fast(seed_genome(stride, {"stride_gain": gain})).joints)
    for joint in ("hip_hind", "shoulder_fore"):
        assert gaits[1][joint] == f"({gaits[0][joint]})*(1+0*(1-{sensor}))"
        assert gaits[2][joint] == f"({gaits[0][joint]})*(1+1*(1-{sensor}))"
    assert all(
        gaits[1][joint] == gaits[0][joint] for joint in gaits[0] if joint not in ("hip_hind", "shoulder_fore")
    )
    assert not any(name in "".join(gaits[2].values()) for name in ("pitch", "load"))  # no such feedback
    batch = motion_batch(gaits, CATALOGUE.names, sensors=HORSE_SENSORS, frequency=(0.6, 1.3))
    seed, zero, scaled = (e.as_record() for e in HorseEvaluator().evaluate(batch))
    return seed, zero, scaled


@pytest.mark.parametrize(
    ("grammar", "sensor"), [("hybrid-stride", "pace"), ("hybrid-cycle-stride", "cycle_pace")]
)
def test_the_stride_grammars_seed_is_the_hybrid_seed_and_its_gain_reads_the_pace(
    grammar: str, sensor: str
) -> None:
    """hybrid-stride.gg is hybrid.gg with only the pace's stride gain on the hip and shoulder (the
    cycle-stride grammar's reads the pace averaged over the cycle): its seed genome (gain 0)
    plays the hybrid's seed, now through the closed loop, whose controls are summed in another
    order (equal to 1e-12, not to the bit); a gain changes the walk."""
    seed, zero, scaled = _stride_gaits(grammar, sensor)
    assert zero["fitness"] == pytest.approx(seed["fitness"], rel=1e-12)
    assert zero["components"]["measured_velocity"] == seed["components"]["measured_velocity"]
    assert scaled["fitness"] != pytest.approx(seed["fitness"], rel=1e-3)
    assert scaled["components"]["measured_velocity"] != seed["components"]["measured_velocity"]


def test_the_averaged_pace_plays_another_gait_than_the_instantaneous_one() -> None:
    """The same gain on ``pace`` and on ``cycle_pace``: the instantaneous pace swings within each
    stride, so it scales the swing far more than the average does at a steady pace near 1."""
    seed, _, instantaneous = _stride_gaits("hybrid-stride", "pace")
    *_, averaged = _stride_gaits("hybrid-cycle-stride", "cycle_pace")
    assert (
        abs(instantaneous["fitness"] - seed["fitness"]) > 10 * abs(averaged["fitness"] - seed["fitness"]) > 0
    )


def test_a_closed_loop_opened_is_its_curves_with_every_sensor_at_rest_played_open_loop() -> None:
    """``MotionBatch.opened`` (the ablation that cuts a closed loop's feedback) plays each curve as
    its nominal: the same controls and states, to the bit, as the phenotype with each sensor written
    as its resting reading (``cycle_pace`` as 1, ``pitch`` as 0), and another gait than the loop's."""
    texts = _seed_texts()
    sensed = dict(texts)
    sensed["hip_hind"] = f"({texts['hip_hind']})*(1+0.8*(1-cycle_pace))+2*pitch"
    at_rest = dict(texts)
    at_rest["hip_hind"] = f"({texts['hip_hind']})*(1+0.8*(1-1))+2*0"
    closed = motion_batch([sensed], CATALOGUE.names, sensors=HORSE_SENSORS)
    opened = closed.opened()
    assert closed.closed_loop
    assert not opened.closed_loop
    written = motion_batch([at_rest], CATALOGUE.names, sensors=HORSE_SENSORS)
    evaluator = HorseEvaluator()
    rows = np.arange(1)
    played = {
        name: evaluator.play(batch, rows, cycles=2)
        for name, batch in (("opened", opened), ("written", written), ("closed", closed))
    }
    evaluator.close()
    for kept in range(3):  # states, sensors, controls
        assert np.array_equal(played["opened"][kept], played["written"][kept])
    assert not np.array_equal(played["opened"][2], played["closed"][2])
