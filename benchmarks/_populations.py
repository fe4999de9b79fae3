"""Populations the backend benchmarks score, built as a run builds them: through a grammar's
:class:`~gaitgram.pipeline.Pipeline`, so that an evolved frequency is played and sensors are read
exactly as ``gaitgram evolve`` plays and reads them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gaitgram.analysis import check
from gaitgram.configuration import RunConfig
from gaitgram.ge.initialisation import ramped_population
from gaitgram.ge.mapper import CodonMode
from gaitgram.ge.operators import int_flip_mutation
from gaitgram.language import load
from gaitgram.motion.gait import MotionBatch
from gaitgram.pipeline import Pipeline
from gaitgram.seed.grammars import seed_genome

GRAMMARS = Path(__file__).resolve().parents[1] / "grammars"
#: Table 1's population.
POPULATION = 75


def pipeline(grammar: str, **settings: object) -> Pipeline:
    """The Table-1 pipeline of ``grammars/<grammar>`` with backend ``settings``."""
    return Pipeline.build(
        check(load(GRAMMARS / grammar)), RunConfig(population=POPULATION, backend_settings=settings)
    )


def generation_zero(grammar: str, size: int = POPULATION, seed: int = 0) -> MotionBatch:
    """Generation 0 as ``gaitgram evolve`` draws it (RampedFullGrow, depth 10, lazy codons, tails of
    0.5), from ``seed``, played at the grammar's own frequencies."""
    built = pipeline(grammar)
    trees = ramped_population(
        built.facts,
        np.random.default_rng(seed),
        size,
        max_depth=10,
        grow_probability=0.5,
        codons=CodonMode.LAZY,
        codon_size=100_000,
        tail=0.5,
    )
    return built.motion(built.map([t.genome for t in trees]), 0)


def mutants(grammar: str, size: int = POPULATION, seed: int = 1, mutation: float = 0.02) -> MotionBatch:
    """The grammar's seed walk with each codon flipped at the runs' default mutation rate: a
    population converged on a walk (a closed-loop grammar's feedback gains drawn anew in each)."""
    built = pipeline(grammar)
    rng = np.random.default_rng(seed)
    walk = seed_genome(built.grammar)
    genomes = [int_flip_mutation(walk, rng, probability=mutation, codon_size=100_000) for _ in range(size)]
    return built.motion(built.map(genomes), 0)
