"""Seeded transfer: a run's first generation is another run's final population (``start_from``),
for example the horse's evolved gaits as the start of a search on a draft horse.

A genome means a gait only under the grammar it was evolved with, so the source must have the
same grammar text; it must have finished, so that what is transferred is its result; and run
``i`` of an arm starts from run ``i`` of the source, so that a study's runs stay independent.
"""

from __future__ import annotations

from pathlib import Path

from gaitgram.evolution.checkpoint import CheckpointError, load_checkpoint
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError
from gaitgram.pipeline import Genome, Pipeline


class TransferError(ValueError):
    """A ``start_from`` that cannot start this run; says why and what would."""


def start_genomes(pipeline: Pipeline, run: int) -> tuple[Genome, ...]:
    """The genomes run ``run`` of ``pipeline``'s config starts from: the best ``population`` of
    the source run's final population, best first; () without ``start_from``."""
    config = pipeline.config
    if config.start_from is None:
        return ()
    path = Path(config.start_from)
    where = f"start_from {config.start_from}"
    try:
        source = RunDirectory.open(path)
    except RunDirectoryError as error:
        raise TransferError(f"{where}: {error}") from None
    if source.pipeline.grammar.source.text != pipeline.grammar.source.text:
        raise TransferError(
            f"{where}: its runs were evolved with another grammar ({source.origin}), under which the "
            "same genomes are other gaits; start from a run of this grammar"
        )
    runs = source.config.runs
    index = 0 if runs == 1 else run
    if index >= runs:
        raise TransferError(
            f"{where}: it has {runs} runs and this is run {run}: run at most {runs}, so that each run "
            "starts from its own, or start from a directory of one run"
        )
    checkpoint = source.checkpoints[index]
    try:
        state = load_checkpoint(
            checkpoint, source.pipeline, fingerprint=source.fingerprints, run=index, with_memory=False
        )
    except (CheckpointError, OSError) as error:
        raise TransferError(f"{where}: run {index} cannot be read: {error}") from None
    if state.generation != source.config.generations:
        raise TransferError(
            f"{where}: run {index} has reached generation {state.generation} of "
            f"{source.config.generations}; start from it when it has finished"
        )
    if len(state.population) < config.population:
        raise TransferError(
            f"{where}: run {index}'s final population has {len(state.population)} gaits, fewer than "
            f"this run's population of {config.population}"
        )
    ranked = sorted(state.population, key=lambda individual: individual.fitness)
    return tuple(tuple(individual.genome) for individual in ranked[: config.population])
