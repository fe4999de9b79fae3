"""What a run leaves on disk: statistics per generation (CSV and JSON lines) and the best individual.

Everything here is derived from the checkpoint and rewritten whole after each
generation, so the files always agree with it, even after a kill and a resume.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gaitgram.fileio import write_atomically
from gaitgram.ge.visualise import ascii_tree
from gaitgram.motion.gait import sampled_curve

if TYPE_CHECKING:
    from gaitgram.evolution.engine import Problem, RunState


def stats_csv(records: list[dict[str, Any]]) -> str:
    columns: list[str] = []
    for record in records:
        columns += [key for key in record if key not in columns]
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(records)
    return out.getvalue()


def best_record(problem: Problem, state: RunState) -> dict[str, Any]:
    best = min(state.population, key=lambda i: i.fitness)
    derivation = problem.mapper.map(best.genome)
    return {
        "generation": state.generation,
        "genome": list(best.genome),
        "used_codons": best.used_codons,
        "phenotype": best.phenotype,
        "joints": dict(best.joints),
        # Each curve in degrees at phases k / CURVE_SAMPLES (null if it cannot be sampled).
        "curves": {joint: _curve(text) for joint, text in best.joints.items()},
        "fitness": best.fitness,
        "status": best.evaluation.status.value,
        "components": dict(best.evaluation.components),
        "detail": best.evaluation.detail,
        "derivation": ascii_tree(derivation),
    }


#: Samples per cycle of the curves written with the best individual: enough to plot, small to store.
CURVE_SAMPLES = 64


def _curve(text: str) -> list[float] | None:
    values, problem, _ = sampled_curve(text, CURVE_SAMPLES)
    return None if problem is not None else [round(float(v), 6) for v in values]


def write_run_records(run_dir: Path, problem: Problem, state: RunState) -> None:
    records = [s.as_record() for s in state.history]
    write_atomically(run_dir / "stats.csv", stats_csv(records))
    write_atomically(run_dir / "stats.jsonl", "".join(json.dumps(r) + "\n" for r in records))
    write_atomically(run_dir / "best.json", json.dumps(best_record(problem, state), indent=1) + "\n")
