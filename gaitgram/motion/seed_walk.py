"""The walk seed: joint-angle curves over one stride for the 12 curves of the paper's Table 3.

The paper Fourier-analyses measured curves (Back & Clayton, *Equine Locomotion*) that are not
available here. These curves are **constructed**, not measured: each is a two-harmonic periodic
curve whose peak-to-peak equals a published walking range of motion, centred inside the joint's
limits, with its flexion peak placed in the swing phase of a walk (duty factor about 0.64, so
swing is the last third of the stride counted from the limb's own hoof contact). The scapula
curve is the one seed curve the paper prints (Fig. 2). ``seeds/README.md`` states the source of
each number. ``build_seed`` is the single definition; the CSV files are its output.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from gaitgram.language.source import describe_os_error
from gaitgram.packaged import packaged

if TYPE_CHECKING:
    from gaitgram.motion.gait import MotionBatch

SEED_JOINTS = (
    "scapula_fore", "shoulder_fore", "elbow_fore", "carpal_fore", "fetlock_fore",
    "hip_hind", "stifle_hind", "tarsal_hind", "fetlock_hind",
    "neck_proximal", "neck_mid", "neck_atlas",
)  # fmt: skip

#: Rows of the shipped CSV: phases k / SAMPLES, k = 0 .. SAMPLES - 1.
SAMPLES = 100


@dataclass(frozen=True)
class CurveRecipe:
    """How one curve is built: range of motion (deg), centre (deg), and the phases (fraction of
    the stride) at which the first and second harmonics peak, with the second's share."""

    range_of_motion: float
    centre: float
    first_peak: float
    second_peak: float
    second_share: float


#: Published walking ranges of motion (seeds/README.md, provenance): carpus 54, tarsus 40, fore fetlock 45,
#: hind fetlock 60, elbow 45, hip 23, neck 45 in all; less certain: shoulder 25, stifle 40.
RECIPES: dict[str, CurveRecipe] = {
    "shoulder_fore": CurveRecipe(25, 0.0, 0.75, 0.30, 0.25),
    "elbow_fore": CurveRecipe(45, 12.0, 0.78, 0.35, 0.25),
    "carpal_fore": CurveRecipe(54, 26.0, 0.80, 0.82, 0.30),
    "fetlock_fore": CurveRecipe(45, 0.0, 0.82, 0.30, 0.35),
    "hip_hind": CurveRecipe(23, 0.0, 0.90, 0.50, 0.20),
    "stifle_hind": CurveRecipe(40, 15.0, 0.78, 0.20, 0.25),
    "tarsal_hind": CurveRecipe(40, 18.0, 0.80, 0.25, 0.30),
    "fetlock_hind": CurveRecipe(60, 5.0, 0.82, 0.30, 0.35),
    # The neck nods twice per stride at the walk: the second harmonic dominates.
    "neck_proximal": CurveRecipe(15, 0.0, 0.25, 0.10, 0.80),
    "neck_mid": CurveRecipe(10, 0.0, 0.25, 0.12, 0.80),
    "neck_atlas": CurveRecipe(8, 0.0, 0.25, 0.15, 0.80),
}

#: The paper's Fig. 2 seed curve, used for the scapula (its range, about 20 degrees, fits).
FIG2_CURVE = "6.97+7.7*sin(1*2*PI*t+1.07)+2.56*sin(2*2*PI*t+2.97)"


class SeedError(ValueError):
    """A seed CSV that cannot be used; the message names the file, line and fix."""


@dataclass(frozen=True)
class SeedCurves:
    """Joint angles (degrees) at phases ``phases``; ``angles[joint]`` aligned with them."""

    phases: NDArray[np.float64]
    angles: dict[str, NDArray[np.float64]]

    def to_csv(self, decimals: int = 4) -> str:
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(["phase", *self.angles])
        for i, phase in enumerate(self.phases):
            writer.writerow([f"{phase:.4f}", *(f"{self.angles[j][i]:.{decimals}f}" for j in self.angles)])
        return out.getvalue()

    def motion_batch(self, samples: int = 256) -> MotionBatch:
        """The seed as a one-gait batch, every curve interpolated (periodically) at ``samples``
        phases: what a backend plays, as it plays a grammar's gaits."""
        from gaitgram.motion.gait import MotionBatch

        grid = np.arange(samples) / samples
        phases = np.append(self.phases, 1.0)
        angles = np.array([np.interp(grid, phases, np.append(c, c[0])) for c in self.angles.values()])
        return MotionBatch(tuple(self.angles), angles[None], (None,), (None,))


def _recipe_curve(recipe: CurveRecipe, phases: NDArray[np.float64]) -> NDArray[np.float64]:
    first = np.cos(2 * math.pi * (phases - recipe.first_peak))
    second = np.cos(4 * math.pi * (phases - recipe.second_peak))
    shape = (1 - recipe.second_share) * first + recipe.second_share * second
    dense = np.linspace(0, 1, 4096, endpoint=False)  # the exact extremes, not just the sampled ones
    dense_shape = (1 - recipe.second_share) * np.cos(2 * math.pi * (dense - recipe.first_peak)) + (
        recipe.second_share * np.cos(4 * math.pi * (dense - recipe.second_peak))
    )
    low, high = dense_shape.min(), dense_shape.max()
    return recipe.centre + (shape - (low + high) / 2) * recipe.range_of_motion / (high - low)


def build_seed(samples: int = SAMPLES) -> SeedCurves:
    """The seed curves, computed (the CSVs are this, rounded)."""
    from gaitgram.motion import compile_motion

    phases = np.arange(samples) / samples
    scapula = compile_motion(FIG2_CURVE)
    angles = {"scapula_fore": scapula.evaluate(phases).values}  # type: ignore[union-attr]
    for joint in SEED_JOINTS[1:]:
        angles[joint] = _recipe_curve(RECIPES[joint], phases)
    return SeedCurves(phases, angles)


def read_seed_csv(path: Path) -> SeedCurves:
    """Read a seed CSV (``phase`` then one column per joint); every problem is a SeedError."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as error:
        raise SeedError(f"{path}: cannot read it: {describe_os_error(error)}") from None
    except UnicodeDecodeError as error:
        raise SeedError(
            f"{path}: cannot read it: not UTF-8 text ({error.reason} at byte {error.start})"
        ) from None
    rows = list(csv.reader(io.StringIO(text)))
    if not rows or not any(cell.strip() for cell in rows[0]):
        raise SeedError(f"{path}: empty; a seed CSV starts with a header: phase,<joint>,<joint>,...")
    header = [cell.strip() for cell in rows[0]]
    if header[0] != "phase" or len(header) < 2:
        raise SeedError(f"{path}:1: the header must be phase,<joint>,...; found {','.join(header)!r}")
    duplicates = {name for name in header if header.count(name) > 1}
    if duplicates:
        raise SeedError(f"{path}:1: column {sorted(duplicates)[0]!r} appears twice")
    values: list[list[float]] = []
    for number, row in enumerate(rows[1:], start=2):
        if not row or not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise SeedError(f"{path}:{number}: {len(row)} values, but the header has {len(header)} columns")
        try:
            parsed = [float(cell) for cell in row]
        except ValueError:
            bad = next(cell for cell in row if not _is_float(cell))
            raise SeedError(f"{path}:{number}: {bad!r} is not a number") from None
        infinite = [i for i, v in enumerate(parsed) if not math.isfinite(v)]
        if infinite:
            at = infinite[0]
            raise SeedError(
                f"{path}:{number}: {header[at]}: {row[at].strip()!r} is not a finite number; a seed's "
                "phases and angles are numbers"
            )
        values.append(parsed)
    if len(values) < 4:
        raise SeedError(f"{path}: {len(values)} rows; a stride needs at least 4 samples")
    table = np.array(values)
    phases = table[:, 0]
    if np.any(np.diff(phases) <= 0) or phases[0] < 0 or phases[-1] >= 1:
        raise SeedError(f"{path}: phases must increase within [0, 1) (one stride, the end excluded)")
    return SeedCurves(phases, {name: table[:, i] for i, name in enumerate(header[1:], start=1)})


def _is_float(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def load_seed() -> SeedCurves:
    """The shipped walk seed (package data; ``seeds/horse_walk.csv`` in the repository is the same)."""
    return read_seed_csv(packaged(__package__, "horse_walk.csv"))
