"""Another body from the one horse: horse.xml edited with ``mujoco.MjSpec`` by scaling laws.

Dynamic similarity (Alexander & Jayes 1983) is what lets a gait carry over: bodies that differ
only in size move alike at equal Froude number if every length scales by one factor and every
force by weight. So, with ``L`` a segment's length scale and ``m`` the mass ratio:

* lengths (segment offsets, capsule lengths, the hoof's depth) scale by ``L``: the trunk, neck
  and head by the body's length scale, the limbs by that times ``leg`` (and the cannons by
  ``cannon`` more); the hind hip moves up or down on the trunk so that the trunk stands level;
* every mass by ``m`` (the segment shares stay the horse's); girths (capsule radii, the hoof's
  sole) by ``L sqrt(m / L^3)``, so a stockier body is thicker rather than denser, and MuJoCo
  computes inertias from these shapes (``I ~ m L^2``);
* a joint's servo stiffness ``kp ~ m g L``, damping ``kv ~ m L sqrt(g L)``, torque limit
  ``~ m g L``, armature ``~ m L^2`` and passive damping like ``kv``, with ``L`` the segment
  scale the joint moves: the same angles then hold the same pose against the same relative sag,
  and the same curves, played at a frequency scaled by ``sqrt(g / L)``, give the same motion.

Angles, joint ranges and control ranges do not change: the joint catalogue and every grammar's
``@joint`` check hold for every body. docs/bodies.md has the figures each body comes out at.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from gaitgram.backends.mujoco_horse.bodies import REFERENCE_WITHERS, Body

#: Limb bodies are named ``<segment>_<fore|hind>_<side>``; the cannons' segment is ``cannon``.
_LIMB_MARKS = ("_fore_", "_hind_")
_FORE_CHAIN = (
    "scapula_fore_left",
    "humerus_fore_left",
    "forearm_fore_left",
    "cannon_fore_left",
    "digit_fore_left",
)
_HIND_CHAIN = ("thigh_hind_left", "crus_hind_left", "cannon_hind_left", "digit_hind_left")
#: Height of the withers' spinous processes over the scapulae's dorsal ends (not modelled), at L = 1.
_SPINOUS = REFERENCE_WITHERS - 1.5


@dataclass(frozen=True)
class Scales:
    """The factors a body is built with, relative to the horse."""

    length: float  # trunk, neck and head; the limbs' attachments on the trunk
    limb: float  # limb segments
    cannon: float  # cannon segments
    mass: float
    girth: float  # capsule radii and hoof soles

    def of_segment(self, name: str) -> float:
        """The length scale of a body's own geometry (its geoms, its children's offsets)."""
        if not any(mark in name for mark in _LIMB_MARKS):
            return self.length
        return self.cannon if name.startswith("cannon_") else self.limb

    def of_joint(self, segment: str) -> float:
        """The length a joint's torques scale with: the limb's (its weight acts through the whole
        limb, cannon included) or, for the neck, the body's."""
        return self.limb if any(mark in segment for mark in _LIMB_MARKS) else self.length


def scales_for(body: Body, spec: mujoco.MjSpec) -> Scales:
    """The factors that give ``body`` its withers height, from the horse's spec at scale 1."""
    unit = Scales(1.0, body.leg, body.leg * body.cannon, 1.0, 1.0)
    drop, _ = _limb_drops(spec, unit)  # the scapulae's dorsal ends, over the ground
    length = body.withers / (drop + _SPINOUS)
    mass = body.mass / _total_mass(spec)
    return Scales(
        length=length,
        limb=length * body.leg,
        cannon=length * body.leg * body.cannon,
        mass=mass,
        girth=length * math.sqrt(mass / length**3),
    )


def scaled_spec(spec: mujoco.MjSpec, body: Body) -> mujoco.MjSpec:
    """Edit the horse's ``spec`` in place into ``body`` and return it (the reference: unchanged)."""
    if body.is_reference:
        return spec
    s = scales_for(body, spec)
    for element in spec.bodies[1:]:
        parent = element.parent.name
        if parent != "world":
            element.pos = np.asarray(element.pos) * s.of_segment(parent)
        own = s.of_segment(element.name)
        for geom in element.geoms:
            _scale_geom(geom, own, s)
        for site in element.sites:
            site.pos = np.asarray(site.pos) * own
            site.size = np.asarray(site.size) * np.array([s.girth, s.girth, own])
        for camera in element.cameras:
            camera.pos = np.asarray(camera.pos) * s.length
    for camera in spec.worldbody.cameras:
        camera.pos = np.asarray(camera.pos) * s.length
    _stand_level(spec, s)
    # Time scales as sqrt(L / g) with the legs' L: the contacts' time constant and the integration
    # step too, or a smaller body meets a relatively softer ground and walks slower (measured:
    # docs/bodies.md, "Dynamic similarity in the simulator").
    time = math.sqrt(s.limb)
    spec.option.timestep = spec.option.timestep * time
    for geom in spec.geoms:
        solref, solimp = np.array(geom.solref), np.array(geom.solimp)
        solref[0] *= time
        solimp[2] *= s.limb  # the width over which the contact stiffens: a length
        geom.solref, geom.solimp = solref, solimp
    for joint in spec.joints:
        if joint.type != mujoco.mjtJoint.mjJNT_HINGE or joint.name == "root_pitch":
            continue
        lever = s.of_joint(joint.parent.name)
        joint.armature = joint.armature * s.mass * lever**2
        joint.damping = np.asarray(joint.damping) * s.mass * lever**1.5
    for actuator in spec.actuators:
        lever = s.of_joint(spec.joint(actuator.target).parent.name)
        stiffness, damping, torque = s.mass * lever, s.mass * lever**1.5, s.mass * lever
        gain, bias = np.array(actuator.gainprm), np.array(actuator.biasprm)
        gain[0] *= stiffness
        bias[1] *= stiffness
        bias[2] *= damping
        actuator.gainprm, actuator.biasprm = gain, bias
        actuator.forcerange = np.asarray(actuator.forcerange) * torque
    return spec


def _scale_geom(geom: mujoco.MjsGeom, length: float, s: Scales) -> None:
    geom.mass = geom.mass * s.mass
    geom.pos = np.asarray(geom.pos) * length
    size = np.array(geom.size)
    if geom.type == mujoco.mjtGeom.mjGEOM_CAPSULE:
        geom.fromto = np.asarray(geom.fromto) * length
        size[0] *= s.girth
    elif geom.type == mujoco.mjtGeom.mjGEOM_BOX:  # a hoof: its sole grows with girth, its depth with length
        size *= np.array([s.girth, s.girth, length])
    else:  # pragma: no cover - horse.xml has only capsules and boxes on the horse
        raise ValueError(f"cannot scale geom {geom.name!r} of type {geom.type}")
    geom.size = size


def _limb_drops(spec: mujoco.MjSpec, s: Scales) -> tuple[float, float]:
    """How far below its attachment on the trunk each limb's sole reaches (fore, hind), at ``s``."""

    def drop(chain: tuple[str, ...]) -> float:
        depth = 0.0
        for parent, child in itertools.pairwise(chain):
            depth -= spec.body(child).pos[2] * s.of_segment(parent)
        hoof = spec.geom(f"hoof_{chain[-1].removeprefix('digit_')}")
        return depth - (hoof.pos[2] - hoof.size[2]) * s.of_segment(chain[-1])

    return drop(_FORE_CHAIN), drop(_HIND_CHAIN)


def _stand_level(spec: mujoco.MjSpec, s: Scales) -> None:
    """Put the trunk at the height where the fore soles touch the ground, and the hips where the
    hind soles do too (the horse's own limbs already stand level)."""
    fore, hind = _limb_drops(spec, Scales(1.0, 1.0, 1.0, 1.0, 1.0))
    trunk = spec.body("trunk")
    scapula = spec.body(_FORE_CHAIN[0]).pos[2]
    height = fore - scapula
    trunk.pos = np.array([trunk.pos[0], trunk.pos[1], height])
    for side in ("left", "right"):
        hip = spec.body(f"thigh_hind_{side}")
        hip.pos = np.array([hip.pos[0], hip.pos[1], hind - height])


def _total_mass(spec: mujoco.MjSpec) -> float:
    return float(sum(geom.mass for geom in spec.geoms if geom.name != "floor"))
