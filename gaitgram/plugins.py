"""Finding plug-ins by entry point: fitness backends and search strategies alike.

A package declares a plug-in in its ``pyproject.toml``::

    [project.entry-points."gaitgram.backends"]      # or "gaitgram.strategies"
    my-backend = "my_package.backend:BACKEND"

Loading a plug-in's spec must be cheap (the linter and every configuration check
read specs); heavy libraries come later, when the spec's ``load`` is called. The
plug-ins gaitgram ships are found even where the installed metadata predates them
(a source checkout), and a third-party package cannot take one of their names. A
name that is not installed gets the nearest installed one as a suggestion.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from importlib import import_module
from typing import Generic, TypeVar

from gaitgram import __version__

Spec = TypeVar("Spec")


class PluginNotFound(LookupError):
    """No plug-in of this kind has the name; the message suggests the nearest installed one."""

    def __init__(self, name: str, kind: str = "plug-in", installed: tuple[str, ...] = ()) -> None:
        super().__init__(name)
        self.name = name
        self.kind = kind
        self.installed = installed

    @property
    def suggestion(self) -> str | None:
        close = difflib.get_close_matches(self.name, self.installed, n=1)
        return close[0] if close else None

    def __str__(self) -> str:
        hint = f"did you mean {self.suggestion}? " if self.suggestion else ""
        return f"no {self.kind} named {self.name!r}; {hint}installed: {', '.join(self.installed)}"


class PluginLoadError(RuntimeError):
    """A plug-in that is declared but cannot be loaded, or is not what it should be."""


@dataclass(frozen=True)
class Declared:
    """A plug-in as declared: where its spec lives and which installed package provides it."""

    name: str
    target: str  # "module:attribute"
    package: str  # "distribution version", what a run records


def package_version(distribution: str) -> str:
    """``"NAME VERSION"`` of an installed distribution, or ``"NAME not installed"`` (cheap: no import)."""
    from importlib.metadata import PackageNotFoundError, version  # 20 ms: only when asked

    try:
        return f"{distribution} {version(distribution)}"
    except PackageNotFoundError:
        return f"{distribution} not installed"


class Registry(Generic[Spec]):
    """The plug-ins of one entry-point group, each loaded once and checked to be a ``spec_type``.

    ``not_found`` and ``load_error`` are the exception classes raised, so that each kind keeps
    its own names (``BackendNotFound``, ``StrategyNotFound``)."""

    def __init__(
        self,
        group: str,
        kind: str,
        spec_type: type[Spec],
        builtin: Mapping[str, str],
        *,
        not_found: type[PluginNotFound] = PluginNotFound,
        load_error: type[PluginLoadError] = PluginLoadError,
    ) -> None:
        self.group = group
        self.kind = kind
        self.spec_type = spec_type
        self.builtin = dict(builtin)
        self.not_found = not_found
        self.load_error = load_error
        self._loaded: dict[str, Spec] = {}

    @cached_property
    def declared(self) -> dict[str, Declared]:
        from importlib.metadata import entry_points  # 20 ms: a built-in is found without it

        found = {}
        for point in entry_points(group=self.group):
            dist = getattr(point, "dist", None)
            package = f"{dist.name} {dist.version}" if dist is not None else "unknown package"
            found[point.name] = Declared(point.name, point.value, package)
        for name in self.builtin:  # a plug-in cannot take a built-in's name
            found[name] = self._builtin(name)
        return found

    def _builtin(self, name: str) -> Declared:
        return Declared(name, self.builtin[name], f"gaitgram {__version__}")

    def names(self) -> tuple[str, ...]:
        return tuple(sorted(self.declared))

    def find(self, name: str) -> Declared:
        if name in self.builtin:  # without scanning the installed packages' entry points
            return self._builtin(name)
        found = self.declared.get(name)
        if found is None:
            raise self.not_found(name, self.kind, self.names())
        return found

    def get(self, name: str) -> Spec:
        if name in self._loaded:
            return self._loaded[name]
        found = self.find(name)
        module, _, attribute = found.target.partition(":")
        try:
            spec = getattr(import_module(module), attribute)
        except Exception as exc:  # a broken plug-in must not take gaitgram down
            raise self.load_error(f"{self.kind} {name!r} ({found.target}) failed to load: {exc}") from exc
        if not isinstance(spec, self.spec_type):
            raise self.load_error(
                f"{self.kind} {name!r} ({found.target}) is not a gaitgram {self.spec_type.__name__}"
            )
        self._loaded[name] = spec
        return spec
