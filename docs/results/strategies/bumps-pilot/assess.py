"""The pilot's best gaits (one per finished run) played as the strategies report plays every best
gait: on the flat floor over the 20-cycle horizon (walk or not, fitness), under both pushes, and
on the ten bump floors of the robustness trial (seeds 26-35). One JSON line per run.

    python docs/results/strategies/bumps-pilot/assess.py OUT > docs/results/strategies/bumps-pilot/runs.jsonl
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from gaitgram.backends.mujoco_horse.robustness import disturbed
from gaitgram.evolution.rundir import RunDirectory


def main(out: str) -> None:
    directory = RunDirectory.open(Path(out))
    pipeline, last = directory.pipeline, directory.config.generations
    runs = [
        run
        for run in sorted(Path(out).glob("run-*"))
        if (run / "best.json").exists() and len((run / "stats.jsonl").read_text().splitlines()) > last
    ]
    bests = [json.loads((run / "best.json").read_text()) for run in runs]
    genomes = [tuple(best["genome"]) for best in bests]
    flat = pipeline.verify(genomes, pipeline.load_evaluator(), last)
    batch = pipeline.motion(pipeline.map(genomes), last)
    settings = dict(pipeline.config.backend_settings)
    trials = {name: disturbed(settings, batch, name) for name in ("push-forward", "push-backward", "bumps")}
    for k, (run, best, played) in enumerate(zip(runs, bests, flat, strict=True)):
        measured = played.evaluation.components
        row = {
            "run": run.name,
            "fitness_on_training_floor": best["fitness"],
            "fitness_flat": played.evaluation.fitness,
            "walk_flat": measured.get("walk") == 1.0,
            "speed_flat": measured.get("measured_velocity"),
            "holds_pushes": [trials[name][k].holds for name in ("push-forward", "push-backward")],
            "bump_floors_held": trials["bumps"][k].held,
            "bump_floors": trials["bumps"][k].floors,
        }
        print(json.dumps(row))


if __name__ == "__main__":
    main(*sys.argv[1:])
