"""The ``mujoco-horse`` backend: a physics-based horse walked in MuJoCo."""

from __future__ import annotations

from importlib.resources import files

from gaitgram.backends.catalogue import load_catalogue
from gaitgram.backends.registry import BackendSpec

CATALOGUE = load_catalogue(files(__name__).joinpath("joints.toml"))

BACKEND = BackendSpec(
    name="mujoco-horse",
    summary="A 500 kg horse with the paper's 12 joint curves, scored by the Froude-number fitness.",
    catalogue=CATALOGUE,
)
