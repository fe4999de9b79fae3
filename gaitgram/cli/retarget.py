"""``gaitgram retarget``: a run's best gait played on another body (the library's
:func:`~gaitgram.evolution.retarget.retarget`)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from gaitgram import jsonio
from gaitgram.backends.api import Evaluation, Verdict
from gaitgram.cli.common import fail
from gaitgram.cli.options import Walk
from gaitgram.cli.selection import SelectionError, select_gait
from gaitgram.evolution.retarget import RetargetError, retarget
from gaitgram.pipeline import PipelineError

#: The measures shown for each playing, where the backend reports them.
_SHOWN = {
    "measured_velocity": "m/s",
    "measured_frequency": "stride Hz",
    "measured_stride": "stride m",
    "measured_duty_factor": "duty",
}


def command(
    run: Annotated[Path, typer.Option("--run", help="The run directory whose best gait is played.")],
    to: Annotated[str, typer.Option("--to", help="The body to play it on, for example draft or shetland.")],
    scaling: Annotated[
        list[str] | None,
        typer.Option(
            help="froude: the cycle frequency scaled by sqrt(h_from / h_to); unscaled: as evolved. "
            "Repeatable; by default both."
        ),
    ] = None,
    walk: Walk = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
) -> None:
    """Play a run's best gait on another body: the same joint curves, scored by that body's
    fitness and checked over its horizon. Exit 1 if it is viable under no scaling."""
    try:
        chosen = select_gait(run=run, walk=walk)
        scalings = scaling or list(chosen.pipeline.spec.retarget_scalings) or ["froude"]
        played = [retarget(chosen.pipeline, [chosen.genome], chosen.generation, to, s) for s in scalings]
    except (SelectionError, PipelineError, RetargetError) as error:
        raise fail(str(error)) from None
    evolved = played[0].evolved_frequencies[0]
    rows = [("as evolved", evolved, chosen.recorded)] if chosen.recorded is not None else []
    rows += [(p.scaling, p.frequencies[0], p.individuals[0].evaluation) for p in played]
    if as_json:
        record = {
            "run": str(run),
            "body": to,
            "generation": chosen.generation,
            "genome": list(chosen.genome),
            "played": [
                {"playing": name, "frequency": hz, **evaluation.as_record()} for name, hz, evaluation in rows
            ],
        }
        typer.echo(jsonio.dumps(record))
    else:
        title = f"{chosen.describe}, on {to}"
        out = Console(highlight=False, markup=False)
        verdict = chosen.pipeline.spec.verdict
        out.print(_table(title, rows, verdict))
        for name, _, evaluation in rows:
            if verdict is not None and evaluation.status.viable and not verdict.holds(evaluation):
                missing = ", ".join(
                    t.removeprefix(f"{verdict.component}_") for t in verdict.failed_terms(evaluation)
                )
                out.print(f"{name}: not a {verdict.label}: {missing}")
            elif evaluation.detail:
                out.print(f"{name}: {evaluation.detail}")
    if not any(p.individuals[0].evaluation.status.viable for p in played):
        raise typer.Exit(1)


def _table(title: str, rows: list[tuple[str, float | None, Evaluation]], verdict: Verdict | None) -> Table:
    table = Table(title=title)
    for column in ("playing", "played Hz", "status", "fitness", *_SHOWN.values()):
        table.add_column(column, justify="left" if column in ("playing", "status") else "right")
    if verdict is not None:
        table.add_column(verdict.label)
    for name, hz, evaluation in rows:
        components = evaluation.components
        cells = [
            name,
            "target" if hz is None else f"{hz:.3f}",
            evaluation.status.value,
            f"{evaluation.fitness:.4g}",
            *(f"{components[key]:.3g}" if key in components else "" for key in _SHOWN),
        ]
        if verdict is not None:
            cells.append("yes" if evaluation.status.viable and verdict.holds(evaluation) else "no")
        table.add_row(*cells)
    return table
