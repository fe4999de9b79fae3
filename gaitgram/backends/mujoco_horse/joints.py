"""The horse's catalogues: its joint curves (``joints.toml``: the 12 curves of the paper's Table 3,
their limits and freedom schedule) and its sensors (``sensors.toml``: what a closed-loop phenotype
may read). Read by the linter and the model alike, without MuJoCo."""

from __future__ import annotations

from gaitgram.backends.catalogue import load_catalogue
from gaitgram.backends.sensors import load_sensors
from gaitgram.packaged import packaged

CATALOGUE = load_catalogue(packaged(__package__, "joints.toml"))
SENSORS = load_sensors(packaged(__package__, "sensors.toml"))
