"""Where run and study directories keep what they keep: the one place their names are spelt.

Every reader and writer (the loop, the records, resuming, reports, assessments, studies) takes a
name from here, so that no reader can look for a file under a name its writer no longer uses.
A run directory (``gaitgram evolve -o DIR``, or a study's arm)::

    manifest.json   what the run is: digests of grammar.gg and config.toml, the --define values,
                    the backend's name and version, the engine revision, gaitgram's version,
                    the search strategy and its version (unless GE), the representation and
                    its version (unless GE), and the run's fingerprint (a digest of all of that)
    grammar.gg      the grammar text the runs use (a copy: editing the original changes nothing)
    config.toml     the resolved configuration: defaults, file and flags, the backend named and
                    its settings spelt out
    run-000/ ...    one directory per run: checkpoint.json, stats.csv, stats.jsonl, best.json, and
                    for strategies other than GE the pickled strategy state the checkpoint
                    names (strategy-NNNNNN.pickle) and the strategy's records (front.json,
                    archive.json, ...); backend.json, what each generation spent in the backend;
                    assessment.json, its best gait measured by ``gaitgram report --assess``
    summary.json    written when every run has finished
    best-walk-assessment.json   the best walk of its runs, measured by ``report --assess --gaits``

A study directory keeps ``study.json`` and its arms, each a run directory, in ``arms/NAME``.
"""

from __future__ import annotations

import re
from pathlib import Path

#: What a run is (digests, versions, fingerprint).
MANIFEST = "manifest.json"
#: The copy of the grammar the runs use.
GRAMMAR = "grammar.gg"
#: The resolved configuration.
CONFIG = "config.toml"
#: Written when every run of the directory has finished.
SUMMARY = "summary.json"

#: A run's state after its last generation: the truth every record is derived from.
CHECKPOINT = "checkpoint.json"
#: A run's statistics, one generation a line (JSON) or a row (CSV).
STATS_JSONL = "stats.jsonl"
STATS_CSV = "stats.csv"
#: A run's best gait, as a report reads it.
BEST = "best.json"
#: What each generation of a run spent in the backend (:mod:`gaitgram.evolution.usage`).
USAGE = "backend.json"
#: The Pareto front a multi-objective strategy keeps, and the repertoire a quality-diversity one does.
FRONT = "front.json"
ARCHIVE = "archive.json"
#: A run's best gait measured beyond its score (``gaitgram report --assess``).
ASSESSMENT = "assessment.json"
#: The best walk of a directory's runs, measured (the walk a report with ``--gaits`` animates).
BEST_WALK = "best-walk-assessment.json"

#: A study's manifest, and the directory that keeps its arms.
STUDY_MANIFEST = "study.json"
ARMS = "arms"

#: What every run directory's name begins with.
RUN_PREFIX = "run-"
#: A run directory's name as messages and help show it.
RUN_SHOWN = "run-NNN"
_RUN_NAME = re.compile(r"run-([0-9]{3,})")


def run_name(run: int) -> str:
    """The name of run ``run``'s directory: ``run-007``."""
    return f"{RUN_PREFIX}{run:03d}"


def run_path(directory: Path, run: int) -> Path:
    """Run ``run``'s directory in ``directory`` (a run directory, or a study's arm)."""
    return directory / run_name(run)


def run_number(name: str) -> int | None:
    """The run a directory's name is of (``run-007``: 7); None for a name :func:`run_name` never gives."""
    found = _RUN_NAME.fullmatch(name)
    return int(found[1]) if found is not None and run_name(int(found[1])) == name else None


def runs_in(directory: Path) -> list[tuple[int, Path]]:
    """Each run whose directory ``directory`` holds, and that directory, by run (none if
    ``directory`` is none)."""
    try:
        found = [(run_number(path.name), path) for path in directory.iterdir() if path.is_dir()]
    except OSError:
        return []
    return sorted((run, path) for run, path in found if run is not None)


def in_run(name: str) -> str:
    """A run's file as messages show it: ``run-NNN/assessment.json``."""
    return f"{RUN_SHOWN}/{name}"


def best_walk_window(window: int | None) -> str:
    """Where the best walk of a directory's runs is kept: of all of them, or of its first ``window``
    (a report over fewer runs than it has, whose best walk may be another)."""
    return BEST_WALK if window is None else f"best-walk-assessment-first-{window}.json"
