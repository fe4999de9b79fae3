"""What a study report reads: run directories, as untrusted input.

The input is a set of arms, each a run directory of ``gaitgram evolve`` (a
study directory's ``arms/*``, or run directories given one by one). Every file
is checked as it is read: the configuration key by key (and against the
manifest's digest), every line of each run's ``stats.jsonl`` and its
``best.json`` field by field, fronts and repertoires member by member. A record
that does not read is a :class:`ReportError` naming the file (and line) and the
command that rewrites it from the run's checkpoint; no number computed from it
ever reaches a statistic.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram import jsonio
from gaitgram.backends.api import Verdict
from gaitgram.backends.registry import get_backend
from gaitgram.evolution.rundir import RunDirectoryError, read_manifest, saved_config
from gaitgram.evolution.usage import RunUsage, UsageError, read_usage
from gaitgram.ge.registry import DEFAULT_REPRESENTATION
from gaitgram.language.source import path_problem
from gaitgram.pipeline import DEFAULT_BACKEND
from gaitgram.plugins import PluginLoadError, PluginNotFound
from gaitgram.report import escape
from gaitgram.runlayout import ARMS, BEST, CONFIG, MANIFEST, STATS_JSONL, STUDY_MANIFEST, run_path
from gaitgram.strategies.kept import RecordError, kept_members
from gaitgram.study.manifest import read_study_manifest
from gaitgram.study.spec import StudyError


class ReportError(ValueError):
    """Run directories that cannot be reported together; the message says why."""


@dataclass(frozen=True)
class RunRecord:
    """One run's history and its final best individual."""

    best: np.ndarray  # per generation
    average: np.ndarray  # per generation, over every individual (unviable at their score)
    average_viable: np.ndarray  # per generation, over viable individuals (NaN if none)
    unviable_share: np.ndarray  # per generation
    evaluations: int
    final_status: str
    walk: bool | None  # the final best is a walk (None: the backend does not say)
    #: What the run hands back holds a walk: its repertoire, its Pareto front, or else its final
    #: population (None: the backend or the records do not say).
    holds_walk: bool | None = None
    #: Per generation, the share of the population that is a walk (None: the records do not say).
    walk_share: np.ndarray | None = None
    #: What the run spent in its backend, as it recorded it (None: a run made before runs did).
    usage: RunUsage | None = None

    @property
    def first_walk(self) -> int | None:
        """The first generation whose population holds a walk; None if none does (or unknown)."""
        if self.walk_share is None:
            return None
        found = np.flatnonzero(self.walk_share > 0)
        return int(found[0]) if len(found) else None


@dataclass(frozen=True)
class ArmRecord:
    name: str
    strategy: str
    path: Path
    budget: int  # planned evaluations per run (new genomes, not re-scored elites)
    generations: int
    population: int
    runs: tuple[RunRecord, ...]
    #: What scored the runs: the backend and its version (its fitness revision), from the manifest.
    backend: str = ""
    backend_version: str = ""
    #: Each run's number (its ``run-NNN`` directory), where only finished runs were read (a study
    #: still running); empty: the runs are 0, 1, ... in order.
    run_numbers: tuple[int, ...] = ()
    planned_runs: int = 0  # the runs the arm will have (0: as many as it has)
    #: The backend's verdict the walks were counted with (None: it declares none).
    verdict: Verdict | None = None
    #: The backend's ``scoring_settings`` that the runs set, sorted (another value scores another
    #: thing: mujoco-horse's ``bump_floors``).
    scoring: tuple[tuple[str, str], ...] = ()
    #: Only the arm's first ``window`` runs are read (``gaitgram report --runs``, a study that has
    #: grown since a report was made over fewer); None: all it plans.
    window: int | None = None
    #: What the runs' genomes are (``gaitgram.ge.registry``), from the configuration.
    representation: str = DEFAULT_REPRESENTATION

    @property
    def numbers(self) -> tuple[int, ...]:
        """Each run's number, in the order of :attr:`runs`."""
        return self.run_numbers or tuple(range(len(self.runs)))

    @property
    def final_best(self) -> np.ndarray:
        return np.array([r.best[-1] for r in self.runs])

    @property
    def final_average(self) -> np.ndarray:
        return np.array([r.average[-1] for r in self.runs])

    @property
    def final_average_viable(self) -> np.ndarray:
        return np.array([r.average_viable[-1] for r in self.runs])

    @property
    def final_unviable_share(self) -> np.ndarray:
        return np.array([r.unviable_share[-1] for r in self.runs])

    @property
    def walk_rate(self) -> float | None:
        return _share([r.walk for r in self.runs])

    @property
    def walks(self) -> int | None:
        """How many runs' best gaits are walks; None if any run's records do not say."""
        flags = [r.walk for r in self.runs]
        return None if any(flag is None for flag in flags) else sum(bool(flag) for flag in flags)

    @property
    def walk_held_rate(self) -> float | None:
        return _share([r.holds_walk for r in self.runs])


def _share(flags: list[bool | None]) -> float | None:
    """The share of true flags; None if any run's records do not say."""
    if any(flag is None for flag in flags):
        return None
    return sum(bool(flag) for flag in flags) / len(flags)


def load_arm(
    path: Path,
    name: str | None = None,
    strategy: str | None = None,
    *,
    redo: str = "",
    finished_only: bool = False,
    runs: int | None = None,
) -> ArmRecord:
    """An arm from a finished run directory; refuses unfinished, unreadable or damaged runs.

    Every file is untrusted input: the configuration is checked key by key (and against the
    manifest's digest, when there is one), every line of each run's ``stats.jsonl`` and its
    ``best.json`` field by field. ``redo`` is the command that rewrites a run's records from
    its checkpoint (default: ``gaitgram evolve --resume`` of the arm). With ``finished_only``, runs
    still running (or not started) are left out instead of refused. With ``runs``, only runs 0 to
    ``runs - 1`` are read (refused if the arm plans fewer).
    """
    problem = path_problem(path, directory=True)
    if problem == "no such directory" and finished_only:  # report --watch, before anything began
        raise ReportError(
            f"{path}: no such directory yet; --watch follows a study or run that has begun: start it "
            f"(gaitgram study STUDY.toml -o {path}, or gaitgram evolve GRAMMAR -o {path}), then watch it"
        )
    if problem is not None:
        raise ReportError(f"{path}: {problem}")
    if not (path / CONFIG).is_file() and not (path / MANIFEST).is_file():
        raise ReportError(f"{path}: not a `gaitgram evolve` run directory (it has no {CONFIG})")
    try:
        manifest = read_manifest(path)
        config = saved_config(path, manifest)
    except RunDirectoryError as error:
        raise ReportError(str(error)) from None
    redo = redo or f"gaitgram evolve --resume {path}"
    if runs is not None and not 1 <= runs <= config.runs:
        raise ReportError(
            f"{path}: --runs {runs} asks for its first {runs} runs, but it plans {config.runs}; give "
            f"--runs from 1 to {config.runs}, or grow the arm first (gaitgram evolve --resume {path} "
            f"--runs {runs})"
        )
    window = runs if runs is not None and runs < config.runs else None
    numbers = [
        run
        for run in range(window or config.runs)
        if not (finished_only and _running(run_path(path, run), config.generations))
    ]
    # What scored the runs (a directory without a manifest, hand-made or of gaitgram 0.1, cannot say).
    backend, version = (manifest["backend"], manifest["backend_version"]) if manifest else ("", "")
    verdict = _verdict(backend or config.backend or DEFAULT_BACKEND)
    scoring = _scoring(backend or config.backend or DEFAULT_BACKEND, config.backend_settings)
    runs = tuple(_load_run(run_path(path, run), config.generations, redo, verdict) for run in numbers)
    return ArmRecord(
        name or escape.encodable(path.name),
        strategy or config.strategy,
        path,
        config.budget,
        config.generations,
        config.population,
        runs,
        backend,
        version,
        tuple(numbers) if finished_only else (),
        window or config.runs,
        verdict,
        scoring,
        window,
        config.representation,
    )


def _running(path: Path, generations: int) -> bool:
    """A run not finished yet: not started, or fewer generations recorded than it will have."""
    try:
        lines = (path / STATS_JSONL).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return True
    return sum(bool(line.strip()) for line in lines) < generations + 1 or not (path / BEST).exists()


def _scoring(backend: str, settings: Mapping[str, Any]) -> tuple[tuple[str, str], ...]:
    """The backend's scoring settings that ``settings`` set, as text (none if it is not installed:
    its version, also compared, then tells the arms apart)."""
    try:
        declared = get_backend(backend).scoring_settings
    except (PluginNotFound, PluginLoadError):
        return ()
    return tuple((key, json.dumps(settings[key])) for key in sorted(declared) if key in settings)


def _verdict(backend: str) -> Verdict | None:
    """The verdict the backend declares (None: it declares none, or is not installed here, in which
    case walks are not counted rather than guessed)."""
    try:
        return get_backend(backend).verdict
    except (PluginNotFound, PluginLoadError):
        return None


def _load_run(path: Path, generations: int, redo: str, verdict: Verdict | None) -> RunRecord:
    rewrite = f"rewrite the run's records from its checkpoint with: {redo}"
    stats = path / STATS_JSONL
    lines = [(n, line) for n, line in enumerate(_lines(stats, rewrite), 1) if line.strip()]
    records = [
        _stats_line(line, f"{stats}:{n}", generation, rewrite) for generation, (n, line) in enumerate(lines)
    ]
    if len(records) < generations + 1:
        raise ReportError(
            f"{path}: the run has {len(records) - 1} of its {generations} generations; finish it first, "
            f"or if it has finished, {rewrite}"
        )
    if len(records) > generations + 1:
        raise ReportError(
            f"{stats}: {len(records)} generations, but the run has {generations + 1} (0..{generations}); "
            f"the file was edited or damaged: {rewrite}"
        )
    best_record = _best_record(path / BEST, records[-1]["best"], rewrite)

    def column(key: str) -> np.ndarray:
        return np.array([math.nan if r.get(key) is None else float(r[key]) for r in records])

    population = np.array([float(r["evaluations"]) for r in records])
    invalid = column("invalid")
    size = population[0] if population[0] else 1.0
    components = best_record["components"]
    return RunRecord(
        best=column("best"),
        average=column("average_all") if "average_all" in records[0] else column("average"),
        average_viable=column("average"),
        unviable_share=invalid / size,
        evaluations=int(population.sum()),
        final_status=best_record["status"],
        walk=None
        if verdict is None or verdict.component not in components
        else verdict.holds_in(components, viable=best_record["status"] == "ok"),
        holds_walk=_holds_walk(path, records[-1], verdict),
        walk_share=_walk_share(records, verdict, int(size)),
        usage=_usage(path),
    )


def _usage(path: Path) -> RunUsage | None:
    try:
        return read_usage(path)
    except UsageError as error:
        raise ReportError(str(error)) from None


def _walk_share(records: list[dict[str, Any]], verdict: Verdict | None, population: int) -> np.ndarray | None:
    """Per generation, the walk component's mean; 0 for a generation in which no gait could be
    measured (all ``population`` unviable: none is a walk, and a run's records then hold no
    means). None when some other generation lacks it (records made before runs recorded it)."""
    key = None if verdict is None else f"mean_{verdict.component}"
    if key is None:
        return None
    shares = []
    for record in records:
        value = record.get(key)
        if value is None and record.get("invalid") == population:
            value = 0.0
        if value is None:
            return None
        shares.append(float(value))
    return np.array(shares)


def _lines(path: Path, rewrite: str) -> list[str]:
    try:
        return path.read_text(encoding="utf-8").splitlines()
    except FileNotFoundError:
        raise ReportError(f"{path} is missing; {rewrite}") from None
    except (OSError, UnicodeDecodeError) as error:
        raise ReportError(f"{path}: cannot read it ({error}); {rewrite}") from None


def _finite(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _count(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _stats_line(line: str, where: str, generation: int, rewrite: str) -> dict[str, Any]:
    """One generation's statistics, as gaitgram writes them: a non-finite number is never one.
    ``where`` is the file and line, as the user's editor numbers it (blank lines included)."""
    damaged = f"the file was edited or damaged: {rewrite}"
    try:
        record = jsonio.object_from(line, where, "a record of one generation")
    except jsonio.ObjectError as error:
        raise ReportError(f"{error}; {damaged}") from None
    if record.get("generation") != generation or not _count(record.get("generation")):
        raise ReportError(
            f"{where}: generation: {record.get('generation')!r}, expected {generation}; {damaged}"
        )
    for key in ("best", "evaluations"):
        if key not in record:
            raise ReportError(f"{where}: {key}: missing; {damaged}")
    if not _finite(record["best"]):
        raise ReportError(f"{where}: best: {record['best']!r} is not a finite number; {damaged}")
    for key in ("evaluations", "invalid"):
        if key in record and not _count(record[key]):
            raise ReportError(f"{where}: {key}: {record[key]!r} is not a count; {damaged}")
    for key, value in record.items():
        if (key in ("average", "average_all", "std") or key.startswith("mean_")) and not (
            value is None or _finite(value)
        ):
            raise ReportError(f"{where}: {key}: {value!r} is not a finite number (or null); {damaged}")
    return record


def _best_record(path: Path, best: float, rewrite: str) -> dict[str, Any]:
    """``best.json``'s status and components, checked, and its fitness the statistics' last best."""
    damaged = f"the file was edited or damaged: {rewrite}"
    try:
        record = jsonio.read_object(path, "a record of the best gait")
    except jsonio.ObjectError as error:
        raise ReportError(f"{error}; {damaged if error.damaged else rewrite}") from None
    components = record.get("components")
    if not isinstance(components, dict) or not all(_finite(v) for v in components.values()):
        raise ReportError(f"{path}: components: not a table of finite numbers; {damaged}")
    if not isinstance(record.get("status"), str):
        raise ReportError(f"{path}: status: missing or not text; {damaged}")
    if record.get("fitness") != best:
        raise ReportError(
            f"{path}: fitness {record.get('fitness')!r} is not the last generation's best in {STATS_JSONL} "
            f"({best!r}); {damaged}"
        )
    return record


def _holds_walk(path: Path, final: dict[str, Any], verdict: Verdict | None) -> bool | None:
    """Whether the run hands back a walk, even one its weighted best is not: a weighted sum can rank
    a walk below a gait that misses the walk window (docs/results/revision-3/strategies)."""
    try:
        members = kept_members(path)
    except RecordError as error:
        raise ReportError(str(error)) from None
    if members is None:
        share = None if verdict is None else final.get(f"mean_{verdict.component}")  # the population's
        return None if share is None else share > 0
    if verdict is None or any(verdict.component not in m["components"] for m in members):
        return None
    return any(verdict.holds_in(m["components"], viable=True) for m in members)


def load_study_arms(directory: Path) -> list[ArmRecord]:
    """The arms of a study directory, in the study's order."""
    return _study_arms(directory)[0]


def _study_arms(
    directory: Path, finished_only: bool = False, runs: int | None = None
) -> tuple[list[ArmRecord], str]:
    """The arms of a study directory, in the study's order, and its title."""
    try:
        manifest = read_study_manifest(directory)
    except StudyError as error:
        raise ReportError(str(error)) from None

    def redo(arm: str) -> str:
        path = directory / ARMS / arm
        return f"gaitgram study {manifest.study_file} -o {directory} (or gaitgram evolve --resume {path})"

    arms = [
        load_arm(
            directory / ARMS / a.name,
            a.name,
            a.strategy,
            redo=redo(a.name),
            finished_only=finished_only,
            runs=runs,
        )
        for a in manifest.arms
    ]
    return arms, manifest.title


def load_arms(
    directories: Sequence[Path], *, finished_only: bool = False, runs: int | None = None
) -> tuple[list[ArmRecord], str]:
    """The arms of study directories (each gives its arms) and run directories of ``gaitgram
    evolve`` (each one arm), and the studies' titles. A run directory given twice, under any
    spelling (a symlink, ``..``, a study and one of its arms), is refused: it would be compared
    with itself. Two arms of the same name are named by their paths. With ``finished_only`` (a
    study still running), only finished runs are read, and arms with none yet are left out. With
    ``runs``, each arm's first ``runs`` runs alone."""
    arms: list[ArmRecord] = []
    titles = []
    for directory in directories:
        if (directory / STUDY_MANIFEST).is_file():
            found, title = _study_arms(directory, finished_only, runs)
            arms += found
            titles.append(title)
        else:
            arms.append(load_arm(directory, finished_only=finished_only, runs=runs))
    if finished_only:
        arms = [a for a in arms if a.runs]
    _refuse_duplicates(arms)
    names = [a.name for a in arms]
    if len(set(names)) != len(names):
        arms = [replace(a, name=escape.encodable(str(a.path))) for a in arms]
    return arms, " + ".join(titles)


def _refuse_duplicates(arms: list[ArmRecord]) -> None:
    seen: dict[tuple[int, int], ArmRecord] = {}
    for arm in arms:
        info = arm.path.stat()
        first = seen.setdefault((info.st_dev, info.st_ino), arm)
        if first is not arm:
            same = "given twice" if first.path == arm.path else f"the same directory as {first.path}"
            raise ReportError(
                f"{arm.path} is {same} ({arm.path.resolve()}): a run directory compared with itself would "
                "look like two arms that agree; give each run directory once"
            )


def check_scoring(arms: list[ArmRecord], *, mixed_scoring: bool = False) -> None:
    """Refuse arms scored by different backends or backend versions (another fitness revision, model
    or simulator), or, unless ``mixed_scoring``, under different scoring settings (other floors):
    their fitness values measure different things."""
    versions = {(a.backend, a.backend_version) for a in arms}
    scorings = {a.scoring for a in arms}
    if len(versions) > 1 or (len(scorings) > 1 and not mixed_scoring):
        allow = (
            "; or give --mixed-scoring to report them together, their fitness apart"
            if len(versions) == 1
            else ""
        )
        raise ReportError(
            f"these arms were scored differently ({scoring_listing(arms)}); their fitness values do not "
            "compare in one table: report them separately, or run them again with one gaitgram and the "
            f"same scoring settings{allow}"
        )


def scoring_listing(arms: Sequence[ArmRecord]) -> str:
    """Each arm's backend, version and scoring settings, for a message."""
    return "; ".join(
        f"{a.name}: "
        + ", ".join(
            [f"{a.backend} {a.backend_version}".strip() or "backend not recorded"]
            + [f"{k} = {v}" for k, v in a.scoring]
        )
        for a in arms
    )


def check_budgets(arms: list[ArmRecord]) -> None:
    budgets = {a.budget for a in arms}
    if len(budgets) > 1:
        listing = ", ".join(f"{a.name}: {a.budget}" for a in arms)
        raise ReportError(
            "these arms were run at different budgets (planned evaluations per run: "
            f"{listing}); their numbers do not compare in one table: report them separately, or run "
            "them again with the same generations, population and elite"
        )


def check_comparable(arms: list[ArmRecord], *, mixed_scoring: bool = False) -> None:
    """Refuse arms whose numbers do not compare in one table: scored differently (under other
    scoring settings, unless ``mixed_scoring``), or at different budgets."""
    check_scoring(arms, mixed_scoring=mixed_scoring)
    check_budgets(arms)
