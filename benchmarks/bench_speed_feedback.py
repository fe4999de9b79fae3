"""The measurement behind the balance README's reading of speed feedback: do GE-hybrid's best
gaits hold the bump floors when a speed-feedback term is added to them?

The first balance design found the open loop's best gaits upright on every bump floor but not
walking again, on the speed term in 28 of 30 runs: on turf the horse walks too slowly, and no
bundled grammar reads ``speed``. Before evolving a grammar that does (two to three hours an arm
here), this asks the cheap question: the committed strategies study's 30 best GE-hybrid gaits
(docs/results/strategies/runs, open loop), each with one speed term added to its hip and/or
shoulder curve, played undisturbed (is it still a walk, checked over the horizon?), on the
trial's ten bump floors and under its two pushes. The terms, in degrees, with the task's target
speed ``V`` (1.605 m/s at Froude 0.48 and the default body):

* **placement**: ``+-k*(speed-V)``, an offset of the limb's whole curve, Raibert's foot placement
  (Legged Robots That Balance, 1986: the foot placed further ahead of the hip when too fast);
* **amplitude**: ``+a*sin(3*(V-speed))*sin(2*PI*t+phi)``, the swing's main harmonic (phase phi of
  the seed's) made larger when too slow, saturating at ``a`` degrees.

The gains are not evolved: evolution could tune them with the rest of the gait, so a term that
fails here is not shown useless in a grammar; one that helps here would be worth the runs. Not a
speed benchmark: a reproducible measurement (docs/results/balance/README.md).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from gaitgram.backends.mujoco_horse.robustness import disturbed
from gaitgram.evolution.rundir import RunDirectory

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "docs" / "results" / "strategies" / "runs" / "arms" / "ge-hybrid"
#: The task's target speed (m/s) at the arm's settings (Froude 0.48, the default body).
TARGET_SPEED = 1.605
#: The seed's main-harmonic phase of each curve given an amplitude term (grammars/hybrid.gg).
MAIN_PHASE = {"hip_hind": 1.18, "shoulder_fore": -2.56}
#: Each variant: its name and, per curve, the text appended to it.
VARIANTS: tuple[tuple[str, dict[str, str]], ...] = (
    ("none (the kept gaits)", {}),
    ("placement +3 deg per m/s, hip and shoulder", dict.fromkeys(MAIN_PHASE, f"+3*(speed-{TARGET_SPEED})")),
    ("placement -3 deg per m/s, hip and shoulder", dict.fromkeys(MAIN_PHASE, f"-3*(speed-{TARGET_SPEED})")),
    ("amplitude up to 4 deg, hip", {"hip_hind": f"+4*sin(3*({TARGET_SPEED}-speed))*sin(2*PI*t+1.18)"}),
    ("amplitude up to 8 deg, hip", {"hip_hind": f"+8*sin(3*({TARGET_SPEED}-speed))*sin(2*PI*t+1.18)"}),
    (
        "amplitude up to 4 deg, shoulder",
        {"shoulder_fore": f"+4*sin(3*({TARGET_SPEED}-speed))*sin(2*PI*t-2.56)"},
    ),
)


def main() -> None:
    directory = RunDirectory.open(ARM)
    pipeline = directory.pipeline
    genomes = [
        tuple(json.loads((ARM / f"run-{run:03d}" / "best.json").read_text())["genome"])
        for run in range(pipeline.config.runs)
    ]
    mapped = pipeline.map(genomes)
    generation = pipeline.config.generations
    settings = dict(pipeline.config.backend_settings)
    evaluator = pipeline.load_evaluator()
    verdict = pipeline.spec.verdict
    assert verdict is not None
    print(f"GE-hybrid's {len(genomes)} best gaits (open loop), a speed term added (V = {TARGET_SPEED} m/s)")
    print(f"{'term added':44} {'flat walk':>9} {'bump floors':>11} {'all ten':>7} {'pushes':>6} {'every':>5}")
    for name, terms in VARIANTS:
        joints = [{j: text + terms.get(j, "") for j, text in m.joints.items()} for m in mapped]
        batch = pipeline.motion(
            [m._replace(joints=j) for m, j in zip(mapped, joints, strict=True)], generation
        )
        flat = evaluator.verify(batch, generation=generation, weights=pipeline.weights_at(generation))
        trials = {d: disturbed(settings, batch, d) for d in ("bumps", "push-forward", "push-backward")}
        walks = [verdict.holds(e) for e in flat]
        held = [t.held / t.floors for t in trials["bumps"]]
        pushed = [
            trials["push-forward"][g].holds and trials["push-backward"][g].holds for g in range(len(batch))
        ]
        every = [w and all(trials[d][g].holds for d in trials) for g, w in enumerate(walks)]
        print(
            f"{name:44} {sum(walks):>5} /{len(batch)} {np.mean(held):11.0%} {sum(h == 1 for h in held):>7}"
            f" {sum(pushed):>6} {sum(every):>5}"
        )
