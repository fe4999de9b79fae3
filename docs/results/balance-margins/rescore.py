"""Each margins run's best gait scored by the default fitness (no speed margin, footfalls not
weighted, the flat floor, its warm-up and 3 scored cycles), so that it compares with the balance
study's arms, whose fitness is that one; with Mann-Whitney U against each reference arm's
recorded final best; and the same without the speed and stride terms (what the margin costs by
design: a gait 4 % fast on strides 4 % long pays about 0.04 on each), beside the reference arms'.
One line per arm.

    python docs/results/balance-margins/rescore.py \\
        docs/results/balance-margins/runs/arms/ge-hybrid-margins \\
        docs/results/balance-margins/runs/arms/ge-hybrid-feedback-margins \\
        --against docs/results/strategies/runs/arms/ge-hybrid \\
        docs/results/balance/runs/arms/ge-hybrid-feedback
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from scipy.stats import mannwhitneyu

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.backends.mujoco_horse.targets import DEFAULT_WEIGHTS
from gaitgram.evolution.rundir import RunDirectory


def finished_bests(arm: Path) -> list[dict]:
    """The best records of the arm's finished runs, in run order."""
    last = RunDirectory.open(arm).config.generations
    return [
        json.loads((run / "best.json").read_text())
        for run in sorted(arm.glob("run-*"))
        if (run / "best.json").exists() and len((run / "stats.jsonl").read_text().splitlines()) > last
    ]


def default_scores(arm: Path) -> list[tuple[float, float]]:
    """Each finished run's best gait under the default fitness: (fitness, fitness without the
    velocity and stride terms)."""
    pipeline = RunDirectory.open(arm).pipeline
    bests = finished_bests(arm)
    batch = pipeline.motion(pipeline.map([tuple(b["genome"]) for b in bests]), pipeline.config.generations)
    evaluator = HorseEvaluator(HorseSettings())
    try:
        return [(e.fitness, _without_aim(e.fitness, e.components)) for e in evaluator.evaluate(batch)]
    finally:
        evaluator.close()


def _without_aim(fitness: float, components: dict[str, float]) -> float:
    return (
        fitness
        - DEFAULT_WEIGHTS["velocity"] * components["velocity"]
        - DEFAULT_WEIGHTS["stride"] * components["stride"]
    )


def main(argv: list[str]) -> None:
    split = argv.index("--against")
    arms, references = [Path(a) for a in argv[:split]], [Path(a) for a in argv[split + 1 :]]
    recorded = {ref.name: [b["fitness"] for b in finished_bests(ref)] for ref in references}
    recorded_without = {
        ref.name: [_without_aim(b["fitness"], b["components"]) for b in finished_bests(ref)]
        for ref in references
    }
    for arm in arms:
        scored = default_scores(arm)
        scores, without = [f for f, _ in scored], [w for _, w in scored]
        row: dict[str, object] = {
            "arm": arm.name,
            "runs": len(scores),
            "median_default_fitness": float(np.median(scores)),
            "median_without_speed_and_stride": float(np.median(without)),
            "references_without_speed_and_stride": {
                k: float(np.median(v)) for k, v in recorded_without.items()
            },
        }
        for name, theirs in recorded.items():
            test = mannwhitneyu(scores, theirs, alternative="two-sided")
            row[f"vs {name}"] = {
                "their_median": float(np.median(theirs)),
                "ratio_of_medians": float(np.median(scores) / np.median(theirs)),
                "mann_whitney_p": float(test.pvalue),
                "a12_lower": float(np.mean([(a < b) + 0.5 * (a == b) for a in scores for b in theirs])),
            }
        row["default_fitness"] = scores
        print(json.dumps(row))


if __name__ == "__main__":
    main(sys.argv[1:])
