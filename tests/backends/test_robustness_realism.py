"""Kept gaits beyond their scores: disturbance trials and the realism distance, on the horse."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from conftest import ROOT
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.joints import CATALOGUE
from gaitgram.backends.mujoco_horse.model import BUMP_HEIGHT, FLAT_START, bumpy_model
from gaitgram.backends.mujoco_horse.realism import _scores, assess, mean_phases
from gaitgram.backends.mujoco_horse.reference import CURVES, MEASURES, real_walks
from gaitgram.backends.mujoco_horse.robustness import (
    BUMP_SEEDS,
    DISTURBANCES,
    PUSH_PHASE,
    PUSH_SECONDS,
    PUSH_SHARE,
    Trial,
    _on_every_floor,
    _push,
    disturbed,
    on_floor,
)
from gaitgram.motion.gait import MotionBatch, motion_batch
from gaitgram.seed import load_seed

CROUCH = dict.fromkeys(CATALOGUE.names, "90")  # every joint flexed to its limit: the horse sinks


def seed_and_crouch() -> MotionBatch:
    seed = load_seed().motion_batch()
    crouch = motion_batch([CROUCH], seed.joints)
    return MotionBatch(seed.joints, np.concatenate([seed.angles, crouch.angles]), (None, None), (None, None))


@pytest.mark.slow
def test_the_seed_recovers_from_a_backward_push_and_a_falling_gait_holds_under_nothing() -> None:
    batch = seed_and_crouch()
    for disturbance in DISTURBANCES:
        seed, crouch = disturbed({}, batch, disturbance.name)
        assert seed.upright, (disturbance.name, seed.detail)  # the seed walk stays up under each
        assert not crouch.upright
        assert not crouch.holds
        assert crouch.detail
        assert "down to" in crouch.detail
        assert crouch.held == 0
        floors = len(BUMP_SEEDS) if disturbance.name == "bumps" else 1
        assert (seed.floors, crouch.floors) == (floors, floors)
        assert 0 <= seed.held <= floors
        assert seed.holds == (seed.held == floors)
    (backward, _) = disturbed({}, batch, "push-backward")
    assert backward.holds, backward.detail
    again = disturbed({}, batch, "push-backward")
    assert [(t.upright, t.walking, t.detail) for t in again] == [
        (t.upright, t.walking, t.detail) for t in disturbed({}, batch, "push-backward")
    ]  # deterministic
    with pytest.raises(ValueError, match="no disturbance named 'shove'"):
        disturbed({}, batch, "shove")
    # One floor of the bumps, played alone, is that floor of the disturbance: the seed's count of
    # floors held is the sum over floors, and each floor's trial names what it lost.
    floors = [on_floor({}, batch, seed) for seed in BUMP_SEEDS]
    (bumps_seed, _) = disturbed({}, batch, "bumps")
    assert sum(floor[0].holds for floor in floors) == bumps_seed.held
    assert all(not floor[1].upright and "down to" in (floor[1].detail or "") for floor in floors)
    lost = [floor[0].detail for floor in floors if not floor[0].holds]
    assert all(detail and detail.startswith("not walking again: ") for detail in lost)


def test_a_push_is_a_share_of_body_weight_on_the_trunk_for_a_tenth_of_a_second() -> None:
    evaluator = HorseEvaluator()
    batch = load_seed().motion_batch()
    forces = _push(evaluator, batch, [(-PUSH_SHARE, PUSH_PHASE)], 6000)
    trunk = evaluator.layout.trunk_body
    pushed = np.flatnonzero(forces[0, :, trunk * 6])
    assert len(pushed) == round(PUSH_SECONDS / evaluator.dt)
    weight = evaluator.layout.total_mass * 9.81
    assert forces[0, pushed[0], trunk * 6] == pytest.approx(-PUSH_SHARE * weight)
    assert np.count_nonzero(forces) == len(pushed)  # nothing else pushed
    assert pushed[0] * evaluator.dt > evaluator.settings.ramp_seconds + 1.5  # after the warm-up


def test_each_bumpy_floor_is_flat_where_the_horse_stands_and_bumped_ahead_its_own_way() -> None:
    fields = []
    for seed in BUMP_SEEDS:
        model = bumpy_model(None, seed)
        field = model.hfield_data.reshape(model.hfield_nrow[0], model.hfield_ncol[0])
        assert field.min() == 0.0
        assert field.max() == pytest.approx(1.0)
        assert model.hfield_size[0][2] == BUMP_HEIGHT
        centre = model.geom_pos[0][0]
        x = centre + np.linspace(-model.hfield_size[0][0], model.hfield_size[0][0], field.shape[1])
        assert not field[:, x < FLAT_START].any()
        assert field[:, x > FLAT_START + 1].mean() > 0.3
        fields.append(field)
    assert len(BUMP_SEEDS) >= 10
    assert all(not np.array_equal(fields[0], other) for other in fields[1:])  # ten turfs, not one


def test_a_scaled_floor_has_bumps_and_cells_scaled_and_the_trials_extent() -> None:
    """``bumpy_model(body, seed, scale)``: the trial's floor at scale 1 (the very model); at a body's
    length scale, bumps, cells and the flat start that many times the trial's over the same extent
    of floor (benchmarks/bench_scaled_bumps.py)."""
    assert bumpy_model(None, 26, 1.0) is bumpy_model(None, 26)
    trial, scaled = bumpy_model("shetland", 26), bumpy_model("shetland", 26, 0.5)
    assert scaled.hfield_size[0][2] == pytest.approx(0.5 * trial.hfield_size[0][2])  # bump height
    assert list(scaled.hfield_size[0][:2]) == list(trial.hfield_size[0][:2])  # the same floor
    assert scaled.geom_pos[0][0] == trial.geom_pos[0][0]
    assert (scaled.hfield_ncol[0] - 1, scaled.hfield_nrow[0] - 1) == (
        2 * (trial.hfield_ncol[0] - 1),
        2 * (trial.hfield_nrow[0] - 1),
    )  # cells half as wide
    field = scaled.hfield_data.reshape(scaled.hfield_nrow[0], scaled.hfield_ncol[0])
    half = scaled.hfield_size[0][0]
    x = scaled.geom_pos[0][0] + np.linspace(-half, half, field.shape[1])
    assert not field[:, x < 0.5 * FLAT_START].any()
    assert field[:, (x > 0.5 * FLAT_START + 0.1) & (x < FLAT_START)].any()  # bumps begin sooner


def test_a_gait_holds_the_bumps_only_on_every_floor_and_says_where_it_did_not() -> None:
    held = Trial("bumps", True, True, None, held=1)
    fell = Trial("bumps", False, False, "fell: trunk down to 0.4 m")
    slowed = Trial("bumps", True, False, "not walking again: speed")
    trials = [held] * len(BUMP_SEEDS)
    assert _on_every_floor("bumps", trials) == Trial(
        "bumps", True, True, None, len(BUMP_SEEDS), len(BUMP_SEEDS)
    )
    one_off = _on_every_floor("bumps", [held, held, slowed, fell, *trials[4:]])
    assert not one_off.holds
    assert (one_off.upright, one_off.walking) == (False, False)
    assert (one_off.floors, one_off.held) == (len(BUMP_SEEDS), len(BUMP_SEEDS) - 2)
    assert one_off.detail == (
        f"held on {len(BUMP_SEEDS) - 2} of {len(BUMP_SEEDS)} floors; on seed {BUMP_SEEDS[2]}: "
        "not walking again: speed"
    )
    stopped = _on_every_floor("bumps", [slowed, *trials[1:]])
    assert (stopped.upright, stopped.walking, stopped.held) == (True, False, len(BUMP_SEEDS) - 1)


def test_the_realism_distance_is_zero_at_the_real_walks_median() -> None:
    real = real_walks()
    assert real == json.loads((ROOT / "seeds" / "dlc_walk.json").read_text())  # shipped copy
    lands = real["phase_after_left_hind"]
    measures = {
        "duty_factor": real["duty_factor"]["median"],
        "phase_fore_left": lands["LeftFrontHoof"]["median"],
        "phase_hind_right": lands["RightHindHoof"]["median"],
        "phase_fore_right": lands["RightFrontHoof"]["median"],
    }
    curves = {name: np.array(real["curves"][name]["mean"]) for name in CURVES}
    assert _scores(measures, curves) == dict.fromkeys(MEASURES, 0.0)
    low, high = real["duty_factor"]["iqr"]
    at_quartile = _scores({**measures, "duty_factor": high}, curves)
    assert at_quartile["duty_factor"] == pytest.approx(
        1.349 * (high - real["duty_factor"]["median"]) / (high - low)
    )
    shifted = {
        **curves,
        "fetlock_fore": curves["fetlock_fore"] + np.array(real["curves"]["fetlock_fore"]["sd"]),
    }
    assert _scores(measures, shifted)["fetlock_fore"] == pytest.approx(1.0)


def test_the_seed_is_measured_beside_the_real_walks() -> None:
    (seed, crouch) = assess({}, seed_and_crouch())
    assert crouch is None  # falls: nothing to measure
    assert seed is not None
    assert set(seed.scores) == set(MEASURES)
    assert seed.scores["duty_factor"] < 0.5  # 0.58 against the real 0.588
    assert seed.scores["phase_hind_right"] < 0.5
    assert 0 < seed.distance < 2
    for name in CURVES:
        assert seed.curves[name].shape == (20,)
        assert np.ptp(seed.curves[name]) > 10  # the limbs swing


def test_a_hoof_that_never_lands_leaves_its_phase_unmeasured_without_a_warning() -> None:
    phases = np.array([[0.0, 0.25, np.nan, 0.75], [0.0, 0.27, np.nan, np.nan]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's "Mean of empty slice" reached the user's terminal
        mean = mean_phases(phases)
        assert np.isnan(mean_phases(np.empty((0, 4)))).all()
    np.testing.assert_array_equal(mean, [0.0, 0.26, np.nan, 0.75])


def test_the_graded_trials_disturbances_have_the_sizes_they_say() -> None:
    """Pushes of 40 % are twice the force of 20 %, at eight distinct steps of the cycle; a slope
    tilts gravity by its angle; 4 cm bumps are the 2 cm floors' draw, twice as tall."""
    from gaitgram.backends.mujoco_horse.robustness import PUSH_PHASES, sloped_model

    evaluator = HorseEvaluator()
    batch = load_seed().motion_batch().take([0] * len(PUSH_PHASES))
    trunk = evaluator.layout.trunk_body * 6
    small = _push(evaluator, batch, [(0.2, p) for p in PUSH_PHASES], 6000)
    large = _push(evaluator, batch, [(-0.4, p) for p in PUSH_PHASES], 6000)
    assert np.array_equal(large, -2 * small)
    starts = [int(np.flatnonzero(small[g, :, trunk])[0]) for g in range(len(PUSH_PHASES))]
    period = 1 / (evaluator.targets.stride_frequency * evaluator.dt)
    assert np.allclose(np.diff(starts), period / 8, atol=1)
    up = sloped_model(None, 6.0)
    g = np.linalg.norm(up.opt.gravity)
    assert np.degrees(np.arctan2(-up.opt.gravity[0], -up.opt.gravity[2])) == pytest.approx(6.0)
    assert g == pytest.approx(9.81)
    assert sloped_model(None, -3.0).opt.gravity[0] > 0  # downhill: pulled forward
    two, four = bumpy_model(None, BUMP_SEEDS[0]), bumpy_model(None, BUMP_SEEDS[0], 1.0, 2 * BUMP_HEIGHT)
    assert np.array_equal(two.hfield_data, four.hfield_data)
    assert four.hfield_size[0, 2] == pytest.approx(2 * two.hfield_size[0, 2])
