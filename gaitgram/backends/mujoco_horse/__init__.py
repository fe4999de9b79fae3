"""The ``mujoco-horse`` backend: a physics-based horse walked in MuJoCo."""

from __future__ import annotations

from collections.abc import Mapping
from importlib.resources import files
from typing import Any

from gaitgram.backends.catalogue import load_catalogue
from gaitgram.backends.registry import BackendSpec

CATALOGUE = load_catalogue(files(__name__).joinpath("joints.toml"))


def load(settings: Mapping[str, Any] | None = None) -> Any:
    """Import MuJoCo only when gaits are to be simulated: the linter needs just the catalogue."""
    from gaitgram.backends.mujoco_horse.evaluator import load as load_evaluator

    return load_evaluator(settings)


BACKEND = BackendSpec(
    name="mujoco-horse",
    summary="A 500 kg horse with the paper's 12 joint curves, scored by the Froude-number fitness.",
    catalogue=CATALOGUE,
    load=load,
)
