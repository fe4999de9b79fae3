"""Study reports: the paper's tables and figures, with the statistics the paper did not compute.

The input is a set of arms, each a run directory of ``gaitgram evolve`` (a
study directory's ``arms/*``, or run directories given one by one). Per arm,
the final generation of every run gives one final best and one final average;
the report shows them in the layout of the paper's Tables 4 and 5 (mean ± SD),
with medians, bootstrap intervals, the share of unviable gaits, the walk rate
and the share of runs that hand back a walk at all, and tests every difference
(:mod:`gaitgram.study.stats`). Arms run at different budgets are refused: their
numbers do not compare.

Written files: ``summary.md``, ``summary.csv``, ``tables.tex`` (booktabs),
``summary.json``, ``convergence.png`` and ``convergence.svg``; for an arm whose
runs keep a Pareto front (``nsga2``) ``front-ARM.png``, the fronts' objectives
pairwise, and for one whose runs keep a repertoire (``map-elites``)
``archive-ARM.png``, its cells as heat maps (:mod:`gaitgram.strategies.figures`);
on request, animations of chosen trade-off gaits and repertoire cells
(:func:`write_gallery`).
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram import jsonio
from gaitgram.evolution.rundir import CONFIG, MANIFEST, RunDirectoryError, read_manifest, saved_config
from gaitgram.fileio import OutputError, check_output, write_atomically
from gaitgram.strategies.figures import (
    Front,
    RecordError,
    Repertoire,
    archive_figure,
    front_figure,
    kept_members,
    load_fronts,
    load_repertoire,
    spread_cells,
    trade_offs,
)
from gaitgram.study.manifest import STUDY_MANIFEST, read_study_manifest
from gaitgram.study.spec import StudyError
from gaitgram.study.stats import Comparison, bootstrap_median_ci, compare


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
    def walk_held_rate(self) -> float | None:
        return _share([r.holds_walk for r in self.runs])


def _share(flags: list[bool | None]) -> float | None:
    """The share of true flags; None if any run's records do not say."""
    if any(flag is None for flag in flags):
        return None
    return sum(bool(flag) for flag in flags) / len(flags)


def load_arm(
    path: Path, name: str | None = None, strategy: str | None = None, *, redo: str = ""
) -> ArmRecord:
    """An arm from a finished run directory; refuses unfinished, unreadable or damaged runs.

    Every file is untrusted input: the configuration is checked key by key (and against the
    manifest's digest, when there is one), every line of each run's ``stats.jsonl`` and its
    ``best.json`` field by field. ``redo`` is the command that rewrites a run's records from
    its checkpoint (default: ``gaitgram evolve --resume`` of the arm).
    """
    if not (path / CONFIG).is_file() and not (path / MANIFEST).is_file():
        raise ReportError(f"{path}: not a `gaitgram evolve` run directory (it has no {CONFIG})")
    try:
        manifest = read_manifest(path)
        config = saved_config(path, manifest)
    except RunDirectoryError as error:
        raise ReportError(str(error)) from None
    redo = redo or f"gaitgram evolve --resume {path}"
    runs = tuple(_load_run(path / f"run-{run:03d}", config.generations, redo) for run in range(config.runs))
    # What scored the runs (a directory without a manifest, hand-made or of gaitgram 0.1, cannot say).
    backend, version = (manifest["backend"], manifest["backend_version"]) if manifest else ("", "")
    return ArmRecord(
        name or path.name,
        strategy or config.strategy,
        path,
        config.budget,
        config.generations,
        config.population,
        runs,
        backend,
        version,
    )


def _load_run(path: Path, generations: int, redo: str) -> RunRecord:
    rewrite = f"rewrite the run's records from its checkpoint with: {redo}"
    stats = path / "stats.jsonl"
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
    best_record = _best_record(path / "best.json", records[-1]["best"], rewrite)

    def column(key: str) -> np.ndarray:
        return np.array([math.nan if r.get(key) is None else float(r[key]) for r in records])

    population = np.array([float(r["evaluations"]) for r in records])
    invalid = column("invalid")
    size = population[0] if population[0] else 1.0
    walk = best_record["components"].get("walk")
    return RunRecord(
        best=column("best"),
        average=column("average_all") if "average_all" in records[0] else column("average"),
        average_viable=column("average"),
        unviable_share=invalid / size,
        evaluations=int(population.sum()),
        final_status=best_record["status"],
        walk=None if walk is None else bool(walk >= 0.5 and best_record["status"] == "ok"),
        holds_walk=_holds_walk(path, records[-1]),
    )


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
        record = json.loads(line)
    except ValueError as error:
        raise ReportError(f"{where}: not JSON ({error}); {damaged}") from None
    if not isinstance(record, dict):
        raise ReportError(f"{where}: not a record of one generation; {damaged}")
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
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ReportError(f"{path} is missing; {rewrite}") from None
    except (OSError, ValueError) as error:
        raise ReportError(f"{path}: cannot read it ({error}); {rewrite}") from None
    damaged = f"the file was edited or damaged: {rewrite}"
    if not isinstance(record, dict):
        raise ReportError(f"{path}: not a record of the best gait; {damaged}")
    components = record.get("components")
    if not isinstance(components, dict) or not all(_finite(v) for v in components.values()):
        raise ReportError(f"{path}: components: not a table of finite numbers; {damaged}")
    if not isinstance(record.get("status"), str):
        raise ReportError(f"{path}: status: missing or not text; {damaged}")
    if record.get("fitness") != best:
        raise ReportError(
            f"{path}: fitness {record.get('fitness')!r} is not the last generation's best in stats.jsonl "
            f"({best!r}); {damaged}"
        )
    return record


def _holds_walk(path: Path, final: dict[str, Any]) -> bool | None:
    """Whether the run hands back a walk, even one its weighted best is not: a weighted sum can rank
    a walk below a gait that misses the walk window (docs/results/revision-3/strategies)."""
    try:
        members = kept_members(path)
    except RecordError as error:
        raise ReportError(str(error)) from None
    if members is None:
        share = final.get("mean_walk")  # over the final population's viable gaits
        return None if share is None else share > 0
    walks = [m["components"].get("walk") for m in members]
    return None if any(w is None for w in walks) else any(w >= 0.5 for w in walks)


def load_study_arms(directory: Path) -> list[ArmRecord]:
    """The arms of a study directory, in the study's order."""
    return _study_arms(directory)[0]


def _study_arms(directory: Path) -> tuple[list[ArmRecord], str]:
    """The arms of a study directory, in the study's order, and its title."""
    try:
        manifest = read_study_manifest(directory)
    except StudyError as error:
        raise ReportError(str(error)) from None

    def redo(arm: str) -> str:
        path = directory / "arms" / arm
        return f"gaitgram study {manifest.study_file} -o {directory} (or gaitgram evolve --resume {path})"

    arms = [
        load_arm(directory / "arms" / a.name, a.name, a.strategy, redo=redo(a.name)) for a in manifest.arms
    ]
    return arms, manifest.title


def load_arms(directories: Sequence[Path]) -> tuple[list[ArmRecord], str]:
    """The arms of study directories (each gives its arms) and run directories of ``gaitgram
    evolve`` (each one arm), and the studies' titles. A run directory given twice, under any
    spelling (a symlink, ``..``, a study and one of its arms), is refused: it would be compared
    with itself. Two arms of the same name are named by their paths."""
    arms: list[ArmRecord] = []
    titles = []
    for directory in directories:
        if (directory / STUDY_MANIFEST).is_file():
            found, title = _study_arms(directory)
            arms += found
            titles.append(title)
        else:
            arms.append(load_arm(directory))
    _refuse_duplicates(arms)
    names = [a.name for a in arms]
    if len(set(names)) != len(names):
        arms = [replace(a, name=str(a.path)) for a in arms]
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


def check_scoring(arms: list[ArmRecord]) -> None:
    """Refuse arms scored by different backends or backend versions (another fitness revision, model
    or simulator): their fitness values measure different things."""
    versions = {(a.backend, a.backend_version) for a in arms}
    if len(versions) > 1:
        listing = "; ".join(f"{a.name}: {a.backend} {a.backend_version}" for a in arms)
        raise ReportError(
            f"these arms were scored differently ({listing}); their fitness values do not compare in one "
            "table: report them separately, or run them again with one gaitgram"
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


# ---- the report ------------------------------------------------------------------------------


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
    )


@dataclass(frozen=True)
class StudyReport:
    arms: tuple[ArmRecord, ...]
    summaries: tuple[ArmSummary, ...]
    best: Comparison  # on each run's final best
    average: Comparison  # on each run's final average

    def as_json(self) -> dict[str, Any]:
        return {
            "backend": self.arms[0].backend,
            "backend_version": self.arms[0].backend_version,
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
                    "walk_held_rate": s.walk_held_rate,
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


def check_comparable(arms: list[ArmRecord]) -> None:
    """Refuse arms whose numbers do not compare in one table: scored differently, or at different
    budgets."""
    check_scoring(arms)
    check_budgets(arms)


def build_report(arms: list[ArmRecord]) -> StudyReport:
    if not arms:
        raise ReportError("nothing to report: no arms")
    check_comparable(arms)
    names = [a.name for a in arms]
    if len(set(names)) != len(names):
        raise ReportError(f"two arms are called {next(n for n in names if names.count(n) > 1)!r}")
    return StudyReport(
        tuple(arms),
        tuple(summarise(a) for a in arms),
        compare({a.name: a.final_best for a in arms}),
        compare({a.name: a.final_average for a in arms}),
    )


def _g(value: float | None, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    return f"{value:.{digits}g}"


def _p(value: float) -> str:
    if math.isnan(value):
        return "n/a"
    return "< 0.0001" if value < 1e-4 else f"{value:.4f}"


def _rate(value: float | None) -> str:
    """A share in whole percent, except that a small share never reads as none."""
    if value is None:
        return "n/a"
    if 0 < value < 0.01:
        return "< 0.1%" if value < 0.001 else f"{value:.1%}"
    return f"{value:.0%}"


def markdown(report: StudyReport, title: str = "", extra: Sequence[str] = ()) -> str:
    lines = [f"# {title}", ""] if title else []
    lines += [
        "Final generation, over runs. Fitness is minimised. *Average* is the population's mean over "
        "every individual, unviable gaits at their score (the paper's Avg. Avg.); *viable average* "
        "leaves them out. *Walk rate*: the share of runs whose best gait is a walk; *walk held*: the "
        "share whose final population (a `nsga2` run's Pareto front, a `map-elites` run's "
        "repertoire) holds one.",
        "",
        "| arm | runs | avg. best | SD | avg. average | SD | median best [95 % CI] | viable average "
        "| unviable | walk rate | walk held |",
        "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|",
    ]
    for s in report.summaries:
        low, high = s.median_best_ci
        lines.append(
            f"| {s.name} | {s.runs} | {_g(s.mean_best)} | {_g(s.sd_best)} | {_g(s.mean_average)} | "
            f"{_g(s.sd_average)} | {_g(s.median_best)} [{_g(low)}, {_g(high)}] | "
            f"{_g(s.mean_average_viable)} | {_rate(s.unviable_share)} | {_rate(s.walk_rate)} | "
            f"{_rate(s.walk_held_rate)} |"
        )
    for label, comparison in (("final best", report.best), ("final average", report.average)):
        lines += [
            "",
            f"**{label}**: Kruskal-Wallis H = {_g(comparison.kruskal_h)}, p = {_p(comparison.kruskal_p)}.",
            "",
            "| pair | U | p | p (Holm) | A12 | effect |",
            "|---|---:|---:|---:|---:|---|",
        ]
        for pair in comparison.pairs:
            lines.append(
                f"| {pair.first} vs {pair.second} | {_g(pair.u)} | {_p(pair.p_value)} | {_p(pair.p_holm)} | "
                f"{pair.a12:.3f} | {pair.magnitude} |"
            )
    lines += [
        "",
        "A12 is the probability that a run of the first arm ends with a lower (better) value than a "
        "run of the second (0.5: no difference; 0.56, 0.64 and 0.71 mark small, medium and large "
        "effects). p-values are two-sided Mann-Whitney U, Holm-adjusted over the pairs.",
        *extra,
    ]
    return "\n".join(lines) + "\n"


_CSV_HEADER = [
    "arm",
    "strategy",
    "runs",
    "mean_best",
    "sd_best",
    "median_best",
    "median_best_ci_low",
    "median_best_ci_high",
    "mean_average",
    "sd_average",
    "mean_average_viable",
    "unviable_share",
    "walk_rate",
    "walk_held_rate",
]


def csv_text(report: StudyReport) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(_CSV_HEADER)
    for s in report.summaries:
        writer.writerow(
            [
                s.name,
                s.strategy,
                s.runs,
                s.mean_best,
                s.sd_best,
                s.median_best,
                *s.median_best_ci,
                s.mean_average,
                s.sd_average,
                s.mean_average_viable,
                s.unviable_share,
                "" if s.walk_rate is None else s.walk_rate,
                "" if s.walk_held_rate is None else s.walk_held_rate,
            ]
        )
    return out.getvalue()


def _tex(text: str) -> str:
    for char, escaped in (
        ("\\", r"\textbackslash{}"),
        ("&", r"\&"),
        ("%", r"\%"),
        ("_", r"\_"),
        ("#", r"\#"),
    ):
        text = text.replace(char, escaped)
    return text


def latex(report: StudyReport) -> str:
    """Booktabs tables, ready for ``\\usepackage{booktabs}``."""
    rows = [
        f"{_tex(s.name)} & {s.runs} & {_g(s.mean_best)} & {_g(s.sd_best)} & {_g(s.mean_average)} & "
        f"{_g(s.sd_average)} & {_tex(_rate(s.walk_rate))} & {_tex(_rate(s.walk_held_rate))} \\\\"
        for s in report.summaries
    ]
    pairs = [
        f"{_tex(p.first)} vs {_tex(p.second)} & {_p(p.p_holm)} & {p.a12:.3f} & {p.magnitude} \\\\"
        for p in report.best.pairs
    ]
    return "\n".join(
        [
            "% gaitgram study report: final best and average over runs (mean and SD).",
            "\\begin{tabular}{lrrrrrrr}",
            "\\toprule",
            "Arm & Runs & Avg.\\ best & SD & Avg.\\ avg. & SD & Walk rate & Walk held \\\\",
            "\\midrule",
            *rows,
            "\\bottomrule",
            "\\end{tabular}",
            "",
            "% Pairwise two-sided Mann-Whitney U on the final best, Holm-adjusted; Vargha-Delaney A12.",
            "\\begin{tabular}{lrrl}",
            "\\toprule",
            "Pair & $p$ (Holm) & $A_{12}$ & Effect \\\\",
            "\\midrule",
            *pairs,
            "\\bottomrule",
            "\\end{tabular}",
            "",
        ]
    )


def save_figure(figure: Any, path: Path, **options: Any) -> None:
    """Render in memory, then replace ``path`` at once: a failed write never leaves half a plot."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format=path.suffix.lstrip(".").lower(), **options)
    write_atomically(path, buffer.getvalue())


def convergence_figure(arms: list[ArmRecord]):  # -> matplotlib.figure.Figure
    """Best (left) and average (right) fitness by generation: the mean over runs with its 95 %
    confidence band (t interval of the mean), as the paper's Figs. 3, 4 and 6 without the band."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator
    from scipy import stats

    figure = Figure(figsize=(11, 4.5), layout="constrained")
    panels = figure.subplots(1, 2)
    for index, arm in enumerate(arms):
        colour = f"C{index % 10}"
        for axes, key in zip(panels, ("best", "average"), strict=True):
            values = np.array([getattr(r, key) for r in arm.runs])  # [runs, generations]
            generations = np.arange(values.shape[1])
            mean = values.mean(axis=0)
            axes.plot(generations, mean, color=colour, label=f"{arm.name} ({len(arm.runs)} runs)")
            if len(arm.runs) > 1:
                sem = values.std(axis=0, ddof=1) / math.sqrt(len(arm.runs))
                half = sem * stats.t.ppf(0.975, len(arm.runs) - 1)
                axes.fill_between(generations, mean - half, mean + half, color=colour, alpha=0.2, linewidth=0)
    for axes, label in zip(panels, ("best fitness", "average fitness (all individuals)"), strict=True):
        axes.set_xlabel("generation")
        axes.xaxis.set_major_locator(MaxNLocator(integer=True))
        axes.set_ylabel(f"{label}, mean over runs")
        axes.grid(alpha=0.3)
    panels[0].legend(fontsize="small")
    figure.suptitle("Mean over runs with 95 % confidence bands (lower is better)")
    return figure


def figure_name(kind: str, arm: str, suffix: str = ".png") -> str:
    """A file name for an arm's figure (arm names may be paths)."""
    return f"{kind}-{re.sub(r'[^A-Za-z0-9_.-]+', '_', arm).strip('_.') or 'arm'}{suffix}"


def _saturation(front_sizes: list[int], population: int) -> str:
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


def strategy_lines(arms: list[ArmRecord]) -> list[str]:
    """The summary's section on fronts and repertoires (empty if no arm keeps either)."""
    lines: list[str] = []
    for arm in arms:
        try:
            fronts = load_fronts(arm.path)
            repertoire = load_repertoire(arm.path)
        except RecordError as error:
            raise ReportError(str(error)) from None
        if fronts:
            names = fronts[0].objectives
            best = np.mean([f.points.min(axis=0) for f in fronts if len(f.points)], axis=0)
            sizes = [len(f.points) for f in fronts]
            lines.append(
                f"- **{arm.name}** ({figure_name('front', arm.name)}): Pareto fronts of {np.mean(sizes):.1f} "
                f"gaits on average; the best of each objective, mean over runs: "
                + ", ".join(f"{n} {_g(v)}" for n, v in zip(names, np.atleast_1d(best), strict=False))
                + _saturation(sizes, arm.population)
            )
        if repertoire is not None:
            together = int(np.sum(repertoire.coverage > 0))
            described = ", ".join(d["name"] for d in repertoire.descriptors)
            lines.append(
                f"- **{arm.name}** ({figure_name('archive', arm.name)}): "
                f"{described}; {np.mean(repertoire.filled):.1f} of "
                f"{repertoire.cells} cells filled per run, {together} by the runs together; best gait "
                f"{_g(float(np.nanmin(repertoire.best)))}"
            )
    if not lines:
        return []
    return ["", "**Fronts and repertoires** (final generation):", "", *lines]


def write_study_report(
    arms: list[ArmRecord],
    out: Path,
    *,
    title: str = "",
    force: bool = False,
    chosen: Sequence[tuple[int, ...]] = (),
    gaits: int = 0,
) -> list[Path]:
    """The report's files; ``chosen`` cells (or ``gaits`` cells spread over each repertoire) are
    outlined on the heat maps: the ones :func:`write_gallery` draws."""
    report = build_report(arms)
    fronts, repertoires = _kept_sets(arms)
    targets, figures = _tables(out), _figures(out, fronts, repertoires)
    existing = [t for t in [*targets, *figures] if t.exists()]
    if existing and not force:
        raise ReportError(
            f"{existing[0]} exists; pass --force to overwrite the report, or choose another --out"
        )
    write_atomically(targets[0], markdown(report, title, strategy_lines(list(arms))))
    write_atomically(targets[1], csv_text(report))
    write_atomically(targets[2], latex(report))
    write_atomically(targets[3], jsonio.dumps(report.as_json(), indent=1) + "\n")
    figure = convergence_figure(list(arms))
    save_figure(figure, targets[4], dpi=120)
    # The same runs give the same SVG, byte for byte: no date, fixed element ids.
    from matplotlib import rc_context  # present: convergence_figure needed it

    with rc_context({"svg.hashsalt": "gaitgram"}):
        save_figure(figure, targets[5], metadata={"Date": None})
    for name, found in fronts.items():
        if found:
            save_figure(front_figure(name, found), out / figure_name("front", name), dpi=120)
    for name, repertoire in repertoires.items():
        if repertoire is not None:
            cells = list(chosen) or spread_cells(repertoire, gaits)
            save_figure(archive_figure(name, repertoire, cells), out / figure_name("archive", name), dpi=120)
    return targets + figures


def write_gallery(
    arms: list[ArmRecord], out: Path, *, gaits: int, chosen: Sequence[tuple[int, ...]] = ()
) -> list[Path]:
    """GIFs of ``gaits`` trade-off gaits spread along each front (run 0's) and of the best gaits
    of the ``chosen`` cells (or ``gaits`` cells spread along the first descriptor) of each
    repertoire, drawn through each arm's own pipeline (mujoco-horse arms only)."""
    from gaitgram.strategies.gallery import render_gaits

    written: list[Path] = []
    for arm, genomes, paths in _gallery(arms, out, gaits=gaits, chosen=chosen):
        render_gaits(arm.path, genomes, paths)
        written += paths
    return written


def _tables(out: Path) -> list[Path]:
    """The files every report writes, in the order :func:`write_study_report` writes them."""
    names = ("summary.md", "summary.csv", "tables.tex", "summary.json", "convergence.png", "convergence.svg")
    return [out / name for name in names]


def _figures(
    out: Path, fronts: dict[str, list[Front]], repertoires: dict[str, Repertoire | None]
) -> list[Path]:
    """One figure per arm that keeps fronts or a repertoire."""
    found = [out / figure_name("front", name) for name, kept in fronts.items() if kept]
    return found + [
        out / figure_name("archive", name) for name, kept in repertoires.items() if kept is not None
    ]


def _kept_sets(arms: list[ArmRecord]) -> tuple[dict[str, list[Front]], dict[str, Repertoire | None]]:
    try:
        return {a.name: load_fronts(a.path) for a in arms}, {a.name: load_repertoire(a.path) for a in arms}
    except RecordError as error:
        raise ReportError(str(error)) from None


def _gallery(
    arms: list[ArmRecord], out: Path, *, gaits: int, chosen: Sequence[tuple[int, ...]]
) -> list[tuple[ArmRecord, list[list[int]], list[Path]]]:
    """What :func:`write_gallery` draws: per arm, the genomes and their GIFs; a chosen cell that
    no run filled is a :class:`ReportError`."""
    if not (gaits or chosen):
        return []
    fronts, repertoires = _kept_sets(arms)
    found = []
    for arm in arms:
        if fronts[arm.name] and gaits:
            members = trade_offs(fronts[arm.name][0], gaits)
            paths = [out / figure_name("front", f"{arm.name}-{k}", ".gif") for k in range(len(members))]
            found.append((arm, [m["genome"] for m in members], paths))
        repertoire = repertoires[arm.name]
        if repertoire is not None:
            cells = list(chosen) or spread_cells(repertoire, gaits)
            missing = [c for c in cells if c not in repertoire.elites]
            if missing:
                raise ReportError(
                    f"arm {arm.name}: cell {','.join(map(str, missing[0]))} is empty in every run; filled: "
                    + " ".join(",".join(map(str, c)) for c in sorted(repertoire.elites))
                )
            paths = [out / figure_name("cell", f"{arm.name}-{'-'.join(map(str, c))}", ".gif") for c in cells]
            found.append((arm, [repertoire.elites[c]["genome"] for c in cells], paths))
    return found


def report_files(
    arms: list[ArmRecord], out: Path, *, gaits: int = 0, chosen: Sequence[tuple[int, ...]] = ()
) -> list[Path]:
    """Every file :func:`write_report` would write, to check before any is written."""
    files = _tables(out) + _figures(out, *_kept_sets(arms))
    return files + [path for _, _, paths in _gallery(arms, out, gaits=gaits, chosen=chosen) for path in paths]


def write_report(
    arms: list[ArmRecord],
    out: Path,
    *,
    title: str = "",
    force: bool = False,
    gaits: int = 0,
    chosen: Sequence[tuple[int, ...]] = (),
) -> list[Path]:
    """The whole report, tables, figures and GIFs, or none of it: every file is checked first
    (an existing one needs ``force``), and if anything fails (a GIF that cannot be rendered, a
    full disk, Ctrl-C) the files and directories made so far are removed again."""
    planned = report_files(arms, out, gaits=gaits, chosen=chosen)
    try:
        for path in planned:
            check_output(path, force=force, parents=True, flag="-o")
    except OutputError as error:
        raise ReportError(str(error)) from None
    made = [d for d in (out, *out.parents) if not d.exists()]
    new = [path for path in planned if not path.exists()]
    try:
        out.mkdir(parents=True, exist_ok=True)
        written = write_study_report(arms, out, title=title, force=force, chosen=chosen, gaits=gaits)
        return written + write_gallery(arms, out, gaits=gaits, chosen=chosen)
    except BaseException:
        for path in new:
            path.unlink(missing_ok=True)
        for directory in made:  # innermost first
            with contextlib.suppress(OSError):
                directory.rmdir()
        raise
