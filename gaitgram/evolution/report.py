"""The paper's figures and tables from run directories (Figs. 3, 4, 6; Tables 4, 5).

For each run directory (one grammar or strategy, several runs): best and
average fitness per generation averaged over runs, plotted together; and a
table of the final generation's average best, its standard deviation, average
average and its standard deviation.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np


class ReportError(ValueError):
    pass


@dataclass(frozen=True)
class RunSet:
    """The statistics of every run in one run directory, generations aligned."""

    label: str
    best: np.ndarray  # [runs, generations]
    average: np.ndarray

    @property
    def runs(self) -> int:
        return self.best.shape[0]


def load_run_set(directory: Path, label: str | None = None) -> RunSet:
    runs = sorted(directory.glob("run-*/stats.jsonl"))
    if not runs:
        raise ReportError(f"{directory}: no run-*/stats.jsonl; is this a `gaitgram evolve` run directory?")
    best, average = [], []
    for path in runs:
        try:
            records = [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line]
        except (OSError, json.JSONDecodeError) as error:
            raise ReportError(f"{path}: cannot read: {error}") from None
        best.append([r["best"] for r in records])
        average.append([math.nan if r["average"] is None else r["average"] for r in records])
    length = min(len(b) for b in best)  # a stopped run is compared on the generations all runs reached
    return RunSet(
        label or directory.name,
        np.array([b[:length] for b in best], dtype=float),
        np.array([a[:length] for a in average], dtype=float),
    )


@dataclass(frozen=True)
class SummaryRow:
    label: str
    runs: int
    generations: int
    average_best: float
    std_best: float
    average_average: float
    std_average: float


def summary_rows(sets: list[RunSet]) -> list[SummaryRow]:
    rows = []
    for s in sets:
        final_best, final_average = s.best[:, -1], s.average[:, -1]
        rows.append(
            SummaryRow(
                s.label,
                s.runs,
                s.best.shape[1] - 1,
                float(final_best.mean()),
                float(final_best.std()),
                float(np.nanmean(final_average)) if np.isfinite(final_average).any() else math.nan,
                float(np.nanstd(final_average)) if np.isfinite(final_average).any() else math.nan,
            )
        )
    return rows


_HEADER = ["grammar", "runs", "generations", "average best", "std best", "average average", "std average"]


def markdown_table(rows: list[SummaryRow]) -> str:
    lines = ["| " + " | ".join(_HEADER) + " |", "|" + "---|" * len(_HEADER)]
    for r in rows:
        lines.append(
            f"| {r.label} | {r.runs} | {r.generations} | {r.average_best:.4g} | {r.std_best:.4g} | "
            f"{r.average_average:.4g} | {r.std_average:.4g} |"
        )
    return "\n".join(lines) + "\n"


def csv_table(rows: list[SummaryRow]) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(_HEADER)
    for r in rows:
        writer.writerow(
            [r.label, r.runs, r.generations, r.average_best, r.std_best, r.average_average, r.std_average]
        )
    return out.getvalue()


def fitness_figure(sets: list[RunSet]):  # -> matplotlib.figure.Figure
    """Best (solid) and average (dashed) fitness against generation, averaged over runs."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(8, 5), layout="constrained")
    axes = figure.add_subplot()
    for index, s in enumerate(sets):
        colour = f"C{index % 10}"
        generations = np.arange(s.best.shape[1])
        axes.plot(generations, s.best.mean(axis=0), color=colour, label=f"{s.label}: best")
        with np.errstate(all="ignore"):
            average = np.nanmean(s.average, axis=0)
        axes.plot(generations, average, color=colour, linestyle="--", label=f"{s.label}: average")
    axes.set_xlabel("generation")
    axes.set_ylabel("fitness (lower is better)")
    axes.set_title(f"Fitness averaged over runs ({', '.join(f'{s.label}: {s.runs}' for s in sets)})")
    axes.grid(alpha=0.3)
    axes.legend(fontsize="small")
    return figure


def write_report(directories: list[Path], out: Path, *, force: bool = False) -> list[Path]:
    """Write fitness.png, fitness.svg, summary.md and summary.csv into ``out``."""
    sets = [load_run_set(d) for d in directories]
    labels = [s.label for s in sets]
    if len(set(labels)) != len(labels):  # same directory name in different places: use the full path
        sets = [load_run_set(d, str(d)) for d in directories]
    targets = [out / name for name in ("fitness.png", "fitness.svg", "summary.md", "summary.csv")]
    existing = [t for t in targets if t.exists()]
    if existing and not force:
        raise ReportError(
            f"{existing[0]} exists; pass --force to overwrite the report, or choose another --out"
        )
    out.mkdir(parents=True, exist_ok=True)
    rows = summary_rows(sets)
    figure = fitness_figure(sets)
    figure.savefig(targets[0], dpi=120)
    figure.savefig(targets[1])
    targets[2].write_text(markdown_table(rows), encoding="utf-8")
    targets[3].write_text(csv_table(rows), encoding="utf-8")
    return targets
