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
from dataclasses import dataclass, replace
from typing import Any

from gaitgram.analysis import CheckResult
from gaitgram.backends.api import SettingsError
from gaitgram.configuration import RunConfig
from gaitgram.pipeline import Pipeline, PipelineError, settings_error
from gaitgram.plugins import PluginLoadError, PluginNotFound, Registry, package_version
from gaitgram.strategies.api import Strategy, StrategyError

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
    * ``takes_start`` says that the strategy's first generation can be another run's final
      population (``start_from``, :attr:`RunContext.start`), not only its own random trees.
    * ``representations`` names the representations whose genomes it can search (None: any, through
      the representation's own initialisation and variation); a run of another is refused.
    """

    name: str
    summary: str
    load: Callable[[], Strategy]
    check: Callable[[Pipeline], Mapping[str, Any]] | None = None
    version: str = ""
    takes_start: bool = False
    representations: frozenset[str] | None = None


class StrategyNotFound(PluginNotFound):
    pass


class StrategyLoadError(PluginLoadError):
    pass


REGISTRY: Registry[StrategySpec] = Registry(
    ENTRY_POINT_GROUP,
    "strategy",
    StrategySpec,
    BUILTIN,
    not_found=StrategyNotFound,
    load_error=StrategyLoadError,
)


def strategy_names() -> tuple[str, ...]:
    return REGISTRY.names()


def get_strategy(name: str) -> StrategySpec:
    return REGISTRY.get(name)


#: ``"NAME VERSION"`` of a strategy's library (its spec's version names it).
library_version = package_version


def load_strategy(pipeline: Pipeline) -> Strategy:
    """The strategy of a built pipeline's config, its library imported (``MissingExtra`` if absent)."""
    return get_strategy(pipeline.config.strategy).load()


def _searches(name: str, representation: str) -> bool:
    """Whether the installed strategy ``name`` searches ``representation``'s genomes."""
    try:
        declared = get_strategy(name).representations
    except (StrategyNotFound, StrategyLoadError):
        return False
    return declared is None or representation in declared


def run_pipeline(checked: CheckResult, config: RunConfig) -> Pipeline:
    """The pipeline of a run: :meth:`Pipeline.build`, then the run's strategy checked against it
    (it can search this grammar and configuration) and its settings normalised, defaults spelt
    out; :class:`~gaitgram.pipeline.PipelineError` says what is wrong and how to fix it."""
    pipeline = Pipeline.build(checked, config)
    try:
        strategy = get_strategy(config.strategy)
    except StrategyNotFound as error:
        raise PipelineError(f"strategy: {error}", key="strategy") from None
    except StrategyLoadError as error:
        raise PipelineError(str(error)) from None
    if strategy.representations is not None and config.representation not in strategy.representations:
        able = [n for n in strategy_names() if _searches(n, config.representation)]
        raise PipelineError(
            f"strategy: {config.strategy} searches {' and '.join(sorted(strategy.representations))} genomes "
            f"only (it varies their codons itself), not {config.representation}'s; search "
            f"{config.representation} with {', '.join(able) or 'no installed strategy'}, or drop "
            f"representation = {config.representation!r}",
            key="strategy",
        )
    if config.start_from is not None and not strategy.takes_start:
        starters = [name for name in strategy_names() if get_strategy(name).takes_start]
        raise PipelineError(
            f"start_from: strategy {config.strategy} starts from its own first generation; the ones "
            f"that start from another run's population: {', '.join(starters) or 'none'}",
            key="start_from",
        )
    if strategy.check is None:
        return pipeline
    try:
        settings = dict(strategy.check(pipeline))
    except SettingsError as error:
        raise settings_error("strategy_settings", error) from None
    except StrategyError as error:
        raise PipelineError(str(error)) from None
    return replace(pipeline, config=replace(pipeline.config, strategy_settings=settings))
