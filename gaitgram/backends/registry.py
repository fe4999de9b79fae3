"""Finding fitness backends: the ``gaitgram.backends`` entry-point group.

A package makes a backend available by declaring, in its ``pyproject.toml``::

    [project.entry-points."gaitgram.backends"]
    my-backend = "my_package.backend:BACKEND"

where ``BACKEND`` is a :class:`BackendSpec`. Loading a spec must be cheap (no
simulator import): the linter loads it to read the joint catalogue.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from importlib.metadata import entry_points
from typing import Any

from gaitgram.backends.catalogue import JointCatalogue

ENTRY_POINT_GROUP = "gaitgram.backends"


@dataclass(frozen=True)
class BackendSpec:
    """What a backend declares about itself.

    ``catalogue`` is None for backends that take any joint names. ``load``
    returns the backend's evaluator; it may import heavy dependencies.
    """

    name: str
    summary: str
    catalogue: JointCatalogue | None
    load: Callable[[], Any] | None = None


class BackendNotFound(LookupError):
    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.name = name


class BackendLoadError(RuntimeError):
    pass


@cache
def _entry_points() -> dict[str, Any]:
    return {ep.name: ep for ep in entry_points(group=ENTRY_POINT_GROUP)}


def backend_names() -> tuple[str, ...]:
    return tuple(sorted(_entry_points()))


@cache
def get_backend(name: str) -> BackendSpec:
    ep = _entry_points().get(name)
    if ep is None:
        raise BackendNotFound(name)
    try:
        spec = ep.load()
    except Exception as exc:  # a broken plug-in must not take gaitgram down
        raise BackendLoadError(f"backend {name!r} ({ep.value}) failed to load: {exc}") from exc
    if not isinstance(spec, BackendSpec):
        raise BackendLoadError(f"backend {name!r} ({ep.value}) is not a gaitgram BackendSpec")
    return spec
