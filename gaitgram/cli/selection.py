"""Which gait ``evaluate``, ``render`` and ``retarget`` show, from their options: either a run
directory's own pipeline and (by default) its best individual, or a grammar with a config file
and flags (:mod:`gaitgram.evolution.selection` chooses; this reads the files the options name and
refuses options that do not go together)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from gaitgram.cli.common import decode_genome, load_usable, read_genome_text, read_inputs
from gaitgram.cli.options import ge_default, parse_defines
from gaitgram.configuration import ConfigError, load_config
from gaitgram.evolution.checkpoint import CheckpointError
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError, run_input
from gaitgram.evolution.selection import SelectedGait, SelectionError, from_pipeline, from_run
from gaitgram.fileio import Input
from gaitgram.ge import CodonMode
from gaitgram.pipeline import Pipeline, PipelineError

__all__ = [
    "Codons",
    "GenomeCodons",
    "GenomeFile",
    "Grammar",
    "MaxWraps",
    "SelectedGait",
    "SelectionError",
    "gait_inputs",
    "select_gait",
]

# The options that choose a gait, as each command that takes them spells them.
Grammar = Annotated[Path | None, typer.Argument(help="The grammar (not with --run).")]
GenomeCodons = Annotated[
    str | None,
    typer.Option(
        "--genome", help="The genome in its representation's syntax: GE's codons, for example 12,7,301."
    ),
]
GenomeFile = Annotated[
    Path | None, typer.Option("--genome-file", help="Read the genome from a file; - for standard input.")
]
Codons = Annotated[
    CodonMode | None,
    typer.Option("--codons", help=f"Codon consumption, lazy or eager (default {ge_default('codons')})."),
]
MaxWraps = Annotated[
    int | None, typer.Option("--max-wraps", min=0, help=f"Wraps allowed (default {ge_default('max_wraps')}).")
]

#: The command-line spelling of each override, for messages.
_FLAGS = {
    "backend": "--backend",
    "codons": "--codons",
    "max_wraps": "--max-wraps",
    "max_depth": "--max-depth",
    "backend_settings": "--set",
}


def select_gait(
    run: Path | None,
    grammar: Path | None = None,
    genome: str | None = None,
    genome_file: Path | None = None,
    generation: int | None = None,
    config: Path | None = None,
    overrides: dict[str, Any] | None = None,
    defines: list[str] | None = None,
    walk: bool = False,
) -> SelectedGait:
    """From ``--run DIR`` (nothing else that changes meaning allowed) or a grammar and options;
    ``walk`` picks the run's best walk rather than its best gait."""
    overrides = overrides or {}
    try:
        if run is not None:
            _refuse_with_run(run, grammar, genome, genome_file, config, overrides, defines, walk)
            directory = RunDirectory.open(run)
            given = None
            if genome is not None or genome_file is not None:
                text, origin = read_genome_text(genome, genome_file)
                given = decode_genome(directory.pipeline.representation, text, origin)
            return from_run(directory, run, given, generation, walk=walk)
        if walk:
            raise SelectionError("--walk picks a gait from a run: give --run DIR")
        if grammar is None:
            raise typer.BadParameter("give a grammar and a genome, or --run DIR", param_hint="GRAMMAR")
        text, origin = read_genome_text(genome, genome_file)
        run_config = load_config(config, overrides)
        pipeline = Pipeline.build(load_usable(grammar, parse_defines(defines)), run_config)
        return from_pipeline(
            pipeline, decode_genome(pipeline.representation, text, origin), generation, str(grammar)
        )
    except (ConfigError, PipelineError, RunDirectoryError, CheckpointError) as error:
        raise SelectionError(str(error)) from None


def gait_inputs(
    run: Path | None, grammar: Path | None, genome_file: Path | None, config: Path | None
) -> list[Input]:
    """What the options that choose a gait read, as inputs no output may write over or into."""
    found = read_inputs(
        (grammar, "the grammar"), (genome_file, "the --genome-file"), (config, "the --config")
    )
    return found if run is None else [run_input(run), *found]


def _refuse_with_run(
    path: Path,
    grammar: Path | None,
    genome: str | None,
    genome_file: Path | None,
    config: Path | None,
    overrides: dict[str, Any],
    defines: list[str] | None,
    walk: bool,
) -> None:
    """``--run DIR`` brings its own grammar, configuration and settings: refuse any given too."""
    given = [_FLAGS.get(name, name) for name, value in overrides.items() if value is not None]
    if grammar is not None:
        given.insert(0, "GRAMMAR")
    if config is not None:
        given.append("--config")
    if defines:
        given.append("--define")
    if given:
        raise SelectionError(
            f"--run {path} uses the run's own grammar, configuration and backend settings; drop "
            f"{', '.join(given)} (or evaluate the grammar on its own, without --run)"
        )
    if walk and (genome is not None or genome_file is not None):
        raise SelectionError("--walk picks the run's best walk; drop --genome/--genome-file, or --walk")
