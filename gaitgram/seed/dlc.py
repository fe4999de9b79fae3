"""Walking-horse kinematics from DeepLabCut keypoints: footfall timing and 2-D angle curves.

The seed's curves are constructed (``seeds/README.md``); real walks are public as DeepLabCut
tracks of horses filmed from the side (Niknejad et al. 2023, *Journal of the ASABE*: the
``NarimanNiknejad/DLC_Horse`` data set, 16 landmarks, 15 fps). From such tracks this module
measures what the landmarks allow:

* **footfalls**: a hoof is in stance while it is still on the ground, that is while it moves
  forward less than a fifth as far as the body (the withers) from one frame to the next;
  touchdowns give each hoof's stride period,
  its duty factor, and the phase at which each hoof lands after the left hind;
* **curves** over one stride of their limb (phase 0 = its hoof's touchdown), averaged over
  strides and clips: fetlock angles (knee-fetlock-hoof, hock-fetlock-hoof), limb protraction
  (withers-knee and hip-hock against the vertical, positive forward) and a head-neck angle
  (nostril-poll-withers).

They are image-plane angles from one camera, not the model's joint angles: a fetlock angle
compares directly; protraction is the sum of the scapula's, shoulder's and elbow's (or the hip's,
stifle's and hock's) contributions, which the landmarks cannot separate; the neck angle is the
whole head-neck bend, not the model's three neck joints.
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gaitgram.extras import require

__all__ = [
    "CURVES",
    "HOOVES",
    "KEYPOINTS",
    "Clip",
    "DlcError",
    "Kinematics",
    "Stride",
    "measure",
    "read_clip",
    "summarise",
]

#: The data set's landmarks, in its files' column order.
KEYPOINTS = (
    "Nostril", "Poll", "Withers",
    "RightKnee", "RightFrontFetlock", "RightFrontHoof",
    "LeftKnee", "LeftFrontFetlock", "LeftFrontHoof",
    "Hip",
    "RightHock", "RightHindFetlock", "RightHindHoof",
    "LeftHock", "LeftHindFetlock", "LeftHindHoof",
)  # fmt: skip

#: hoof -> (its limb's fetlock, its limb's upper landmark, the body landmark above the limb)
HOOVES = {
    "LeftHindHoof": ("LeftHindFetlock", "LeftHock", "Hip"),
    "LeftFrontHoof": ("LeftFrontFetlock", "LeftKnee", "Withers"),
    "RightHindHoof": ("RightHindFetlock", "RightHock", "Hip"),
    "RightFrontHoof": ("RightFrontFetlock", "RightKnee", "Withers"),
}

#: The measured curves: name -> the model joint it is compared with (None: no single joint).
CURVES = {
    "fetlock_fore": "fetlock_fore",
    "fetlock_hind": "fetlock_hind",
    "protraction_fore": None,  # scapula + shoulder + elbow
    "protraction_hind": None,  # hip + stifle + tarsus
    "head_neck": None,  # the whole neck and head
}

#: Landmarks below this DeepLabCut likelihood are treated as missing.
MIN_LIKELIHOOD = 0.6
#: A hoof is in stance while its forward speed is under this share of the withers'.
STANCE_SPEED_SHARE = 0.2
#: Samples per stride of the averaged curves.
CURVE_SAMPLES = 20
#: Strides shorter or longer than this (seconds) are tracking errors, not walk strides.
STRIDE_SECONDS = (0.6, 2.0)


class DlcError(ValueError):
    """A file that is not a readable DeepLabCut track; the message names it and says why."""


@dataclass(frozen=True)
class Clip:
    """One tracked video: ``xy[frame, keypoint]`` in pixels (image y down), NaN where missing."""

    name: str
    fps: float
    xy: NDArray[np.float64]

    def point(self, keypoint: str) -> NDArray[np.float64]:
        return self.xy[:, KEYPOINTS.index(keypoint)]


@dataclass(frozen=True)
class Stride:
    """One hoof's stride: touchdown frame to the next, and the frames it was on the ground."""

    hoof: str
    start: int
    end: int
    stance_frames: int

    @property
    def frames(self) -> int:
        return self.end - self.start


@dataclass
class Kinematics:
    """What one or more clips measure; the lists hold one entry per stride found."""

    clips: int = 0
    strides: list[tuple[str, float, float]] = field(default_factory=list)  # (hoof, seconds, duty)
    offsets: dict[str, list[float]] = field(default_factory=dict)  # hoof -> phases after left hind
    curves: dict[str, list[NDArray[np.float64]]] = field(default_factory=dict)


def read_clip(path: Path, fps: float = 15.0) -> Clip:
    """A DeepLabCut ``.h5`` (needs h5py: ``pip install 'gaitgram[dlc]'``) or ``.csv`` track."""
    if not path.is_file():
        raise DlcError(f"cannot read {path}: no such file")
    if path.suffix.lower() == ".csv":
        values = _read_csv(path)
    elif path.suffix.lower() in (".h5", ".hdf5"):
        values = _read_h5(path)
    else:
        raise DlcError(f"{path}: not a DeepLabCut track (expected .h5 or .csv)")
    if values.ndim != 2 or values.shape[1] != 3 * len(KEYPOINTS) or len(values) < 3:
        raise DlcError(
            f"{path}: expected at least 3 frames of {3 * len(KEYPOINTS)} values "
            f"({len(KEYPOINTS)} landmarks x (x, y, likelihood)), found shape {values.shape}"
        )
    triples = values.reshape(len(values), len(KEYPOINTS), 3)
    xy = triples[:, :, :2].copy()
    xy[~(triples[:, :, 2] >= MIN_LIKELIHOOD)] = np.nan
    return Clip(path.name, fps, xy)


def _read_h5(path: Path) -> NDArray[np.float64]:
    h5py = require("h5py", "reading DeepLabCut .h5 files")
    try:
        with h5py.File(path, "r") as data:
            table = data["df_with_missing/table"]
            kind = table.attrs.get("values_block_0_kind", b"")
            values = np.asarray(table["values_block_0"], dtype=np.float64)
    except (OSError, KeyError, ValueError, TypeError) as error:
        raise DlcError(f"{path}: not a DeepLabCut track ({error})") from None
    names = _keypoint_names(kind.decode("latin-1") if isinstance(kind, bytes) else str(kind))
    if names and tuple(names) != KEYPOINTS:
        raise DlcError(f"{path}: its landmarks are {', '.join(names)}; expected {', '.join(KEYPOINTS)}")
    return values


def _keypoint_names(kind: str) -> list[str]:
    """The landmark names from pandas' pickled column index, read as text (never unpickled)."""
    found = [name for name in re.findall(r"\nV([^\n]*)\np\d+", kind) if name not in ("x", "y", "likelihood")]
    return list(dict.fromkeys(found))


def _read_csv(path: Path) -> NDArray[np.float64]:
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            rows = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError) as error:
        raise DlcError(f"{path}: cannot read it ({error})") from None
    if len(rows) < 4 or rows[0][:1] != ["scorer"]:
        raise DlcError(f"{path}: not a DeepLabCut CSV (its first line must start with 'scorer')")
    names = list(dict.fromkeys(rows[1][1:]))
    if tuple(names) != KEYPOINTS:
        raise DlcError(f"{path}: its landmarks are {', '.join(names)}; expected {', '.join(KEYPOINTS)}")
    try:
        values = [[float(v) if v else math.nan for v in row[1:]] for row in rows[3:]]
        return np.array(values, dtype=np.float64)
    except ValueError as error:
        raise DlcError(f"{path}: a value is not a number ({error})") from None


def _filled(series: NDArray[np.float64]) -> NDArray[np.float64]:
    """Gaps of missing frames linearly interpolated; ends held."""
    good = ~np.isnan(series)
    if good.sum() < 2:
        return np.full_like(series, np.nan)
    frames = np.arange(len(series))
    return np.interp(frames, frames[good], series[good])


def _angle(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Signed angle (degrees) from direction ``a`` to direction ``b``, in (-180, 180]."""
    turn = np.arctan2(b[:, 1], b[:, 0]) - np.arctan2(a[:, 1], a[:, 0])
    return np.degrees((turn + np.pi) % (2 * np.pi) - np.pi)


def _world(clip: Clip) -> dict[str, NDArray[np.float64]]:
    """Every landmark with y up and x forward (the horse walks either way past the camera)."""
    points = {}
    for keypoint in KEYPOINTS:
        x, y = clip.point(keypoint).T
        points[keypoint] = np.column_stack([_filled(x), -_filled(y)])
    forward = np.nanmean(np.diff(points["Withers"][:, 0]))
    if forward < 0:
        for value in points.values():
            value[:, 0] *= -1
    return points


def _curves(points: dict[str, NDArray[np.float64]]) -> dict[str, dict[str, NDArray[np.float64]]]:
    """Per hoof, the curves read on its limb (and the head-neck angle, read on every limb)."""
    down = np.array([[0.0, -1.0]])
    head = _angle(points["Nostril"] - points["Poll"], points["Withers"] - points["Poll"])
    found = {}
    for hoof, (fetlock, upper, body) in HOOVES.items():
        end = "fore" if "Front" in hoof else "hind"
        cannon, pastern = points[fetlock] - points[upper], points[hoof] - points[fetlock]
        limb = points[upper] - points[body]
        found[hoof] = {
            f"fetlock_{end}": _angle(cannon, pastern),
            f"protraction_{end}": -_angle(np.repeat(down, len(limb), axis=0), limb),
            "head_neck": np.abs(head),
        }
    return found


def _strides(hoof: str, x: NDArray[np.float64], body_speed: float, fps: float) -> list[Stride]:
    """Strides from frame-to-frame displacements: interval ``i`` (frame i to i + 1) is stance when
    the hoof moves less than a fifth of the body, after a 3-frame median (which keeps the corners
    of lift-off and landing) and with one-interval blips removed. Central differences would
    smear each lift-off and landing over a frame, which at 15 fps takes 0.13 off the duty factor."""
    smooth = np.median(np.stack([np.roll(x, 1), x, np.roll(x, -1)]), axis=0)  # tracking jitter
    smooth[[0, -1]] = x[[0, -1]]
    stance = _without_blips(np.diff(smooth) < STANCE_SPEED_SHARE * body_speed)
    touchdowns = [i for i in range(1, len(stance)) if stance[i] and not stance[i - 1]]
    low, high = (round(s * fps) for s in STRIDE_SECONDS)
    return [
        Stride(hoof, a, b, int(stance[a:b].sum())) for a, b in pairwise(touchdowns) if low <= b - a <= high
    ]


def _without_blips(stance: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Runs of one interval (a jittering landmark, not a footfall) take their neighbours' state."""
    found = stance.copy()
    for i in range(1, len(found) - 1):
        if found[i] != found[i - 1] and found[i] != found[i + 1]:
            found[i] = found[i - 1]
    return found


def measure(clips: Iterable[Clip]) -> Kinematics:
    """Footfalls and stride-normalised curves of every clip, pooled."""
    found = Kinematics()
    for clip in clips:
        points = _world(clip)
        body_speed = float(np.nanmedian(np.diff(points["Withers"][:, 0])))
        if not body_speed > 0 or np.isnan(points["Withers"]).all():
            continue  # standing, or the withers never tracked: no walk to read
        found.clips += 1
        curves = _curves(points)
        strides = {h: _strides(h, points[h][:, 0], body_speed, clip.fps) for h in HOOVES}
        for hoof, hoof_strides in strides.items():
            for stride in hoof_strides:
                found.strides.append((hoof, stride.frames / clip.fps, stride.stance_frames / stride.frames))
                phase = np.linspace(0, 1, CURVE_SAMPLES, endpoint=False)
                frames = np.arange(stride.start, stride.end + 1)
                for name, series in curves[hoof].items():
                    if not np.isnan(series[frames]).any():
                        curve = np.interp(phase, (frames - stride.start) / stride.frames, series[frames])
                        found.curves.setdefault(name, []).append(curve)
        for stride in strides["LeftHindHoof"]:
            for hoof in HOOVES:
                lands = [s.start for s in strides[hoof] if stride.start <= s.start < stride.end]
                if lands:
                    found.offsets.setdefault(hoof, []).append((lands[0] - stride.start) / stride.frames)
    return found


def summarise(kinematics: Kinematics, seed: Sequence[float] | None = None) -> dict[str, object]:
    """Medians and spreads: what ``gaitgram seed derive`` writes."""
    if not kinematics.strides:
        raise DlcError("no walk strides found: are these side views of walking horses?")
    seconds = np.array([s for _, s, _ in kinematics.strides])
    duty = np.array([d for _, _, d in kinematics.strides])
    curves = {}
    for name, runs in sorted(kinematics.curves.items()):
        stacked = np.array(runs)
        mean = stacked.mean(axis=0)
        curves[name] = {
            "model_joint": CURVES[name],
            "strides": len(runs),
            "mean": [round(float(v), 2) for v in mean],
            "sd": [round(float(v), 2) for v in stacked.std(axis=0)],
            "range_of_motion": round(float(mean.max() - mean.min()), 1),
            "median_stride_range": round(float(np.median(stacked.max(axis=1) - stacked.min(axis=1))), 1),
        }
    offsets = {
        hoof: {"median": round(float(np.median(v)), 3), "iqr": _iqr(v), "strides": len(v)}
        for hoof, v in kinematics.offsets.items()
    }
    return {
        "clips": kinematics.clips,
        "strides": len(kinematics.strides),
        "stride_seconds": {"median": round(float(np.median(seconds)), 3), "iqr": _iqr(seconds)},
        "stride_frequency_hz": round(float(1 / np.median(seconds)), 3),
        "duty_factor": {"median": round(float(np.median(duty)), 3), "iqr": _iqr(duty)},
        "duty_factor_by_hoof": {
            hoof: round(float(np.median([d for h, _, d in kinematics.strides if h == hoof])), 3)
            for hoof in HOOVES
            if any(h == hoof for h, _, _ in kinematics.strides)
        },
        "phase_after_left_hind": offsets,
        "curves": curves,
    }


def _iqr(values: Sequence[float] | NDArray[np.float64]) -> list[float]:
    low, high = np.percentile(np.asarray(values, dtype=np.float64), [25, 75])
    return [round(float(low), 3), round(float(high), 3)]
