"""Joint catalogues: the joints a backend can drive, their limits and grouping.

A catalogue is plain data, loaded without importing the backend's simulator, so
that ``gaitgram check`` can verify ``@joint`` annotations cheaply.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # a plug-in may pass its package data as importlib.resources gives it
    from importlib.resources.abc import Traversable

__all__ = ["CatalogueError", "Joint", "JointCatalogue", "load_catalogue"]


@dataclass(frozen=True, slots=True)
class Joint:
    """One driven curve. Angles are degrees relative to the neutral pose."""

    name: str
    group: str  # e.g. "forelimb", "hindlimb", "neck"
    limits: tuple[float, float]
    description: str = ""
    free_from: int = 0  # the generation Table 3 of the paper frees it in


@dataclass(frozen=True)
class JointCatalogue:
    joints: tuple[Joint, ...]

    @cached_property
    def _by_name(self) -> dict[str, Joint]:
        return {j.name: j for j in self.joints}

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    def get(self, name: str) -> Joint | None:
        return self._by_name.get(name)

    def __len__(self) -> int:
        return len(self.joints)


class CatalogueError(ValueError):
    pass


def load_catalogue(resource: Path | Traversable) -> JointCatalogue:
    """Read a catalogue TOML file: a list of ``[[joint]]`` tables."""
    try:
        data = tomllib.loads(resource.read_text(encoding="utf-8"))
        joints = tuple(
            Joint(
                name=entry["name"],
                group=entry["group"],
                limits=(float(entry["limits"][0]), float(entry["limits"][1])),
                description=entry.get("description", ""),
                free_from=int(entry.get("free_from", 0)),
            )
            for entry in data["joint"]
        )
    except (KeyError, IndexError, TypeError, ValueError, tomllib.TOMLDecodeError) as exc:
        raise CatalogueError(f"{resource}: not a joint catalogue: {exc}") from exc
    names = [j.name for j in joints]
    if len(set(names)) != len(names):
        raise CatalogueError(f"{resource}: joint names repeat")
    return JointCatalogue(joints)
