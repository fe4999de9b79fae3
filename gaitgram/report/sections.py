"""A study report as data: what every format shows, computed once, drawn by the renderers.

A :class:`StudyReport` holds the per-arm summaries (:class:`ArmSummary`), the
rank tests (:class:`~gaitgram.report.stats.Comparison`) and the report's
**sections** (:class:`Section`) in document order: the summary, then further
sections such as the fronts and repertoires of ``nsga2`` and ``map-elites`` arms
or the animated gaits. A section is plain data: a title, text, named
:class:`Table` s (columns of a :class:`Kind`, rows of raw values), rank tests,
notes and named :class:`Figure` s (the data a figure is drawn from, or a gait
to animate).

**Adding a section** (issue 26's realism and robustness, say) is building one
more :class:`Section` and putting it in :attr:`StudyReport.sections`: every
renderer draws every section generically. Markdown and HTML draw all of it;
LaTeX a booktabs table per table; CSV a file per table
(``SECTION-TABLE.csv``); JSON the tables and tests under ``sections``; the
figures are written as files and embedded in the HTML (a new kind of figure
data needs a drawer in :mod:`gaitgram.report.figures`). The summary itself is
drawn generically in Markdown and HTML, and in its committed layouts in
``summary.csv``, ``tables.tex`` and ``summary.json``, which studies in
docs/results keep byte for byte.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram.backends.api import Verdict
from gaitgram.ge.registry import DEFAULT_REPRESENTATION, Genome
from gaitgram.report import escape
from gaitgram.report.records import ArmRecord, ReportError, check_comparable, scoring_listing
from gaitgram.report.stats import (
    Comparison,
    bootstrap_median_ci,
    compare,
    compare_rates,
    compare_spreads,
    wilson_interval,
)
from gaitgram.strategies.kept import Front, Repertoire

# ---- the building blocks of a section --------------------------------------------------------


class Kind(Enum):
    """What a column's values are, which says how each format writes them: CSV and JSON keep the
    raw values, Markdown, LaTeX and HTML format them (:func:`cell_text`)."""

    TEXT = "text"
    COUNT = "count"  # a whole number
    VALUE = "value"  # four significant digits
    P = "p"  # a p-value: four decimals, "< 0.0001"
    SHARE = "share"  # a share (0..1), in whole percent
    A12 = "a12"  # three decimals
    INTERVAL = "interval"  # (value, low, high): "value [low, high]"
    SHARE_INTERVAL = "share interval"  # (share, low, high), in whole percent

    @property
    def interval(self) -> bool:
        """Whether a value is (value, low, high): CSV writes three columns, HTML sorts by the first."""
        return self in (Kind.INTERVAL, Kind.SHARE_INTERVAL)


def value_text(value: float | None, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    return f"{value:.{digits}g}"


def p_text(value: float) -> str:
    if math.isnan(value):
        return "n/a"
    return "< 0.0001" if value < 1e-4 else f"{value:.4f}"


def share_text(value: float | None) -> str:
    """A share in whole percent, except that a small share never reads as none."""
    if value is None:
        return "n/a"
    if 0 < value < 0.01:
        return "< 0.1%" if value < 0.001 else f"{value:.1%}"
    return f"{value:.0%}"


def cell_text(kind: Kind, value: Any) -> str:
    """A table cell as Markdown, LaTeX and HTML show it."""
    if kind is Kind.TEXT:
        return str(value)
    if kind is Kind.COUNT:
        return "n/a" if value is None else str(value)
    if kind is Kind.P:
        return p_text(value)
    if kind is Kind.SHARE:
        return share_text(value)
    if kind is Kind.A12:
        return f"{value:.3f}"
    if kind is Kind.INTERVAL:
        middle, low, high = value
        return f"{value_text(middle)} [{value_text(low)}, {value_text(high)}]"
    if kind is Kind.SHARE_INTERVAL:
        if value is None:
            return "n/a"
        share, low, high = value
        return f"{share_text(share)} [{share_text(low)}, {share_text(high)}]"
    return value_text(value)


@dataclass(frozen=True)
class Column:
    key: str  # the CSV header and JSON key
    header: str  # the Markdown, LaTeX and HTML header
    kind: Kind = Kind.VALUE


@dataclass(frozen=True)
class Table:
    name: str  # names its CSV file and JSON key; unique within its section
    columns: tuple[Column, ...]
    rows: tuple[tuple[Any, ...], ...]  # raw values (None: no value), one per column
    caption: str = ""


@dataclass(frozen=True)
class RankTests:
    """The rank tests of one measure, one value per run (e.g. each run's final best)."""

    label: str  # "final best"
    comparison: Comparison

    def table(self) -> Table:
        return Table(
            "pairs",
            (
                Column("pair", "pair", Kind.TEXT),
                Column("u", "U"),
                Column("p", "p", Kind.P),
                Column("p_holm", "p (Holm)", Kind.P),
                Column("a12", "A12", Kind.A12),
                Column("effect", "effect", Kind.TEXT),
            ),
            tuple(
                (f"{p.first} vs {p.second}", p.u, p.p_value, p.p_holm, p.a12, p.magnitude)
                for p in self.comparison.pairs
            ),
        )


@dataclass(frozen=True)
class Figure:
    """A figure the report writes as files (``NAME.png``, ...) and embeds in its HTML; ``data`` is
    what :mod:`gaitgram.report.figures` draws (or, for a ``.gif``, the gait the gallery animates)."""

    name: str
    caption: str
    data: Any
    formats: tuple[str, ...] = ("png",)

    @property
    def files(self) -> tuple[str, ...]:
        return tuple(f"{self.name}.{suffix}" for suffix in self.formats)


def figure_name(kind: str, arm: str, suffix: str = ".png") -> str:
    """A file name for an arm's figure (arm names may be paths)."""
    return f"{kind}-{re.sub(r'[^A-Za-z0-9_.-]+', '_', arm).strip('_.') or 'arm'}{suffix}"


@dataclass(frozen=True)
class Section:
    """One part of the report, drawn by every renderer (see the module's docstring)."""

    name: str  # an identifier: names the section in JSON and its tables' CSV files
    title: str = ""  # none: the section continues the one before (the summary has none)
    scope: str = ""  # what the section covers, after the title: "final generation"
    text: str = ""  # a paragraph before the tables (Markdown inline: *em*, **strong**, `code`)
    tables: tuple[Table, ...] = ()
    tests: tuple[RankTests, ...] = ()
    notes: tuple[str, ...] = ()  # a list after the tests (Markdown inline)
    footnote: str = ""
    figures: tuple[Figure, ...] = ()


# ---- figure data -----------------------------------------------------------------------------


@dataclass(frozen=True)
class Band:
    """A measure by generation: the mean over runs and the half-width of its 95 % confidence
    interval (t interval of the mean; None for one run)."""

    mean: np.ndarray
    half: np.ndarray | None

    @classmethod
    def of(cls, values: np.ndarray) -> Band:
        """From ``values[run, generation]``."""
        from scipy import stats

        runs = values.shape[0]
        mean = values.mean(axis=0)
        if runs < 2:
            return cls(mean, None)
        sem = values.std(axis=0, ddof=1) / math.sqrt(runs)
        return cls(mean, sem * stats.t.ppf(0.975, runs - 1))


@dataclass(frozen=True)
class Curves:
    """One arm's convergence: best and average fitness by generation."""

    arm: str
    runs: int
    best: Band
    average: Band


@dataclass(frozen=True)
class Convergence:
    arms: tuple[Curves, ...]


@dataclass(frozen=True)
class Fronts:
    """An arm's final Pareto fronts, one per run that keeps one."""

    arm: str
    fronts: tuple[Front, ...]


@dataclass(frozen=True)
class RepertoireMap:
    """An arm's merged repertoire, with the cells the report animates outlined."""

    arm: str
    repertoire: Repertoire
    chosen: tuple[tuple[int, ...], ...]


@dataclass(frozen=True)
class Gait:
    """A gait to animate: a genome, drawn through its run directory's own pipeline."""

    run_directory: Path
    genome: Genome


# ---- the summary ----------------------------------------------------------------------------


@dataclass(frozen=True)
class ArmSummary:
    name: str
    strategy: str
    runs: int
    mean_best: float
    sd_best: float
    median_best: float
    median_best_ci: tuple[float, float]
    mean_average: float
    sd_average: float
    mean_average_viable: float
    unviable_share: float
    walk_rate: float | None
    walk_held_rate: float | None
    walks: int | None = None  # runs whose best gait is a walk
    walk_rate_ci: tuple[float, float] | None = None  # Wilson's 95 % interval
    representation: str = DEFAULT_REPRESENTATION  # what the runs' genomes are

    @property
    def walk_rate_cell(self) -> tuple[float, float, float] | None:
        if self.walk_rate is None or self.walk_rate_ci is None:
            return None
        return (self.walk_rate, *self.walk_rate_ci)


def summarise(arm: ArmRecord) -> ArmSummary:
    best, average = arm.final_best, arm.final_average
    viable = arm.final_average_viable
    return ArmSummary(
        arm.name,
        arm.strategy,
        len(arm.runs),
        float(best.mean()),
        float(best.std(ddof=1)) if len(best) > 1 else math.nan,
        float(np.median(best)),
        bootstrap_median_ci(best),
        float(average.mean()),
        float(average.std(ddof=1)) if len(average) > 1 else math.nan,
        float(np.nanmean(viable)) if np.isfinite(viable).any() else math.nan,
        float(arm.final_unviable_share.mean()),
        arm.walk_rate,
        arm.walk_held_rate,
        arm.walks,
        None if arm.walks is None else wilson_interval(arm.walks, len(arm.runs)),
        arm.representation,
    )


SUMMARY_TEXT = (
    "Final generation, over runs. Fitness is minimised. *Average* is the population's mean over "
    "every individual, unviable gaits at their score (the paper's Avg. Avg.); *viable average* "
    "leaves them out. *Walk rate*: the share of runs whose best gait is a walk, with Wilson's 95 % "
    "interval; *walk held*: the "
    "share whose final population (a `nsga2` run's Pareto front, a `map-elites` run's "
    "repertoire) holds one."
)
A12_NOTE = (
    "A12 is the probability that a run of the first arm ends with a lower (better) value than a "
    "run of the second (0.5: no difference; 0.56, 0.64 and 0.71 mark small, medium and large "
    "effects). p-values are two-sided Mann-Whitney U, Holm-adjusted over the pairs."
)
ONE_ARM_NOTE = (
    "One arm: the rank tests (Kruskal-Wallis, Mann-Whitney U, A12), which compare arms, are left "
    "out; report two or more run directories, or a study's arms, together to compare them."
)


def names_representations(summaries: Sequence[ArmSummary]) -> bool:
    """Whether the report names each arm's representation: when any arm's is not GE (a report of GE
    arms alone reads as it always did)."""
    return any(s.representation != DEFAULT_REPRESENTATION for s in summaries)


def summary_table(summaries: Sequence[ArmSummary]) -> Table:
    """The paper's Table 4/5 layout, with the statistics it did not compute; each arm's
    representation beside its name when not every arm is GE."""
    value = Kind.VALUE
    table = Table(
        "summary",
        (
            Column("arm", "arm", Kind.TEXT),
            Column("runs", "runs", Kind.COUNT),
            Column("mean_best", "avg. best", value),
            Column("sd_best", "SD", value),
            Column("mean_average", "avg. average", value),
            Column("sd_average", "SD", value),
            Column("median_best", "median best [95 % CI]", Kind.INTERVAL),
            Column("mean_average_viable", "viable average", value),
            Column("unviable_share", "unviable", Kind.SHARE),
            Column("walk_rate", "walk rate [95 % CI]", Kind.SHARE_INTERVAL),
            Column("walk_held_rate", "walk held", Kind.SHARE),
        ),
        tuple(
            (
                s.name,
                s.runs,
                s.mean_best,
                s.sd_best,
                s.mean_average,
                s.sd_average,
                (s.median_best, *s.median_best_ci),
                s.mean_average_viable,
                s.unviable_share,
                s.walk_rate_cell,
                s.walk_held_rate,
            )
            for s in summaries
        ),
    )
    if not names_representations(summaries):
        return table
    column = Column("representation", "representation", Kind.TEXT)
    return replace(
        table,
        columns=(table.columns[0], column, *table.columns[1:]),
        rows=tuple(
            (row[0], s.representation, *row[1:]) for row, s in zip(table.rows, summaries, strict=True)
        ),
    )


def convergence(arms: Sequence[ArmRecord]) -> Convergence:
    return Convergence(
        tuple(
            Curves(
                arm.name,
                len(arm.runs),
                Band.of(np.array([r.best for r in arm.runs])),
                Band.of(np.array([r.average for r in arm.runs])),
            )
            for arm in arms
        )
    )


CONVERGENCE_CAPTION = (
    "Best (left) and average (right) fitness by generation: the mean over runs with its 95 % "
    "confidence band, as the paper's Figures 3, 4 and 6 (lower is better)."
)


# ---- fronts and repertoires ------------------------------------------------------------------


def saturation(front_sizes: list[int], population: int) -> str:
    """A warning when the whole population is non-dominated, common with three or more
    objectives: Pareto rank then tells no gait from another and NSGA-II selects by crowding
    alone, spreading the population along the front instead of pressing it forward."""
    whole = sum(size >= population for size in front_sizes)
    if not whole:
        return ""
    return (
        f". In {whole} of {len(front_sizes)} runs the final front is the whole population "
        f"({population}): rank no longer selects, crowding alone does; fewer objectives "
        "(strategy setting `objectives`) restore the pressure"
    )


def fronts_section(
    arms: Sequence[ArmRecord],
    fronts: Mapping[str, Sequence[Front]],
    repertoires: Mapping[str, Repertoire | None],
    outlined: Mapping[str, Sequence[tuple[int, ...]]],
) -> Section | None:
    """The fronts of ``nsga2`` arms and the repertoires of ``map-elites`` arms, with their figures
    (the fronts' first); ``outlined``: the cells of each repertoire the report animates. None if no
    arm keeps either."""
    notes: list[str] = []
    front_figures: list[Figure] = []
    archive_figures: list[Figure] = []
    for arm in arms:
        found, repertoire = fronts[arm.name], repertoires[arm.name]
        if found:
            name = figure_name("front", arm.name, "")
            names = found[0].objectives
            best = np.mean([f.points.min(axis=0) for f in found if len(f.points)], axis=0)
            sizes = [len(f.points) for f in found]
            means = zip(names, np.atleast_1d(best), strict=False)
            notes.append(
                f"**{escape.markdown(arm.name)}** ({escape.markdown(name)}.png): Pareto fronts of "
                f"{np.mean(sizes):.1f} gaits on average; the best of each objective, mean over runs: "
                + ", ".join(f"{escape.markdown(n)} {value_text(v)}" for n, v in means)
                + saturation(sizes, arm.population)
            )
            caption = (
                f"{escape.markdown(arm.name)}: the final Pareto fronts, objectives pairwise (lower is better)"
            )
            front_figures.append(Figure(name, caption, Fronts(arm.name, tuple(found))))
        if repertoire is not None:
            name = figure_name("archive", arm.name, "")
            together = int(np.sum(repertoire.coverage > 0))
            described = ", ".join(escape.markdown(d["name"]) for d in repertoire.descriptors)
            notes.append(
                f"**{escape.markdown(arm.name)}** ({escape.markdown(name)}.png): "
                f"{described}; {np.mean(repertoire.filled):.1f} of "
                f"{repertoire.cells} cells filled per run, {together} by the runs together; best gait "
                f"{value_text(float(np.nanmin(repertoire.best)))}"
            )
            caption = (
                f"{escape.markdown(arm.name)}: the best fitness in each cell, and how many runs filled it"
            )
            cells = tuple(outlined.get(arm.name, ()))
            archive_figures.append(Figure(name, caption, RepertoireMap(arm.name, repertoire, cells)))
    if not notes:
        return None
    figures = (*front_figures, *archive_figures)
    return Section(
        "fronts", "Fronts and repertoires", "final generation", notes=tuple(notes), figures=figures
    )


# ---- where the runs started -------------------------------------------------------------------


START_TEXT = (
    "The best of each run's first generation beside its last: where the search started (from "
    "random derivations, or from another run's population) and what it made of it. A started "
    "arm's first-generation best at or below another arm's final best is that arm's whole search, "
    "saved."
)


def start_section(arms: Sequence[ArmRecord]) -> Section:
    """Each arm's first-generation best and final best, with the rank tests of the first."""
    initial = {arm.name: [float(r.best[0]) for r in arm.runs] for arm in arms}
    table = Table(
        "bests",
        (
            Column("arm", "arm", Kind.TEXT),
            Column("runs", "runs", Kind.COUNT),
            Column("median_initial_best", "median first-generation best [95 % CI]", Kind.INTERVAL),
            Column("median_final_best", "median final best [95 % CI]", Kind.INTERVAL),
        ),
        tuple(
            (
                arm.name,
                len(arm.runs),
                (float(np.median(initial[arm.name])), *bootstrap_median_ci(initial[arm.name])),
                (float(np.median(arm.final_best)), *bootstrap_median_ci(arm.final_best)),
            )
            for arm in arms
        ),
    )
    tests = (RankTests("first-generation best", compare(initial)),)
    return Section("start", "Where the runs started", "generation 0", START_TEXT, (table,), tests)


# ---- how soon a walk is found -----------------------------------------------------------------


FIRST_WALK_TEXT = (
    "The first generation whose population holds a walk (the backend's verdict: each "
    "generation's best candidates are checked over the horizon until one holds): how much search "
    "each arm needed to find one. A run that never finds one counts as one generation after its "
    "last in the rank tests, behind every run that does."
)


def first_walk_section(arms: Sequence[ArmRecord]) -> Section | None:
    """When each arm's runs first held a walk, with the rank tests; None where the records do not
    say (a backend that judges no walks, older runs)."""
    if not arms or any(r.walk_share is None for arm in arms for r in arm.runs):
        return None
    found = {arm.name: [r.first_walk for r in arm.runs] for arm in arms}
    ranked = {arm.name: [arm.generations + 1 if g is None else g for g in found[arm.name]] for arm in arms}
    rows = []
    for arm in arms:
        seen = [g for g in found[arm.name] if g is not None]
        rows.append(
            (
                arm.name,
                len(arm.runs),
                len(seen),
                float(np.median(ranked[arm.name])) if len(seen) * 2 > len(arm.runs) else None,
                min(seen) if seen else None,
                max(seen) if seen else None,
            )
        )
    table = Table(
        "generations",
        (
            Column("arm", "arm", Kind.TEXT),
            Column("runs", "runs", Kind.COUNT),
            Column("found", "runs that found one", Kind.COUNT),
            Column("median_generation", "median generation"),
            Column("earliest", "earliest", Kind.COUNT),
            Column("latest", "latest found", Kind.COUNT),
        ),
        tuple(rows),
        "median over every run (n/a when half or more never found one)",
    )
    tests = (RankTests("generation of the first walk", compare(ranked)),)
    return Section("first-walk", "The first walk", "over generations", FIRST_WALK_TEXT, (table,), tests)


# ---- walk rates and spreads compared ----------------------------------------------------------


WALK_RATES_TEXT = (
    "Whether two arms' walk rates (the share of runs whose best gait is a walk) differ: Fisher's "
    "exact test on each pair's counts, two-sided, Holm-adjusted over the pairs. Small counts "
    "separate only large differences: with 10 runs an arm, 9 walks against 5 is p = 0.14."
)


def walk_rates_section(arms: Sequence[ArmRecord]) -> Section | None:
    """Fisher's exact test of each pair's walk rates; None where walks are not counted."""
    if len(arms) < 2 or any(arm.walks is None for arm in arms):
        return None
    counts = {arm.name: (int(arm.walks or 0), len(arm.runs)) for arm in arms}
    pairs = compare_rates(counts)
    table = Table(
        "pairs",
        (
            Column("pair", "pair", Kind.TEXT),
            Column("walks_first", "walks, first", Kind.TEXT),
            Column("walks_second", "walks, second", Kind.TEXT),
            Column("p", "p", Kind.P),
            Column("p_holm", "p (Holm)", Kind.P),
        ),
        tuple(
            (
                f"{p.first} vs {p.second}",
                "{}/{}".format(*counts[p.first]),
                "{}/{}".format(*counts[p.second]),
                p.p_value,
                p.p_holm,
            )
            for p in pairs
        ),
    )
    return Section("walk-rates", "Walk rates compared", "runs' best gaits", WALK_RATES_TEXT, (table,))


SPREAD_TEXT = (
    "How far apart each arm's runs end: the standard deviation and interquartile range of the "
    "final bests, and whether they differ by Levene's test centred on the median (the "
    "Brown-Forsythe test, robust to the skew of fitness values), over all arms and for each pair, "
    "Holm-adjusted. The largest spread is a finding only where the test separates it."
)


def spread_section(arms: Sequence[ArmRecord]) -> Section | None:
    """The spread of each arm's final bests, and the Brown-Forsythe tests of it."""
    if len(arms) < 2:
        return None
    finals = {arm.name: np.asarray(arm.final_best, dtype=float) for arm in arms}
    spreads = Table(
        "arms",
        (
            Column("arm", "arm", Kind.TEXT),
            Column("runs", "runs", Kind.COUNT),
            Column("sd", "SD"),
            Column("iqr", "IQR"),
        ),
        tuple(
            (
                name,
                len(values),
                float(values.std(ddof=1)) if len(values) > 1 else math.nan,
                float(np.subtract(*np.percentile(values, [75, 25]))),
            )
            for name, values in finals.items()
        ),
    )
    tested = compare_spreads(finals)
    pairs = Table(
        "pairs",
        (
            Column("pair", "pair", Kind.TEXT),
            Column("w", "W"),
            Column("p", "p", Kind.P),
            Column("p_holm", "p (Holm)", Kind.P),
        ),
        tuple((f"{p.first} vs {p.second}", p.statistic, p.p_value, p.p_holm) for p in tested.pairs),
    )
    overall = (
        f"Brown-Forsythe over all arms: W = {value_text(tested.statistic, 3)}, p {p_phrase(tested.p_value)}."
    )
    title, scope = "Spread of the final bests", "final generation"
    return Section("spread", title, scope, SPREAD_TEXT, (spreads, pairs), notes=(overall,))


def p_phrase(value: float) -> str:
    """A p-value after "p": "= 0.0123", or "< 0.0001"."""
    text = p_text(value)
    return text if text.startswith("<") else f"= {text}"


# ---- the report ------------------------------------------------------------------------------


def verdict_json(verdict: Verdict | None) -> dict[str, Any] | None:
    """What the walk counts of a report mean: the backend's verdict (``walk``), the revision of its
    criterion (``v2``) and its terms, as this code declares them; ``backend_version`` beside it
    says which fitness revision scored the runs, and so which criterion their recorded terms are of."""
    if verdict is None:
        return None
    return {
        "component": verdict.component,
        "label": verdict.label,
        "version": verdict.version,
        "terms": list(verdict.terms),
    }


#: Sections that say how to read a report, put before its summary: a study still running, a grown
#: study read at its first runs, arms scored differently.
LEADING = ("progress", "window", "scoring")


@dataclass(frozen=True)
class StudyReport:
    arms: tuple[ArmRecord, ...]
    summaries: tuple[ArmSummary, ...]
    best: Comparison  # on each run's final best
    average: Comparison  # on each run's final average
    title: str = ""
    #: The sections after the summary, in order: fronts and repertoires, the animated gaits.
    sections: tuple[Section, ...] = ()

    @property
    def summary(self) -> Section:
        """The summary: the tables of the paper and every difference tested (of one arm, none:
        one sentence says so)."""
        tests = (RankTests("final best", self.best), RankTests("final average", self.average))
        compared = len(self.arms) > 1
        return Section(
            "summary",
            text=SUMMARY_TEXT,
            tables=(summary_table(self.summaries),),
            tests=tests if compared else (),
            footnote=A12_NOTE if compared else ONE_ARM_NOTE,
            figures=(Figure("convergence", CONVERGENCE_CAPTION, convergence(self.arms), ("png", "svg")),),
        )

    @property
    def document(self) -> tuple[Section, ...]:
        """Every section in order: those that say how to read the rest (:data:`LEADING`) first,
        then the summary, then the other :attr:`sections`."""
        leading = tuple(s for s in self.sections if s.name in LEADING)
        return (*leading, self.summary, *(s for s in self.sections if s.name not in LEADING))

    @property
    def figures(self) -> tuple[Figure, ...]:
        return tuple(f for s in self.document for f in s.figures)

    def as_json(self) -> dict[str, Any]:
        """The summary in its committed layout, then the further sections' tables and tests (if any
        section has either)."""
        shown = names_representations(self.summaries)
        data: dict[str, Any] = {
            "backend": self.arms[0].backend,
            "backend_version": self.arms[0].backend_version,
            "verdict": verdict_json(self.arms[0].verdict),
            "arms": [
                {
                    "name": s.name,
                    "strategy": s.strategy,
                    "runs": s.runs,
                    "budget": a.budget,
                    "final_best": [float(v) for v in a.final_best],
                    "final_average": [float(v) for v in a.final_average],
                    "mean_best": s.mean_best,
                    "sd_best": s.sd_best,
                    "median_best": s.median_best,
                    "median_best_ci95": list(s.median_best_ci),
                    "mean_average": s.mean_average,
                    "sd_average": s.sd_average,
                    "mean_average_viable": s.mean_average_viable,
                    "unviable_share": s.unviable_share,
                    "walk_rate": s.walk_rate,
                    "walks": s.walks,
                    "walk_rate_ci95": None if s.walk_rate_ci is None else list(s.walk_rate_ci),
                    "walk_held_rate": s.walk_held_rate,
                    # what scored it, where a setting changes what the fitness measures (bump floors)
                    **({"scoring": {k: json.loads(v) for k, v in a.scoring}} if a.scoring else {}),
                    # read at its first runs alone (report --runs): it holds more
                    **({"first_runs": a.window} if a.window is not None else {}),
                    # what its genomes are, where not every arm's is GE's
                    **({"representation": s.representation} if shown else {}),
                }
                for s, a in zip(self.summaries, self.arms, strict=True)
            ],
            "kruskal_wallis": {
                "best": {"h": self.best.kruskal_h, "p": self.best.kruskal_p},
                "average": {"h": self.average.kruskal_h, "p": self.average.kruskal_p},
            },
            "pairs": [
                {
                    "first": p.first,
                    "second": p.second,
                    "best": {"u": p.u, "p": p.p_value, "p_holm": p.p_holm, "a12": p.a12},
                    "average": {"u": q.u, "p": q.p_value, "p_holm": q.p_holm, "a12": q.a12},
                }
                for p, q in zip(self.best.pairs, self.average.pairs, strict=True)
            ],
        }
        sections = {s.name: _section_json(s) for s in self.sections if s.tables or s.tests}
        if sections:
            data["sections"] = sections
        return data


def _section_json(section: Section) -> dict[str, Any]:
    return {
        "title": section.title,
        "tables": {t.name: [_row_json(t.columns, row) for row in t.rows] for t in section.tables},
        "tests": {
            t.label: {
                "kruskal_wallis": {"h": t.comparison.kruskal_h, "p": t.comparison.kruskal_p},
                "pairs": [
                    {
                        "first": p.first,
                        "second": p.second,
                        "u": p.u,
                        "p": p.p_value,
                        "p_holm": p.p_holm,
                        "a12": p.a12,
                    }
                    for p in t.comparison.pairs
                ],
            }
            for t in section.tests
        },
    }


def _row_json(columns: Sequence[Column], row: Sequence[Any]) -> dict[str, Any]:
    record: dict[str, Any] = {}
    for column, value in zip(columns, row, strict=True):
        if column.kind is Kind.INTERVAL:
            record[column.key], *interval = value
            record[f"{column.key}_ci95"] = interval
        else:
            record[column.key] = value
    return record


def scoring_section(arms: Sequence[ArmRecord]) -> Section:
    """What a report of arms scored under different settings (``--mixed-scoring``) says first."""
    return Section(
        "scoring",
        "Scored differently",
        "the fitness values do not compare across these arms",
        text=(
            f"The arms were scored under different settings ({escape.markdown(scoring_listing(arms))}): "
            "their fitness "
            "values, and the rank tests on them (final best, final average, first-generation best), "
            "measure different things and are not to be compared across these arms. Walks, realism "
            "and robustness are measured the same way on every arm's gaits, and compare."
        ),
    )


def build_report(
    arms: Sequence[ArmRecord],
    *,
    title: str = "",
    sections: Sequence[Section] = (),
    mixed_scoring: bool = False,
) -> StudyReport:
    """The report of ``arms``: each arm summarised, every difference tested; ``sections`` follow the
    summary. With ``mixed_scoring``, arms scored under different scoring settings are reported
    together, a section saying first that their fitness values do not compare."""
    if not arms:
        raise ReportError("nothing to report: no arms")
    check_comparable(list(arms), mixed_scoring=mixed_scoring)
    if len({a.scoring for a in arms}) > 1:
        sections = (scoring_section(arms), *sections)
    names = [a.name for a in arms]
    if len(set(names)) != len(names):
        raise ReportError(f"two arms are called {next(n for n in names if names.count(n) > 1)!r}")
    return StudyReport(
        tuple(arms),
        tuple(summarise(a) for a in arms),
        compare({a.name: a.final_best for a in arms}),
        compare({a.name: a.final_average for a in arms}),
        title,
        tuple(without_untested(s, said=len(arms) < 2) for s in sections),
    )


def without_untested(section: Section, *, said: bool) -> Section:
    """``section`` without its rank tests of fewer than two arms (no pair to test: a one-arm
    report, or one arm measured of several), which would print as empty tables of "n/a"; unless
    that is ``said`` already (a one-arm report's summary says it once), a note says why."""
    tested = tuple(t for t in section.tests if t.comparison.pairs)
    if len(tested) == len(section.tests):
        return section
    note = () if said or tested else (UNTESTED_NOTE,)
    return replace(section, tests=tested, notes=(*section.notes, *note))


UNTESTED_NOTE = "No rank tests here: they compare arms, and fewer than two have values to compare."
