"""Joint-angle curves of a derivation over one cycle, one panel per joint, the seed dashed beside it."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from gaitgram.motion.expression import Motion, compile_motion, phase_grid


def curves_figure(
    joints: Sequence[str],
    phenotypes: Mapping[str, str],
    seed: Mapping[str, np.ndarray] | None = None,
    *,
    samples: int = 200,
    title: str | None = None,
) -> Any:
    """A matplotlib Figure (Agg, no display needed): evolved curve solid, seed dashed."""
    from matplotlib.figure import Figure

    columns = 4
    rows = math.ceil(len(joints) / columns)
    figure = Figure(figsize=(3.2 * columns, 2.4 * rows), layout="constrained")
    phases = phase_grid(samples)
    for index, joint in enumerate(joints):
        axes = figure.add_subplot(rows, columns, index + 1)
        axes.set_title(joint, fontsize=9)
        axes.grid(alpha=0.3)
        if seed is not None and joint in seed:
            values = np.asarray(seed[joint])
            axes.plot(np.arange(len(values)) / len(values), values, "--", color="0.5", label="seed")
        text = phenotypes.get(joint)
        if text is None:
            axes.axhline(0, color="C0", label="neutral (no curve)")
        else:
            motion = compile_motion(text)
            curve = motion.evaluate(phases) if isinstance(motion, Motion) else None
            if curve is not None and curve.ok:
                axes.plot(phases, curve.values, color="C0", label="evolved")
            else:
                problem = str(motion) if curve is None else str(curve.error)
                axes.text(
                    0.5,
                    0.5,
                    problem,
                    ha="center",
                    va="center",
                    wrap=True,
                    fontsize=7,
                    color="C3",
                    transform=axes.transAxes,
                )
        if index % columns == 0:
            axes.set_ylabel("degrees")
        if index >= len(joints) - columns:
            axes.set_xlabel("phase of the cycle")
    figure.axes[0].legend(fontsize=7)
    if title:
        figure.suptitle(title)
    return figure
