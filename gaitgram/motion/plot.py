"""Joint-angle curves of a derivation over one cycle, one panel per joint, the seed dashed beside it.

A curve that reads sensors (a closed loop) has no fixed shape: its panel shows the *nominal* curve,
every sensor at its resting reading (:func:`gaitgram.motion.gait.sensed_curve`, as runs sample it),
and says so in its title and legend."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from gaitgram.motion.expression import Motion, compile_motion, phase_grid
from gaitgram.motion.gait import Sensors, sensed_curve
from gaitgram.motion.names import reads

#: What a closed loop's panel is labelled with.
NOMINAL = "nominal (sensors at rest)"


def curves_figure(
    joints: Sequence[str],
    phenotypes: Mapping[str, str],
    seed: Mapping[str, np.ndarray] | None = None,
    *,
    samples: int = 200,
    title: str | None = None,
    sensors: Sensors | None = None,
) -> Any:
    """A matplotlib Figure (Agg, no display needed): evolved curve solid, seed dashed. ``sensors``
    are the backend's: a curve that reads them is drawn nominal."""
    from matplotlib.figure import Figure

    closed = False
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
        elif sensors is not None and reads(text, sensors.names):
            closed = True
            axes.set_title(f"{joint} (closed loop)", fontsize=9)
            values, _, problem, detail = sensed_curve(text, samples, sensors)
            if problem is None:
                axes.plot(phases, values, color="C1", label=NOMINAL)
                axes.legend(fontsize=7)
            else:
                _problem(axes, str(detail))
        else:
            motion = compile_motion(text)
            curve = motion.evaluate(phases) if isinstance(motion, Motion) else None
            if curve is not None and curve.ok:
                axes.plot(phases, curve.values, color="C0", label="evolved")
            else:
                _problem(axes, str(motion) if curve is None else str(curve.error))
        if index % columns == 0:
            axes.set_ylabel("degrees")
        if index >= len(joints) - columns:
            axes.set_xlabel("phase of the cycle")
    figure.axes[0].legend(fontsize=7)
    if closed:
        title = f"{title}: " if title else ""
        title += "closed loop, drawn nominal (every sensor at rest)"
    if title:
        figure.suptitle(title)
    return figure


def _problem(axes: Any, text: str) -> None:
    """Why a panel has no curve, written across it."""
    axes.text(
        0.5, 0.5, text, ha="center", va="center", wrap=True, fontsize=7, color="C3", transform=axes.transAxes
    )
