"""``gaitgram evaluate``: one individual through the run's pipeline, every component shown."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from gaitgram import jsonio
from gaitgram.backends.api import Evaluation
from gaitgram.cli.common import err, fail
from gaitgram.cli.options import Defines, Settings, Walk, ge_default, parse_settings
from gaitgram.cli.selection import (
    Codons,
    GenomeCodons,
    GenomeFile,
    Grammar,
    MaxWraps,
    SelectedGait,
    SelectionError,
    select_gait,
)
from gaitgram.evolution.selection import score
from gaitgram.pipeline import DEFAULT_BACKEND, Individual, PipelineError

_Run = Annotated[
    Path | None,
    typer.Option("--run", help="Use this run directory's own pipeline; by default, its best gait."),
]
_Generation = Annotated[
    int | None,
    typer.Option(
        min=0, help="Score as in this generation: its joint freedom and weights (default: the last)."
    ),
]
_Config = Annotated[
    Path | None, typer.Option("--config", "-c", help="A run.toml: codons, backend, settings, weights.")
]
_Backend = Annotated[
    str | None,
    typer.Option(help=f"Fitness backend (default: the grammar's @backend, else {DEFAULT_BACKEND})."),
]
_MaxDepth = Annotated[
    int | None,
    typer.Option(min=1, help=f"Deepest rule node (default: {ge_default('max_depth') or 'none'})."),
]
_Horizon = Annotated[
    int | None,
    typer.Option(
        min=1,
        metavar="CYCLES",
        help="Check the gait over this many cycles, not the run's horizon: does a run's best walk "
        "stay one for longer?",
    ),
]


def command(
    grammar: Grammar = None,
    run: _Run = None,
    genome: GenomeCodons = None,
    genome_file: GenomeFile = None,
    generation: _Generation = None,
    config: _Config = None,
    backend: _Backend = None,
    codons: Codons = None,
    max_wraps: MaxWraps = None,
    max_depth: _MaxDepth = None,
    setting: Settings = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    walk: Walk = False,
    defines: Defines = None,
    horizon: _Horizon = None,
) -> None:
    """Map a genome, simulate its gait and print the fitness, its components and the status.

    With --run, the gait is scored by the run's own pipeline, and re-scoring the run's best must
    reproduce the fitness the run recorded (exit 2 if it does not). Exit 1 if the gait is not viable.
    """
    overrides = {
        "backend": backend,
        "codons": codons.value if codons is not None else None,
        "max_wraps": max_wraps,
        "max_depth": max_depth,
        "backend_settings": parse_settings(setting) or None,
    }
    try:
        chosen = select_gait(run, grammar, genome, genome_file, generation, config, overrides, defines, walk)
        scored = score(chosen, horizon)
    except (SelectionError, PipelineError) as error:
        raise fail(str(error)) from None
    if as_json:
        typer.echo(jsonio.dumps(_record(chosen, scored, horizon)))
    else:
        _show(chosen, scored)
    _check_reproduced(chosen, scored.evaluation, horizon)
    if not scored.evaluation.status.viable:
        raise typer.Exit(1)


def _check_reproduced(chosen: SelectedGait, evaluation: Evaluation, horizon: int | None) -> None:
    """Exit 2 unless re-scoring gave what the run recorded: the same evaluation, or with another
    horizon the same fitness (the check's own components differ) or an unviable one (it failed
    the longer check, which exit 1 then says)."""
    recorded = chosen.recorded
    if recorded is None:
        return
    if set(recorded.components) < set(evaluation.components):
        # Recorded before the backend measured more (a component weighted 0 by default, such as
        # mujoco-horse's footfalls): the record is compared on what it holds.
        evaluation = replace(
            evaluation, components={k: evaluation.components[k] for k in recorded.components}
        )
    same = (
        recorded == evaluation
        if horizon is None
        else (not evaluation.status.viable or evaluation.fitness == recorded.fitness)
    )
    if not same:
        raise fail(
            f"re-scoring gives fitness {evaluation.fitness!r} ({evaluation.status}), but the run "
            f"recorded {recorded.fitness!r} ({recorded.status}): the backend is not "
            "deterministic, or the run was altered"
        )


def _record(chosen: SelectedGait, scored: Individual, horizon: int | None) -> dict[str, Any]:
    """``--json``: the gait (which run's, with ``--run``), where it was scored, over what horizon,
    and its evaluation."""
    record = {
        "backend": chosen.pipeline.backend,
        "gait": chosen.describe,
        **({"run": chosen.run} if chosen.run is not None else {}),
        **({"horizon": horizon} if horizon is not None else {}),
        "generation": chosen.generation,
        "genome": list(chosen.genome),
        "phenotype": scored.phenotype,
        **scored.evaluation.as_record(),
    }
    if chosen.recorded is not None:
        record["recorded_fitness"] = chosen.recorded.fitness
    return record


def _show(chosen: SelectedGait, scored: Individual) -> None:
    """For people: the fitness and its components, the scored cycles, and the backend's verdict
    (why it is not a walk, say)."""
    evaluation = scored.evaluation
    out = Console(highlight=False, markup=False)
    table = Table(title=f"{chosen.pipeline.backend}: {evaluation.status.value}", show_header=True)
    table.add_column("component")
    table.add_column("value", justify="right")
    table.add_row("fitness", f"{evaluation.fitness:.6g}", style="bold")
    for key, value in evaluation.components.items():
        table.add_row(key, f"{value:.6g}")
    out.print(table)
    if evaluation.cycles:
        out.print(_cycles_table(evaluation.cycles))
    verdict = chosen.pipeline.spec.verdict
    if verdict is not None:
        out.print(verdict.sentence(evaluation), markup=False)
    err.print(chosen.describe)
    if evaluation.detail:
        out.print(evaluation.detail, markup=False)


def _cycles_table(cycles: dict[str, tuple[float, ...]] | Any) -> Table:
    """The scored cycles side by side, so their spread shows."""
    count = max(len(values) for values in cycles.values())
    table = Table(title="scored cycles", show_header=True)
    table.add_column("measure")
    for c in range(count):
        table.add_column(f"cycle {c + 1}", justify="right")
    for name, values in cycles.items():
        table.add_row(name, *(f"{v:.4g}" for v in values))
    return table
