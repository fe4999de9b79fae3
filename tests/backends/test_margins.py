"""The fitness's margins (docs/fitness.md, "Margins"): ``speed_margin`` aims the speed and stride
terms above the walk's targets while the criterion keeps them, and ``footfalls`` measures how far
the footfalls land from the real walk's phases. Both are off by default, and a run without them
scores and records as before (tests/evolution/test_committed_runs.py re-scores every committed
run)."""

from __future__ import annotations

import pytest

from gaitgram.backends.api import GaitStatus, SettingsError
from gaitgram.backends.mujoco_horse import BACKEND, check_settings
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.settings import MAX_SPEED_MARGIN, HorseSettings
from gaitgram.backends.mujoco_horse.targets import DEFAULT_WEIGHTS, PAPER_WEIGHTS
from gaitgram.seed import load_seed


@pytest.mark.parametrize("value", [-0.01, MAX_SPEED_MARGIN + 0.01, "4 %", True])
def test_a_bad_margin_is_refused_naming_the_setting(value: object) -> None:
    with pytest.raises(SettingsError, match="speed_margin"):
        HorseSettings.from_mapping({"speed_margin": value})


def test_margins_are_off_unless_asked_and_a_margin_is_a_scoring_setting() -> None:
    assert "speed_margin" not in check_settings({})  # runs without one keep their fingerprints
    assert check_settings({"speed_margin": 0.04})["speed_margin"] == 0.04
    assert "speed_margin" in BACKEND.scoring_settings  # reports refuse to mix it unasked
    assert DEFAULT_WEIGHTS["footfalls"] == PAPER_WEIGHTS["footfalls"] == 0.0
    assert "footfalls" in BACKEND.components({})
    assert "footfalls" in BACKEND.weight_names({})


def test_the_seed_scored_with_a_margin_moves_only_its_speed_and_stride_terms() -> None:
    batch = load_seed().motion_batch()
    evaluator = HorseEvaluator(HorseSettings())
    (plain,) = evaluator.evaluate(batch)
    (aimed,) = HorseEvaluator(HorseSettings(speed_margin=0.04)).evaluate(batch)
    assert plain.status is aimed.status is GaitStatus.OK
    targets, measured = evaluator.targets, plain.components
    for component, value, target in (
        ("velocity", measured["measured_velocity"], targets.velocity),
        ("stride", measured["measured_stride"], targets.stride_length),
    ):
        assert plain.components[component] == pytest.approx(abs(value - target) / target, rel=1e-12)
        assert aimed.components[component] == pytest.approx(
            abs(value - 1.04 * target) / (1.04 * target), rel=1e-12
        )
    untouched = {k for k in plain.components if k not in ("velocity", "stride")}
    assert {k: aimed.components[k] for k in untouched} == {k: plain.components[k] for k in untouched}
    assert aimed.components["walk"] == plain.components["walk"]  # the criterion keeps its targets
    assert 0 <= plain.components["footfalls"] < 0.10  # the seed is a walk: within the criterion


def test_weighting_footfalls_scores_them() -> None:
    batch = load_seed().motion_batch()
    evaluator = HorseEvaluator(HorseSettings())
    (plain,) = evaluator.evaluate(batch)
    (weighted,) = evaluator.evaluate(batch, weights={**DEFAULT_WEIGHTS, "footfalls": 2.0})
    assert weighted.fitness == pytest.approx(plain.fitness + 2.0 * plain.components["footfalls"])
