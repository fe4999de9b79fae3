"""mujoco-horse throughput: evaluations/s against a raw ``mujoco.rollout`` of the same gaits, for
fitness revision 4 and for revision 3's window (the ramp and 3 cycles), side by side.

Three 75-gait populations:

* generation 0 of the free grammar (``grammars/free.gg``, Fig. 5, no seed data): RampedFullGrow
  initialisation as ``gaitgram evolve`` draws it (depth 10, half grown, lazy codons, tails of
  0.5). Many of these gaits fall over early, and dropping them is where chunking pays.
* generation 0 of the hybrid grammar (``grammars/hybrid.gg``, the paper's overall winner): built
  around the seed walk fitted to the horse, so hardly any fall; this row shows the cost of
  chunking when there is nothing to drop.
* evolved: the hybrid grammar's seed walk with each codon flipped at the runs' default mutation
  rate (0.02), a population converged on a walk.

Then every body of ``bodies.toml`` evaluates the evolved population (the same gaits, each at its
body's target frequency): evaluations/s and the ratio to the horse's, measured in the same run.
A body's time step and its cycle both scale with the square root of its size (dynamic
similarity), so every body simulates about the same number of steps for its cycles, and should
evaluate at about the horse's rate (measured: 0.86-1.00 of it). Last, the evolved population
scored on bump floors besides the flat one (``bump_floors``): its time, steps and time per step
against the flat floor's, and the raw rollout's time per step on each floor against the flat's
(what MuJoCo itself charges for the height field's contacts).

All run the same model on the same gaits in the same process, measurements interleaved and the
best of several taken (the machine's load drifts). The raw figure is ``mujoco.rollout`` of each
gait's control array for the steps its evaluation would take were it not dropped (building the
controls is not timed); the backend figure is a whole ``evaluate``: controls, chunked rollouts
that drop gaits once unviable, records, measures and scores. Targets: above 1.0 for a generation 0
that loses gaits to falls, about 1.0 (at least 0.9) for a population that does not.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from gaitgram.analysis import check
from gaitgram.backends.api import GaitStatus
from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.bodies import BODIES
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


def raw_rollout(evaluator: HorseEvaluator, batch: MotionBatch, rows: np.ndarray) -> tuple[int, float, float]:
    """Steps, wall seconds and CPU seconds (the process's, every thread) of the raw
    ``mujoco.rollout`` of each gait for exactly the steps its evaluation would simulate were none
    dropped: gaits of one length in one call (threads share it), building the controls untimed."""
    frequencies = evaluator.frequencies(batch, rows)
    ends = evaluator.ends(frequencies)
    seconds, cpu, steps = 0.0, 0.0, 0
    for length in np.unique(ends):
        group = rows[ends == length]
        control = evaluator.controls(batch, group)[:, :length]
        start = time.process_time()
        seconds += timed(lambda control=control: evaluator.simulate(control))
        cpu += time.process_time() - start
        steps += len(group) * int(length)
    return steps, seconds, cpu


def compare(evaluator: HorseEvaluator, batch: MotionBatch) -> tuple[int, float, float, float, int]:
    """Simulated gaits, unviable share, best raw and best evaluate seconds (interleaved), and the
    steps evaluate simulates."""
    rows = np.array([g for g, problem in enumerate(batch.problems) if problem is None])
    results = evaluator.evaluate(batch)  # warms up both paths' buffers and pools
    raw_rollout(evaluator, batch, rows)
    unviable = sum(results[g].status is not GaitStatus.OK for g in rows) / len(rows)
    raw = full = float("inf")
    before = evaluator.simulated_steps
    evaluator.evaluate(batch)
    simulated = evaluator.simulated_steps - before
    for _ in range(ROUNDS):
        raw = min(raw, raw_rollout(evaluator, batch, rows)[1])
        full = min(full, timed(lambda: evaluator.evaluate(batch)))
    return len(rows), unviable, raw, full, simulated


#: Revision 3 simulated the ramp and 3 cycles, and checked nothing over a horizon; with revision 4's
#: code, the fewest warm-up cycles (2) and 1 scored cycle make the same window.
REVISION_3_WINDOW = {"warmup_seconds": 0.0, "cycles": 1}


def main() -> None:
    threads = os.cpu_count() or 1
    populations = (
        ("free.gg generation 0", generation_zero(grammar=GRAMMARS / "free.gg")),
        ("hybrid.gg generation 0", generation_zero()),
        ("hybrid.gg evolved (seed, mutation 0.02)", evolved()),
    )
    revisions = (
        ("r4", HorseEvaluator(HorseSettings(threads=threads))),
        ("r3 window", HorseEvaluator(HorseSettings(threads=threads, **REVISION_3_WINDOW))),
    )
    try:
        r4 = revisions[0][1]
        print(
            f"{POPULATION} gaits; revision 4 simulates the ramp, the warm-up (whole cycles of at least "
            f"1.5 s) and 3 scored cycles, {r4.nstep * r4.dt:.2f} s at the target's 0.95 Hz; revision 3's "
            f"window is the ramp and 3 cycles; {threads} threads, chunks of {r4.chunk_steps} steps; "
            f"best of {ROUNDS}, interleaved; raw: mujoco.rollout of each gait's own steps, none dropped"
        )
        print(
            f"{'population':<40} {'fitness':>9} {'unviable':>8} {'raw mujoco.rollout':>20} "
            f"{'mujoco-horse':>16} {'ratio':>6} {'steps':>9} {'r4/r3 time':>10}"
        )
        for label, batch in populations:
            times = {}
            for revision, evaluator in revisions:
                gaits, unviable, raw, full, steps = compare(evaluator, batch)
                times[revision] = full
                print(
                    f"{label:<40} {revision:>9} {unviable:8.0%} {gaits / raw:10.1f} evals/s "
                    f"{gaits / full:8.1f} evals/s {raw / full:6.2f} {steps:9d}"
                    + (f" {times['r4'] / full:10.2f}" if revision != "r4" else "")
                )
        batch = evolved()
        verifier = revisions[0][1]
        check = min(timed(lambda: verifier.verify(batch.take([0]))) for _ in range(3))
        one = min(timed(lambda: verifier.evaluate(batch.take([0]))) for _ in range(3))
        print(
            f"one gait checked over the {verifier.horizon}-cycle horizon: {check:.3f} s, against {one:.3f} s "
            f"for its evaluation alone ({check / one:.1f}x)"
        )
    finally:
        for _, evaluator in revisions:
            evaluator.close()
    per_body(threads)
    on_bump_floors(threads)


def on_bump_floors(threads: int) -> None:
    """The price of ``bump_floors``: the evolved population scored on the flat floor and on 1 and 3
    bump floors besides, against the flat floor alone in the same run, in time, in steps and per
    step (a gait that falls on the flat is not played on the floors, nor one that falls on a
    floor on the floors after it). Then what MuJoCo itself charges for a step on a floor of bumps:
    the raw ``mujoco.rollout`` of the same controls on the flat and on each floor, per step, wall
    and CPU: the height field's contacts, which the model has, and no evaluation overhead."""
    batch = evolved()
    print(
        f"\n{'bump floors':<12} {'steps':>8} {'mujoco-horse':>16} {'time vs flat':>12} {'steps vs flat':>13} "
        f"{'per step vs flat':>16} {'cpu per step':>12}"
    )
    evaluators = [
        HorseEvaluator(HorseSettings(threads=threads, bump_floors=floors or None))
        for floors in ((), (0,), (0, 1, 2))
    ]
    try:
        steps, walls, cpus = [], [float("inf")] * 3, [float("inf")] * 3
        for evaluator in evaluators:
            evaluator.evaluate(batch)  # warm-up, and the floors built
            before = evaluator.simulated_steps
            evaluator.evaluate(batch)
            steps.append(evaluator.simulated_steps - before)
        for _ in range(ROUNDS):  # interleaved
            for k, evaluator in enumerate(evaluators):
                cpu = time.process_time()
                walls[k] = min(walls[k], timed(lambda e=evaluator: e.evaluate(batch)))
                cpus[k] = min(cpus[k], time.process_time() - cpu)
        for floors, n, wall, cpu in zip(("none (flat)", "0", "0, 1, 2"), steps, walls, cpus, strict=True):
            print(
                f"{floors:<12} {n:8d} {len(batch) / wall:8.1f} evals/s {wall / walls[0]:12.2f} "
                f"{n / steps[0]:13.2f} {(wall / n) / (walls[0] / steps[0]):16.2f} "
                f"{(cpu / n) / (cpus[0] / steps[0]):12.2f}"
            )
        flat, floored = evaluators[0], evaluators[2]
        control = flat.controls(batch, np.arange(len(batch)))
        models = [("flat", flat), *((f"floor {seed}", floor) for seed, floor in floored.floors)]
        raw = {name: [float("inf"), float("inf")] for name, _ in models}
        for _ in range(ROUNDS):  # interleaved
            for name, evaluator in models:
                cpu = time.process_time()
                wall = timed(lambda e=evaluator: e.simulate(control))
                raw[name] = [min(raw[name][0], wall), min(raw[name][1], time.process_time() - cpu)]
        simulated = control.shape[0] * control.shape[1]
        print(
            f"raw mujoco.rollout of the same {simulated} steps, per step against the flat "
            f"(best of {ROUNDS}): "
            + ", ".join(
                f"{name} {wall / raw['flat'][0]:.2f} wall, {cpu / raw['flat'][1]:.2f} CPU "
                f"({cpu / simulated * 1e6:.1f} us/step)"
                for name, (wall, cpu) in raw.items()
            )
        )
    finally:
        for evaluator in evaluators:
            evaluator.close()


def per_body(threads: int) -> None:
    """Evaluations/s of the evolved population on every body, against the horse's in the same run."""
    batch = evolved()
    print(f"\n{'body':<10} {'hip m':>6} {'dt ms':>6} {'steps':>7} {'mujoco-horse':>16} {'vs horse':>8}")
    horse = None
    for name in BODIES:
        evaluator = HorseEvaluator(HorseSettings(threads=threads, body=name))
        try:
            evaluator.evaluate(batch)  # warm-up
            before = evaluator.simulated_steps
            evaluator.evaluate(batch)
            steps = evaluator.simulated_steps - before
            best = min(timed(lambda e=evaluator: e.evaluate(batch)) for _ in range(ROUNDS))
            rate = len(batch.angles) / best
            horse = horse or rate
            print(
                f"{name:<10} {evaluator.layout.hip_height:6.3f} {evaluator.dt * 1e3:6.2f} {steps:7d} "
                f"{rate:8.1f} evals/s {rate / horse:8.2f}"
            )
        finally:
            evaluator.close()
