"""The mujoco-horse backend: targets, controls, metrics, statuses, determinism."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gaitgram.backends.api import WORST_FITNESS, GaitStatus
from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, HorseSettings
from gaitgram.backends.mujoco_horse.targets import duty_factor_for, walk_targets
from gaitgram.backends.registry import get_backend
from gaitgram.motion.gait import motion_batch

JOINTS = CATALOGUE.names
#: Gentle limb swings: the horse shuffles, lifting its hooves, without falling.
WALKISH = {
    "shoulder_fore": "5*sin(2*PI*t)",
    "elbow_fore": "10*sin(2*PI*t+1)+5",
    "carpal_fore": "10*sin(2*PI*t+1.5)+7.5",
    "hip_hind": "5*sin(2*PI*t)",
    "stifle_hind": "7.5*sin(2*PI*t+1)+2.5",
    "tarsal_hind": "7.5*sin(2*PI*t+1.5)+5",
}
#: Hind limbs folded hard: the hindquarters come down.
COLLAPSE = {"hip_hind": "40", "stifle_hind": "60", "tarsal_hind": "60", "fetlock_hind": "60"}


@pytest.fixture(scope="module")
def evaluator() -> HorseEvaluator:
    ev = HorseEvaluator(HorseSettings(threads=2))
    yield ev
    ev.close()


def test_targets_from_the_froude_number() -> None:
    t = walk_targets(0.48, 1.14)
    assert t.velocity == pytest.approx(0.48 * math.sqrt(9.81 * 1.14))
    assert t.stride_length == pytest.approx(1.14 * 2.3 * (0.48**2) ** 0.3)
    assert t.stride_frequency == pytest.approx(t.velocity / t.stride_length)
    # A horse's walk: 1.35-2.05 m/s, strides 1.6-1.9 m at about 0.9 Hz, duty factor 0.6-0.65.
    assert 1.35 < t.velocity < 2.05
    assert 1.6 < t.stride_length < 1.9
    assert 0.8 < t.stride_frequency < 1.0
    assert 0.6 < t.duty_factor < 0.66
    assert duty_factor_for(0.0) == 0.75
    assert duty_factor_for(1.0) == 0.45
    assert t.phase_offsets == {"hind_left": 0.0, "fore_left": 0.25, "hind_right": 0.5, "fore_right": 0.75}
    with pytest.raises(ValueError, match="froude"):
        walk_targets(0)


def test_controls_follow_the_curves_with_limb_phases(evaluator: HorseEvaluator) -> None:
    batch = motion_batch([{"hip_hind": "10*sin(2*PI*t)"}], JOINTS)
    control = evaluator.controls(batch, np.array([0]))[0]  # [steps, actuators]
    layout = evaluator.layout
    left, right = layout.curve_actuators["hip_hind"]
    after_ramp = slice(evaluator.ramp_steps, None)
    offset_left = control[after_ramp, left] - layout.neutral_ctrl[left]
    offset_right = control[after_ramp, right] - layout.neutral_ctrl[right]
    assert np.abs(offset_left).max() == pytest.approx(math.radians(10), rel=1e-3)
    # Right hind is half a cycle after left hind: its curve is the left one negated.
    np.testing.assert_allclose(offset_right, -offset_left, atol=1e-3)
    neck = layout.curve_actuators["neck_mid"][0]
    np.testing.assert_allclose(control[:, neck], layout.neutral_ctrl[neck])  # undriven: neutral
    assert (control[: evaluator.ramp_steps // 4, left] - layout.neutral_ctrl[left]).max() < math.radians(3)


def test_standing_walking_and_falling_are_told_apart(evaluator: HorseEvaluator) -> None:
    batch = motion_batch([{}, WALKISH, COLLAPSE, None, {"hip_hind": "1/(t-t)"}], JOINTS)
    stand, walk, fall, invalid, bad = evaluator.evaluate(batch)
    assert stand.status is GaitStatus.OK
    assert abs(stand.components["measured_velocity"]) < 0.02
    assert stand.components["measured_duty_factor"] == pytest.approx(1.0)
    assert walk.status is GaitStatus.OK
    assert walk.components["measured_duty_factor"] < 0.95  # hooves leave the ground
    assert fall.status in (GaitStatus.FELL, GaitStatus.FLIPPED)
    assert fall.fitness == WORST_FITNESS
    assert stand.fitness < fall.fitness
    assert invalid.status is GaitStatus.INVALID_GENOME
    assert bad.status is GaitStatus.INVALID_MOTION
    assert {"velocity", "duty_factor", "stride", "energy"} <= walk.components.keys()


def test_same_batch_same_results_with_one_and_two_threads() -> None:
    rng = np.random.default_rng(4)
    gaits = [
        {j: f"{rng.uniform(-15, 15):.2f}*sin(2*PI*t+{rng.uniform(0, 6):.2f})" for j in JOINTS}
        for _ in range(6)
    ]
    batch = motion_batch(gaits, JOINTS)
    one, two = (
        HorseEvaluator(HorseSettings(threads=1, cycles=1)),
        HorseEvaluator(HorseSettings(threads=2, cycles=1)),
    )
    try:
        assert [e.as_record() for e in one.evaluate(batch)] == [e.as_record() for e in two.evaluate(batch)]
    finally:
        one.close()
        two.close()


def test_weights_change_the_fitness_not_the_components(evaluator: HorseEvaluator) -> None:
    batch = motion_batch([WALKISH], JOINTS)
    (default,) = evaluator.evaluate(batch)
    (energy_only,) = evaluator.evaluate(batch, weights={"energy": 1.0})
    assert default.components == energy_only.components
    assert energy_only.fitness == pytest.approx(default.components["energy"])


def test_settings_are_validated() -> None:
    with pytest.raises(ValueError, match="unknown mujoco-horse setting"):
        get_backend("mujoco-horse").load({"frode": 0.3})
    with pytest.raises(ValueError, match="cycles"):
        HorseSettings.from_mapping({"cycles": 0})


def test_render_writes_a_gif_and_a_strip(tmp_path: Path) -> None:
    grammar = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
    env = {**os.environ, "MUJOCO_GL": "egl"}
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "gaitgram",
            "render",
            str(grammar),
            "--genome",
            "5,17,3,99,1000,42,7,8,9,10,11,12,13",
            "--max-wraps",
            "10",
            "-o",
            str(tmp_path / "walk.gif"),
            "--fps",
            "5",
        ],
        capture_output=True,
        text=True,
        env=env,
    )
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "walk.gif").read_bytes()[:6] == b"GIF89a"
    assert (tmp_path / "walk.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.slow  # a horse run, then a render
def test_render_the_best_of_a_run(tmp_path: Path) -> None:
    grammar = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
    env = {**os.environ, "MUJOCO_GL": "egl", "COLUMNS": "300"}  # usage errors unwrapped

    def gaitgram(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True, env=env
        )

    evolve = gaitgram(
        "evolve", str(grammar), "--generations", "1", "--population", "8", "-o", str(tmp_path / "r"), "-q"
    )
    assert evolve.returncode == 0, evolve.stderr
    render = gaitgram("render", "--run", str(tmp_path / "r"), "-o", str(tmp_path / "best.gif"), "--fps", "4")
    assert render.returncode == 0, render.stderr
    assert (tmp_path / "best.gif").stat().st_size > 1000
    missing = gaitgram("render", "--run", str(tmp_path), "-o", str(tmp_path / "x.gif"))
    assert missing.returncode == 2
    assert "not a `gaitgram evolve` run directory" in missing.stderr


@pytest.mark.parametrize("count", [300, pytest.param(3_000, marks=pytest.mark.slow)])
def test_thousands_of_random_free_grammar_phenotypes_are_all_scored(count: int) -> None:
    """Fig. 5's free grammar as printed (bare expressions, with / and *) makes wild curves:
    divisions by zero, huge values. None may break a batch. (grammars/free.gg is the tamed
    version that passes `gaitgram test`.)

    A short simulation (one cycle) keeps this to seconds a batch; the code path is the full one.
    300 gaits in the default run, 3,000 (three batches) in the slow one.
    """
    from gaitgram.analysis import check
    from gaitgram.ge import compile_mapper
    from gaitgram.ge.initialisation import ramped_population
    from gaitgram.language import parse

    figure_5 = "\n".join(
        [
            "@backend mujoco-horse",
            "<prog> ::= " + ";".join(f"<{joint}>" for joint in JOINTS),
            *(f"@joint {joint}\n<{joint}> ::= <expr>" for joint in JOINTS),
            "<expr> ::= <expr><op><expr> | (<expr><op><expr>) | <pre-op>(<expr>*t) | <var>",
            "<op> ::= + | - | / | *",
            "<pre-op> ::= sin | cos",
            "<var> ::= float[0..10 step 0.5] | t",
        ]
    )
    checked = check(parse(figure_5))
    assert not checked.errors
    mapper = compile_mapper(checked.grammar, max_wraps=0)
    trees = ramped_population(checked.facts, np.random.default_rng(11), count, max_depth=7)
    phenotypes = [m.joints for m in mapper.map_many([t.genome for t in trees])]
    assert all(phenotypes)  # valid derivations: every one a phenotype
    evaluator = HorseEvaluator(HorseSettings(cycles=1, ramp_seconds=0.1, threads=2))
    statuses: dict[GaitStatus, int] = {}
    try:
        for start in range(0, len(phenotypes), 1000):
            batch = motion_batch(phenotypes[start : start + 1000], JOINTS)
            results = evaluator.evaluate(batch)
            assert len(results) == len(batch)
            for result in results:
                assert math.isfinite(result.fitness)
                statuses[result.status] = statuses.get(result.status, 0) + 1
    finally:
        evaluator.close()
    assert sum(statuses.values()) == count
    assert statuses.get(GaitStatus.OK, 0) > 0
    assert statuses.get(GaitStatus.INVALID_MOTION, 0) > 0  # Fig. 5 divides by zero now and then


def test_the_seed_walk_scores_better_than_standing_which_beats_falling(evaluator: HorseEvaluator) -> None:
    """The ordering that makes the fitness meaningful, on grammars/hybrid.gg's unchanged seed."""
    from gaitgram.ge import compile_mapper
    from gaitgram.language import load
    from gaitgram.seed.grammars import seed_genome

    grammar = load(Path(__file__).resolve().parents[2] / "grammars" / "hybrid.gg")
    mapped = compile_mapper(grammar).map_fast(seed_genome(grammar))
    assert mapped.valid
    seed_walk, standing, falling = evaluator.evaluate(motion_batch([mapped.joints, {}, COLLAPSE], JOINTS))
    assert seed_walk.status is GaitStatus.OK
    assert standing.status is GaitStatus.OK
    assert falling.status in (GaitStatus.FELL, GaitStatus.FLIPPED)
    assert seed_walk.fitness < standing.fitness < falling.fitness
    assert seed_walk.components["measured_duty_factor"] < 0.9  # it steps
