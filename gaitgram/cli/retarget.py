"""``gaitgram retarget``: a run's best gait played on another body (the library's
:func:`~gaitgram.evolution.retarget.retarget`)."""

from __future__ import annotations

import statistics
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from gaitgram import jsonio
from gaitgram.backends.api import Evaluation, Verdict
from gaitgram.cli.common import fail
from gaitgram.cli.options import Walk
from gaitgram.cli.selection import SelectedGait, SelectionError, select_gait
from gaitgram.evolution.retarget import Retargeted, RetargetError, RunBest, retarget, retarget_runs
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError
from gaitgram.extras import MissingExtra, require
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
    each_run: Annotated[
        bool,
        typer.Option(
            "--each-run",
            help="Play every finished run's best (a study arm's results), not the best of all.",
        ),
    ] = False,
    runs: Annotated[
        int | None,
        typer.Option(
            "--runs",
            min=1,
            help="With --each-run: the first N runs alone (runs 0 to N-1), as an arm that has grown "
            "since stood.",
            show_default=False,
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
) -> None:
    """Play a run's best gait on another body: the same joint curves, scored by that body's
    fitness and checked over its horizon. Exit 1 if it is viable under no scaling."""
    if each_run and walk:
        raise fail("--each-run plays each run's best gait; drop --walk or --each-run")
    if runs is not None and not each_run:
        raise fail("--runs chooses the runs --each-run plays; add --each-run, or drop --runs")
    twice = next((s for i, s in enumerate(scaling or []) if s in (scaling or [])[:i]), None)
    if twice is not None:
        raise fail(f"--scaling {twice} is given twice; each scaling is played once, give it once")
    try:
        if each_run:
            directory = RunDirectory.open(run)
            scalings = scaling or list(directory.pipeline.spec.retarget_scalings)
            results = retarget_runs(directory, to, scalings, runs)
            verdict = directory.pipeline.spec.verdict
        else:
            chosen = select_gait(run=run, walk=walk)
            scalings = scaling or list(chosen.pipeline.spec.retarget_scalings) or ["froude"]
            played = [retarget(chosen.pipeline, [chosen.genome], chosen.generation, to, s) for s in scalings]
    except (SelectionError, PipelineError, RetargetError, RunDirectoryError) as error:
        raise fail(str(error)) from None
    if each_run:
        _show_runs(run, to, results, verdict, as_json)
        viable = any(e.status.viable for r in results for _, _, e in r.played)
    else:
        _show_best(run, to, chosen, played, as_json)
        viable = any(p.individuals[0].evaluation.status.viable for p in played)
    if not viable:
        raise typer.Exit(1)


def _show_best(run: Path, to: str, chosen: SelectedGait, played: list[Retargeted], as_json: bool) -> None:
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
        return
    out = Console(highlight=False, markup=False)
    verdict = chosen.pipeline.spec.verdict
    out.print(_table(f"{chosen.describe}, on {to}", rows, verdict))
    for name, _, evaluation in rows:
        _explain(out, name, evaluation, verdict)


def _show_runs(run: Path, to: str, results: list[RunBest], verdict: Verdict | None, as_json: bool) -> None:
    if as_json:
        record = {
            "run": str(run),
            "body": to,
            "runs": [
                {
                    "run": r.run,
                    "generation": r.generation,
                    "genome": list(r.genome),
                    "played": [
                        {"playing": "as evolved", "frequency": r.evolved_frequency, **r.recorded.as_record()}
                    ]
                    + [{"playing": s, "frequency": hz, **e.as_record()} for s, hz, e in r.played],
                }
                for r in results
            ],
            "summary": _summary(results, verdict),
        }
        typer.echo(jsonio.dumps(record))
        return
    out = Console(highlight=False, markup=False)
    for r in results:
        rows = [("as evolved", r.evolved_frequency, r.recorded), *r.played]
        out.print(_table(f"{run} run {r.run}, best, generation {r.generation}, on {to}", rows, verdict))
        for name, _, evaluation in rows:
            _explain(out, name, evaluation, verdict)
    for line in _summary_lines(_summary(results, verdict), to, verdict):
        out.print(line, soft_wrap=True)


def _summary(results: list[RunBest], verdict: Verdict | None) -> dict[str, Any]:
    """What the runs say together; without scipy (the stats extra), the counts alone, and how to
    get the intervals and tests."""
    names = [name for name, _, _ in results[0].played]
    fitness = {name: [r.played[i][2].fitness for r in results] for i, name in enumerate(names)}
    walks = None
    if verdict is not None:
        walks = {name: [verdict.holds(r.played[i][2]) for r in results] for i, name in enumerate(names)}
    try:
        require("scipy", "the intervals and paired tests of retarget --each-run")
    except MissingExtra as missing:
        playings = {
            name: {"median_fitness": statistics.median(fitness[name])}
            | ({} if walks is None else {"walks": sum(walks[name])})
            for name in names
        }
        return {"runs": len(results), "playings": playings, "paired": [], "note": str(missing)}
    from gaitgram.report.stats import paired_summary

    return paired_summary(fitness, walks)


def _summary_lines(summary: dict[str, Any], to: str, verdict: Verdict | None) -> list[str]:
    runs, lines = summary["runs"], []
    for name, entry in summary["playings"].items():
        if verdict is not None:
            interval = entry.get("wilson95")
            wilson = "" if interval is None else f" (Wilson 95 %: {interval[0]:.0%}-{interval[1]:.0%})"
            lines.append(
                f"{name}: {entry['walks']} of {runs} runs' bests are a {verdict.label} on {to}{wilson}; "
                f"median fitness {entry['median_fitness']:.4g}"
            )
    for test in summary["paired"]:
        lines.append(
            f"{test['first']} vs {test['second']}, paired by run: fitness lower under {test['first']} in "
            f"{test['first_lower']} of {test['pairs']}; Wilcoxon signed-rank W = {test['statistic']:g}, "
            f"p = {test['p_value']:.4g}"
        )
        if "mcnemar_p" in test and verdict is not None:
            lines.append(
                f"  a {verdict.label} under {test['first']} only in {test['walks_first_only']}, under "
                f"{test['second']} only in {test['walks_second_only']}; "
                f"McNemar's exact p = {test['mcnemar_p']:.4g}"
            )
    if "note" in summary:
        lines.append(summary["note"])
    return lines


def _explain(out: Console, name: str, evaluation: Evaluation, verdict: Verdict | None) -> None:
    if verdict is not None and evaluation.status.viable and not verdict.holds(evaluation):
        missing = ", ".join(t.removeprefix(f"{verdict.component}_") for t in verdict.failed_terms(evaluation))
        out.print(f"{name}: not a {verdict.label}: {missing}")
    elif evaluation.detail:
        out.print(f"{name}: {evaluation.detail}")


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
