"""Which gait to show or score, and through which pipeline: a run directory's best gait (or best
walk, or a given genome at one of its generations), or a genome through a pipeline built from a
grammar and a configuration.

The same :class:`~gaitgram.pipeline.Pipeline` that ``evolve`` used either way, so a gait is never
re-mapped or re-scored with settings other than the ones it was evolved with (``gaitgram
evaluate``, ``render`` and ``retarget``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from gaitgram.backends.api import Evaluation
from gaitgram.evolution.rundir import RunDirectory, best_of_runs, best_walk_of_runs
from gaitgram.pipeline import Genome, Individual, Pipeline

__all__ = ["SelectedGait", "SelectionError", "from_pipeline", "from_run", "judged", "score"]


@dataclass(frozen=True)
class SelectedGait:
    pipeline: Pipeline
    genome: Genome
    generation: int
    #: What the run recorded for this genome (its best), to check that re-evaluating reproduces it.
    recorded: Evaluation | None
    describe: str
    #: The run of a run directory it is the best gait or best walk of (None: a genome given).
    run: int | None = None


class SelectionError(ValueError):
    pass


def from_pipeline(pipeline: Pipeline, genome: Genome, generation: int | None, name: str) -> SelectedGait:
    """``genome`` through ``pipeline`` (built from the grammar ``name``), as in ``generation``
    (default: the configuration's last)."""
    at = pipeline.config.generations if generation is None else generation
    return SelectedGait(pipeline, genome, at, None, f"{name}, generation {at}")


def from_run(
    directory: RunDirectory, path: Path, genome: Genome | None, generation: int | None, *, walk: bool
) -> SelectedGait:
    """From the run directory at ``path``: ``genome`` as in ``generation`` (default: the last
    planned); without a genome, the runs' best gait (or, with ``walk``, best walk) as in
    ``generation`` (default: the last reached), with what the run recorded for it there."""
    if walk:
        kept = best_walk_of_runs(directory)
        at = _reached(generation, kept.generation, f"the best walk of {path} is run {kept.run}'s, which")
        recorded = kept.evaluation if at == kept.generation else None
        describe = f"{path} run {kept.run}, best walk, generation {at}"
        return SelectedGait(directory.pipeline, kept.genome, at, recorded, describe, kept.run)
    if genome is None:
        run, last, best = best_of_runs(directory)
        at = _reached(generation, last, f"the best gait of {path} is run {run}'s, which")
        recorded = best.evaluation if at == last else None
        describe = f"{path} run {run}, best, generation {at}"
        return SelectedGait(directory.pipeline, best.genome, at, recorded, describe, run)
    planned = directory.config.generations
    at = _reached(generation, planned, f"{path} runs generations 0..{planned} only;", planned=True)
    return SelectedGait(directory.pipeline, genome, at, None, f"{path}, generation {at}")


def score(chosen: SelectedGait, horizon: int | None = None) -> Individual:
    """The gait scored by its pipeline's evaluator as a run keeps a gait: checked over the
    backend's horizon (``horizon`` cycles, if given)."""
    evaluator = chosen.pipeline.load_evaluator(horizon=horizon)
    try:
        (scored,) = chosen.pipeline.verify([chosen.genome], evaluator, chosen.generation)
    finally:
        evaluator.close()
    return scored


def judged(chosen: SelectedGait) -> Evaluation:
    """What the run recorded for the gait (its best, or best walk, where it kept it), else its
    score now, as a run keeps a gait: what its backend's verdict is read from."""
    return chosen.recorded if chosen.recorded is not None else score(chosen).evaluation


def _reached(generation: int | None, last: int, subject: str, *, planned: bool = False) -> int:
    """``generation``, or ``last`` by default; a generation beyond ``last`` is refused: the run
    never scored anything there (its joint freedom and weights may not even be defined)."""
    if generation is None:
        return last
    if generation > last:
        said = subject if planned else f"{subject} has reached generations 0..{last} only;"
        raise SelectionError(
            f"--generation {generation}: {said} give one of them, or leave --generation out for the last"
        )
    return generation
