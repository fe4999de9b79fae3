"""The horse's physics: loading ``horse.xml`` and describing its layout.

Physics only (the dm_control split of physics and task): which actuators, joints
and geoms belong to which of the 12 curves of ``joints.toml``, the standing pose
and its control targets. Nothing here scores a gait.

Angles are radians here; the curves' degrees are converted by the caller. Every
hinge is 0 in the neutral pose and positive in flexion, so a control target is
``neutral_ctrl + radians(curve value)``.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from types import MappingProxyType

import mujoco
import numpy as np

from gaitgram.backends.catalogue import JointCatalogue
from gaitgram.backends.mujoco_horse.bodies import body_named
from gaitgram.backends.mujoco_horse.joints import CATALOGUE
from gaitgram.backends.mujoco_horse.scaling import scaled_spec
from gaitgram.packaged import packaged

#: The four limbs, named as the suffix of their joints (``hip_hind_left``), in the
#: walk's lateral footfall sequence: hind left, fore left, hind right, fore right.
LIMBS: tuple[str, ...] = ("hind_left", "fore_left", "hind_right", "fore_right")
SIDES: tuple[str, ...] = ("left", "right")
#: Full physics state (time, qpos, qvel, act, ...): what ``mujoco.rollout`` starts from.
STATE_SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS

_XML = "horse.xml"


def _xml() -> str:
    return packaged(__package__, _XML).read_text(encoding="utf-8")


@cache
def _master_model(body: str | None = None) -> mujoco.MjModel:
    if body_named(body).is_reference:  # horse.xml compiled as it is: its runs' results stay exact
        return mujoco.MjModel.from_xml_string(_xml())
    return master_spec(body).compile()


def master_spec(body: str | None = None) -> mujoco.MjSpec:
    """A body (the horse by default) as an editable spec, MuJoCo's model editing: for variants of
    its world, such as another floor. Every body is built from the one ``horse.xml``
    (:mod:`~gaitgram.backends.mujoco_horse.scaling`); raises :class:`UnknownBody`."""
    return scaled_spec(mujoco.MjSpec.from_string(_xml()), body_named(body))


def load_model(body: str | None = None) -> mujoco.MjModel:
    """A body's model (the horse by default); a private copy each call (each body is compiled
    once per process)."""
    return copy.copy(_master_model(body))


#: Floors of random bumps (:func:`bumpy_model`): heights uniform up to ``BUMP_HEIGHT`` in square
#: cells of ``BUMP_CELL``, uneven turf under a 14 cm hoof.
BUMP_HEIGHT = 0.02  # m
BUMP_CELL = 0.1  # m
FLAT_START = 1.0  # m ahead of the standing horse, and all of it behind
BUMP_LENGTH = 60.0  # m of floor ahead: more than the longest walk over a horizon


def bumpy_model(
    body: str | None, seed: int, scale: float = 1.0, height: float = BUMP_HEIGHT
) -> mujoco.MjModel:
    """A body (None: the horse) on a floor of random bumps drawn from ``seed``, flat where it
    stands and just ahead: the robustness trial's floors, and the ones a fitness scoring bumps
    (``bump_floors``) plays gaits on. ``scale`` sizes the turf: bumps, cells and the flat start
    ``scale`` times the trial's (1: the trial's floors, the very models; a body's length scale:
    turf as uneven for it as the trial's is for the horse). The floor's extent does not scale (a
    smaller floor would end under a walk), so another scale draws another sample of such turf.
    ``height`` is the bumps' full height before scaling (the graded robustness trial's taller bumps:
    the same cells, the same draw, each bump ``height / BUMP_HEIGHT`` times as tall).
    Compiled once per process; callers must not change it."""
    return _bumpy_model(body, seed, float(scale), float(height))


@cache
def _bumpy_model(body: str | None, seed: int, scale: float, height: float) -> mujoco.MjModel:
    spec = master_spec(body)
    rng = np.random.default_rng(seed)
    behind = 10.0  # m of floor behind the standing horse
    cell = BUMP_CELL * scale
    half_length, half_width = (BUMP_LENGTH + behind) / 2, 2.0
    ncol, nrow = round(2 * half_length / cell) + 1, round(2 * half_width / cell) + 1
    centre = half_length - behind
    x = centre + np.linspace(-half_length, half_length, ncol)
    heights = rng.uniform(0.0, 1.0, size=(nrow, ncol))
    heights[:, x < FLAT_START * scale] = 0.0
    heights[0, -1] = 1.0  # the scale is the bumps' full height, whatever the draw
    field = spec.add_hfield()
    field.name = "bumps"
    field.nrow, field.ncol = nrow, ncol
    field.size = [half_length, half_width, height * scale, 0.1]
    field.userdata = heights.ravel().tolist()
    floor = spec.geom("floor")
    floor.type = mujoco.mjtGeom.mjGEOM_HFIELD
    floor.hfieldname = "bumps"
    floor.pos = [centre, 0, 0]
    return spec.compile()


def _frozen(array: np.ndarray) -> np.ndarray:
    array = np.array(array)
    array.setflags(write=False)
    return array


def _id(model: mujoco.MjModel, objtype: mujoco.mjtObj, name: str) -> int:
    index = mujoco.mj_name2id(model, objtype, name)
    if index < 0:
        raise LookupError(f"the horse model has no {objtype.name.removeprefix('mjOBJ_').lower()} {name!r}")
    return index


def curve_limbs(curve: str) -> tuple[str | None, ...]:
    """The limbs a curve drives (``fore_left``, ``fore_right``), or ``(None,)`` for a neck curve."""
    parts = curve.split("_")
    if len(parts) == 2 and parts[1] in ("fore", "hind"):
        return tuple(f"{parts[1]}_{side}" for side in SIDES)
    return (None,)


def joint_name(curve: str, limb: str | None) -> str:
    """The hinge (and actuator) a curve drives on a limb: ``hip_hind``, ``hind_left`` → ``hip_hind_left``."""
    return curve if limb is None else f"{curve}_{limb.split('_')[1]}"


@dataclass(frozen=True, eq=False)
class HorseLayout:
    """Where the 12 curves and the body parts live in the model's arrays.

    Mappings are keyed by curve (``curves``, the order of ``joints.toml``) or by
    limb (``LIMBS``). Per-actuator tuples and arrays have ``model.nu`` entries.
    """

    curves: tuple[str, ...]
    #: per curve: actuator ids, hinge qpos addresses, dof addresses and limbs, aligned
    curve_actuators: Mapping[str, tuple[int, ...]]
    curve_qpos: Mapping[str, tuple[int, ...]]
    curve_dofs: Mapping[str, tuple[int, ...]]
    curve_limbs: Mapping[str, tuple[str | None, ...]]
    #: per actuator: its joint's name, its curve (name and index into ``curves``), its limb
    actuator_joint: tuple[str, ...]
    actuator_curve: tuple[str, ...]
    actuator_curve_index: np.ndarray
    actuator_limb: tuple[str | None, ...]
    actuator_qpos: np.ndarray
    actuator_dof: np.ndarray
    ctrl_low: np.ndarray
    ctrl_high: np.ndarray
    #: per limb: the hoof's contact geom, and the address of its touch sensor in sensordata
    hoof_geoms: Mapping[str, int]
    hoof_touch: Mapping[str, int]
    trunk_body: int
    trunk_geom: int
    head_geom: int
    floor_geom: int
    #: every sensor's slice of ``MjData.sensordata`` by name
    sensors: Mapping[str, slice]
    #: control targets that hold every hinge at 0 while standing (gravity-compensated)
    neutral_ctrl: np.ndarray
    #: the settled standing pose: qpos with the trunk over the origin, at rest
    stand_qpos: np.ndarray
    standing_height: float  # trunk centre above the ground, standing (m)
    root_dofs: int  # degrees of freedom of the trunk (x, z, pitch), before the hinges in qvel
    hip_height: float  # hip (coxofemoral) joint above the ground, standing: h of the Froude number (m)
    total_mass: float  # kg
    timestep: float  # s

    def initial_state(self, model: mujoco.MjModel) -> np.ndarray:
        """The standing pose at rest as a ``STATE_SPEC`` vector (an ``initial_state`` for rollouts)."""
        data = mujoco.MjData(model)
        data.qpos[:] = self.stand_qpos
        data.ctrl[:] = self.neutral_ctrl
        state = np.empty(mujoco.mj_stateSize(model, STATE_SPEC))
        mujoco.mj_getState(model, data, state, STATE_SPEC)
        return state


def _settle(model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray, seconds: float) -> None:
    data.ctrl[:] = ctrl
    for _ in range(round(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)


def _stand(model: mujoco.MjModel, act_qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Settle on the ground from the neutral pose, correcting the targets for the servos' sag."""
    data = mujoco.MjData(model)
    ctrl = np.zeros(model.nu)
    for _ in range(3):
        mujoco.mj_resetData(model, data)
        _settle(model, data, ctrl, 1.5)
        ctrl = np.clip(ctrl - data.qpos[act_qpos], *model.actuator_ctrlrange.T)
    mujoco.mj_resetData(model, data)
    _settle(model, data, ctrl, 3.0)
    qpos = data.qpos.copy()
    qpos[model.jnt_qposadr[_id(model, mujoco.mjtObj.mjOBJ_JOINT, "root_x")]] = 0.0  # over the origin
    return ctrl, qpos


def build_layout(model: mujoco.MjModel, catalogue: JointCatalogue = CATALOGUE) -> HorseLayout:
    """Describe ``model`` (the horse, possibly with changed options) against the joint catalogue.

    Raises LookupError when a curve's joint or actuator is missing. Settles the
    horse for a few simulated seconds to find its standing pose (~0.1 s).
    """
    obj = mujoco.mjtObj
    curves = catalogue.names
    curve_actuators: dict[str, tuple[int, ...]] = {}
    curve_qpos: dict[str, tuple[int, ...]] = {}
    curve_dofs: dict[str, tuple[int, ...]] = {}
    limbs_of: dict[str, tuple[str | None, ...]] = {}
    act_joint: list[str] = [""] * model.nu
    act_curve: list[str] = [""] * model.nu
    act_limb: list[str | None] = [None] * model.nu
    for curve in curves:
        limbs = curve_limbs(curve)
        names = [joint_name(curve, limb) for limb in limbs]
        acts = tuple(_id(model, obj.mjOBJ_ACTUATOR, n) for n in names)
        joints = [_id(model, obj.mjOBJ_JOINT, n) for n in names]
        for a, j, n, limb in zip(acts, joints, names, limbs, strict=True):
            if model.actuator_trnid[a, 0] != j or model.jnt_type[j] != mujoco.mjtJoint.mjJNT_HINGE:
                raise LookupError(f"actuator {n!r} does not drive the hinge {n!r}")
            act_joint[a], act_curve[a], act_limb[a] = n, curve, limb
        curve_actuators[curve] = acts
        curve_qpos[curve] = tuple(int(model.jnt_qposadr[j]) for j in joints)
        curve_dofs[curve] = tuple(int(model.jnt_dofadr[j]) for j in joints)
        limbs_of[curve] = limbs
    if "" in act_curve:
        raise LookupError(f"actuators driven by no curve: {[i for i, c in enumerate(act_curve) if not c]}")
    act_qpos = np.array([model.jnt_qposadr[model.actuator_trnid[a, 0]] for a in range(model.nu)])
    act_dof = np.array([model.jnt_dofadr[model.actuator_trnid[a, 0]] for a in range(model.nu)])

    sensors = {
        mujoco.mj_id2name(model, obj.mjOBJ_SENSOR, s): slice(
            int(model.sensor_adr[s]), int(model.sensor_adr[s] + model.sensor_dim[s])
        )
        for s in range(model.nsensor)
    }
    ctrl, stand_qpos = _stand(model, act_qpos)
    data = mujoco.MjData(model)
    data.qpos[:] = stand_qpos
    mujoco.mj_kinematics(model, data)
    hip = _id(model, obj.mjOBJ_JOINT, "hip_hind_left")
    trunk = _id(model, obj.mjOBJ_BODY, "trunk")
    return HorseLayout(
        curves=curves,
        curve_actuators=MappingProxyType(curve_actuators),
        curve_qpos=MappingProxyType(curve_qpos),
        curve_dofs=MappingProxyType(curve_dofs),
        curve_limbs=MappingProxyType(limbs_of),
        actuator_joint=tuple(act_joint),
        actuator_curve=tuple(act_curve),
        actuator_curve_index=_frozen(np.array([curves.index(c) for c in act_curve])),
        actuator_limb=tuple(act_limb),
        actuator_qpos=_frozen(act_qpos),
        actuator_dof=_frozen(act_dof),
        ctrl_low=_frozen(model.actuator_ctrlrange[:, 0]),
        ctrl_high=_frozen(model.actuator_ctrlrange[:, 1]),
        hoof_geoms=MappingProxyType({limb: _id(model, obj.mjOBJ_GEOM, f"hoof_{limb}") for limb in LIMBS}),
        hoof_touch=MappingProxyType({limb: sensors[f"hoof_{limb}"].start for limb in LIMBS}),
        trunk_body=trunk,
        trunk_geom=_id(model, obj.mjOBJ_GEOM, "trunk"),
        head_geom=_id(model, obj.mjOBJ_GEOM, "head"),
        floor_geom=_id(model, obj.mjOBJ_GEOM, "floor"),
        sensors=MappingProxyType(sensors),
        neutral_ctrl=_frozen(ctrl),
        stand_qpos=_frozen(stand_qpos),
        standing_height=float(data.xpos[trunk][2]),
        root_dofs=int(model.body_dofnum[trunk]),
        hip_height=float(data.xanchor[hip][2]),
        total_mass=float(model.body_subtreemass[0]),
        timestep=float(model.opt.timestep),
    )


@cache
def horse_layout(body: str | None = None) -> HorseLayout:
    """The layout of :func:`load_model`'s body (computed once per process and body)."""
    return build_layout(_master_model(body))
