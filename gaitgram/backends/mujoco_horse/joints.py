"""The horse's joint catalogue (``joints.toml``): the 12 curves of the paper's Table 3, their
limits and freedom schedule. Read by the linter and the model alike, without MuJoCo."""

from __future__ import annotations

from gaitgram.backends.catalogue import load_catalogue
from gaitgram.packaged import packaged

CATALOGUE = load_catalogue(packaged(__package__, "joints.toml"))
