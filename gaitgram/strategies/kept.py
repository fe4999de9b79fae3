"""The sets of gaits the multi-objective and quality-diversity strategies keep: fronts and repertoires.

Read from the records a run directory keeps beside ``best.json`` (``front.json``
of ``nsga2``, ``archive.json`` of ``map-elites``, or any plug-in that writes the
same), so a report or ``--walk`` needs neither the strategy's library nor its
pickled state. The report draws them (:mod:`gaitgram.report.figures`).
"""

from __future__ import annotations

import math
from collections.abc import Collection, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram import jsonio
from gaitgram.runlayout import ARCHIVE, FRONT, runs_in


class RecordError(ValueError):
    """A front or archive record that cannot be read; says which file."""


def _read(path: Path) -> dict[str, Any]:
    try:
        return jsonio.read_object(path, "a record")
    except jsonio.ObjectError as error:
        if error.damaged:
            raise RecordError(
                f"{path}: malformed ({error.problem}); the file was edited or damaged"
            ) from None
        raise RecordError(str(error)) from None


def _records(
    arm: Path, name: str, runs: Collection[int] | None = None
) -> Iterator[tuple[int, Path, dict[str, Any]]]:
    """(run, file, its content) of each of an arm's runs that keeps the record ``name``: of the
    runs numbered ``runs`` (a report's), or of every run directory there is."""
    for run, directory in runs_in(arm):
        path = directory / name
        if (runs is None or run in runs) and path.is_file():
            yield run, path, _read(path)


#: Where a strategy keeps the set of gaits it hands back, and the key of its members.
KEPT_SETS = ((ARCHIVE, "elites"), (FRONT, "front"))


def kept_members(run_dir: Path) -> tuple[dict[str, Any], ...] | None:
    """The gaits a run hands back when its strategy keeps a set (a repertoire's cells, a Pareto
    front), each a record with its fitness, components and genome (checked to be numbers); None
    if it keeps neither, when what it hands back is its final population (in its checkpoint)."""
    for name, key in KEPT_SETS:
        path = run_dir / name
        if path.is_file():
            members = _read(path).get(key)
            if not isinstance(members, list) or not all(_is_gait(m) for m in members):
                raise RecordError(
                    f"{path}: malformed (its {key!r} is not a list of gaits, each with a fitness, "
                    "numeric components and a genome of integers)"
                )
            return tuple(members)
    return None


def _finite(value: Any) -> bool:
    """A number gaitgram could have written (its JSON never holds NaN or infinities)."""
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _is_gait(member: Any) -> bool:
    number = _finite
    return (
        isinstance(member, dict)
        and number(member.get("fitness"))
        and isinstance(member.get("components"), dict)
        and all(number(v) for v in member["components"].values())
        and isinstance(member.get("genome"), list)
        and all(isinstance(c, int) and not isinstance(c, bool) for c in member["genome"])
        and isinstance(member.get("cycles", {}), dict)
        and all(
            isinstance(values, list) and all(number(v) for v in values)
            for values in member.get("cycles", {}).values()
        )
    )


# ---- Pareto fronts --------------------------------------------------------------------------


@dataclass(frozen=True)
class Front:
    """One run's final Pareto front: ``points[i, k]`` is member ``i``'s objective ``k``."""

    run: int
    objectives: tuple[str, ...]
    points: np.ndarray
    members: tuple[dict[str, Any], ...]


def load_fronts(arm: Path, runs: Collection[int] | None = None) -> list[Front]:
    """The fronts of an arm's runs (those that keep one; of ``runs`` alone, if given)."""
    fronts = []
    for run, path, data in _records(arm, FRONT, runs):
        try:
            names = data["objectives"]
            if not isinstance(names, list) or not names or not all(isinstance(o, str) for o in names):
                raise ValueError("objectives is not a list of names")
            objectives = tuple(names)
            members = tuple(data["front"])
            values = [m["objectives"] for m in members]
            if not all(isinstance(v, list) and all(_finite(x) for x in v) for v in values):
                raise ValueError("a member's objectives are not finite numbers")
            points = np.array(values, dtype=float).reshape(-1, len(objectives))
        except (KeyError, TypeError, ValueError) as error:
            raise RecordError(f"{path}: malformed ({error})") from None
        fronts.append(Front(run, objectives, points, members))
    return fronts


def non_dominated(points: np.ndarray) -> np.ndarray:
    """A mask of the rows no other row dominates (minimisation)."""
    keep = np.ones(len(points), dtype=bool)
    for i, point in enumerate(points):
        no_worse = np.all(points <= point, axis=1)
        better = np.any(points < point, axis=1)
        keep[i] = not np.any(no_worse & better)
    return keep


# ---- repertoires ----------------------------------------------------------------------------


@dataclass(frozen=True)
class Repertoire:
    """An arm's archives merged: the best gait found in each cell by any run."""

    descriptors: tuple[dict[str, Any], ...]
    best: np.ndarray  # fitness per cell, NaN where empty; shape = the bins
    coverage: np.ndarray  # runs that filled each cell
    elites: dict[tuple[int, ...], dict[str, Any]]  # cell -> its best gait's record (with "run")
    filled: tuple[int, ...]  # cells each run filled
    cells: int


def load_repertoire(arm: Path, runs: Collection[int] | None = None) -> Repertoire | None:
    """The merged archives of an arm's runs (of ``runs`` alone, if given), or None if they keep
    none."""
    descriptors: tuple[dict[str, Any], ...] | None = None
    best: np.ndarray | None = None
    coverage: np.ndarray | None = None
    elites: dict[tuple[int, ...], dict[str, Any]] = {}
    filled = []
    for run, path, data in _records(arm, ARCHIVE, runs):
        try:
            if descriptors is None:
                descriptors = _descriptors(data["descriptors"])
                shape = tuple(int(d["bins"]) for d in descriptors)
                best = np.full(shape, np.nan)
                coverage = np.zeros(shape, dtype=int)
            assert best is not None
            assert coverage is not None
            filled.append(len(data["elites"]))
            for elite in data["elites"]:
                cell = elite["cell"]
                if not (
                    isinstance(cell, list)
                    and len(cell) == best.ndim
                    and all(isinstance(i, int) and 0 <= i < n for i, n in zip(cell, best.shape, strict=True))
                ):
                    raise ValueError(
                        f"cell {cell!r} is not a cell of the {'x'.join(map(str, best.shape))} grid"
                    )
                cell = tuple(cell)
                coverage[cell] += 1
                if not _finite(elite["fitness"]):
                    raise ValueError(
                        f"cell {list(cell)}: fitness {elite['fitness']!r} is not a finite number"
                    )
                fitness = float(elite["fitness"])
                if np.isnan(best[cell]) or fitness < best[cell]:
                    best[cell] = fitness
                    elites[cell] = {**elite, "run": run}
        except (KeyError, TypeError, ValueError, IndexError, AssertionError) as error:
            raise RecordError(f"{path}: malformed ({error})") from None
    if descriptors is None or best is None or coverage is None:
        return None
    return Repertoire(descriptors, best, coverage, elites, tuple(filled), int(best.size))


#: More cells than any archive map-elites makes (its settings allow at most 10,000).
MAX_CELLS = 1_000_000


def _descriptors(value: Any) -> tuple[dict[str, Any], ...]:
    """An archive's descriptors: one or two, each a name, a finite range and a count of bins."""
    if not isinstance(value, list) or not 1 <= len(value) <= 2:
        raise ValueError("descriptors is not a list of one or two descriptors")
    for d in value:
        if not (
            isinstance(d, dict)
            and isinstance(d.get("name"), str)
            and _finite(d.get("low"))
            and _finite(d.get("high"))
            and d["low"] < d["high"]
            and isinstance(d.get("bins"), int)
            and not isinstance(d["bins"], bool)
            and d["bins"] >= 1
        ):
            raise ValueError(f"descriptor {d!r} is not a name, a range low < high and bins >= 1")
    if math.prod(d["bins"] for d in value) > MAX_CELLS:
        raise ValueError(f"the descriptors make more than {MAX_CELLS} cells")
    return tuple(value)
