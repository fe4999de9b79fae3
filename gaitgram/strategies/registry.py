"""Finding search strategies: the ``gaitgram.strategies`` entry-point group.

A package makes a strategy available as a backend does, in its ``pyproject.toml``::

    [project.entry-points."gaitgram.strategies"]
    hill-climb = "my_package.strategy:STRATEGY"

where ``STRATEGY`` is a :class:`StrategySpec`. Loading a spec must be cheap
(every run configuration is checked against it); the optimiser library is
imported by ``spec.load()``, only when a run starts. The built-in strategies
are found even where the installed metadata predates them (a source checkout),
and a plug-in cannot take one of their names.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache
from importlib import import_module
from importlib.metadata import PackageNotFoundError, entry_points, version
from typing import TYPE_CHECKING, Any

from gaitgram.strategies.api import Strategy

if TYPE_CHECKING:
    from gaitgram.pipeline import Pipeline

ENTRY_POINT_GROUP = "gaitgram.strategies"

#: The strategies gaitgram ships (also declared as entry points in its pyproject.toml).
BUILTIN = {
    "ge": "gaitgram.strategies.ge:STRATEGY",
    "random": "gaitgram.strategies.random_search:STRATEGY",
    "cma-es": "gaitgram.strategies.cma_es:STRATEGY",
    "nsga2": "gaitgram.strategies.nsga2:STRATEGY",
    "map-elites": "gaitgram.strategies.map_elites:STRATEGY",
}


@dataclass(frozen=True)
class StrategySpec:
    """What a strategy declares about itself.

    * ``load()`` returns the :class:`~gaitgram.strategies.api.Strategy`; it may import a heavy
      library, and raises :class:`~gaitgram.extras.MissingExtra` when that is not installed.
    * ``check(pipeline)`` returns the strategy's settings (``pipeline.config.strategy_settings``)
      normalised, defaults spelt out, or raises
      :class:`~gaitgram.backends.api.SettingsError` naming a bad key, or
      :class:`~gaitgram.strategies.api.StrategyError` when the grammar or configuration is one
      the strategy cannot search. Cheap: no library.
    * ``version`` changes whenever the same run could come out differently (the strategy's code,
      its library's release); a run is not resumed under another.
    """

    name: str
    summary: str
    load: Callable[[], Strategy]
    check: Callable[[Pipeline], Mapping[str, Any]] | None = None
    version: str = ""


class StrategyNotFound(LookupError):
    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.name = name


class StrategyLoadError(RuntimeError):
    pass


@cache
def _entry_points() -> dict[str, str]:
    found = {ep.name: ep.value for ep in entry_points(group=ENTRY_POINT_GROUP)}
    return {**found, **BUILTIN}  # a plug-in cannot take a built-in's name


def strategy_names() -> tuple[str, ...]:
    return tuple(sorted(_entry_points()))


@cache
def get_strategy(name: str) -> StrategySpec:
    target = _entry_points().get(name)
    if target is None:
        raise StrategyNotFound(name)
    module, _, attribute = target.partition(":")
    try:
        spec = getattr(import_module(module), attribute)
    except Exception as exc:  # a broken plug-in must not take gaitgram down
        raise StrategyLoadError(f"strategy {name!r} ({target}) failed to load: {exc}") from exc
    if not isinstance(spec, StrategySpec):
        raise StrategyLoadError(f"strategy {name!r} ({target}) is not a gaitgram StrategySpec")
    return spec


def library_version(distribution: str) -> str:
    """``"NAME VERSION"`` of an installed distribution, or ``"NAME not installed"`` (cheap: no import)."""
    try:
        return f"{distribution} {version(distribution)}"
    except PackageNotFoundError:
        return f"{distribution} not installed"


def load_strategy(pipeline: Pipeline) -> Strategy:
    """The strategy of a built pipeline's config, its library imported (``MissingExtra`` if absent)."""
    return get_strategy(pipeline.config.strategy).load()
