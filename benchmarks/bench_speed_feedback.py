"""The measurements behind the balance README's reading of speed on bumps: what the trial's turf
does to GE-hybrid's best gaits, and whether a speed-feedback term added to them makes them hold it.

The first balance design found the open loop's best gaits upright on every bump floor but not
walking again, on the speed term in 28 of 30 runs, and no bundled grammar read speed. Two tables,
on the committed strategies study's 30 best GE-hybrid gaits (docs/results/strategies/runs, open
loop):

1. **What turf does**: each gait played over the horizon on the flat floor and on the trial's
   first three test floors (seeds 26-28), measured cycle by cycle after the warm-up: the medians
   over gaits of the speed, stride length, stride frequency and duty factor, over the first five
   cycles after the warm-up and the horizon's last five, and how many gaits keep every one of the last five
   cycles within 10 % of the target speed (the walk criterion's speed term).
2. **Speed terms added**: each gait with one term added to (or scaling) its hip and/or shoulder
   curve, played undisturbed (is it still a walk, checked over the horizon?), on the trial's ten
   bump floors and under its two pushes. With ``pace`` the speed as a share of the target
   (1.605 m/s at Froude 0.48 on the default body), the terms, in degrees:

   * **placement** ``+-k*(pace-1)``: the whole curve moved, Raibert's foot placement (Legged
     Robots That Balance, 1986: the foot further ahead when too fast);
   * **amplitude** ``+a*sin(4.8*(1-pace))*sin(2*PI*t+phi)``: the swing's main harmonic (phase phi,
     the seed's) larger when too slow, saturating at ``a`` degrees;
   * **stride** ``(curve)*(1+g*(1-pace))``: the whole curve scaled up when too slow (a longer
     stride at the same frequency), and constant scales for comparison (no feedback: a longer
     stride everywhere).

The gains are set by hand, not evolved: evolution could tune them with the rest of the gait, so a
term that fails here is not shown useless in a grammar; one that helps here is worth the runs.
Not a speed benchmark: a reproducible measurement (docs/results/balance/README.md). About 35
minutes on 2 cores.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.measures import measure_cycles
from gaitgram.backends.mujoco_horse.model import bumpy_model
from gaitgram.backends.mujoco_horse.robustness import disturbed
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.motion.gait import MotionBatch

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "docs" / "results" / "strategies" / "runs" / "arms" / "ge-hybrid"
#: The first cycle measured (the horizon's cycles 0-1 are the warm-up's).
FIRST_CYCLE = 2
#: The test floors the first table plays (the trial's first three).
FLOORS = (26, 27, 28)
#: The seed's main-harmonic phase of the curves given an amplitude term (grammars/hybrid.gg).
HIP_PHASE, SHOULDER_PHASE = 1.18, -2.56
PLACED = ("hip_hind", "shoulder_fore")
#: Each variant: its name and, per curve, a template of its new text (``{}``: the curve's own).
VARIANTS: tuple[tuple[str, dict[str, str]], ...] = (
    ("none (the kept gaits)", {}),
    ("placement +4.8*(pace-1), hip and shoulder", dict.fromkeys(PLACED, "{}+4.8*(pace-1)")),
    ("placement -4.8*(pace-1), hip and shoulder", dict.fromkeys(PLACED, "{}-4.8*(pace-1)")),
    ("amplitude up to 4 deg, hip", {"hip_hind": f"{{}}+4*sin(4.8*(1-pace))*sin(2*PI*t+{HIP_PHASE})"}),
    ("amplitude up to 8 deg, hip", {"hip_hind": f"{{}}+8*sin(4.8*(1-pace))*sin(2*PI*t+{HIP_PHASE})"}),
    (
        "amplitude up to 4 deg, shoulder",
        {"shoulder_fore": f"{{}}+4*sin(4.8*(1-pace))*sin(2*PI*t{SHOULDER_PHASE:+})"},
    ),
    ("stride (1+0.3*(1-pace)), hip and shoulder", dict.fromkeys(PLACED, "({})*(1+0.3*(1-pace))")),
    ("stride (1+0.5*(1-pace)), hip and shoulder", dict.fromkeys(PLACED, "({})*(1+0.5*(1-pace))")),
    ("stride (1+1*(1-pace)), hip and shoulder", dict.fromkeys(PLACED, "({})*(1+1*(1-pace))")),
    ("stride 1.03 (constant), hip and shoulder", dict.fromkeys(PLACED, "({})*1.03")),
    ("stride 1.05 (constant), hip and shoulder", dict.fromkeys(PLACED, "({})*1.05")),
    ("stride 1.08 (constant), hip and shoulder", dict.fromkeys(PLACED, "({})*1.08")),
)


def main() -> None:
    pipeline = RunDirectory.open(ARM).pipeline
    genomes = [
        tuple(json.loads((ARM / f"run-{run:03d}" / "best.json").read_text())["genome"])
        for run in range(pipeline.config.runs)
    ]
    mapped = pipeline.map(genomes)
    generation = pipeline.config.generations
    settings = dict(pipeline.config.backend_settings)
    kept = pipeline.motion(mapped, generation)
    turf_table(settings, kept)
    print()
    evaluator = pipeline.load_evaluator()
    verdict = pipeline.spec.verdict
    assert verdict is not None
    print(f"GE-hybrid's {len(genomes)} best gaits (open loop), a speed term added")
    print(f"{'term':44} {'flat walk':>9} {'bump floors':>11} {'all ten':>7} {'pushes':>6} {'every':>5}")
    for name, templates in VARIANTS:
        joints = [
            {j: templates[j].format(text) if j in templates else text for j, text in m.joints.items()}
            for m in mapped
        ]
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


def turf_table(settings: dict[str, object], batch: MotionBatch) -> None:
    horse = HorseSettings.from_mapping(settings)
    rows = np.arange(len(batch))
    print(f"GE-hybrid's {len(batch)} best gaits cycle by cycle (medians over gaits; first / last 5 cycles)")
    heads = ("speed m/s", "stride m", "stride Hz", "duty")
    print(f"{'floor':10} " + " ".join(f"{h:>13}" for h in heads) + f" {'last 5 in 10 %':>15}")
    for label, model in [("flat", None), *((f"bumps {s}", bumpy_model(horse.body, s, 1.0)) for s in FLOORS)]:
        evaluator = HorseEvaluator(horse, model=model)
        try:
            horizon = evaluator.horizon
            state, sensors, control = evaluator.play(batch, rows, horizon)
            frequencies = evaluator.frequencies(batch, rows)
            scored = evaluator.score(state, sensors, control, {}, frequencies, horizon)
            recordings = evaluator.recordings(state, sensors, control, frequencies)
            target = evaluator.targets.velocity
            cycles = [
                measure_cycles(r, FIRST_CYCLE, horizon, evaluator.gap_steps)
                for e, r in zip(scored, recordings, strict=True)
                if e.status.viable
            ]
        finally:
            evaluator.close()
        speed = np.array([c.speed for c in cycles])
        columns = [
            speed,
            np.array([np.nanmean(c.stride_length, axis=1) for c in cycles]),
            np.array([np.nanmean(c.stride_frequency, axis=1) for c in cycles]),
            np.array([c.duty_factor.mean(axis=1) for c in cycles]),
        ]
        kept = int((np.abs(speed[:, -5:] / target - 1) <= 0.1).all(axis=1).sum())
        shown = " ".join(f"{np.median(x[:, :5]):6.3f}/{np.median(x[:, -5:]):6.3f}" for x in columns)
        print(f"{label:10} {shown} {kept:>9} of {len(cycles)}")
