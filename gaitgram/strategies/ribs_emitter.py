"""pyribs' side of ``map-elites``: an archive that admits only viable gaits, and an emitter that
varies genomes from it with GE's operators.

A module of its own because it imports ribs: the strategy's spec must load
without it, and pickled ``map-elites`` states name this class.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from ribs.archives import ArchiveBase, GridArchive
from ribs.emitters import EmitterBase

from gaitgram.strategies.api import Genome
from gaitgram.strategies.common import GEVariation


def as_objects(genomes: list[Genome]) -> np.ndarray:
    """A batch of genomes as ribs solutions: a 1-D array of tuples."""
    array = np.empty(len(genomes), dtype=object)
    for i, genome in enumerate(genomes):
        array[i] = genome
    return array


class ViableArchive(GridArchive):
    """MAP-Elites' grid (a cell keeps a solution only if it beats the elite there; ties keep the
    first), except that solutions scoring ``floor`` or worse, the unviable gaits, never enter: they
    have no measures to place them by. (``GridArchive``'s own ``threshold_min`` would do that only
    with CMA-MAE's soft thresholds, under which a worse gait can replace a better one.)"""

    def __init__(self, *, floor: float, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.floor = floor

    def add(self, solution: Any, objective: Any, measures: Any, **fields: Any) -> dict[str, np.ndarray]:
        objective = np.asarray(objective, dtype=float)
        viable = objective > self.floor
        info = {"status": np.zeros(len(objective), dtype=np.int32), "value": objective - self.floor}
        if viable.any():
            added = super().add(
                np.asarray(solution)[viable],
                objective[viable],
                np.asarray(measures)[viable],
                **{name: np.asarray(value)[viable] for name, value in fields.items()},
            )
            for name, values in added.items():
                info[name] = np.asarray(info.get(name, np.zeros(len(objective), dtype=values.dtype)))
                info[name][viable] = values
        return info


class GenomeEmitter(EmitterBase):
    """MAP-Elites' variation for GE genomes: parents drawn uniformly from the archive's elites
    (by the archive's generator), crossed with the run's probability, mutated; its first batch is
    the initial population it was given.

    ``draw(generator, n)`` (fresh random genomes, for an archive with no elite yet) and the
    variation's mapper are attached for each batch and never pickled.
    """

    def __init__(
        self,
        archive: ArchiveBase,
        *,
        initial: list[Genome],
        batch_size: int,
        variation: GEVariation,
        generator: np.random.Generator,
    ) -> None:
        super().__init__(archive, solution_dim=(), bounds=None, lower_bounds=None, upper_bounds=None)
        self.initial = list(initial)
        self.batch_size = batch_size
        self.variation = variation
        self.generator = generator
        self.draw: Callable[[np.random.Generator, int], list[Genome]] | None = None

    def __getstate__(self) -> dict[str, object]:
        return {**self.__dict__, "draw": None}

    def ask(self) -> np.ndarray:
        if self.initial:
            genomes, self.initial = self.initial, []
            return as_objects(genomes)
        if self.archive.empty:  # nothing viable yet: start again from fresh trees
            assert self.draw is not None
            return as_objects(self.draw(self.generator, self.batch_size))
        count = self.batch_size + self.batch_size % 2
        parents = list(self.archive.sample_elites(count)["solution"])
        children: list[Genome] = []
        for first, second in zip(parents[::2], parents[1::2], strict=True):
            if self.generator.random() < self.variation.crossover:
                children += self.variation.cross(first, second, self.generator)
            else:
                children += [first, second]
        return as_objects(self.variation.mutate(children[: self.batch_size], self.generator))
