"""Does a closed loop's feedback hold the disturbances, or the curves it came with? An ablation.

Each best gait of a closed-loop arm is played twice: as evolved, and with its feedback cut
(``MotionBatch.opened``: each curve played open loop as its nominal, every sensor held at its
resting reading; for ``cycle_pace``, 1, the stride gain's factor ``1+g*(1-cycle_pace)`` is 1 and
the curves are the open-loop ones the gait was evolved with). Both are checked for a walk over
the horizon on the flat floor (criterion v2), under today's trial (the 20 % pushes forward and
backward, the ten 2 cm bump floors), on the graded trial's ten 4 cm floors and on the 3 degree
slope down. Paired counts and exact McNemar tests
(scipy's binomial test on the discordant pairs) say whether the feedback is what holds.

A second table says why a 4 cm floor is lost: the speed of each of the horizon's last five cycles
(the ones a disturbed gait must walk again in; the walk criterion holds every one within 10 % of
the target), as a share of the target, per play that stayed upright: the medians over plays of
their mean, slowest and fastest cycle, and the share of plays whose every cycle is within 10 %.

    python -m benchmarks feedback_ablation [--arm DIR] [--runs N]

Default arm: docs/results/balance-cycle-stride/runs/arms/ge-hybrid-cycle-stride-4cm. Not a speed
benchmark: a reproducible measurement (docs/results/balance-cycle-stride/README.md). About 9
minutes for 30 gaits on 2 cores.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from scipy.stats import binomtest

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.measures import measure_cycles
from gaitgram.backends.mujoco_horse.model import BUMP_HEIGHT, bumpy_model
from gaitgram.backends.mujoco_horse.robustness import BUMP_SEEDS, RECOVERY_CYCLES, Rung, disturbed, on_rung
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError
from gaitgram.motion.gait import MotionBatch

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "docs" / "results" / "balance-cycle-stride" / "runs" / "arms" / "ge-hybrid-cycle-stride-4cm"


def outcomes(settings: dict[str, object], batch: MotionBatch) -> dict[str, list[int]]:
    """Per gait of ``batch``: 1/0 per test, and the 4 cm floors held (0-10)."""
    horse = HorseSettings.from_mapping(settings)
    evaluator = HorseEvaluator(horse)
    try:
        flat = evaluator.verify(batch, weights={})
    finally:
        evaluator.close()
    walk = [int(e.status.viable and e.components.get("walk") == 1.0) for e in flat]
    trial = {name: disturbed(settings, batch, name) for name in ("push-forward", "push-backward", "bumps")}
    four = on_rung(settings, batch, Rung("bumps", 4, "cm"))
    down = on_rung(settings, batch, Rung("slope-down", 3, "deg"))
    n = len(batch)
    return {
        "walk": walk,
        "pushes": [int(all(trial[p][g].holds for p in ("push-forward", "push-backward"))) for g in range(n)],
        "2 cm floors (all ten)": [int(trial["bumps"][g].holds) for g in range(n)],
        "today's trial (walk, all)": [
            walk[g] * int(all(trial[name][g].holds for name in trial)) for g in range(n)
        ],
        "4 cm floors (all ten)": [int(t.holds) for t in four],
        "4 cm floors held": [t.held for t in four],
        "3 deg down": [int(t.holds) for t in down],
    }


def last_cycle_speeds(settings: dict[str, object], batch: MotionBatch) -> np.ndarray:
    """Per play (gait x 4 cm floor) that stayed upright, its last five cycles' speeds / target."""
    horse = HorseSettings.from_mapping(settings)
    rows = np.arange(len(batch))
    found = []
    for seed in BUMP_SEEDS:
        evaluator = HorseEvaluator(horse, model=bumpy_model(horse.body, seed, 1.0, 2 * BUMP_HEIGHT))
        try:
            horizon = evaluator.horizon
            state, sensors, control = evaluator.play(batch, rows, horizon)
            frequencies = evaluator.frequencies(batch, rows)
            scored = evaluator.score(state, sensors, control, {}, frequencies, horizon)
            recordings = evaluator.recordings(state, sensors, control, frequencies)
            found += [
                measure_cycles(r, horizon - RECOVERY_CYCLES, horizon, evaluator.gap_steps).speed
                / evaluator.targets.velocity
                for e, r in zip(scored, recordings, strict=True)
                if e.status.viable
            ]
        finally:
            evaluator.close()
    return np.array(found)


def main(argv: list[str] | None = None) -> None:
    arm = Path(argv[argv.index("--arm") + 1]) if argv and "--arm" in argv else ARM
    try:
        pipeline = RunDirectory.open(arm).pipeline
    except RunDirectoryError as error:
        raise SystemExit(f"--arm: {error}") from None
    runs = sorted(arm.glob("run-*/best.json"))
    if argv and "--runs" in argv:
        given = argv[argv.index("--runs") + 1 :][:1]
        if not given or not given[0].isdigit() or int(given[0]) < 1:
            raise SystemExit(f"--runs takes a whole number of runs, at least 1, not {' '.join(given)!r}")
        runs = runs[: int(given[0])]
    mapped = pipeline.map([tuple(json.loads(path.read_text())["genome"]) for path in runs])
    generation = pipeline.config.generations
    evolved = pipeline.motion(mapped, generation)
    if not evolved.closed_loop:
        raise SystemExit(f"{arm}: no best gait reads a sensor; there is no feedback to cut")
    ablated = evolved.opened()
    settings = dict(pipeline.config.backend_settings)
    with_loop, without = outcomes(settings, evolved), outcomes(settings, ablated)
    print(f"the {len(runs)} best gaits of {arm}: feedback as evolved, and cut (open loop, sensors at rest)")
    print(f"{'test':28} {'evolved':>8} {'cut':>8} {'only evolved':>13} {'only cut':>9} {'McNemar p':>10}")
    for test in with_loop:
        a, b = np.asarray(with_loop[test]), np.asarray(without[test])
        if test == "4 cm floors held":
            better, worse = int((a > b).sum()), int((a < b).sum())
            p = binomtest(better, better + worse).pvalue if better + worse else 1.0
            print(
                f"{test:28} {a.sum():>5}/{10 * len(a)} {b.sum():>4}/{10 * len(b)} {better:>13} {worse:>9} "
                f"{p:>10.3f}  (gaits holding more floors; sign test)"
            )
            continue
        only_a, only_b = int((a > b).sum()), int((a < b).sum())
        p = binomtest(only_a, only_a + only_b).pvalue if only_a + only_b else 1.0
        print(f"{test:28} {a.sum():>5}/{len(a)} {b.sum():>5}/{len(b)} {only_a:>13} {only_b:>9} {p:>10.3f}")
    print()
    print("4 cm floors, the horizon's last five cycles: speed / target (medians over upright plays)")
    print(f"{'feedback':10} {'plays':>6} {'mean':>6} {'slowest':>8} {'fastest':>8} {'all within 10 %':>16}")
    for label, batch in (("evolved", evolved), ("cut", ablated)):
        speeds = last_cycle_speeds(settings, batch)
        within = float((np.abs(speeds - 1) <= 0.1).all(axis=1).mean())
        print(
            f"{label:10} {len(speeds):>6} {np.median(speeds.mean(axis=1)):>6.3f} "
            f"{np.median(speeds.min(axis=1)):>8.3f} {np.median(speeds.max(axis=1)):>8.3f} {within:>16.0%}"
        )
