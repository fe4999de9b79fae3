"""Which gait ``evaluate`` and ``render`` show, and through which pipeline.

Either a run directory's own pipeline and (by default) its best individual, or
a grammar with a config file and flags: the same :class:`~gaitgram.pipeline.Pipeline`
that ``evolve`` uses either way, so a gait is never re-mapped or re-scored with
settings other than the ones it was evolved with.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import typer

from gaitgram.backends.api import Evaluation
from gaitgram.cli.common import load_usable, read_genome
from gaitgram.cli.options import parse_defines
from gaitgram.evolution.checkpoint import CheckpointError
from gaitgram.evolution.config import ConfigError, load_config
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError, best_of_runs, best_walk_of_runs
from gaitgram.pipeline import Pipeline, PipelineError


@dataclass(frozen=True)
class SelectedGait:
    pipeline: Pipeline
    genome: tuple[int, ...]
    generation: int
    #: What the run recorded for this genome (its best), to check that re-evaluating reproduces it.
    recorded: Evaluation | None
    describe: str


class SelectionError(ValueError):
    pass


#: The command-line spelling of each override, for messages.
_FLAGS = {
    "backend": "--backend",
    "codons": "--codons",
    "max_wraps": "--max-wraps",
    "max_depth": "--max-depth",
    "backend_settings": "--set",
}


def select_gait(
    *,
    run: Path | None,
    grammar: Path | None,
    genome: str | None,
    genome_file: Path | None,
    generation: int | None,
    config: Path | None,
    overrides: dict[str, Any],
    defines: list[str] | None,
    walk: bool = False,
) -> SelectedGait:
    """From ``--run DIR`` (nothing else that changes meaning allowed) or a grammar and options;
    ``walk`` picks the run's best walk rather than its best gait."""
    try:
        if run is not None:
            return _from_run(run, grammar, genome, genome_file, generation, config, overrides, defines, walk)
        if walk:
            raise SelectionError("--walk picks a gait from a run: give --run DIR")
        if grammar is None:
            raise typer.BadParameter("give a grammar and a genome, or --run DIR", param_hint="GRAMMAR")
        codons = read_genome(genome, genome_file)
        run_config = load_config(config, overrides)
        pipeline = Pipeline.build(load_usable(grammar, parse_defines(defines)), run_config)
        at = run_config.generations if generation is None else generation
        return SelectedGait(pipeline, codons, at, None, f"{grammar}, generation {at}")
    except (ConfigError, PipelineError, RunDirectoryError, CheckpointError) as error:
        raise SelectionError(str(error)) from None


def _from_run(
    path: Path,
    grammar: Path | None,
    genome: str | None,
    genome_file: Path | None,
    generation: int | None,
    config: Path | None,
    overrides: dict[str, Any],
    defines: list[str] | None,
    walk: bool,
) -> SelectedGait:
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
    directory = RunDirectory.open(path)
    if walk:
        kept = best_walk_of_runs(directory)
        at = _reached(generation, kept.generation, f"the best walk of {path} is run {kept.run}'s, which")
        recorded = kept.evaluation if at == kept.generation else None
        describe = f"{path} run {kept.run}, best walk, generation {at}"
        return SelectedGait(directory.pipeline, kept.genome, at, recorded, describe)
    if genome is None and genome_file is None:
        run, last, best = best_of_runs(directory)
        at = _reached(generation, last, f"the best gait of {path} is run {run}'s, which")
        recorded = best.evaluation if at == last else None
        return SelectedGait(
            directory.pipeline, best.genome, at, recorded, f"{path} run {run}, best, generation {at}"
        )
    codons = read_genome(genome, genome_file)
    planned = directory.config.generations
    at = _reached(generation, planned, f"{path} runs generations 0..{planned} only;", planned=True)
    return SelectedGait(directory.pipeline, codons, at, None, f"{path}, generation {at}")


def _reached(generation: int | None, last: int, subject: str, *, planned: bool = False) -> int:
    """``--generation``, or ``last`` by default; a generation beyond ``last`` is refused: the run
    never scored anything there (its joint freedom and weights may not even be defined)."""
    if generation is None:
        return last
    if generation > last:
        said = subject if planned else f"{subject} has reached generations 0..{last} only;"
        raise SelectionError(
            f"--generation {generation}: {said} give one of them, or leave --generation out for the last"
        )
    return generation
