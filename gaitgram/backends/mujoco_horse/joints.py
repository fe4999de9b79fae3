"""The horse's joint catalogue (``joints.toml``): the 12 curves of the paper's Table 3, their
limits and freedom schedule. Read by the linter and the model alike, without MuJoCo."""

from __future__ import annotations

from importlib.resources import files

from gaitgram.backends.catalogue import load_catalogue

CATALOGUE = load_catalogue(files(__package__).joinpath("joints.toml"))
