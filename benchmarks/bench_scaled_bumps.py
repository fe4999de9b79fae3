"""The measurement behind the retarget study's question of bump size: do the other bodies' best
gaits hold on bumps scaled to the body as they hold on the horse's 2 cm?

The robustness trial plays every body on the same turf: bumps up to 2 cm in 10 cm cells. A Shetland
(hip 0.69 m) meets them as a horse would meet 3.3 cm ones. Here each run's best gait of each arm of
the committed retarget study (docs/results/retarget/runs) is played on the trial's ten floors (seeds
26-35) with turf scaled by the body's length scale (its standing hip height over the horse's: bumps,
cells and the flat start that many times the trial's, as dynamic similarity scales a body; the
floor's extent is the trial's, so each is another sample of such turf), and the floors it holds
on are set beside
the ones it held on the trial's turf (its kept ``assessment.json``), paired by run (Wilcoxon
signed-rank). Not a speed benchmark: a reproducible measurement (docs/results/retarget/README.md,
"What the transfer does not change").
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy import stats

from benchmarks._bumps import kept_best_gaits
from gaitgram.backends.mujoco_horse.model import BUMP_HEIGHT, horse_layout
from gaitgram.backends.mujoco_horse.robustness import disturbed

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "docs" / "results" / "retarget" / "runs" / "arms"


def main() -> None:
    horse = horse_layout(None).hip_height
    print(
        "per arm: the mean share of the ten bump floors its runs' best gaits hold on, on the trial's "
        f"turf ({BUMP_HEIGHT * 100:.0f} cm bumps, kept) and on turf scaled to the body; paired by run"
    )
    widths = {"scale": 6, "bumps cm": 9, "gaits": 6, "trial": 6, "scaled": 7, "Wilcoxon p": 11}
    print(f"{'arm':<20} " + " ".join(f"{name:>{width}}" for name, width in widths.items()))
    for arm in sorted(STUDY.iterdir()):
        settings, kept, batch = kept_best_gaits(arm)
        scale = horse_layout(settings.get("body")).hip_height / horse
        scaled = [t.held / t.floors for t in disturbed(settings, batch, "bumps", bump_scale=scale)]
        differs = any(a != b for a, b in zip(kept, scaled, strict=True))
        p = stats.wilcoxon(kept, scaled).pvalue if differs else 1.0
        print(
            f"{arm.name:<20} {scale:6.3f} {BUMP_HEIGHT * 100 * scale:9.2f} {len(kept):6d} "
            f"{np.mean(kept):6.0%} {np.mean(scaled):7.0%} {p:11.4f}"
        )
