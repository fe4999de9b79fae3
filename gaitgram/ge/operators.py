"""Variation and selection (the paper's Table 1): one-point crossover, int-flip mutation,
tournaments, elitism and generational replacement.

Every function takes the random generator explicitly: the same seed gives the
same population, whatever else runs. Fitness is minimised; ``inf`` (invalid
individuals) loses every comparison.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from gaitgram.ge.initialisation import CODON_SIZE

#: A GE genome: its codons.
Codons = tuple[int, ...]


def one_point_crossover(
    first: Codons,
    second: Codons,
    rng: np.random.Generator,
    *,
    fixed_point: bool = True,
    used: tuple[int, int] | None = None,
) -> tuple[Codons, Codons]:
    """Swap the tails of two genomes after a cut point.

    ``fixed_point`` cuts both at the same index (GEVA's fixed one-point, the
    paper's setting); otherwise each parent gets its own point (PonyGE2's
    variable one-point). ``used`` (codons each parent used when mapped) limits
    the cut to the part that affected the phenotype; by default the whole genome.
    """
    limit_a = max(1, min(len(first), used[0] if used else len(first)))
    limit_b = max(1, min(len(second), used[1] if used else len(second)))
    if len(first) < 2 or len(second) < 2:
        return first, second  # nothing to cut
    if fixed_point:
        point = int(rng.integers(1, max(2, min(limit_a, limit_b, len(first) - 1, len(second) - 1) + 1)))
        cut_a = cut_b = point
    else:
        cut_a = int(rng.integers(1, max(2, min(limit_a, len(first) - 1) + 1)))
        cut_b = int(rng.integers(1, max(2, min(limit_b, len(second) - 1) + 1)))
    return first[:cut_a] + second[cut_b:], second[:cut_b] + first[cut_a:]


def int_flip_mutation(
    genome: Codons,
    rng: np.random.Generator,
    *,
    probability: float,
    codon_size: int = CODON_SIZE,
    used: int | None = None,
) -> Codons:
    """Replace each codon, with ``probability``, by a uniform random one (within ``used`` if given)."""
    span = len(genome) if used is None else min(used, len(genome))
    if span == 0:
        return genome
    flips = rng.random(span) < probability
    if not flips.any():
        return genome
    values = rng.integers(0, codon_size, size=span)
    mutated = list(genome)
    for i in np.flatnonzero(flips):
        mutated[i] = int(values[i])
    return tuple(mutated)


def tournament(fitness: Sequence[float], rng: np.random.Generator, *, size: int, count: int) -> list[int]:
    """Indices of ``count`` tournament winners; each tournament draws ``size`` with replacement.

    Ties go to the lower index, so selection is reproducible.
    """
    values = np.asarray(fitness, dtype=float)
    values = np.where(np.isnan(values), np.inf, values)
    entrants = rng.integers(0, len(values), size=(count, size))
    scores = values[entrants]
    # argmin returns the first minimum; order entrants so that means the lowest index.
    order = np.argsort(entrants, axis=1, kind="stable")
    entrants = np.take_along_axis(entrants, order, axis=1)
    scores = np.take_along_axis(scores, order, axis=1)
    return [int(i) for i in entrants[np.arange(count), np.argmin(scores, axis=1)]]


def elite(fitness: Sequence[float], count: int) -> list[int]:
    """Indices of the ``count`` best individuals, best first (ties by index)."""
    values = np.asarray(fitness, dtype=float)
    values = np.where(np.isnan(values), np.inf, values)
    return [int(i) for i in np.argsort(values, kind="stable")[:count]]
