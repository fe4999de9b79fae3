"""What a run leaves on disk: statistics per generation (CSV and JSON lines) and the best individual.

Everything here is derived from the checkpoint and rewritten whole after each
generation, so the files always agree with it, even after a kill and a resume.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

from gaitgram import jsonio
from gaitgram.fileio import write_atomically
from gaitgram.ge.visualise import ascii_tree
from gaitgram.language.model import FREQUENCY
from gaitgram.motion.gait import motion_batch
from gaitgram.pipeline import Individual, Pipeline
from gaitgram.runlayout import BEST, STATS_CSV, STATS_JSONL
from gaitgram.strategies.api import RunState


def stats_csv(records: list[dict[str, Any]]) -> str:
    columns: list[str] = []
    for record in records:
        columns += [key for key in record if key not in columns]
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(records)
    return out.getvalue()


def best_record(pipeline: Pipeline, state: RunState) -> dict[str, Any]:
    best = state.best
    representation = pipeline.representation
    derivation = representation.derivation(best.genome)
    return {
        "generation": state.generation,
        "genome": representation.to_json(best.genome),
        f"used_{representation.counts}": best.used,
        "phenotype": best.phenotype,
        "joints": dict(best.joints),
        # Each curve as the backend received it: degrees at phases k / CURVE_SAMPLES, frozen joints
        # at 0 (null if the individual has no usable motion).
        "curves": _curves(pipeline, best, state.generation),
        "fitness": best.fitness,
        "status": best.evaluation.status.value,
        "components": dict(best.evaluation.components),
        # Per scored cycle, for backends that measure cycles one by one: their spread.
        "cycles": {name: list(values) for name, values in best.evaluation.cycles.items()},
        "detail": best.evaluation.detail,
        "derivation": ascii_tree(derivation),
    }


#: Samples per cycle of the curves written with the best individual: enough to plot, small to store.
CURVE_SAMPLES = 64


def _curves(pipeline: Pipeline, best: Individual, generation: int) -> dict[str, list[float] | None]:
    """The grammar's joints through the same unit conversion and freedom schedule as scoring."""
    joints = tuple(j for j in best.joints if j != FREQUENCY)
    batch = motion_batch(
        [best.joints if best.phenotype is not None else None],
        joints,
        units=pipeline.grammar.units,
        n_samples=CURVE_SAMPLES,
        frozen=pipeline.frozen_at(generation),
        sensors=pipeline.sensors,
    )
    if batch.problems[0] is not None:
        return dict.fromkeys(joints)
    return {joint: [round(float(v), 6) for v in batch.angles[0, j]] for j, joint in enumerate(joints)}


def run_records(pipeline: Pipeline, state: RunState) -> dict[str, str]:
    """The files a run's state gives (name -> text), in the order they are written."""
    records = [jsonio.finite_or_none(s.as_record()) for s in state.history]
    return {
        STATS_CSV: stats_csv(records),
        STATS_JSONL: "".join(jsonio.dumps(r) + "\n" for r in records),
        BEST: record_text(best_record(pipeline, state)),
    }


def record_text(content: Any) -> str:
    """A JSON record as a run directory keeps it (``best.json``, a strategy's records)."""
    return jsonio.dumps(content, indent=1) + "\n"


def write_run_records(run_dir: Path, pipeline: Pipeline, state: RunState) -> None:
    for name, text in run_records(pipeline, state).items():
        write_atomically(run_dir / name, text)
