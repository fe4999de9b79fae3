"""Sensors: what a backend lets a closed-loop phenotype read, declared as data.

A backend declares its sensors as it declares its joints (:mod:`~gaitgram.backends.catalogue`):
a TOML file of ``[[sensor]]`` tables, read without importing the simulator, so that ``gaitgram
check``, hover and completion know them. Each sensor has a name (what a phenotype writes), a
unit, a line for people, and how the simulation reads it (``read``, a table the backend's
simulation layer interprets: :mod:`gaitgram.backends.mujoco.sensing` for MuJoCo backends).

Two kinds need saying:

* a **per-limb** sensor (``per_limb = true``) reads the limb of the joint whose curve uses it: in
  a curve shared by the left and right hind legs, ``load`` is the left hoof's load on the left leg
  and the right hoof's on the right. A joint that drives no limb (``groups`` lists the joint
  groups that do) cannot read it;
* a **periodic** sensor (``periodic = true``) is a phase in [0, 1) that advances with the cycle,
  like ``t``: curves of it are sampled on the phase grid and read at every physics step, where
  the others are read at the control rate and held between ticks.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from collections.abc import Iterator, Mapping
    from importlib.resources.abc import Traversable

__all__ = ["Sensor", "SensorCatalogue", "SensorCatalogueError", "load_sensors"]


@dataclass(frozen=True, slots=True)
class Sensor:
    name: str
    unit: str
    description: str
    per_limb: bool = False
    periodic: bool = False
    #: What it reads standing at rest: what a plot of a closed loop assumes.
    nominal: float = 0.0
    #: The joint groups (catalogue ``group``) whose curves may read it; empty: every joint.
    groups: frozenset[str] = frozenset()
    #: How the simulation reads it: a table its backend's simulation layer interprets.
    read: Mapping[str, Any] = field(default_factory=dict, compare=False)

    def readable_by(self, group: str) -> bool:
        return not self.groups or group in self.groups


@dataclass(frozen=True)
class SensorCatalogue:
    sensors: tuple[Sensor, ...]

    @cached_property
    def _by_name(self) -> dict[str, Sensor]:
        return {s.name: s for s in self.sensors}

    @property
    def names(self) -> frozenset[str]:
        return frozenset(self._by_name)

    @property
    def periodic(self) -> frozenset[str]:
        return frozenset(s.name for s in self.sensors if s.periodic)

    def get(self, name: str) -> Sensor | None:
        return self._by_name.get(name)

    def nominal(self) -> dict[str, float]:
        return {s.name: s.nominal for s in self.sensors}

    def __len__(self) -> int:
        return len(self.sensors)

    def __iter__(self) -> Iterator[Sensor]:
        return iter(self.sensors)


class SensorCatalogueError(ValueError):
    pass


_KEYS = frozenset({"name", "unit", "description", "per_limb", "periodic", "nominal", "groups", "read"})


def load_sensors(resource: Path | Traversable) -> SensorCatalogue:
    """Read a sensor catalogue TOML file: a list of ``[[sensor]]`` tables."""
    try:
        data = tomllib.loads(resource.read_text(encoding="utf-8"))
        sensors = []
        for entry in data["sensor"]:
            unknown = sorted(set(entry) - _KEYS)
            if unknown:
                raise ValueError(f"sensor {entry.get('name')!r}: unknown keys {', '.join(unknown)}")
            name = entry["name"]
            if not (isinstance(name, str) and name.isidentifier() and name.isascii()):
                raise ValueError(f"sensor name {name!r} is not an identifier")
            sensors.append(
                Sensor(
                    name=name,
                    unit=str(entry["unit"]),
                    description=str(entry["description"]),
                    per_limb=bool(entry.get("per_limb", False)),
                    periodic=bool(entry.get("periodic", False)),
                    nominal=float(entry.get("nominal", 0.0)),
                    groups=frozenset(entry.get("groups", ())),
                    read=MappingProxyType(dict(entry.get("read", {}))),
                )
            )
    except (KeyError, TypeError, ValueError, tomllib.TOMLDecodeError) as exc:
        raise SensorCatalogueError(f"{resource}: not a sensor catalogue: {exc}") from exc
    names = [s.name for s in sensors]
    if len(set(names)) != len(names):
        raise SensorCatalogueError(f"{resource}: sensor names repeat")
    return SensorCatalogue(tuple(sensors))
