"""The MuJoCo horse: its structure, its joint layout, and that it stands and moves sanely.

Every body of ``bodies.toml`` is built from horse.xml and must pass every test the horse passes.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from mujoco import rollout

from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.bodies import BODIES, Body
from gaitgram.backends.mujoco_horse.model import (
    LIMBS,
    STATE_SPEC,
    HorseLayout,
    horse_layout,
    load_model,
)

RANGE_MARGIN_DEG = 10.0  # horse.xml: joint range = limits widened by 10 degrees


@pytest.fixture(scope="module", params=list(BODIES))
def body(request: pytest.FixtureRequest) -> Body:
    return BODIES[request.param]


@pytest.fixture(scope="module")
def model(body: Body) -> mujoco.MjModel:
    return load_model(body.name)


@pytest.fixture(scope="module")
def layout(body: Body) -> HorseLayout:
    return horse_layout(body.name)


def _tilt_deg(quat: np.ndarray) -> float:
    """Angle between the trunk's up axis and the world's."""
    mat = np.empty(9)
    mujoco.mju_quat2Mat(mat, quat)
    return math.degrees(math.acos(np.clip(mat[8], -1.0, 1.0)))


def _touching_floor(model: mujoco.MjModel, data: mujoco.MjData, layout: HorseLayout) -> set[int]:
    touching = set()
    for contact in data.contact[: data.ncon]:
        pair = {int(contact.geom1), int(contact.geom2)}
        if layout.floor_geom in pair:
            touching |= pair - {layout.floor_geom}
    return touching


# --- structure ---------------------------------------------------------------------------------


def test_mass_is_the_bodys(model: mujoco.MjModel, body: Body) -> None:
    assert model.body_subtreemass[0] == pytest.approx(body.mass, rel=1e-6)


def test_joints_and_actuators(model: mujoco.MjModel) -> None:
    types = [int(t) for t in model.jnt_type]
    # The trunk in the sagittal plane: forward and vertical slides and a pitch hinge.
    assert [model.joint(j).name for j in range(3)] == ["root_x", "root_z", "root_pitch"]
    assert types.count(mujoco.mjtJoint.mjJNT_SLIDE) == 2
    assert types.count(mujoco.mjtJoint.mjJNT_HINGE) == 21 + 1
    assert model.njnt == 24
    assert horse_layout().root_dofs == 3
    assert model.nu == 21
    assert all(model.jnt_type[model.actuator_trnid[a, 0]] == mujoco.mjtJoint.mjJNT_HINGE for a in range(21))


def test_each_curve_drives_its_joints(model: mujoco.MjModel, layout: HorseLayout) -> None:
    assert layout.curves == CATALOGUE.names
    assert len(layout.curves) == 12
    for joint in CATALOGUE.joints:
        acts = layout.curve_actuators[joint.name]
        assert len(acts) == (1 if joint.group == "neck" else 2), joint.name
        assert len(layout.curve_qpos[joint.name]) == len(acts) == len(layout.curve_dofs[joint.name])
        names = [model.actuator(a).name for a in acts]
        if joint.group == "neck":
            assert names == [joint.name]
        else:
            assert names == [f"{joint.name}_left", f"{joint.name}_right"]
        for a, qadr in zip(acts, layout.curve_qpos[joint.name], strict=True):
            j = model.actuator_trnid[a, 0]
            assert model.joint(j).name == model.actuator(a).name
            assert model.jnt_qposadr[j] == qadr == layout.actuator_qpos[a]
            assert layout.actuator_curve[a] == joint.name
            assert layout.curves[layout.actuator_curve_index[a]] == joint.name
    every = sorted(a for acts in layout.curve_actuators.values() for a in acts)
    assert every == list(range(model.nu))
    limbs = [limb for limb in layout.actuator_limb if limb is not None]
    assert sorted(set(limbs)) == sorted(LIMBS)
    assert {limb: limbs.count(limb) for limb in LIMBS} == {
        "fore_left": 5,
        "fore_right": 5,
        "hind_left": 4,
        "hind_right": 4,
    }


def test_ranges_follow_the_catalogue(model: mujoco.MjModel, layout: HorseLayout) -> None:
    for joint in CATALOGUE.joints:
        low, high = (math.radians(v) for v in joint.limits)
        for a in layout.curve_actuators[joint.name]:
            assert model.actuator_ctrlrange[a] == pytest.approx([low, high], abs=1e-6)
            assert model.actuator_ctrllimited[a]
            j = model.actuator_trnid[a, 0]
            margin = math.radians(RANGE_MARGIN_DEG)
            assert model.jnt_range[j] == pytest.approx([low - margin, high + margin], abs=1e-6)
            assert model.jnt_limited[j]
    assert np.all(layout.neutral_ctrl >= layout.ctrl_low)
    assert np.all(layout.neutral_ctrl <= layout.ctrl_high)


@pytest.mark.parametrize(
    ("joint", "forward"),
    [
        ("scapula_fore_left", True),  # protraction
        ("shoulder_fore_left", False),
        ("elbow_fore_left", True),
        ("carpal_fore_left", False),
        ("fetlock_fore_left", False),
        ("hip_hind_right", True),
        ("stifle_hind_right", False),
        ("tarsal_hind_right", True),
        ("fetlock_hind_right", False),
    ],
)
def test_flexion_is_positive_limbs(model: mujoco.MjModel, joint: str, forward: bool) -> None:
    """Flexing a joint moves the hoof below it the way the anatomy says."""
    limb = joint.split("_", 1)[1]
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    hoof = model.geom(f"hoof_{limb}").id
    before = data.geom_xpos[hoof].copy()
    data.qpos[model.joint(joint).qposadr[0]] = 0.2
    mujoco.mj_kinematics(model, data)
    dx = data.geom_xpos[hoof][0] - before[0]
    assert (dx > 0.02) if forward else (dx < -0.02)


@pytest.mark.parametrize("joint", ["neck_proximal", "neck_mid"])
def test_neck_flexion_lowers_the_head(model: mujoco.MjModel, joint: str) -> None:
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    head = model.geom("head").id
    before = data.geom_xpos[head][2]
    data.qpos[model.joint(joint).qposadr[0]] = 0.2
    mujoco.mj_kinematics(model, data)
    assert data.geom_xpos[head][2] < before - 0.05


def test_only_hooves_trunk_and_head_touch_the_floor(model: mujoco.MjModel, layout: HorseLayout) -> None:
    def collide(g1: int, g2: int) -> bool:
        return bool(
            (model.geom_contype[g1] & model.geom_conaffinity[g2])
            or (model.geom_contype[g2] & model.geom_conaffinity[g1])
        )

    horse = [g for g in range(model.ngeom) if g != layout.floor_geom]
    with_floor = {g for g in horse if collide(g, layout.floor_geom)}
    assert with_floor == {*layout.hoof_geoms.values(), layout.trunk_geom, layout.head_geom}
    assert not any(collide(a, b) for i, a in enumerate(horse) for b in horse[i + 1 :])


def test_load_model_gives_independent_copies() -> None:
    first, second = load_model(), load_model()
    first.opt.timestep = 0.01
    assert second.opt.timestep != 0.01


def test_layout_figures(layout: HorseLayout, body: Body) -> None:
    scale = body.withers / BODIES["horse"].withers
    assert 1.1 * scale * body.leg <= layout.hip_height <= 1.2 * scale  # legs as bodies.toml proportions them
    assert layout.hip_height <= body.nominal_hip_height + 1e-9  # a time budget sized by it suffices
    assert 1.0 * scale * body.leg <= layout.standing_height <= 1.4 * scale
    assert layout.total_mass == pytest.approx(body.mass, rel=1e-6)
    assert 0.001 <= layout.timestep <= 0.005
    assert set(layout.hoof_geoms) == set(LIMBS) == set(layout.hoof_touch)


# --- dynamics ----------------------------------------------------------------------------------


@pytest.mark.parametrize("compensated", [True, False], ids=["neutral_ctrl", "zero_ctrl"])
def test_stands_still_for_ten_seconds(model: mujoco.MjModel, layout: HorseLayout, compensated: bool) -> None:
    """Dropped in its neutral pose (qpos0) with neutral targets, the horse stands still."""
    data = mujoco.MjData(model)
    data.ctrl[:] = layout.neutral_ctrl if compensated else 0.0
    mujoco.mj_forward(model, data)
    trunk_pos, trunk_quat = layout.sensors["trunk_pos"], layout.sensors["trunk_quat"]
    start = data.sensordata[trunk_pos].copy()
    heights, tilts, drifts = [], [], []
    for step in range(round(10.0 / model.opt.timestep)):
        mujoco.mj_step(model, data)
        if step % 10 == 0:
            heights.append(data.sensordata[trunk_pos][2])
            tilts.append(_tilt_deg(data.sensordata[trunk_quat]))
            drifts.append(np.linalg.norm(data.sensordata[trunk_pos][:2] - start[:2]))
    assert np.isfinite(data.qpos).all()
    assert max(abs(h - start[2]) for h in heights) < 0.03
    assert max(tilts) < 5.0
    assert max(drifts) < 0.05
    assert np.abs(data.qvel).max() < 0.05  # at rest
    hinge_dev = np.degrees(np.abs(data.qpos[layout.actuator_qpos]))
    assert hinge_dev.max() < (0.5 if compensated else 3.0)
    touching = _touching_floor(model, data, layout)
    assert touching == set(layout.hoof_geoms.values())  # all four hooves, nothing else
    touch = np.array([data.sensordata[layout.hoof_touch[limb]] for limb in LIMBS])
    assert np.all(touch > 0.1 * layout.total_mass * 9.81)  # each hoof carries some of the weight
    assert touch.sum() == pytest.approx(layout.total_mass * 9.81, rel=0.02)


def test_initial_state_is_at_rest_and_rollout_matches_stepping(
    model: mujoco.MjModel, layout: HorseLayout
) -> None:
    nstep = 500
    state0 = layout.initial_state(model)
    ctrl = np.tile(layout.neutral_ctrl, (1, nstep, 1))
    states, _ = rollout.rollout(model, mujoco.MjData(model), state0, ctrl)
    qpos = states[0, :, 1 : 1 + model.nq]
    assert np.abs(qpos - layout.stand_qpos).max() < 2e-3

    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, state0, STATE_SPEC)
    data.ctrl[:] = layout.neutral_ctrl
    for _ in range(nstep):
        mujoco.mj_step(model, data)
    np.testing.assert_array_equal(data.qpos, qpos[-1])


def test_driven_limbs_stay_finite(model: mujoco.MjModel, layout: HorseLayout) -> None:
    """Walk-like sines on every joint, then limit-to-limit square waves: the state stays finite."""
    dt = model.opt.timestep
    t = np.arange(round(5.0 / dt)) * dt
    walk = {"hind_left": 0.0, "fore_left": 0.25, "hind_right": 0.5, "fore_right": 0.75, None: 0.0}
    phase = 2 * np.pi * np.array([walk[limb] for limb in layout.actuator_limb])
    half = (layout.ctrl_high - layout.ctrl_low) / 2
    sines = layout.neutral_ctrl + 0.4 * half * np.sin(2 * np.pi * 0.9 * t[:, None] + phase)
    squares = np.where(np.sin(2 * np.pi * 3.0 * t[:, None] + phase) > 0, layout.ctrl_high, layout.ctrl_low)
    ctrl = np.clip(np.stack([sines, squares]), layout.ctrl_low, layout.ctrl_high)
    states, _ = rollout.rollout(model, [mujoco.MjData(model)], layout.initial_state(model), ctrl)
    assert np.isfinite(states).all()
    qvel = states[:, :, 1 + model.nq : 1 + model.nq + model.nv]
    assert np.abs(qvel).max() < 1e3
