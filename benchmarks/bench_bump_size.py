"""The measurement behind the strategies README's reading of the 90 % goal: how small must the
bumps be for GE-hybrid's best gaits to keep walking on them?

The robustness trial's floors have bumps up to 2 cm (docs/study.md); GE-hybrid's best gaits of
the committed strategies study (docs/results/strategies/runs) hold on 17 % of them and on all ten
in no run. Here the same gaits are played on ten floors of the same seeds (26-35) with turf scaled
by 0.25, 0.5 and 0.75 (bumps, cells and the flat start that much smaller, over the trial's extent
of floor: another sample of such turf at each scale), beside the
trial's kept results at 1: per scale, the mean share of floors held and the runs whose best gait
holds on all ten (the goal's "stays a walk under the disturbances", on bumps alone). Not a speed
benchmark: a reproducible measurement (docs/results/strategies/README.md).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks._bumps import kept_best_gaits
from gaitgram.backends.mujoco_horse.model import BUMP_HEIGHT
from gaitgram.backends.mujoco_horse.robustness import disturbed

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "docs" / "results" / "strategies" / "runs" / "arms" / "ge-hybrid"
SCALES = (0.25, 0.5, 0.75)


def main() -> None:
    settings, kept, batch = kept_best_gaits(ARM)
    print(f"GE-hybrid's {len(kept)} best gaits on ten floors, the turf scaled")
    print(f"{'scale':>6} {'bumps cm':>9} {'floors held':>12} {'hold all ten':>13}")
    for scale in SCALES:
        held = [t.held / t.floors for t in disturbed(settings, batch, "bumps", bump_scale=scale)]
        _row(scale, held)
    _row(1.0, kept)


def _row(scale: float, held: list[float]) -> None:
    every = sum(share == 1.0 for share in held)
    print(f"{scale:6.2f} {BUMP_HEIGHT * 100 * scale:9.2f} {np.mean(held):12.0%} {every:>7d} of {len(held)}")
