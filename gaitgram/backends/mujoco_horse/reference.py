"""The real walks the horse's gaits are held against, and how a report reads its assessments.

``seeds/dlc_walk.json`` (``gaitgram seed derive`` on 169 side-view clips of horses walked in hand;
Niknejad et al. 2023) is the reference: :func:`real_walks` reads it, the one place that does.
:func:`assessment` declares, as data (:class:`~gaitgram.backends.api.Assessment`), what the
horse's ``assess`` keeps (:mod:`~gaitgram.backends.mujoco_horse.assessment`): the measures beside
the real walks' values, the curves on their band, the terms of the realism distance
(:mod:`~gaitgram.backends.mujoco_horse.realism`), and how a disturbance trial names the walk terms
a gait failed (:mod:`~gaitgram.backends.mujoco_horse.robustness`). No numpy, no MuJoCo: the spec
declares it cheaply, and a report reads it without simulating anything.
"""

from __future__ import annotations

import json
from functools import cache
from typing import Any

from gaitgram.backends.api import Assessment, ReferenceCurve, ReferenceMeasure
from gaitgram.packaged import packaged

#: Phases at which the real walks' curves are given.
CURVE_SAMPLES = 20
CURVES = ("fetlock_fore", "fetlock_hind", "protraction_fore", "protraction_hind")
#: The measures the realism distance averages, in the order reports list them.
MEASURES = ("duty_factor", "phase_fore_left", "phase_hind_right", "phase_fore_right", *CURVES)
CURVE_TITLES = {
    "fetlock_fore": "fore fetlock (deg)",
    "fetlock_hind": "hind fetlock (deg)",
    "protraction_fore": "fore limb protraction (deg)",
    "protraction_hind": "hind limb protraction (deg)",
}
#: What a trial's detail says before the walk terms a gait failed to walk again by.
NOT_WALKING = "not walking again: "


@cache
def real_walks() -> dict[str, Any]:
    """The DLC_Horse summary shipped with gaitgram (``seeds/dlc_walk.json``)."""
    return json.loads(packaged(__package__, "dlc_walk.json").read_text(encoding="utf-8"))


@cache
def assessment() -> Assessment:
    """What a report reads of the horse's kept assessments, and the real walks beside them."""
    real = real_walks()
    text = (
        "Each run's best gait played as scored and measured as the real walks were: DLC_Horse, "
        f"{real['clips']} clips of horses walked in hand ({real['strides']} strides; "
        "`seeds/dlc_walk.json`). Per arm, the median over its runs' best gaits that stand and step. "
        "Stride frequency and length are the gait's at its own speed, beside what Alexander's relations "
        "predict at that speed for the model's hip height (Froude-scaled). The **realism distance** of a "
        "gait is the mean over eight measures (duty factor, three footfall phases, four curves) of its "
        "distance from the real walks in units of their spread: 0 is their median gait, about 0.67 a gait "
        "at their quartiles in every measure (docs/study.md). Image-plane angles from one camera compare "
        "in shape and range, not to the degree."
    )
    curves = tuple(
        ReferenceCurve(
            name, CURVE_TITLES[name], tuple(real["curves"][name]["mean"]), tuple(real["curves"][name]["sd"])
        )
        for name in CURVES
    )
    return Assessment(
        title="Gaits held against real horses",
        text=text,
        measures=_measures(real),
        scored=MEASURES,
        curves=curves,
        figure="Best gaits beside the real walks (DLC_Horse: mean and SD)",
        failed_terms=NOT_WALKING,
    )


def _iqr(summary: dict[str, Any]) -> str:
    low, high = summary["iqr"]
    return f"IQR {low:g} to {high:g}"


def _measures(real: dict[str, Any]) -> tuple[ReferenceMeasure, ...]:
    """The realism table's rows: each measure beside the real walks' value and what it is."""
    lands = real["phase_after_left_hind"]
    low, high = real["stride_seconds"]["iqr"]
    rows = [
        ReferenceMeasure("speed", "speed (m/s)", None, "not measured (pixels)"),
        ReferenceMeasure("froude", "Froude number v / sqrt(g h)", None, ""),
        ReferenceMeasure(
            "duty_factor", "duty factor", real["duty_factor"]["median"], _iqr(real["duty_factor"])
        ),
        ReferenceMeasure(
            "predicted_duty_factor", "duty factor, Alexander & Jayes at its speed", None, "Froude-scaled"
        ),
        *(
            ReferenceMeasure(
                f"phase_{limb}",
                f"{said} lands after left hind (stride)",
                lands[hoof]["median"],
                _iqr(lands[hoof]),
            )
            for limb, said, hoof in (
                ("fore_left", "left fore", "LeftFrontHoof"),
                ("hind_right", "right hind", "RightHindHoof"),
                ("fore_right", "right fore", "RightFrontHoof"),
            )
        ),
        ReferenceMeasure(
            "stride_frequency",
            "stride frequency (Hz)",
            real["stride_frequency_hz"],
            f"IQR {1 / high:.3g} to {1 / low:.3g}",
        ),
        ReferenceMeasure(
            "predicted_stride_frequency",
            "stride frequency, Alexander at its speed (Hz)",
            None,
            "Froude-scaled",
        ),
        ReferenceMeasure("stride_length", "stride length (m)", None, "not measured (pixels)"),
        ReferenceMeasure(
            "predicted_stride_length", "stride length, Alexander at its speed (m)", None, "Froude-scaled"
        ),
    ]
    for name in CURVES:
        curve = real["curves"][name]
        mean = [float(v) for v in curve["mean"]]
        title = CURVE_TITLES[name].removesuffix(" (deg)")
        rows.append(
            ReferenceMeasure(
                f"{name}_range",
                f"{title}: range over a stride (deg)",
                curve["range_of_motion"],
                f"of the mean stride; a median stride's {curve['median_stride_range']:g}",
            )
        )
        if name.startswith("protraction"):
            rows += [
                ReferenceMeasure(
                    f"{name}_max", f"{title}: most protracted (deg)", max(mean), "of the mean stride"
                ),
                ReferenceMeasure(
                    f"{name}_min", f"{title}: most retracted (deg)", min(mean), "of the mean stride"
                ),
            ]
    return tuple(rows)
