"""The ``mujoco-horse`` backend: a physics-based horse walked in MuJoCo."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from dataclasses import asdict
from functools import cache
from typing import Any

from gaitgram.backends.api import Verdict
from gaitgram.backends.mujoco_horse.bodies import BODIES, NOMINAL_HIP_HEIGHT, SCALINGS
from gaitgram.backends.mujoco_horse.joints import CATALOGUE, SENSORS
from gaitgram.backends.mujoco_horse.reference import assessment
from gaitgram.backends.mujoco_horse.settings import WEIGHT_NAMES, HorseSettings, weights_in_force
from gaitgram.backends.mujoco_horse.targets import (
    CYCLE_FREQUENCIES,
    DEFAULT_FROUDE,
    DEFAULT_WEIGHTS,
    TASK_REVISION,
    WALK_COMPONENTS,
    WALK_CRITERION,
    stride_frequency,
    unviable_fitness,
)
from gaitgram.backends.registry import BackendSpec
from gaitgram.packaged import packaged

#: What a viable gait's evaluation reports (evaluator.py's ``_judge``; a test keeps them equal).
COMPONENTS = WEIGHT_NAMES | {
    "measured_velocity",
    "measured_duty_factor",
    "measured_stride",
    "measured_frequency",
    "measured_work",
    "measured_speed_spread",
    *WALK_COMPONENTS,
    "walk",
    "checked_cycles",
}


def load(settings: Mapping[str, Any] | None = None) -> Any:
    """Import MuJoCo only when gaits are to be simulated: the linter needs just the catalogue."""
    from gaitgram.backends.mujoco_horse.evaluator import load as load_evaluator

    return load_evaluator(settings)


def retarget(settings: Mapping[str, Any], motion: Any, body: str, scaling: str) -> tuple[dict[str, Any], Any]:
    """Import MuJoCo only to play gaits on another body (it measures each body's hip height)."""
    from gaitgram.backends.mujoco_horse.retarget import retarget as play_on

    return play_on(settings, motion, body, scaling)


def assess(settings: Mapping[str, Any], motion: Any) -> list[dict[str, Any]]:
    """Import MuJoCo only to measure kept gaits beyond their scores (``report --assess``)."""
    from gaitgram.backends.mujoco_horse.assessment import assess_gaits

    return assess_gaits(settings, motion)


def render(settings: Mapping[str, Any], motion: Any, **how: Any) -> list[list[Any]]:
    """Import MuJoCo only to draw gaits (``gaitgram render``, a report's GIFs)."""
    from gaitgram.backends.mujoco_horse.render import render as draw

    return draw(settings, motion, **how)


def check_settings(settings: Mapping[str, Any]) -> dict[str, Any]:
    """Every setting spelt out, defaults included: a run directory records the values it used."""
    return {k: v for k, v in asdict(HorseSettings.from_mapping(settings)).items() if v is not None}


def scored_components(settings: Mapping[str, Any]) -> tuple[str, ...]:
    """The components the fitness weighs (the frequency is measured, but not scored by default)."""
    weights = weights_in_force(None, settings.get("weights"))
    return tuple(name for name in DEFAULT_WEIGHTS if weights.get(name, 0.0) > 0)


@cache
def _version() -> str:
    """The fitness formula's revision, the simulator's release and a digest of the model files
    (when a run records it: importlib.metadata would slow every ``gaitgram check``)."""
    from importlib.metadata import PackageNotFoundError, version

    digest = hashlib.sha256()
    for name in ("horse.xml", "joints.toml"):
        digest.update(packaged(__name__, name).read_bytes())
    try:
        simulator = version("mujoco")
    except PackageNotFoundError:  # pragma: no cover - mujoco is a core dependency
        simulator = "unknown"
    return f"fitness r{TASK_REVISION}, mujoco {simulator}, model {digest.hexdigest()[:12]}"


BACKEND = BackendSpec(
    name="mujoco-horse",
    summary="A 500 kg horse with the paper's 12 joint curves, scored by the Froude-number fitness.",
    catalogue=CATALOGUE,
    load=load,
    check_settings=check_settings,
    weight_names=lambda settings: WEIGHT_NAMES,
    runtime_settings=frozenset({"threads"}),
    horizon_setting="horizon_cycles",
    version=_version,
    unviable_fitness=lambda settings, weights: unviable_fitness(
        weights_in_force(weights, settings.get("weights"))
    ),
    cycle_frequencies=CYCLE_FREQUENCIES,
    objectives=scored_components,
    # From a slow walk to a fast trot: speed (m/s) and the share of the cycle a hoof is down.
    descriptors={"measured_velocity": (0.0, 3.0), "measured_duty_factor": (0.3, 0.9)},
    verdict=Verdict("walk", "walk", WALK_COMPONENTS, "walk_sustained", WALK_CRITERION),
    components=lambda settings: COMPONENTS | ({"bumps_fitness"} if settings.get("bump_floors") else set()),
    scoring_settings=frozenset({"bump_floors", "bump_height", "speed_margin"}),
    bodies={name: body.summary for name, body in BODIES.items()},
    retarget=retarget,
    retarget_scalings=SCALINGS,
    assess=assess,
    assessment=assessment,
    render=render,
    # The target's stride frequency on the nominal horse, at the default Froude number.
    cycle_frequency=stride_frequency(DEFAULT_FROUDE, NOMINAL_HIP_HEIGHT),
    sensors=SENSORS,
)
