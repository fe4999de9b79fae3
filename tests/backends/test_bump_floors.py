"""``bump_floors``: a fitness that also plays each gait on seeded floors of bumps, as the robustness
trial does, so that evolution sees uneven ground (the strategies study's pilot: scored on one bump
floor, GE's best gaits held on 82 % of the trial's floors against 23 % scored on the flat)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from benchmarks._populations import generation_zero
from gaitgram.backends.api import Evaluation, GaitStatus, SettingsError
from gaitgram.backends.mujoco_horse import BACKEND, check_settings
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, on_floors
from gaitgram.backends.mujoco_horse.model import BUMP_HEIGHT, bumpy_model
from gaitgram.backends.mujoco_horse.robustness import BUMP_SEEDS
from gaitgram.backends.mujoco_horse.settings import (
    DEFAULT_BUMP_HEIGHT,
    MAX_BUMP_FLOORS,
    TEST_FLOORS,
    HorseSettings,
)
from gaitgram.cli import app
from gaitgram.motion.gait import MotionBatch, motion_batch
from gaitgram.seed import load_seed

runner = CliRunner()
FLOORS = (0, 1)


@pytest.mark.parametrize(
    ("value", "said"),
    [
        (3, "must be a list of floor seeds"),
        ([], "must be a list of floor seeds"),
        ([0, "1"], "must be a whole number"),
        ([0, True], "must be a whole number"),
        ([0, -1], "distinct whole numbers >= 0"),
        ([2, 2], "distinct whole numbers >= 0"),
        (list(range(MAX_BUMP_FLOORS + 1)), f"at most {MAX_BUMP_FLOORS} floors"),
        ([0, 27], "seed 27 is one of the floors the robustness trial tests kept gaits on (26-35)"),
    ],
)
def test_bad_floors_are_refused_naming_the_setting(value: object, said: str) -> None:
    with pytest.raises(SettingsError, match="bump_floors") as refused:
        HorseSettings.from_mapping({"bump_floors": value})
    assert said in str(refused.value)


def test_the_test_floors_are_the_robustness_trial_s_and_flat_runs_keep_their_settings() -> None:
    assert BUMP_SEEDS == TEST_FLOORS
    assert "bump_floors" not in check_settings({})  # runs scored on the flat keep their fingerprints
    assert check_settings({"bump_floors": [4, 0]})["bump_floors"] == (4, 0)
    assert "bumps_fitness" in BACKEND.components({"bump_floors": [0]})
    assert "bumps_fitness" not in BACKEND.components({})
    assert "bump_floors" in BACKEND.scoring_settings


def test_a_gait_scored_on_floors_is_the_mean_or_unviable_where_it_fails() -> None:
    flat = Evaluation(0.2, GaitStatus.OK, {"walk": 1.0}, cycles={"speed": (1.0,)})
    bumpy = [Evaluation(0.4, GaitStatus.OK, {"walk": 0.0}), Evaluation(0.6, GaitStatus.OK, {})]
    scored = on_floors(flat, bumpy, (7, 8))
    assert scored.fitness == pytest.approx((0.2 + 0.4 + 0.6) / 3)
    assert scored.components == {"walk": 1.0, "bumps_fitness": pytest.approx(0.5)}  # judged on the flat
    assert scored.cycles == flat.cycles
    fell = Evaluation(99.0, GaitStatus.FELL, {}, "trunk down to 0.4 m")
    unviable = on_floors(flat, [bumpy[0], fell, Evaluation.unviable(GaitStatus.FLIPPED)], (7, 8, 9))
    assert (unviable.status, unviable.fitness) == (GaitStatus.FELL, 99.0)
    assert unviable.detail == "on bump floor 8: trunk down to 0.4 m"


def seed_and_crouch() -> MotionBatch:
    seed = load_seed().motion_batch()
    crouch = motion_batch([dict.fromkeys(seed.joints, "90")], seed.joints)
    return MotionBatch(seed.joints, np.concatenate([seed.angles, crouch.angles]), (None, None), (None, None))


def test_the_evaluator_scores_each_gait_on_the_flat_and_on_each_floor() -> None:
    batch = seed_and_crouch()
    scored = HorseEvaluator(HorseSettings(bump_floors=FLOORS))
    assert "floors" not in vars(scored)  # built when first scored on: playing a gait plays it on the flat
    walk, crouch = scored.evaluate(batch)
    assert [seed for seed, _ in scored.floors] == list(FLOORS)
    flat = HorseEvaluator(HorseSettings()).evaluate(batch)
    apart = [
        HorseEvaluator(HorseSettings(), model=bumpy_model(None, seed)).evaluate(batch) for seed in FLOORS
    ]
    assert walk.status is GaitStatus.OK
    assert walk.fitness == pytest.approx((flat[0].fitness + apart[0][0].fitness + apart[1][0].fitness) / 3)
    assert walk.components["bumps_fitness"] == pytest.approx((apart[0][0].fitness + apart[1][0].fitness) / 2)
    assert apart[0][0].fitness != flat[0].fitness  # the floors are not flat
    assert {k: v for k, v in walk.components.items() if k != "bumps_fitness"} == flat[0].components
    assert crouch == flat[1]  # falls on the flat: not played on the floors
    (verified,) = scored.verify(batch.take([0]))
    assert verified.fitness == walk.fitness  # checked longer on the flat, scored the same
    assert verified.components["checked_cycles"] == scored.horizon
    scored.close()


def test_a_run_scored_on_floors_is_not_compared_with_one_scored_on_the_flat(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    config = study / "arms" / "gamma" / "config.toml"
    config.write_text(config.read_text() + "[backend_settings]\nbump_floors = [0, 1]\n")
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "r")])
    assert result.exit_code == 2
    assert "scored differently" in result.stderr
    assert "alpha: backend not recorded; " in result.stderr
    assert "gamma: backend not recorded, bump_floors = [0, 1])" in result.stderr
    assert not (tmp_path / "r").exists()
    assert "give --mixed-scoring to report them together" in result.stderr
    alone = runner.invoke(app, ["report", str(study / "arms" / "gamma"), "-o", str(tmp_path / "g")])
    assert alone.exit_code == 0, alone.stderr
    mixed = runner.invoke(app, ["report", str(study), "--mixed-scoring", "-o", str(tmp_path / "m")])
    assert mixed.exit_code == 0, mixed.stderr
    said = (tmp_path / "m" / "summary.md").read_text()
    assert said.index("**Scored differently**") < said.index("| arm | runs |")  # said before the table
    assert "gamma: backend not recorded, bump_floors = [0, 1])" in said
    assert "not to be compared across these arms" in said
    arms = {a["name"]: a for a in json.loads((tmp_path / "m" / "summary.json").read_text())["arms"]}
    assert arms["gamma"]["scoring"] == {"bump_floors": [0, 1]}
    assert "scoring" not in arms["alpha"]  # the flat floor: nothing recorded, as before the setting
    flat = runner.invoke(
        app, ["report", str(study / "arms" / "alpha"), "--mixed-scoring", "-o", str(tmp_path / "a")]
    )
    assert "Scored differently" not in flat.stdout  # one scoring: nothing to say


def test_a_gait_that_fails_on_a_floor_is_not_played_on_the_floors_after_it() -> None:
    """Its evaluation is that failure's whatever the later floors say, so they are spared: the
    same evaluations as every floor scoring every gait that stood, fewer steps."""
    seeds = (0, 1, 2)
    batch = generation_zero("free.gg", 40).take([3, 8, 27, 0, 1, 2, 4, 5, 6, 7])
    flat = HorseEvaluator(HorseSettings())
    apart = [HorseEvaluator(HorseSettings(), model=bumpy_model(None, seed)) for seed in seeds]
    on_flat = flat.evaluate(batch)
    standing = [g for g, evaluation in enumerate(on_flat) if evaluation.status.viable]
    every = [dict(zip(standing, floor.evaluate(batch.take(standing)), strict=True)) for floor in apart]
    assert not every[0][0].status.viable  # the first gait fails on the first floor
    expected = [
        on_floors(on_flat[g], [found[g] for found in every], seeds) if g in standing else on_flat[g]
        for g in range(len(batch))
    ]
    scored = HorseEvaluator(HorseSettings(bump_floors=seeds))
    assert [e.as_record() for e in scored.evaluate(batch)] == [e.as_record() for e in expected]
    # Steps: the flat's, then each floor's on the gaits that stood on the flat and every floor before.
    steps = flat.simulated_steps
    for floor, found in zip(apart, every, strict=True):
        floor.simulated_steps = 0
        floor.evaluate(batch.take(standing))
        steps += floor.simulated_steps
        standing = [g for g in standing if found[g].status.viable]
    assert scored.simulated_steps == steps
    scored.close()


@pytest.mark.parametrize(
    ("settings", "said"),
    [
        ({"bump_floors": [0], "bump_height": 0.2}, "in [0.005, 0.1] (0.04: 4 cm), not 0.2"),
        ({"bump_floors": [0], "bump_height": 0.0}, "in [0.005, 0.1]"),
        ({"bump_floors": [0], "bump_height": "4cm"}, "must be a number"),
        ({"bump_height": 0.04}, "no bump_floors are set: add bump_floors = [0]"),
        ({"bump_hieght": 0.04}, "did you mean bump_height?"),
    ],
)
def test_bad_bump_heights_are_refused_naming_the_setting(settings: dict[str, object], said: str) -> None:
    with pytest.raises(SettingsError, match="bump_h") as refused:
        HorseSettings.from_mapping(settings)
    assert said in str(refused.value)


def test_a_bump_height_sizes_the_scored_floors_and_the_default_is_the_trial_s_2_cm() -> None:
    """``bump_height`` plays the bump floors' same draw taller; left out (or 2 cm), a run keeps the
    fingerprint and every score of the runs made before it."""
    assert "bump_height" not in check_settings({"bump_floors": [0]})
    assert "bump_height" not in check_settings({"bump_floors": [0], "bump_height": 0.02})  # the default
    assert DEFAULT_BUMP_HEIGHT == BUMP_HEIGHT
    assert check_settings({"bump_floors": [0], "bump_height": 0.04})["bump_height"] == 0.04
    assert "bump_height" in BACKEND.scoring_settings  # reports refuse to mix heights unasked
    batch = load_seed().motion_batch()
    (before,) = HorseEvaluator(HorseSettings(bump_floors=(0,))).evaluate(batch)
    (two,) = HorseEvaluator(HorseSettings(bump_floors=(0,), bump_height=0.02)).evaluate(batch)
    assert two.as_record() == before.as_record()
    tall = HorseEvaluator(HorseSettings(bump_floors=(0,), bump_height=0.04))
    (four,) = tall.evaluate(batch)
    (apart,) = HorseEvaluator(HorseSettings(), model=bumpy_model(None, 0, height=0.04)).evaluate(batch)
    assert four.components["bumps_fitness"] == apart.fitness != before.components["bumps_fitness"]
    assert {k: v for k, v in four.components.items() if k != "bumps_fitness"} == {
        k: v for k, v in before.components.items() if k != "bumps_fitness"
    }  # judged on the flat floor as before
    tall.close()
