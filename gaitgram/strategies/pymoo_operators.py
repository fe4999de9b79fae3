"""pymoo's side of ``nsga2``: GE's genomes as pymoo variables, GE's operators as pymoo operators.

A module of its own because it imports pymoo: the strategy's spec must load
without it, and pickled ``nsga2`` states name these classes.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pymoo.core.crossover import Crossover
from pymoo.core.duplicate import DuplicateElimination
from pymoo.core.mutation import Mutation
from pymoo.core.problem import Problem

from gaitgram.strategies.api import Genome
from gaitgram.strategies.common import GEVariation


def as_objects(genomes: list[Genome]) -> np.ndarray:
    """pymoo's X for genomes: one variable per individual, the genome tuple itself."""
    array = np.empty((len(genomes), 1), dtype=object)
    for i, genome in enumerate(genomes):
        array[i, 0] = genome
    return array


class GenomeProblem(Problem):
    """Genomes as one object variable; the pipeline scores them, never this class."""

    def __init__(self, n_obj: int) -> None:
        super().__init__(n_var=1, n_obj=n_obj, vtype=object)


class GECrossover(Crossover):
    """GE's one-point crossover; pymoo draws whether a pair crosses (the run's probability)."""

    def __init__(self, variation: GEVariation) -> None:
        super().__init__(2, 2, prob=variation.crossover)
        self.variation = variation

    def _do(self, problem: Any, x: np.ndarray, *args: Any, random_state: Any = None, **kwargs: Any) -> Any:
        children = np.empty((2, x.shape[1], 1), dtype=object)
        for k in range(x.shape[1]):
            children[0, k, 0], children[1, k, 0] = self.variation.cross(x[0, k, 0], x[1, k, 0], random_state)
        return children


class GEMutation(Mutation):
    """GE's int-flip mutation of every offspring (each codon with the run's probability)."""

    def __init__(self, variation: GEVariation) -> None:
        super().__init__(prob=1.0)
        self.variation = variation

    def _do(self, problem: Any, x: np.ndarray, *args: Any, random_state: Any = None, **kwargs: Any) -> Any:
        return as_objects(self.variation.mutate([row[0] for row in x], random_state))


class PhenotypeDuplicates(DuplicateElimination):
    """Offspring whose phenotype the population (or an earlier offspring) already has are drawn
    again: without this, copies of one gait crowd NSGA-II's front (a mutation of unused codons
    changes the genome, not the gait). Invalid genomes count as duplicates only of themselves."""

    def __init__(self, variation: GEVariation) -> None:
        super().__init__()
        self.variation = variation

    def _key(self, individual: Any) -> object:
        genome = individual.X[0]
        mapper = self.variation.mapper
        if mapper is None:
            raise RuntimeError("GEVariation.mapper is not attached")
        phenotype = mapper.map_fast(genome).phenotype
        return phenotype if phenotype is not None else ("invalid", genome)

    def _do(self, pop: Any, other: Any, is_duplicate: np.ndarray) -> np.ndarray:
        seen = {self._key(o) for o in other} if other is not None else set()
        for i, individual in enumerate(pop):
            key = self._key(individual)
            if key in seen:
                is_duplicate[i] = True
            else:
                seen.add(key)
        return is_duplicate
