"""The walk seed fitted to the horse: limb curves whose hooves walk, by inverse kinematics.

The recipe curves of :func:`gaitgram.seed.build_seed` have published ranges and
timings per joint, but nothing ties the joints of a limb together: played on the
horse, the fore hoof sank lowest in late stance and dragged forward through its
swing, so the horse shuffled backwards (v = -0.07 m/s). A walking limb's hoof
stays on the ground and moves back steadily under the body for the stance, then
lifts and swings forward. This module asks for exactly that, per limb and phase,
and solves for the joint angles nearest the recipe curves that produce it:

* stance, phases [0, duty): the hoof moves back by ``excursion`` at constant
  speed, at standing height, its sole flat;
* swing, [duty, 1): it returns with a smooth (half-cosine) profile, lifted by
  ``lift`` at mid-swing.

Hoof positions are relative to the standing pose with the trunk level. The neck
keeps its recipe curves. Numbers and what they rest on: ``seeds/README.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from gaitgram.backends.mujoco_horse.joints import CATALOGUE
from gaitgram.backends.mujoco_horse.model import horse_layout, joint_name, load_model
from gaitgram.extras import require
from gaitgram.motion.seed_walk import SeedCurves

#: The limb chains the fit solves, proximal to distal (left limbs; right ones share the curves).
CHAINS = {
    "fore_left": ("scapula_fore", "shoulder_fore", "elbow_fore", "carpal_fore", "fetlock_fore"),
    "hind_left": ("hip_hind", "stifle_hind", "tarsal_hind", "fetlock_hind"),
}


@dataclass(frozen=True)
class FootPath:
    """The hoof path asked of every limb (metres and stride fractions): a real walk at the target
    speed (seeds/README.md, "Refitted to the real walk")."""

    #: Backward travel of the hoof during stance, relative to the trunk: the real walk's stance
    #: share times Alexander's stride at the target speed (0.59 x 1.69 m).
    excursion: float = 1.0
    duty: float = 0.60  # stance share of the stride: the DLC_Horse walks' 0.59
    lift: float = 0.15  # hoof height at mid-swing
    #: The trunk this much below its standing height: at standing height a hoof 0.5 m ahead of or
    #: behind its limb cannot reach the ground within the joint limits.
    crouch: float = 0.045
    reference_weight: float = 0.02  # pull towards the recipe curves, per degree, against 1 per cm
    margin: float = 6.0  # degrees kept clear of each joint limit, for the grammars' variations
    harmonics: int = 8  # Fourier harmonics kept in each fitted curve


def hoof_target(path: FootPath, phase: float) -> tuple[float, float, bool]:
    """(forward, up) displacement of the hoof from standing, relative to the trunk, in metres, and
    whether it is in stance."""
    if phase < path.duty:
        progress = phase / path.duty
        return path.excursion / 2 - path.excursion * progress, path.crouch, True
    progress = (phase - path.duty) / (1 - path.duty)
    forward = -path.excursion / 2 + path.excursion * (0.5 - 0.5 * np.cos(np.pi * progress))
    return float(forward), path.crouch + path.lift * float(np.sin(np.pi * progress)), False


def _limits(curve: str) -> tuple[float, float]:
    joint = CATALOGUE.get(curve)
    assert joint is not None, curve  # CHAINS names catalogue curves
    return joint.limits


def fit_seed(reference: SeedCurves, path: FootPath = FootPath(), body: str | None = None) -> SeedCurves:
    """``reference`` with its limb curves replaced by the nearest ones whose hooves follow ``path``
    on ``body`` (the horse by default)."""
    angles = dict(reference.angles)
    for limb, curves in CHAINS.items():
        fitted = _fit_limb(limb, curves, reference, path, body)
        for i, curve in enumerate(curves):
            angles[curve] = low_pass(fitted[:, i], path.harmonics)
    return SeedCurves(reference.phases, angles)


def low_pass(curve: np.ndarray, harmonics: int) -> np.ndarray:
    """A periodic curve keeping its first ``harmonics`` Fourier harmonics: the sum-of-sines form
    the grammars are built from, without the solver's small wiggles."""
    spectrum = np.fft.rfft(curve)
    spectrum[harmonics + 1 :] = 0
    return np.fft.irfft(spectrum, n=len(curve))


def _fit_limb(
    limb: str, curves: tuple[str, ...], reference: SeedCurves, path: FootPath, body: str | None
) -> np.ndarray:
    """Joint angles [phases, curves] (degrees) of one limb chain, solved phase by phase."""
    optimize = require("scipy.optimize", "fitting the seed")
    model = load_model(body)
    layout = horse_layout(body)
    data = mujoco.MjData(model)
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"hoof_{limb}")
    qpos = np.array(
        [
            model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint_name(c, limb))]
            for c in curves
        ]
    )

    def hoof(degrees: np.ndarray) -> tuple[np.ndarray, float]:
        """The hoof's position and its sole's pitch (degrees), the trunk standing level."""
        data.qpos[:] = layout.stand_qpos
        data.qpos[qpos] += np.radians(degrees)
        mujoco.mj_kinematics(model, data)
        rotation = data.site_xmat[site].reshape(3, 3)
        return data.site_xpos[site].copy(), float(np.degrees(np.arctan2(rotation[2, 0], rotation[0, 0])))

    standing, standing_tilt = hoof(np.zeros(len(curves)))

    def residuals(
        degrees: np.ndarray, forward: float, up: float, stance: bool, wanted: np.ndarray
    ) -> np.ndarray:
        position, tilt = hoof(degrees)
        return np.concatenate(
            [
                [(position[0] - standing[0] - forward) * 100, (position[2] - standing[2] - up) * 100],
                [(tilt - standing_tilt) * (1.0 if stance else 0.2)],  # the sole flat in stance
                path.reference_weight * (degrees - wanted),
            ]
        )

    limits = np.array([_limits(c) for c in curves]).T + np.array([[path.margin], [-path.margin]])
    fitted = np.empty((len(reference.phases), len(curves)))
    start = np.clip([reference.angles[c][0] for c in curves], limits[0] + 1e-6, limits[1] - 1e-6)
    for k, phase in enumerate(reference.phases):
        wanted = np.array([reference.angles[c][k] for c in curves])
        # From the previous phase's solution: the curves come out smooth.
        start = optimize.least_squares(
            residuals, start, bounds=limits, args=(*hoof_target(path, float(phase)), wanted)
        ).x
        fitted[k] = start
    return fitted
