"""``gaitgram evaluate``: one individual through the fitness backend, every component shown."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from gaitgram.cli.common import err, load_usable, read_genome
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.evolution.config import RunConfig
from gaitgram.evolution.session import SessionError, choose_backend, joint_order, load_evaluator
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.motion.gait import motion_batch


def command(
    grammar: Annotated[Path, typer.Argument(help="The grammar.", show_default=False)],
    genome: Annotated[str | None, typer.Option(help="Codons, e.g. 12,7,301.")] = None,
    genome_file: Annotated[Path | None, typer.Option(help="Codons from a file; - for stdin.")] = None,
    backend: Annotated[str | None, typer.Option(help="Fitness backend [the grammar's @backend].")] = None,
    generation: Annotated[int, typer.Option(min=0, help="Generation (joint freedom, weights).")] = 1_000_000,
    codons: Annotated[CodonMode, typer.Option(help="lazy or eager codon consumption.")] = CodonMode.LAZY,
    max_wraps: Annotated[int, typer.Option(min=0)] = 3,
    setting: Annotated[
        list[str] | None,
        typer.Option("--set", metavar="KEY=JSON", help="Backend setting, e.g. froude=0.5."),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    defines: Defines = None,
) -> None:
    """Map a genome, simulate its gait and print the fitness, its components and the status."""
    codon_values = read_genome(genome, genome_file)
    checked = load_usable(grammar, parse_defines(defines))
    settings = {}
    for item in setting or []:
        key, sep, raw = item.partition("=")
        if not sep:
            raise typer.BadParameter(f"{item!r} is not KEY=VALUE", param_hint="--set")
        try:
            settings[key] = json.loads(raw)
        except json.JSONDecodeError:
            settings[key] = raw
    name = choose_backend(RunConfig(backend=backend), checked)
    try:
        evaluator = load_evaluator(name, settings)
    except SessionError as error:
        err.print(f"error: {error}", style="bold red")
        raise typer.Exit(2) from None
    try:
        mapped = compile_mapper(checked.grammar, codons=codons, max_wraps=max_wraps).map_fast(codon_values)
        frozen = {j.joint for j in checked.grammar.joints if not j.is_free(generation)}
        batch = motion_batch(
            [mapped.joints if mapped.valid else None],
            joint_order(name, checked),
            units=checked.grammar.units,
            frozen=frozen,
        )
        (evaluation,) = evaluator.evaluate(batch, generation=generation)
    finally:
        evaluator.close()
    if as_json:
        typer.echo(json.dumps({"backend": name, "phenotype": mapped.phenotype, **evaluation.as_record()}))
    else:
        out = Console(highlight=False)
        table = Table(title=f"{name}: {evaluation.status.value}", show_header=True)
        table.add_column("component")
        table.add_column("value", justify="right")
        table.add_row("fitness", f"{evaluation.fitness:.6g}", style="bold")
        for key, value in evaluation.components.items():
            table.add_row(key, f"{value:.6g}")
        out.print(table)
        if evaluation.detail:
            out.print(evaluation.detail)
    if not evaluation.status.viable:
        raise typer.Exit(1)
