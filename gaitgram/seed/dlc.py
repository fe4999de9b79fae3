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
from array import array
from bisect import bisect_left
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path
from typing import TextIO

import numpy as np
from numpy.typing import NDArray

from gaitgram.extras import require
from gaitgram.language.source import path_problem

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
#: Coordinates beyond this many pixels from the image origin (no camera makes such images), like
#: non-finite ones (``inf``, ``nan``) and non-finite likelihoods, are treated as missing.
MAX_COORDINATE = 1.0e6
#: Frame rates ``--fps`` accepts: a camera films between these.
FPS_RANGE = (1.0, 1000.0)
#: The longest track read: 500,000 frames is over 2 hours at 60 fps. Measuring that many takes
#: about 0.5 GB (``python -m benchmarks dlc``); longer is not a walk but a day's filming.
MAX_FRAMES = 500_000
#: The longest CSV line read: a frame takes under 1,000 characters.
MAX_LINE = 16_384
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
    read: list[str] = field(default_factory=list)  # every clip's name, walking or not
    strides: list[tuple[str, float, float]] = field(default_factory=list)  # (hoof, seconds, duty)
    offsets: dict[str, list[float]] = field(default_factory=dict)  # hoof -> phases after left hind
    curves: dict[str, list[NDArray[np.float64]]] = field(default_factory=dict)


def read_clip(path: Path, fps: float = 15.0) -> Clip:
    """A DeepLabCut ``.h5`` (needs h5py: ``pip install 'gaitgram[dlc]'``) or ``.csv`` track.

    A landmark is missing in a frame when its likelihood is under :data:`MIN_LIKELIHOOD` or not a
    number, or a coordinate is not finite or beyond :data:`MAX_COORDINATE`; missing stretches are
    interpolated. Tracks over :data:`MAX_FRAMES` frames are refused."""
    if not FPS_RANGE[0] <= fps <= FPS_RANGE[1]:  # also refuses nan
        raise DlcError(f"{fps} frames per second: a camera films at {FPS_RANGE[0]:g} to {FPS_RANGE[1]:g}")
    problem = path_problem(path)
    if problem is not None:
        where = (
            " (give the tracks in it, or the directory to `gaitgram seed derive`)" if path.is_dir() else ""
        )
        raise DlcError(f"cannot read {path}: {problem}{where}")
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
    likelihood = triples[:, :, 2]
    tracked = (
        (likelihood >= MIN_LIKELIHOOD) & np.isfinite(likelihood) & (np.abs(xy) <= MAX_COORDINATE).all(axis=2)
    )
    xy[~tracked] = np.nan
    return Clip(path.name, fps, xy)


def _too_long(path: Path) -> DlcError:
    return DlcError(
        f"{path}: over {MAX_FRAMES:,} frames; tracks this long are refused (no walk lasts that long): "
        "split the video into clips"
    )


def _read_h5(path: Path) -> NDArray[np.float64]:
    h5py = require("h5py", "reading DeepLabCut .h5 files")
    try:
        with h5py.File(path, "r") as data:
            table = data["df_with_missing/table"]
            kind = table.attrs.get("values_block_0_kind", b"")
            if len(table) > MAX_FRAMES:  # before reading any of it
                raise _too_long(path)
            values = np.asarray(table["values_block_0"], dtype=np.float64)
    except DlcError:
        raise
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
    """The values after the frame number, line by line into one flat buffer: memory is 8 bytes a
    value, not the hundred that Python lists of strings would take."""
    width = 1 + 3 * len(KEYPOINTS)
    values = array("d")
    reader = None
    try:
        with path.open(newline="", encoding="utf-8-sig") as handle:  # a byte order mark is allowed
            reader = csv.reader(_lines(handle, path))
            header = [next(reader, []) for _ in range(3)]
            if header[0][:1] != ["scorer"]:
                raise DlcError(f"{path}: not a DeepLabCut CSV (its first line must start with 'scorer')")
            names = list(dict.fromkeys(header[1][1:]))
            if tuple(names) != KEYPOINTS:
                raise DlcError(
                    f"{path}:2: its landmarks are {', '.join(names) or 'not named'}; expected "
                    + ", ".join(KEYPOINTS)
                )
            frames = 0
            for row in reader:
                if not row:
                    continue  # a blank line
                if len(row) != width:
                    raise DlcError(
                        f"{path}:{reader.line_num}: {len(row)} values where a frame has {width} (its "
                        f"number, then x, y and likelihood of each of the {len(KEYPOINTS)} landmarks); "
                        "fix or delete the line"
                    )
                if frames == MAX_FRAMES:
                    raise _too_long(path)
                values.extend(_numbers(row, path, reader.line_num))
                frames += 1
    except csv.Error as error:  # a field over csv's size limit
        raise DlcError(f"{path}:{reader.line_num if reader else 1}: not a CSV line ({error})") from None
    except UnicodeDecodeError:
        line = reader.line_num + 1 if reader else 1
        raise DlcError(f"{path}:{line}: not UTF-8 text; DeepLabCut writes its CSVs as UTF-8") from None
    except OSError as error:
        raise DlcError(f"{path}: cannot read it ({error.strerror or error})") from None
    return np.frombuffer(values, dtype=np.float64).reshape(-1, width - 1)


def _lines(handle: TextIO, path: Path) -> Iterator[str]:
    """The file's lines, each read with a bound: one endless line must not fill the memory."""
    number = 0
    while line := handle.readline(MAX_LINE + 1):
        number += 1
        if len(line) > MAX_LINE:
            raise DlcError(
                f"{path}:{number}: a line over {MAX_LINE:,} characters; a DeepLabCut frame takes under 1,000"
            )
        yield line


def _numbers(row: list[str], path: Path, line: int) -> list[float]:
    """A row's values after the frame number; an empty cell is missing (NaN)."""
    try:
        return [float(v) for v in row[1:]]
    except ValueError:
        pass
    found = []
    for column, text in enumerate(row[1:], start=2):
        try:
            found.append(float(text) if text.strip() else math.nan)
        except ValueError:
            raise DlcError(
                f"{path}:{line}: column {column}: {text!r} is not a number; coordinates and "
                "likelihoods are numbers (an empty cell is a missing one)"
            ) from None
    return found


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


def _world(clip: Clip) -> tuple[dict[str, NDArray[np.float64]], dict[str, NDArray[np.float64]]] | None:
    """The withers and hooves with y up and x forward (the horse walks either way past the
    camera), their gaps interpolated, and every landmark as tracked (NaN where missing); None if
    the withers, which give the body's speed and direction, are tracked in under two frames.
    (Footfalls are read on the filled paths: a hoof lost at the frame it lands may land a frame
    early or late, which no frame says.)"""
    tracked = {k: clip.point(k) * np.array([1.0, -1.0]) for k in KEYPOINTS}
    points = {k: _filled_path(tracked[k]) for k in ("Withers", *HOOVES)}  # what footfalls read
    if np.isnan(points["Withers"]).any():  # filled: either complete or never tracked
        return None
    forward = np.mean(np.diff(points["Withers"][:, 0]))
    if forward < 0:
        for value in (*points.values(), *tracked.values()):
            value[:, 0] *= -1
    return points, tracked


def _filled_path(xy: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.column_stack([_filled(xy[:, 0]), _filled(xy[:, 1])])


def _segment(tracked: dict[str, NDArray[np.float64]], start: str, end: str) -> NDArray[np.float64]:
    """The vector from landmark ``start`` to ``end`` in each frame, interpolated over the frames
    where either is missing. A segment of a limb keeps its length and turns with the limb: over a
    gap it stays what it was, where a lone landmark moved on its own would cut the corner its
    path turns (a hoof stops at touchdown)."""
    return _filled_path(tracked[end] - tracked[start])


def _curves(tracked: dict[str, NDArray[np.float64]]) -> dict[str, dict[str, NDArray[np.float64]]]:
    """Per hoof, the curves read on its limb (and the head-neck angle, read on every limb), from
    the landmarks as tracked: angles between segments (:func:`_segment`), so that an angle that
    holds steady holds over a gap."""

    def segment(start: str, end: str) -> NDArray[np.float64]:
        return _segment(tracked, start, end)

    down = np.array([[0.0, -1.0]])
    head = _angle(segment("Poll", "Nostril"), segment("Poll", "Withers"))
    found = {}
    for hoof, (fetlock, upper, body) in HOOVES.items():
        end = "fore" if "Front" in hoof else "hind"
        cannon, pastern = segment(upper, fetlock), segment(fetlock, hoof)
        limb = segment(body, upper)
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
        found.read.append(clip.name)
        world = _world(clip)
        if world is None:
            continue  # the withers never tracked: no walk to read
        points, tracked = world
        body_speed = float(np.median(np.diff(points["Withers"][:, 0])))
        if not body_speed > 0:
            continue  # standing
        found.clips += 1
        curves = _curves(tracked)
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
        starts = {hoof: [s.start for s in hoof_strides] for hoof, hoof_strides in strides.items()}
        for stride in strides["LeftHindHoof"]:
            for hoof in HOOVES:  # the first touchdown within the stride (starts ascend)
                first = bisect_left(starts[hoof], stride.start)
                if first < len(starts[hoof]) and starts[hoof][first] < stride.end:
                    lands = starts[hoof][first]
                    found.offsets.setdefault(hoof, []).append((lands - stride.start) / stride.frames)
    return found


def summarise(kinematics: Kinematics, seed: Sequence[float] | None = None) -> dict[str, object]:
    """Medians and spreads: what ``gaitgram seed derive`` writes."""
    if not kinematics.strides:
        names = kinematics.read
        shown = ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
        raise DlcError(
            f"no walk strides found in {shown or 'no tracks'}: are these side views of walking horses, "
            f"with landmarks tracked at a likelihood of {MIN_LIKELIHOOD} or more?"
        )
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
