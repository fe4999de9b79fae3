"""``map-elites``: a repertoire of gaits, the best in each cell of a grid of gait descriptors.

One run of GE finds one good gait; MAP-Elites (pyribs' ``GridArchive`` and
``Scheduler``) keeps the best gait found for every combination of descriptors
that tell gaits apart: by default the measured speed and duty factor on
``mujoco-horse``, from slow walks toward the trot. Descriptors are fitness
components the backend measures; values beyond a descriptor's range fall in
its edge cells. A cell keeps a gait only if it scores better than the one it
holds (ties keep the first); unviable gaits never enter.

Variation is GE's: parents drawn uniformly from the archive, one-point
crossover and int-flip mutation with the run's settings
(:class:`~gaitgram.strategies.ribs_emitter.GenomeEmitter`). Generation 0 is GE's
initial population; every later generation evaluates ``population - elite``
offspring, GE's budget. The run's population (for its statistics) is the best
``elite`` gaits so far and the newest batch; ``archive.json`` in each run
directory is the repertoire, which ``gaitgram report`` draws as a heat map.
A run whose scores change during it (a weight schedule, joints coming free) is
refused: the archive would keep stale scores.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitgram.backends.api import GaitStatus, SettingsError
from gaitgram.extras import require
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.runlayout import ARCHIVE
from gaitgram.strategies.api import Genome, RunContext, RunState, Strategy, StrategyError
from gaitgram.strategies.common import (
    GEVariation,
    batch_size,
    component,
    elitist,
    initial_genomes,
    known_keys,
    reported,
    require_fixed_scores,
)
from gaitgram.strategies.registry import StrategySpec, library_version

REVISION = 1
DEFAULT_BINS = 10
MAX_CELLS = 100_000


@dataclass(frozen=True)
class Descriptor:
    name: str
    low: float
    high: float
    bins: int

    def as_setting(self) -> dict[str, Any]:
        return {"name": self.name, "low": self.low, "high": self.high, "bins": self.bins}


@dataclass
class ArchiveMemory:
    scheduler: Any  # ribs Scheduler: the GridArchive and the GenomeEmitter
    variation: GEVariation
    descriptors: tuple[Descriptor, ...]

    @property
    def archive(self) -> Any:
        return self.scheduler.archive


class MapElites(Strategy):
    def __init__(self) -> None:
        require("ribs", "map-elites runs")

    def start(self, context: RunContext, rng: np.random.Generator) -> ArchiveMemory:
        from ribs.schedulers import Scheduler

        from gaitgram.strategies.ribs_emitter import GenomeEmitter, ViableArchive

        pipeline = context.pipeline
        config = pipeline.config
        descriptors = descriptors_of(context.settings)
        archive = ViableArchive(
            floor=-pipeline.unviable_fitness(0),  # objective = -fitness: unviable gaits never enter
            solution_dim=(),
            solution_dtype=object,
            dims=[d.bins for d in descriptors],
            ranges=[(d.low, d.high) for d in descriptors],
            seed=context.integer_seed(1),
            extra_fields={"individual": ((), object)},
        )
        variation = GEVariation(config.representation_settings)
        emitter = GenomeEmitter(
            archive,
            initial=initial_genomes(pipeline, rng, config.population),
            batch_size=batch_size(config, 1),
            variation=variation,
            generator=context.generator(),
        )
        return ArchiveMemory(Scheduler(archive, [emitter]), variation, descriptors)

    def restore(self, context: RunContext, memory: Any) -> ArchiveMemory:
        if not isinstance(memory, ArchiveMemory):
            raise StrategyError("its strategy state is not a map-elites state")
        if memory.descriptors != descriptors_of(context.settings):
            raise StrategyError("its map-elites archive has other descriptors than the run's")
        return memory

    def ask(self, context: RunContext, state: RunState) -> list[Genome]:
        memory: ArchiveMemory = state.memory
        pipeline = context.pipeline
        (emitter,) = memory.scheduler.emitters
        memory.variation.mapper = pipeline.representation.mapper  # type: ignore[attr-defined]
        emitter.draw = lambda generator, n: initial_genomes(pipeline, generator, n)
        try:
            return list(memory.scheduler.ask())
        finally:
            memory.variation.mapper = None
            emitter.draw = None

    def tell(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[Individual]:
        memory: ArchiveMemory = state.memory
        corner = [d.low for d in memory.descriptors]  # unviable gaits: at the floor, never added
        measures = [
            [component(i, d.name) for d in memory.descriptors]
            if i.evaluation.status is GaitStatus.OK
            else corner
            for i in evaluated
        ]
        individuals = np.empty(len(evaluated), dtype=object)
        for k, individual in enumerate(evaluated):
            individuals[k] = individual
        memory.scheduler.tell(
            np.array([-i.fitness for i in evaluated], dtype=float),
            np.array(measures, dtype=float),
            individual=individuals,
        )
        return elitist(state, context.pipeline, evaluated)[0]

    def keeps(self, context: RunContext, state: RunState, evaluated: list[Individual]) -> list[int]:
        """The new gaits that would take a cell: the best new gait in its cell, if it beats the
        cell's elite (ties keep the first, as the archive does)."""
        memory: ArchiveMemory = state.memory
        new = [k for k, i in enumerate(evaluated) if i.evaluation.status is GaitStatus.OK]
        if not new:
            return []
        measures = np.array([[component(evaluated[k], d.name) for d in memory.descriptors] for k in new])
        cells = memory.archive.index_of(measures)
        occupied, elites = memory.archive.retrieve(measures)
        taken: dict[int, int] = {}
        for k, cell, held, incumbent in zip(new, cells, occupied, elites["objective"], strict=True):
            objective = -evaluated[k].fitness
            if held and objective <= incumbent:
                continue
            if int(cell) not in taken or objective > -evaluated[taken[int(cell)]].fitness:
                taken[int(cell)] = k
        return sorted(taken.values())

    def records(self, context: RunContext, state: RunState) -> dict[str, Any]:
        return {ARCHIVE: archive_record(state.generation, state.memory)}


def archive_record(generation: int, memory: ArchiveMemory) -> dict[str, Any]:
    """The repertoire: every filled cell (its grid index, measures and best gait), best first."""
    archive = memory.archive
    data = archive.data()
    cells = []
    for index, measures, individual in zip(
        archive.int_to_grid_index(data["index"]), data["measures"], data["individual"], strict=True
    ):
        cells.append(
            {
                "cell": [int(i) for i in index],
                "measures": [float(m) for m in measures],
                "fitness": individual.fitness,
                "components": dict(individual.evaluation.components),
                "cycles": {name: list(values) for name, values in individual.evaluation.cycles.items()},
                "genome": list(individual.genome),
                "phenotype": individual.phenotype,
            }
        )
    cells.sort(key=lambda c: (c["fitness"], c["cell"]))
    return {
        "generation": generation,
        "descriptors": [d.as_setting() for d in memory.descriptors],
        "cells": int(archive.cells),
        "filled": len(cells),
        "elites": cells,
    }


def descriptors_of(settings: Mapping[str, Any]) -> tuple[Descriptor, ...]:
    """The normalised ``descriptors`` setting (as :func:`check` wrote it)."""
    return tuple(Descriptor(d["name"], d["low"], d["high"], d["bins"]) for d in settings["descriptors"])


def _descriptor(value: Any, index: int, pipeline: Pipeline) -> Descriptor:
    """One descriptor, its name first: a misspelt one is named as such (with the name it is
    close to), not asked for a range the backend would suggest for the name meant."""
    key = f"descriptors[{index}]"
    hints = dict(pipeline.spec.descriptors or {})
    if isinstance(value, str):
        value = {"name": value}
    if not isinstance(value, Mapping) or not isinstance(value.get("name"), str) or not value["name"]:
        raise SettingsError(key, 'must be a component name or a table { name = "...", low, high, bins }')
    unknown = set(value) - {"name", "low", "high", "bins"}
    if unknown:
        raise SettingsError(f"{key}.{sorted(unknown)[0]}", "unknown; a descriptor has name, low, high, bins")
    name = value["name"]
    reported(pipeline, name, f"{key}.name")
    if ("low" not in value or "high" not in value) and name not in hints:
        raise SettingsError(
            key, f"give the range of {name!r}: low = ..., high = ... (the backend suggests none)"
        )
    low, high = (
        value.get("low", hints.get(name, (0.0, 0.0))[0]),
        value.get("high", hints.get(name, (0.0, 0.0))[1]),
    )
    for what, number in (("low", low), ("high", high)):
        if isinstance(number, bool) or not isinstance(number, int | float) or not math.isfinite(number):
            raise SettingsError(f"{key}.{what}", f"must be a number, not {number!r}")
    if not low < high:
        raise SettingsError(key, f"low must be below high, not {low!r}..{high!r}")
    bins = value.get("bins", DEFAULT_BINS)
    if isinstance(bins, bool) or not isinstance(bins, int) or not 1 <= bins <= 1000:
        raise SettingsError(f"{key}.bins", f"must be a whole number in [1, 1000], not {bins!r}")
    return Descriptor(name, float(low), float(high), bins)


def check(pipeline: Pipeline) -> Mapping[str, Any]:
    settings = pipeline.config.strategy_settings
    known_keys(settings, ("descriptors",), "map-elites")
    hints = dict(pipeline.spec.descriptors or {})
    given = settings.get("descriptors", list(hints))
    if not isinstance(given, list) or not given:
        where = f"backend {pipeline.backend!r} suggests none" if not hints else "a list is needed"
        raise SettingsError(
            "descriptors",
            f"name one or two measured components to tell gaits apart ({where}): descriptors = "
            '[{ name = "...", low = 0.0, high = 1.0, bins = 10 }]',
        )
    if len(given) > 2:
        raise SettingsError("descriptors", f"one or two descriptors (a line or a grid), not {len(given)}")
    descriptors = [_descriptor(value, i, pipeline) for i, value in enumerate(given)]
    if len({d.name for d in descriptors}) != len(descriptors):
        raise SettingsError("descriptors", "names a component twice")
    if math.prod(d.bins for d in descriptors) > MAX_CELLS:
        raise SettingsError("descriptors", f"more than {MAX_CELLS} cells; use fewer bins")
    require_fixed_scores(pipeline, "map-elites", "its archive")
    return {"descriptors": [d.as_setting() for d in descriptors]}


STRATEGY = StrategySpec(
    name="map-elites",
    summary="A repertoire: the best gait in each cell of a grid of gait descriptors (pyribs MAP-Elites).",
    load=MapElites,
    check=check,
    version=f"map-elites r{REVISION}; {library_version('ribs')}",
    representations=frozenset({"ge"}),
)
