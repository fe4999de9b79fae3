"""The report's section on what the runs spent in their backends, from what each run recorded
(:mod:`gaitgram.evolution.usage`): the steps simulated and the wall seconds inside the backend.

With a raw simulation's rate measured on the same machine (``python -m benchmarks evolve``), a
run's seconds per step against it is its overhead, read off the run itself. Runs made before
runs recorded these have no figures, and a report of such runs only (every committed one) has no
such section.
"""

from __future__ import annotations

import statistics
from collections.abc import Sequence

from gaitgram.report.records import ArmRecord
from gaitgram.report.sections import Column, Kind, Section, Table
from gaitgram.runlayout import USAGE

USAGE_TEXT = (
    "What each arm's runs spent in the backend, as each run recorded it beside its checkpoint "
    f"(`{USAGE}`): the steps it simulated (summed over gaits; a backend that does not count "
    "them has none) and the wall seconds inside the backend's `evaluate` and `verify`, over the "
    "generations counted (a run resumed from a checkpoint made before runs recorded them counts "
    "only the later ones). The seconds are the machine's that ran the run, under whatever else ran "
    "on it; the time per step set against a raw simulation's on the same machine (`python -m "
    "benchmarks evolve`) is what the run spent beyond stepping the simulation."
)


def usage_section(arms: Sequence[ArmRecord]) -> Section | None:
    """Per arm, its runs' recorded usage; None where no run records any."""
    if not any(run.usage is not None for arm in arms for run in arm.runs):
        return None
    rows = []
    for arm in arms:
        usages = [run.usage for run in arm.runs if run.usage is not None]
        expected = sum(arm.generations + 1 for run in arm.runs if run.usage is not None)
        counted = sum(len(usage.generations) for usage in usages)
        seconds = sum(usage.seconds for usage in usages)
        steps = [usage.steps for usage in usages]
        total = None if not usages or any(s is None for s in steps) else sum(steps)  # type: ignore[misc]
        rows.append(
            (
                arm.name,
                f"{len(usages)}/{len(arm.runs)}",
                f"{counted}/{expected}",
                total,
                round(statistics.median(steps)) if total is not None else None,  # type: ignore[type-var]
                seconds if usages else None,
                statistics.median(usage.seconds for usage in usages) if usages else None,
                seconds / total * 1e6 if total else None,
            )
        )
    table = Table(
        "arms",
        (
            Column("arm", "arm", Kind.TEXT),
            Column("runs_recorded", "runs recorded", Kind.TEXT),
            Column("generations_counted", "generations counted", Kind.TEXT),
            Column("simulated_steps", "steps simulated", Kind.COUNT),
            Column("median_run_steps", "steps, median run", Kind.COUNT),
            Column("backend_seconds", "seconds in the backend", Kind.VALUE),
            Column("median_run_seconds", "seconds, median run", Kind.VALUE),
            Column("microseconds_per_step", "µs per step", Kind.VALUE),
        ),
        tuple(rows),
    )
    return Section("backend-usage", "Time in the backend", "as each run recorded it", USAGE_TEXT, (table,))
