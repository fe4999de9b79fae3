"""Variation and selection keep genomes valid and are reproducible."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from gaitgram.ge.operators import elite, int_flip_mutation, one_point_crossover, tournament

codon_lists = st.lists(st.integers(0, 99_999), min_size=0, max_size=40).map(tuple)


@given(codon_lists, codon_lists, st.integers(0, 2**32 - 1), st.booleans())
def test_crossover_keeps_codons_and_total_length(a: tuple, b: tuple, seed: int, fixed: bool) -> None:
    c, d = one_point_crossover(a, b, np.random.default_rng(seed), fixed_point=fixed)
    assert len(c) + len(d) == len(a) + len(b)
    assert sorted(c + d) == sorted(a + b)
    if fixed:  # the same cut in both: the children swap lengths
        assert (len(c), len(d)) == (len(b), len(a)) or (c, d) == (a, b)
    assert all(isinstance(x, int) and 0 <= x < 100_000 for x in c + d)


@given(codon_lists, codon_lists, st.integers(0, 2**32 - 1))
def test_crossover_within_used_part_cuts_inside_it(a: tuple, b: tuple, seed: int) -> None:
    c, d = one_point_crossover(a, b, np.random.default_rng(seed), fixed_point=True, used=(3, 3))
    if len(a) >= 2 and len(b) >= 2:
        assert any(c == a[:p] + b[p:] and d == b[:p] + a[p:] for p in (1, 2, 3))


@given(codon_lists, st.integers(0, 2**32 - 1), st.floats(0, 1))
def test_mutation_keeps_length_and_range(genome: tuple, seed: int, p: float) -> None:
    mutated = int_flip_mutation(genome, np.random.default_rng(seed), probability=p, codon_size=1000)
    assert len(mutated) == len(genome)
    assert all(0 <= x < 100_000 for x in mutated)
    changed = [i for i, (x, y) in enumerate(zip(genome, mutated, strict=True)) if x != y]
    assert all(mutated[i] < 1000 for i in changed)


def test_mutation_rate_is_per_codon() -> None:
    rng = np.random.default_rng(0)
    genome = tuple(range(1000, 11_000))
    mutated = int_flip_mutation(genome, rng, probability=0.02, codon_size=1000)
    flips = sum(x != y for x, y in zip(genome, mutated, strict=True))
    assert 150 < flips < 250  # 200 expected


def test_mutation_within_used_part_only() -> None:
    genome = tuple([5] * 20)
    mutated = int_flip_mutation(genome, np.random.default_rng(1), probability=1.0, codon_size=3, used=4)
    assert mutated[4:] == genome[4:]


def test_tournament_prefers_lower_fitness_and_treats_nan_as_worst() -> None:
    fitness = [5.0, float("nan"), 1.0, float("inf"), 3.0]
    rng = np.random.default_rng(2)
    winners = tournament(fitness, rng, size=5, count=400)
    # NaN and inf win only tournaments where every entrant is NaN or inf: (2/5)**5, about 1 %.
    assert winners.count(1) + winners.count(3) < 20
    assert winners.count(2) > winners.count(4) > winners.count(0)
    assert tournament(fitness, np.random.default_rng(2), size=5, count=400) == winners


def test_elite_is_best_first_with_stable_ties() -> None:
    assert elite([3.0, 1.0, 1.0, float("nan"), 0.5], 3) == [4, 1, 2]
