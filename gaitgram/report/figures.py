"""The report's figures, drawn from the report's data (:mod:`gaitgram.report.sections`).

One drawer per kind of figure data, registered with :func:`drawer`: convergence
(the paper's Figures 3, 4 and 6 with confidence bands), Pareto fronts
(objectives pairwise), repertoires (heat maps) and gaits' curves beside the
real walks'. A new kind of figure (a section's) registers its own drawer.
Figures need matplotlib (the ``plot`` extra), imported when one is drawn; the
same data give the same files, byte for byte (no dates in them, fixed SVG ids).
"""

from __future__ import annotations

import io
import math
from functools import singledispatch
from typing import TYPE_CHECKING, Any

import numpy as np

from gaitgram.report.escape import printable
from gaitgram.report.realism_robustness import RealismCurves
from gaitgram.report.sections import Convergence, Fronts, RepertoireMap

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def draw(data: Any) -> Figure:
    """The matplotlib figure of ``data`` (a :class:`~gaitgram.report.sections.Figure`'s). Its text is
    text: a ``$`` in an arm's name is a dollar, not mathematics to parse (or fail to); each drawer
    shows a name :func:`~gaitgram.report.escape.printable` (an SVG holds no control character)."""
    from matplotlib import rc_context

    with rc_context({"text.parse_math": False}):
        return drawer(data)


@singledispatch
def drawer(data: Any) -> Figure:
    """The drawer of a kind of figure data (``@drawer.register``)."""
    raise TypeError(f"no drawer for figure data of type {type(data).__name__}")


def rendered(figure: Figure, suffix: str) -> bytes:
    """The figure as a file of that format: PNG at 120 dpi; SVG without a date, with fixed ids."""
    from matplotlib import rc_context

    buffer = io.BytesIO()
    if suffix == "svg":
        with rc_context({"svg.hashsalt": "gaitgram"}):
            figure.savefig(buffer, format="svg", metadata={"Date": None})
    else:
        figure.savefig(buffer, format=suffix, dpi=120)
    return buffer.getvalue()


@drawer.register(Convergence)
def convergence_figure(data: Convergence) -> Figure:
    """Best (left) and average (right) fitness by generation: the mean over runs with its 95 %
    confidence band (t interval of the mean), as the paper's Figs. 3, 4 and 6 without the band."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    figure = Figure(figsize=(11, 4.5), layout="constrained")
    panels = figure.subplots(1, 2)
    for index, curves in enumerate(data.arms):
        colour = f"C{index % 10}"
        for axes, band in zip(panels, (curves.best, curves.average), strict=True):
            generations = np.arange(len(band.mean))
            axes.plot(
                generations, band.mean, color=colour, label=f"{printable(curves.arm)} ({curves.runs} runs)"
            )
            if band.half is not None:
                low, high = band.mean - band.half, band.mean + band.half
                axes.fill_between(generations, low, high, color=colour, alpha=0.2, linewidth=0)
    for axes, label in zip(panels, ("best fitness", "average fitness (all individuals)"), strict=True):
        axes.set_xlabel("generation")
        axes.xaxis.set_major_locator(MaxNLocator(integer=True))
        axes.set_ylabel(f"{label}, mean over runs")
        axes.grid(alpha=0.3)
    panels[0].legend(fontsize="small")
    figure.suptitle("Mean over runs with 95 % confidence bands (lower is better)")
    return figure


@drawer.register(Fronts)
def front_figure(data: Fronts) -> Figure:
    """Every pair of objectives as a scatter of each run's front (one colour per run)."""
    from matplotlib.figure import Figure

    name, fronts = printable(data.arm), data.fronts
    objectives = fronts[0].objectives
    pairs = [(a, b) for a in range(len(objectives)) for b in range(a + 1, len(objectives))]
    columns = min(3, len(pairs))
    rows = math.ceil(len(pairs) / columns)
    figure = Figure(figsize=(max(6.5, 4.2 * columns), 3.8 * rows + 0.4), layout="constrained")
    panels = np.atleast_1d(figure.subplots(rows, columns, squeeze=False).ravel())
    for panel, (a, b) in zip(panels, pairs, strict=False):
        for front in fronts:
            panel.scatter(
                front.points[:, a],
                front.points[:, b],
                s=14,
                color=f"C{front.run % 10}",
                label=f"run {front.run} ({len(front.points)})",
            )
        panel.set_xlabel(printable(objectives[a]))
        panel.set_ylabel(printable(objectives[b]))
        panel.grid(alpha=0.3)
    for panel in panels[len(pairs) :]:
        panel.set_visible(False)
    if len(fronts) <= 10:
        panels[0].legend(fontsize="x-small", title="front size", title_fontsize="x-small")
    figure.suptitle(
        f"{name}: final Pareto fronts of {len(fronts)} run(s)\nobjectives pairwise, lower is better"
    )
    return figure


@drawer.register(RepertoireMap)
def archive_figure(data: RepertoireMap) -> Figure:
    """The best fitness in each cell (left) and how many runs filled it (right), as heat maps,
    the cells the report animates outlined."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    name, repertoire, chosen = printable(data.arm), data.repertoire, data.chosen
    d = repertoire.descriptors
    best = repertoire.best if repertoire.best.ndim == 2 else repertoire.best[:, None]
    coverage = repertoire.coverage if repertoire.coverage.ndim == 2 else repertoire.coverage[:, None]
    x = (d[0]["low"], d[0]["high"])
    y = (d[1]["low"], d[1]["high"]) if len(d) > 1 else (0.0, 1.0)
    figure = Figure(figsize=(11, 4.5), layout="constrained")
    panels = figure.subplots(1, 2)
    runs = len(repertoire.filled)
    for panel, values, label, cmap, ticks in (
        (panels[0], best, "best fitness (lower is better)", "viridis_r", None),
        (
            panels[1],
            coverage.astype(float),
            f"runs that filled the cell (of {runs})",
            "Greys",
            MaxNLocator(integer=True),
        ),
    ):
        image = panel.imshow(
            values.T, origin="lower", extent=(*x, *y), aspect="auto", cmap=cmap, interpolation="nearest"
        )
        figure.colorbar(image, ax=panel, label=label, ticks=ticks)
        panel.set_xlabel(printable(d[0]["name"]))
        panel.set_ylabel(printable(d[1]["name"]) if len(d) > 1 else "")
    width = (x[1] - x[0]) / best.shape[0]
    height = (y[1] - y[0]) / best.shape[1]
    for cell in chosen:
        i, j = cell[0], cell[1] if len(cell) > 1 else 0
        panels[0].add_patch(
            _rectangle((x[0] + i * width, y[0] + j * height), width, height, label=f"{i},{j}")
        )
        centre = (x[0] + (i + 0.5) * width, y[0] + (j + 0.5) * height)
        panels[0].annotate(f"{i},{j}", centre, color="red", fontsize=7, ha="center", va="center")
    mean_filled = float(np.mean(repertoire.filled)) if repertoire.filled else 0.0
    figure.suptitle(
        f"{name}: repertoire of {runs} run(s): {int(np.sum(repertoire.coverage > 0))} of "
        f"{repertoire.cells} cells filled together, {mean_filled:.1f} per run"
    )
    return figure


def _rectangle(corner: tuple[float, float], width: float, height: float, label: str) -> Any:
    from matplotlib.patches import Rectangle

    return Rectangle(corner, width, height, fill=False, edgecolor="red", linewidth=1.5, label=label)


@drawer.register(RealismCurves)
def realism_figure(data: RealismCurves) -> Figure:
    """The curves of the arms' best gaits over one stride (on the horse, the fetlock and protraction
    curves from the hoof's footfall), each arm in its colour, on the real walks' mean and SD
    (grey): a panel per curve the backend declares, two to a row."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11, 3.5 * math.ceil(len(data.reference) / 2)), layout="constrained")
    panels = np.atleast_1d(figure.subplots(math.ceil(len(data.reference) / 2), 2, sharex=True)).ravel()
    for panel in panels[len(data.reference) :]:
        panel.set_visible(False)
    for panel, reference in zip(panels, data.reference, strict=False):
        name = reference.name
        mean, sd = np.array(reference.mean), np.array(reference.sd)
        phase = np.arange(len(mean)) / len(mean)
        panel.fill_between(phase, mean - sd, mean + sd, color="0.8", linewidth=0, label="real walks: SD")
        panel.plot(phase, mean, color="0.4", linestyle="--", label="real walks: mean")
        for arm in data.arms:
            colour = f"C{arm.colour % 10}"
            for other in arm.others:
                curve = other[name]
                panel.plot(np.arange(len(curve)) / len(curve), curve, color=colour, alpha=0.3, linewidth=0.8)
            if arm.best is not None:
                curve = arm.best[name]
                panel.plot(
                    np.arange(len(curve)) / len(curve),
                    curve,
                    color=colour,
                    linewidth=2,
                    label=printable(arm.arm),
                )
        panel.set_title(reference.title, fontsize="medium")
        panel.grid(alpha=0.3)
    for panel in panels[max(0, len(data.reference) - 2) : len(data.reference)]:  # each column's lowest
        panel.set_xlabel("share of the stride, from the hoof's footfall")
    panels[0].legend(fontsize="small")
    figure.suptitle(printable(data.title))
    return figure
