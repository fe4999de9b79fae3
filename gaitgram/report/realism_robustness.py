"""The report's realism and robustness sections: each run's best gait held against real horses and
pushed.

Read from the assessments ``gaitgram report --assess`` keeps in each run directory
(:mod:`gaitgram.report.assess`; untrusted input, checked as read), never simulated here: the
report stays fast and deterministic. Only arms whose backend measures its gaits have these
sections, and what they show is what that backend declares it keeps
(:class:`~gaitgram.backends.api.Assessment`): nothing here knows which backend it is.

**Realism** (on the horse, *Gaits held against real horses*): per arm, the median over its runs'
best gaits of each measure the backend declares, beside the reference's value and spread (on the
horse, the DLC_Horse walks); the realism distance per gait per arm, with the rank tests, and its
terms; and a figure overlaying the arms' best gaits' curves on the reference's band.

**Robustness** (*Robust, not only sustained*): per arm, the share of the runs' best gaits that stay
upright and walking under each disturbance the assessments name (on the horse, fore-aft pushes and
bumpy floors), and under all of them, with the verdict's terms the gaits failed.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitgram import jsonio
from gaitgram.backends.api import Assessment, ReferenceCurve
from gaitgram.ge.registry import Genome
from gaitgram.report import escape
from gaitgram.report.assess import FORMAT, assessing, assessment_path, best_walk_path, kept_key
from gaitgram.report.records import ArmRecord, ReportError
from gaitgram.report.sections import Column, Figure, Kind, RankTests, Section, Table, figure_name
from gaitgram.report.stats import bootstrap_median_ci, compare
from gaitgram.runlayout import ASSESSMENT, BEST, in_run, run_path

# ---- what the runs keep ------------------------------------------------------------------------


@dataclass(frozen=True)
class Trial:
    disturbance: str
    describe: str
    upright: bool
    walking: bool
    detail: str | None
    floors: int  # how many floors the gait was played on (the bumps: several, each seeded)
    held: int  # on how many of them it held

    @property
    def holds(self) -> bool:
        return self.upright and self.walking


@dataclass(frozen=True)
class Assessed:
    """One run's best gait, as its kept assessment measured it."""

    run: int
    genome: Genome
    fitness: float
    walk: bool | None  # the gait is a walk by the walk criterion (the run's records)
    gait: str  # "measured", "falls" (or does not step), "invalid"
    measures: dict[str, float] | None
    scores: dict[str, float] | None
    distance: float | None
    curves: dict[str, np.ndarray] | None
    trials: tuple[Trial, ...]
    #: The graded trial's rungs (robustness.py's GRADES), None where it was not measured.
    graded: tuple[Rung, ...] | None = None


@dataclass(frozen=True)
class Rung:
    """One rung of the graded trial: a family of disturbance at one size, played ``plays`` times
    (floors, phases), held ``held`` times; it holds when it held every play."""

    family: str
    size: float
    unit: str
    describe: str
    upright: bool
    walking: bool
    detail: str | None
    plays: int
    held: int

    @property
    def holds(self) -> bool:
        return self.upright and self.walking


@dataclass(frozen=True)
class ArmAssessed:
    arm: str
    runs: int
    found: tuple[Assessed, ...]  # current assessments, by run
    missing: tuple[int, ...]  # runs with none
    stale: tuple[int, ...]  # runs whose assessment is of another gait, scoring or format
    walk: Assessed | None = None  # the arm's best walk (which may be no run's best gait), if kept
    #: What the arm's backend declares its assessments keep (None: the sections show no realism).
    assessment: Assessment | None = None

    @property
    def measured(self) -> tuple[Assessed, ...]:
        return tuple(a for a in self.found if a.gait == "measured")

    @property
    def best(self) -> Assessed | None:
        """The measured gait of the best fitness (the arm's best of its runs' bests)."""
        measured = self.measured
        return min(measured, key=lambda a: (a.fitness, a.run)) if measured else None


def load_assessed(arm: ArmRecord) -> ArmAssessed | None:
    """The kept assessments of ``arm``'s runs; None for an arm whose backend measures no gaits."""
    declared = assessing(arm.backend)
    if declared is None:
        return None
    found, missing, stale = [], [], []
    for run, record in zip(arm.numbers, arm.runs, strict=True):
        path = assessment_path(arm.path, run)
        if not path.exists():
            missing.append(run)
            continue
        kept = _read(path, arm)
        best = _best_json(arm, run)
        expected = (
            FORMAT,
            arm.backend_version,
            best.get("generation"),
            best.get("genome"),
            best.get("fitness"),
        )
        if kept_key(kept) != expected:
            stale.append(run)
            continue
        found.append(_assessed(kept, run, record.walk, path, arm, declared))
    walk = None
    walk_path = best_walk_path(arm.path, arm.window)
    if walk_path.exists():
        kept = _read(walk_path, arm)
        run = kept.get("run")
        if kept.get("format") == FORMAT and kept.get("backend_version") == arm.backend_version:
            if not isinstance(run, int) or isinstance(run, bool):
                raise ReportError(f"{walk_path}: run: not a run number; {_again(arm)}")
            walk = _assessed(kept, run, True, walk_path, arm, declared)
    return ArmAssessed(arm.name, len(arm.runs), tuple(found), tuple(missing), tuple(stale), walk, declared)


def _again(arm: ArmRecord) -> str:
    window = f" --runs {arm.window}" if arm.window else ""
    return f"measure it again with: gaitgram report --assess{window} {arm.path}"


def _read(path: Any, arm: ArmRecord) -> dict[str, Any]:
    try:
        return jsonio.read_object(path, "an assessment of a gait")
    except jsonio.ObjectError as error:
        damaged = "the file was edited or damaged: " if error.damaged else ""
        raise ReportError(f"{error}; {damaged}{_again(arm)}") from None


def _best_json(arm: ArmRecord, run: int) -> dict[str, Any]:
    """``best.json`` (the report's records read and checked it already)."""
    return jsonio.read_object(run_path(arm.path, run) / BEST)


def _number(value: Any) -> bool:
    """A finite number (a kept file holds null for no value, never NaN or infinity)."""
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _count(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _assessed(
    kept: dict[str, Any], run: int, walk: bool | None, path: Any, arm: ArmRecord, declared: Assessment
) -> Assessed:
    """A kept assessment, checked field by field against what the backend ``declared`` it keeps (a
    number may be null: no value)."""

    def damaged(what: str) -> ReportError:
        return ReportError(f"{path}: {what}; the file was edited or damaged: {_again(arm)}")

    gait = kept.get("gait")
    if gait not in ("measured", "falls", "invalid"):
        raise damaged(f"gait: {gait!r} is not measured, falls or invalid")
    realism = kept.get("realism")
    measures = scores = curves = None
    distance = None
    if gait == "measured":
        if not isinstance(realism, dict):
            raise damaged("realism: missing")
        measures, scores = realism.get("measures"), realism.get("scores")
        for name, table in (("measures", measures), ("scores", scores)):
            if not isinstance(table, dict) or not all(v is None or _number(v) for v in table.values()):
                raise damaged(f"realism.{name}: not a table of numbers")
        if set(scores) != set(declared.scored):
            raise damaged(f"realism.scores: not the scores of {', '.join(declared.scored)}")
        measures = {k: math.nan if v is None else float(v) for k, v in measures.items()}
        scores = {k: math.nan if v is None else float(v) for k, v in scores.items()}
        distance = realism.get("distance")
        if not _number(distance) or not math.isfinite(distance):
            raise damaged("realism.distance: not a finite number")
        raw = realism.get("curves")
        names = [curve.name for curve in declared.curves]
        if not isinstance(raw, dict) or set(raw) != set(names):
            raise damaged(f"realism.curves: not the curves {', '.join(names)}")
        curves = {}
        for name in names:
            values = raw[name]
            if not isinstance(values, list) or not values or not all(_number(v) for v in values):
                raise damaged(f"realism.curves.{name}: not a list of numbers")
            curves[name] = np.array(values, dtype=float)
    trials = kept.get("trials")
    if not isinstance(trials, list):
        raise damaged("trials: not a list")
    checked = []
    for trial in trials:
        if not (
            isinstance(trial, dict)
            and isinstance(trial.get("disturbance"), str)
            and isinstance(trial.get("describe"), str)
            and isinstance(trial.get("upright"), bool)
            and isinstance(trial.get("walking"), bool)
            and (trial.get("detail") is None or isinstance(trial.get("detail"), str))
            and _count(trial.get("floors"))
            and _count(trial.get("held"))
            and trial["floors"] > 0
            and trial["held"] <= trial["floors"]
            and (trial["held"] == trial["floors"]) == (trial["upright"] and trial["walking"])
        ):
            raise damaged(
                "trials: a trial is not a disturbance, its description, upright, walking, detail, "
                "floors and held (no more than floors, all of them when it holds)"
            )
        checked.append(
            Trial(
                trial["disturbance"],
                trial["describe"],
                trial["upright"],
                trial["walking"],
                trial["detail"],
                trial["floors"],
                trial["held"],
            )
        )
    graded = None if "graded" not in kept else _graded(kept["graded"], damaged)
    fitness = kept.get("fitness")
    if not _number(fitness):
        raise damaged("fitness: not a number")
    genome = _genome(kept.get("genome"))
    if genome is None:
        raise damaged("genome: not a genome (a list of codons, or of genes that are lists of them)")
    return Assessed(
        run,
        genome,
        float(fitness),
        walk,
        gait,
        measures,
        scores,
        distance,
        curves,
        tuple(checked),
        graded,
    )


def _graded(rungs: Any, damaged: Any) -> tuple[Rung, ...]:
    """The graded trial's rungs as kept, checked field by field."""
    if not isinstance(rungs, list):
        raise damaged("graded: not a list")
    checked = []
    for rung in rungs:
        if not (
            isinstance(rung, dict)
            and isinstance(rung.get("family"), str)
            and _number(rung.get("size"))
            and math.isfinite(rung["size"])
            and isinstance(rung.get("unit"), str)
            and isinstance(rung.get("describe"), str)
            and isinstance(rung.get("upright"), bool)
            and isinstance(rung.get("walking"), bool)
            and (rung.get("detail") is None or isinstance(rung.get("detail"), str))
            and _count(rung.get("plays"))
            and _count(rung.get("held"))
            and rung["plays"] > 0
            and rung["held"] <= rung["plays"]
            and (rung["held"] == rung["plays"]) == (rung["upright"] and rung["walking"])
        ):
            raise damaged(
                "graded: a rung is not a family, size, unit, description, upright, walking, detail, "
                "plays and held (no more than plays, all of them when it holds)"
            )
        checked.append(
            Rung(
                rung["family"],
                float(rung["size"]),
                rung["unit"],
                rung["describe"],
                rung["upright"],
                rung["walking"],
                rung["detail"],
                rung["plays"],
                rung["held"],
            )
        )
    return tuple(checked)


# ---- figure data -------------------------------------------------------------------------------


@dataclass(frozen=True)
class ArmCurves:
    arm: str
    colour: int  # the arm's index in the report: its colour in every figure
    best: dict[str, np.ndarray] | None  # the arm's best gait's curves
    others: tuple[dict[str, np.ndarray], ...]  # its other runs' best gaits'


@dataclass(frozen=True)
class RealismCurves:
    """Each arm's best gaits' curves over one stride (on the horse, the fetlock and protraction
    curves from the hoof's footfall), on the reference's mean and SD."""

    arms: tuple[ArmCurves, ...]
    title: str
    reference: tuple[ReferenceCurve, ...]


# ---- the sections ------------------------------------------------------------------------------

ASSESS_TEXT = (
    "These need simulation, kept in each run directory: `gaitgram report --assess` measures "
    f"each run's best gait once ({in_run(ASSESSMENT)}); every report after reads them."
)


def _pending_note(assessed: ArmAssessed) -> str | None:
    parts = []
    if assessed.missing:
        parts.append(f"{len(assessed.missing)} not measured yet")
    if assessed.stale:
        parts.append(f"{len(assessed.stale)} measured on another gait or scoring (stale)")
    if not parts:
        return None
    return (
        f"**{escape.markdown(assessed.arm)}**: of {assessed.runs} runs' best gaits, {' and '.join(parts)}: "
        "`gaitgram report --assess` measures them"
    )


def _value(gait: Assessed, key: str) -> float:
    """A measure of the gait: a kept one, or ``CURVE_max`` / ``CURVE_min``, an extreme of a kept curve."""
    assert gait.measures is not None
    assert gait.curves is not None
    for which in ("max", "min"):
        curve = gait.curves.get(key.removesuffix(f"_{which}")) if key.endswith(f"_{which}") else None
        if curve is not None:
            return float(np.max(curve) if which == "max" else np.min(curve))
    return gait.measures.get(key, math.nan)


def _median(values: Sequence[float]) -> float | None:
    finite = [v for v in values if math.isfinite(v)]
    return float(np.median(finite)) if finite else None


def realism_section(arms: Sequence[ArmRecord], assessed: Sequence[ArmAssessed]) -> Section | None:
    """The realism section of the arms whose gaits were measured (``assessed``, in the report's
    order), as their backend declares it; None if none."""
    declared = _declared(assessed)
    if declared is None:
        return None
    title, scope = declared.title, "each run's best gait"
    notes = tuple(n for n in map(_pending_note, assessed) if n)
    measured = [a for a in assessed if a.measured]
    if not measured:
        return Section("realism", title, scope, text="Not measured yet. " + ASSESS_TEXT, notes=notes)
    text = f"{declared.text} {ASSESS_TEXT}"
    columns = [
        Column("measure", "measure", Kind.TEXT),
        Column("real", "real walks"),
        Column("real_spread", "real walks: spread", Kind.TEXT),
    ]
    columns += [Column(a.arm, a.arm) for a in measured]
    rows = tuple(
        (
            row.label,
            row.value,
            row.spread,
            *(_median([_value(g, row.key) for g in a.measured]) for a in measured),
        )
        for row in declared.measures
    )
    measures = Table("measures", tuple(columns), rows, "medians over each arm's runs' best gaits")
    distance_columns = (
        Column("arm", "arm", Kind.TEXT),
        Column("runs", "runs", Kind.COUNT),
        Column("measured", "measured", Kind.COUNT),
        Column("falls", "fall or do not step", Kind.COUNT),
        Column("median_distance", "median distance [95 % CI]", Kind.INTERVAL),
        Column("mean_distance", "mean distance"),
        Column("best_distance", "closest"),
        Column("best_gait_distance", "best gait's"),
    )
    distance_rows = []
    for a in assessed:
        values = np.array([g.distance for g in a.measured], dtype=float)
        best = a.best
        distance_rows.append(
            (
                a.arm,
                a.runs,
                len(values),
                sum(g.gait != "measured" for g in a.found),
                (float(np.median(values)), *bootstrap_median_ci(values))
                if len(values)
                else (None, None, None),
                float(values.mean()) if len(values) else None,
                float(values.min()) if len(values) else None,
                best.distance if best else None,
            )
        )
    distance = Table(
        "distance",
        distance_columns,
        tuple(distance_rows),
        "realism distance of each run's best gait (lower is closer to the real walks); best gait's: the "
        "arm's best by fitness",
    )
    score_columns = (
        Column("arm", "arm", Kind.TEXT),
        *(Column(name, name.replace("_", " ")) for name in declared.scored),
    )
    scores = Table(
        "scores",
        score_columns,
        tuple(
            (a.arm, *(_median([g.scores[s] for g in a.measured if g.scores]) for s in declared.scored))
            for a in measured
        ),
        "median distance per measure, in the real walks' spread (each term of the realism distance)",
    )
    tests = (
        RankTests("realism distance", compare({a.arm: [g.distance for g in a.measured] for a in measured})),
    )
    figure = Figure(
        "realism",
        "Each arm's best gait (thick) and its other runs' best gaits (thin) over one stride from the hoof's "
        "footfall, on the real walks' mean and SD (grey)",
        _curves(arms, measured, declared.figure, declared.curves),
        ("png", "svg"),
    )
    falls = [
        f"**{escape.markdown(a.arm)}**: runs "
        f"{', '.join(str(g.run) for g in a.found if g.gait != 'measured')} hand back "
        "a best gait that falls or does not step: nothing to measure"
        for a in assessed
        if any(g.gait != "measured" for g in a.found)
    ]
    return Section(
        "realism",
        title,
        scope,
        text=text,
        tables=(measures, distance, scores),
        tests=tests,
        notes=(*notes, *falls),
        figures=(figure,),
    )


def _declared(assessed: Sequence[ArmAssessed]) -> Assessment | None:
    """What the arms' backend declares its assessments keep (a report's arms share one backend)."""
    return next((a.assessment for a in assessed if a.assessment is not None), None)


def _curves(
    arms: Sequence[ArmRecord],
    assessed: Sequence[ArmAssessed],
    title: str,
    reference: tuple[ReferenceCurve, ...],
    highlight: dict[str, Assessed | None] | None = None,
) -> RealismCurves:
    """Each arm's curves on the ``reference``'s: ``highlight``'s gait thick (default: the arm's best
    by fitness)."""
    index = {a.name: k for k, a in enumerate(arms)}
    chosen = {a.arm: (highlight or {}).get(a.arm, a.best) for a in assessed}
    return RealismCurves(
        tuple(
            ArmCurves(
                a.arm,
                index.get(a.arm, k),
                chosen[a.arm].curves if chosen[a.arm] else None,
                tuple(g.curves for g in a.measured if g is not chosen[a.arm] and g.curves is not None),
            )
            for k, a in enumerate(assessed)
        ),
        title,
        reference,
    )


def arm_curves_figure(
    arms: Sequence[ArmRecord], assessed: ArmAssessed, walk: Genome | None = None
) -> Figure | None:
    """One arm's best gaits' curves on the real walks' band, to show beside its animated ``walk``
    (a genome): thick, that walk's, if it is a run's best gait; else the arm's best by fitness."""
    if not assessed.measured or assessed.assessment is None:
        return None
    kept_walk = [assessed.walk] if assessed.walk and assessed.walk.gait == "measured" else []
    same = [g for g in (*assessed.measured, *kept_walk) if walk is not None and g.genome == tuple(walk)]
    shown = same[0] if same else assessed.best
    assert shown is not None
    if same and shown is assessed.walk:
        thick = f"thick: the walk beside (from run {shown.run}'s last population)"
    elif same:
        thick = f"thick: the walk beside, run {shown.run}'s best gait"
    else:
        thick = f"thick: run {shown.run}'s, the best by fitness (the walk beside is not a run's best gait)"
    caption = (
        f"{escape.markdown(assessed.arm)}: its runs' best gaits over one stride beside the real walks "
        "(grey: mean and SD); " + thick
    )
    title = f"{assessed.arm} beside the real walks"
    data = _curves(arms, [assessed], title, assessed.assessment.curves, {assessed.arm: shown})
    return Figure(figure_name("curves", assessed.arm, ""), caption, data, ("png",))


def measured_nothing(assessed: Sequence[ArmAssessed]) -> bool:
    """No gait of any arm measured yet (none kept, not even a stale one): the realism and
    robustness sections would each say only that."""
    return bool(assessed) and not any(a.found or a.stale or a.walk for a in assessed)


def unmeasured_section(assessed: Sequence[ArmAssessed]) -> Section:
    """One sentence in place of the realism, robustness and graded robustness sections of arms
    none of whose gaits was measured yet."""
    declared = _declared(assessed)
    realism = f"{declared.title.lower()}, " if declared is not None else ""
    return Section(
        "unmeasured",
        "Not measured yet",
        "each run's best gait",
        text=(
            f"The sections on {realism}robustness and graded robustness need simulation: "
            f"`gaitgram report --assess` measures each run's best gait once ({in_run(ASSESSMENT)}), "
            "and every report after reads them."
        ),
    )


def robustness_section(arms: Sequence[ArmRecord], assessed: Sequence[ArmAssessed]) -> Section | None:
    """The robustness section of the arms whose gaits were measured; None if none."""
    if not assessed:
        return None
    declared = _declared(assessed)
    failed_terms = declared.failed_terms if declared is not None else ""
    title, scope = "Robust, not only sustained", "each run's best gait"
    notes = [n for n in map(_pending_note, assessed) if n]
    tried = [a for a in assessed if any(g.trials for g in a.found)]
    if not tried:
        return Section(
            "robustness", title, scope, text="Not measured yet. " + ASSESS_TEXT, notes=tuple(notes)
        )
    disturbances: dict[str, str] = {}
    for a in tried:
        for g in a.found:
            for t in g.trials:
                disturbances.setdefault(t.disturbance, t.describe)
    names = list(disturbances)
    floored = [n for n in names if any((t := _trial(g, n)) and t.floors > 1 for a in tried for g in a.found)]
    text = (
        "Each run's best gait played from the standing horse to the horizon under each disturbance: "
        + "; ".join(f"**{escape.markdown(n)}**: {escape.markdown(d)}" for n, d in disturbances.items())
        + ". A gait **holds** when it stays upright for the whole horizon and is walking again by the walk "
        "criterion over the horizon's last cycles (docs/study.md)"
        + (", on every floor where it is played on several" if floored else "")
        + ". Shares are of the runs' best gaits measured; *walk*: the best gait is a walk undisturbed"
        + (
            "; *floors held*: the mean share of the floors on which a gait holds (one seeded floor is "
            "one sample of uneven ground)"
            if floored
            else ""
        )
        + ". "
        + ASSESS_TEXT
    )
    columns = [
        Column("arm", "arm", Kind.TEXT),
        Column("measured", "measured", Kind.COUNT),
        Column("walk", "walk", Kind.SHARE),
        *(Column(f"holds_{n}", f"holds: {n}", Kind.SHARE) for n in names),
        *(Column(f"floors_held_{n}", f"{n}: floors held", Kind.SHARE) for n in floored),
        Column("holds_all", "holds all", Kind.SHARE),
        Column("walk_holds_all", "walk, holds all", Kind.SHARE),
    ]
    rows = []
    not_held: dict[str, dict[str, list[float]]] = {n: {} for n in floored}
    for a in assessed:
        found = a.found
        n = len(found)

        def share(flags: Sequence[bool], n: int = n) -> float | None:
            return sum(flags) / n if n else None

        holds = {t: [_holds(g, t) for g in found] for t in names}
        held = {t: [_floors_held(g, t) for g in found] for t in floored}
        every = [all(_holds(g, t) for t in names) for g in found]
        walks = [g.walk for g in found]
        rows.append(
            (
                a.arm,
                n,
                None if any(w is None for w in walks) else share([bool(w) for w in walks]),
                *(share(holds[t]) for t in names),
                *(sum(held[t]) / n if n else None for t in floored),
                share(every),
                None
                if any(w is None for w in walks)
                else share([bool(w) and e for w, e in zip(walks, every, strict=True)]),
            )
        )
        for t in floored:
            not_held[t][a.arm] = [1.0 - h for h in held[t]]
        failures = []
        for t in names:
            trials = [trial for g in found if (trial := _trial(g, t))]
            fell = sum(not trial.upright for trial in trials)
            stopped = [trial for trial in trials if trial.upright and not trial.walking]
            where = " on some floor" if t in floored else ""
            said = [f"{fell} fell{where}"] if fell else []
            if stopped:
                terms = _failing_terms(stopped, failed_terms)
                first = " on the first floor not held" if t in floored else ""
                why = f" (walk terms failing{first}: {terms})" if terms else ""
                said.append(f"{len(stopped)} stayed up but were not walking again{where}{why}")
            if said:
                failures.append(f"{escape.markdown(t)}: " + ", ".join(said))
        if failures:
            notes.append(f"**{escape.markdown(a.arm)}**: " + "; ".join(failures))
    table = Table(
        "shares", tuple(columns), tuple(rows), "share of the runs' best gaits that stay upright and walking"
    )
    tests = tuple(
        RankTests(f"{t}: share of floors not held", compare(not_held[t]))
        for t in floored
        if sum(bool(v) for v in not_held[t].values()) >= 2
    )
    return Section("robustness", title, scope, text=text, tables=(table,), tests=tests, notes=tuple(notes))


def _failing_terms(trials: Sequence[Any], prefix: str) -> str:
    """How many of ``trials`` fail each walk term (on the first floor not held, for floors), most
    first: ``speed 28, footfalls 17``, read from each detail, where the terms follow ``prefix``
    (the backend's ``Assessment.failed_terms``; empty: none is counted); what a detail does not
    say is not counted."""
    if not prefix:
        return ""
    pattern = re.compile(re.escape(prefix) + r"([a-z_]+(?:, [a-z_]+)*)")
    counts: dict[str, int] = {}
    for trial in trials:
        found = pattern.search(trial.detail or "")
        for term in found.group(1).split(", ") if found else ():
            counts[term] = counts.get(term, 0) + 1
    return ", ".join(f"{term} {n}" for term, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))


def _trial(gait: Assessed, name: str) -> Any:
    return next((t for t in gait.trials if t.disturbance == name), None)


def _holds(gait: Assessed, name: str) -> bool:
    trial = _trial(gait, name)
    return bool(trial and trial.holds)


def _floors_held(gait: Assessed, name: str) -> float:
    """The share of its floors a gait holds on under ``name`` (none when it was not played)."""
    trial = _trial(gait, name)
    return trial.held / trial.floors if trial else 0.0


__all__ = [
    "ASSESSMENT",
    "ArmAssessed",
    "Assessed",
    "RealismCurves",
    "arm_curves_figure",
    "load_assessed",
    "realism_section",
    "robustness_section",
]


def _integer(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _genome(value: Any) -> Genome | None:
    """A kept genome as its representation holds it (every representation's JSON is a list of
    ints, or a list of genes that are lists of ints: GE, πGE and CFG-GP, or SGE and DSGE), None if
    it is neither."""
    if not isinstance(value, list):
        return None
    if all(_integer(c) for c in value):
        return tuple(value)
    if all(isinstance(gene, list) and all(_integer(c) for c in gene) for gene in value):
        return tuple(tuple(gene) for gene in value)
    return None
