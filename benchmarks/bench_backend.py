"""mujoco-horse throughput: evaluations/s against a raw full-length ``mujoco.rollout`` of the same gaits.

Three 75-gait populations:

* generation 0 of the free grammar (``grammars/free.gg``, Fig. 5, no seed data): RampedFullGrow
  initialisation as ``gaitgram evolve`` draws it (depth 10, half grown, lazy codons, tails of
  0.5). Many of these gaits fall over early, and dropping them is where chunking pays.
* generation 0 of the hybrid grammar (``grammars/hybrid.gg``, the paper's overall winner): built
  around the seed walk fitted to the horse, so hardly any fall; this row shows the cost of
  chunking when there is nothing to drop.
* evolved: the hybrid grammar's seed walk with each codon flipped at the runs' default mutation
  rate (0.02), a population converged on a walk.

Both run the same model on the same gaits in the same process, measurements interleaved and the
best of several taken (the machine's load drifts). The raw figure is ``mujoco.rollout`` of the
full control arrays alone (building them is not timed); the backend figure is a whole
``evaluate``: controls, chunked rollouts that drop gaits once unviable, metrics and scores.
Target: above 1.0 for a generation 0 that loses gaits to falls.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from gaitgram.analysis import check
from gaitgram.backends.api import GaitStatus
from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, HorseSettings
from gaitgram.ge import compile_mapper
from gaitgram.ge.initialisation import ramped_population
from gaitgram.ge.mapper import CodonMode
from gaitgram.ge.operators import int_flip_mutation
from gaitgram.language import load
from gaitgram.motion.gait import MotionBatch, motion_batch
from gaitgram.seed.grammars import seed_genome

GRAMMARS = Path(__file__).resolve().parents[1] / "grammars"
GRAMMAR = GRAMMARS / "hybrid.gg"
POPULATION = 75
ROUNDS = 5


def _batch(grammar, genomes) -> MotionBatch:
    mapped = compile_mapper(grammar).map_many(genomes)
    phenotypes = [m.joints if m.valid else None for m in mapped]
    return motion_batch(phenotypes, CATALOGUE.names, units=grammar.units)


def generation_zero(size: int = POPULATION, seed: int = 0, grammar: Path = GRAMMAR) -> MotionBatch:
    checked = check(load(grammar))
    trees = ramped_population(
        checked.facts,
        np.random.default_rng(seed),
        size,
        max_depth=10,
        grow_probability=0.5,
        codons=CodonMode.LAZY,
        codon_size=100_000,
        tail=0.5,
    )
    return _batch(checked.grammar, [t.genome for t in trees])


def evolved(size: int = POPULATION, seed: int = 1, mutation: float = 0.02) -> MotionBatch:
    grammar = check(load(GRAMMAR)).grammar
    rng = np.random.default_rng(seed)
    walk = seed_genome(grammar)
    return _batch(
        grammar, [int_flip_mutation(walk, rng, probability=mutation, codon_size=100_000) for _ in range(size)]
    )


def timed(work) -> float:
    start = time.perf_counter()
    work()
    return time.perf_counter() - start


def compare(evaluator: HorseEvaluator, batch: MotionBatch) -> tuple[int, float, float, float]:
    """Simulated gaits, unviable share, best raw and best evaluate seconds (interleaved)."""
    rows = np.array([g for g, problem in enumerate(batch.problems) if problem is None])
    control = evaluator.controls(batch, rows)
    results = evaluator.evaluate(batch)  # warms up both paths' buffers and pools
    evaluator.simulate(control)
    unviable = sum(results[g].status is not GaitStatus.OK for g in rows) / len(rows)
    raw = full = float("inf")
    for _ in range(ROUNDS):
        raw = min(raw, timed(lambda: evaluator.simulate(control)))
        full = min(full, timed(lambda: evaluator.evaluate(batch)))
    return len(rows), unviable, raw, full


def main() -> None:
    threads = os.cpu_count() or 1
    populations = (
        ("free.gg generation 0", generation_zero(grammar=GRAMMARS / "free.gg")),
        ("hybrid.gg generation 0", generation_zero()),
        ("hybrid.gg evolved (seed, mutation 0.02)", evolved()),
    )
    evaluator = HorseEvaluator(HorseSettings(threads=threads))
    try:
        seconds = evaluator.nstep * evaluator.dt
        print(
            f"{POPULATION} gaits x {evaluator.nstep} steps ({seconds:.2f} s simulated each), "
            f"{threads} threads, chunks of {evaluator.chunk_steps} steps; "
            f"best of {ROUNDS}, interleaved"
        )
        print(
            f"{'population':<40} {'unviable':>8} {'raw mujoco.rollout':>20} {'mujoco-horse':>16} {'ratio':>7}"
        )
        for label, batch in populations:
            gaits, unviable, raw, full = compare(evaluator, batch)
            print(
                f"{label:<40} {unviable:8.0%} {gaits / raw:10.1f} evals/s {gaits / full:8.1f} evals/s "
                f"{raw / full:7.2f}"
            )
    finally:
        evaluator.close()
