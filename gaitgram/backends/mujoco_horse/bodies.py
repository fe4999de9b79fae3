"""The bodies a run can walk: ``bodies.toml`` read as data, without importing MuJoCo.

Settings are checked before anything is simulated, so a misspelt body is refused with the names
there are; :mod:`~gaitgram.backends.mujoco_horse.scaling` builds the MuJoCo model of a body.
"""

from __future__ import annotations

import difflib
import tomllib
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from gaitgram.packaged import packaged

#: How a gait played on another body is timed (``retarget.py``): its cycle frequency scaled by
#: dynamic similarity, or the frequency it was evolved at.
SCALINGS = ("froude", "unscaled")
#: The body horse.xml describes, the one every other body is scaled from.
REFERENCE_BODY = "horse"
#: The reference's height at the withers (m): horse.xml's scapulae end 1.50 m up, and the withers'
#: spinous processes, not modelled, add about 0.1 m.
REFERENCE_WITHERS = 1.6
#: The reference's hip (coxofemoral) height for sizing a simulation before the model is built (the
#: model measures 1.138 m).
NOMINAL_HIP_HEIGHT = 1.14


@dataclass(frozen=True)
class Body:
    """A body as ``bodies.toml`` gives it: sizes, proportions, and what they rest on."""

    name: str
    summary: str
    withers: float  # m
    mass: float  # kg
    leg: float  # limb segments' length relative to the length scale
    cannon: float  # cannons' length relative to the rest of the limb
    sources: tuple[str, ...]

    @property
    def is_reference(self) -> bool:
        return self.name == REFERENCE_BODY

    @property
    def nominal_hip_height(self) -> float:
        """The hip height to size a simulation by before the model is built: never below the built
        body's (limbs are at most as long as a scaled horse's), so a time budget is not exceeded."""
        if self.is_reference:
            return NOMINAL_HIP_HEIGHT
        return NOMINAL_HIP_HEIGHT * self.withers / REFERENCE_WITHERS


class UnknownBody(LookupError):
    """A body name that ``bodies.toml`` does not define."""

    def __init__(self, name: str) -> None:
        close = difflib.get_close_matches(name, list(BODIES), n=1)
        hint = f"did you mean {close[0]!r}?" if close else f"the bodies are {', '.join(BODIES)}"
        super().__init__(f"no body is called {name!r}; {hint}")
        self.name = name


_FIELDS = {"summary": str, "withers": float, "mass": float, "leg": float, "cannon": float, "sources": list}


def _body(name: str, table: dict[str, Any]) -> Body:
    missing = sorted(set(_FIELDS) - set(table))
    unknown = sorted(set(table) - set(_FIELDS))
    if missing or unknown:
        raise ValueError(f"bodies.toml [{name}]: missing {missing}, unknown {unknown}")
    for key, kind in _FIELDS.items():
        value = table[key]
        if kind is float:
            if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
                raise ValueError(f"bodies.toml [{name}].{key} must be a positive number, not {value!r}")
        elif not isinstance(value, kind):
            raise ValueError(f"bodies.toml [{name}].{key} must be a {kind.__name__}, not {value!r}")
    return Body(
        name=name,
        summary=table["summary"],
        withers=float(table["withers"]),
        mass=float(table["mass"]),
        leg=float(table["leg"]),
        cannon=float(table["cannon"]),
        sources=tuple(str(source) for source in table["sources"]),
    )


def _load() -> MappingProxyType[str, Body]:
    text = packaged(__package__, "bodies.toml").read_text(encoding="utf-8")
    bodies = {name: _body(name, table) for name, table in tomllib.loads(text).items()}
    if REFERENCE_BODY not in bodies:
        raise ValueError(f"bodies.toml must define the reference body [{REFERENCE_BODY}]")
    return MappingProxyType(bodies)


#: Every body by name, in the file's order (the reference first).
BODIES = _load()


def body_named(name: str | None) -> Body:
    """The body called ``name`` (the reference when None); raises :class:`UnknownBody`."""
    try:
        return BODIES[REFERENCE_BODY if name is None else name]
    except KeyError:
        raise UnknownBody(str(name)) from None
