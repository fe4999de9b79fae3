"""The walking task without MuJoCo: measures, walk criterion v2 and fitness over synthetic recordings.

Each recording is built from a gait with known answers (speed, duty factor, footfall phases,
stride), so every measure and every walk term is checked against what it must be, and each
term is shown to fail on the gait that breaks it: a gait accelerating through the window, a trot,
a pace, a diagonal-sequence walk, a gait that drags a hoof, a gait that pitches.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from gaitgram.backends.api import Evaluation, GaitStatus
from gaitgram.backends.mujoco_horse import BACKEND
from gaitgram.backends.mujoco_horse.measures import (
    HOOVES,
    Recording,
    measure_cycles,
    touchdowns,
    window,
)
from gaitgram.backends.mujoco_horse.targets import (
    COMPONENT_CAP,
    DEFAULT_WEIGHTS,
    PAPER_WEIGHTS,
    WALK_COMPONENTS,
    WALK_TERMS,
    unviable_fitness,
    walk_targets,
)
from gaitgram.backends.mujoco_horse.task import (
    fitness_components,
    footfall_error,
    walk_terms,
    weighted_fitness,
)
from gaitgram.pipeline import honest

HIP = 1.1388
TARGETS = walk_targets(0.48, HIP)
DT = 0.002
RAMP = 250  # steps
GAP = 100  # 0.2 s
#: The real walk's footfalls after the left hind (DLC_Horse medians), in HOOVES order.
WALK = (0.0, 0.25, 0.5, 0.731)


def recording(
    *,
    frequency: float = TARGETS.stride_frequency,
    speed: float | Callable[[np.ndarray], np.ndarray] = TARGETS.velocity,
    duty: float | Sequence[float] = 0.6,
    offsets: Sequence[float] = WALK,
    cycles: int = 8,
    pitch: Callable[[np.ndarray], np.ndarray] | None = None,
    power: float = 1000.0,
) -> Recording:
    """A gait with known answers: the trunk at ``speed`` after the ramp (standing before), each hoof
    down for ``duty`` of every cycle from its offset on, and still on the ground while down."""
    steps = RAMP + round(cycles / (frequency * DT))
    t = np.arange(steps + 1) * DT
    after = np.clip(t - RAMP * DT, 0.0, None)
    velocity = speed(after) if callable(speed) else np.full_like(after, speed)
    velocity = np.where(t > RAMP * DT, velocity, 0.0)
    trunk_x = np.concatenate([[0.0], np.cumsum(velocity[1:] * DT)])
    duties = np.broadcast_to(np.asarray(duty, dtype=float), (len(HOOVES),))
    contact = np.ones((steps + 1, len(HOOVES)), dtype=bool)
    hoof_x = np.zeros((steps + 1, len(HOOVES)))
    for h, (offset, share) in enumerate(zip(offsets, duties, strict=True)):
        phase = np.mod(frequency * after - offset, 1.0)
        down = (phase < share) | (t <= RAMP * DT)
        contact[:, h] = down
        # While down the hoof stays where it landed: under the trunk at touchdown.
        landed = np.maximum.accumulate(np.where(down & ~np.roll(down, 1), np.arange(steps + 1), 0))
        hoof_x[:, h] = trunk_x[landed]
    tilt = pitch(t) if pitch is not None else np.zeros_like(t)
    return Recording(
        timestep=DT,
        frequency=frequency,
        ramp_steps=RAMP,
        trunk_x=trunk_x,
        trunk_z=np.full_like(t, 1.2),
        pitch=tilt,
        roll=np.zeros_like(t),
        contact=contact,
        hoof_x=hoof_x,
        power=np.full_like(t, power),
    )


def measured(rec: Recording, first: int = 2, last: int = 5):
    return measure_cycles(rec, first, last, GAP)


def terms(rec: Recording, first: int = 2, last: int = 5) -> dict[str, bool]:
    return walk_terms(measured(rec, first, last), TARGETS)


# ---- measures -------------------------------------------------------------------------------


def test_a_steady_walk_measures_what_it_was_built_with() -> None:
    rec = recording()
    cycles = measured(rec)
    f, v = TARGETS.stride_frequency, TARGETS.velocity
    np.testing.assert_allclose(cycles.speed, v, rtol=1e-3)
    np.testing.assert_allclose(cycles.duty_factor, 0.6, atol=0.01)
    np.testing.assert_allclose(cycles.stride_length, v / f, rtol=2e-3)
    np.testing.assert_allclose(cycles.stride_frequency, f, rtol=2e-3)
    np.testing.assert_allclose(cycles.work, 1000.0 / f, rtol=2e-3)
    np.testing.assert_allclose(cycles.phases, np.tile(WALK, (3, 1)), atol=0.005)
    means = window(cycles)
    assert means.velocity == pytest.approx(v, rel=1e-3)
    assert means.speed_spread < 1e-3
    assert means.power == pytest.approx(1000.0)


def test_touchdowns_need_a_gap_off_the_ground_and_standing_is_not_one() -> None:
    contact = np.ones((1000, 1), dtype=bool)  # standing: no footfall
    assert len(touchdowns(contact, GAP)[0]) == 0
    contact[300:350] = False  # a 50-step lift: chatter, not a stride
    contact[500:700] = False  # a 200-step swing: a footfall at 700
    assert touchdowns(contact, GAP)[0].tolist() == [700]


def test_a_hoof_that_never_lifts_took_no_stride() -> None:
    rec = recording(duty=(1.0, 0.6, 0.6, 0.6))
    means = window(measured(rec))
    f, v = TARGETS.stride_frequency, TARGETS.velocity
    assert means.stride_length == pytest.approx(0.75 * v / f, rel=2e-3)  # three hooves of four
    assert not terms(rec)["stride_length"]


def test_cycles_are_the_gaits_own() -> None:
    slow = recording(frequency=0.6, speed=1.0, cycles=6)
    cycles = measured(slow, 2, 5)
    np.testing.assert_allclose(cycles.stride_frequency, 0.6, rtol=2e-3)
    np.testing.assert_allclose(cycles.stride_length, 1.0 / 0.6, rtol=2e-3)
    assert len(cycles) == 3
    with pytest.raises(ValueError, match="covers"):
        measured(slow, 5, 8)


# ---- walk criterion v2, term by term --------------------------------------------------------


def test_a_real_walk_at_the_target_passes_every_term() -> None:
    assert all(terms(recording()).values())
    assert {f"walk_{t.name}" for t in WALK_TERMS} == set(WALK_COMPONENTS)
    assert "sustained" not in terms(recording())  # only the check over the horizon can say


def test_a_gait_accelerating_through_the_window_is_not_steady() -> None:
    v = TARGETS.velocity
    rec = recording(speed=lambda t: v * np.minimum(0.5 + 0.12 * t, 1.05))  # still gaining speed
    found = terms(rec)
    assert not found["steady"]
    assert not found["speed"]  # its first scored cycle is more than 10 % slow
    spread = window(measured(rec)).speed_spread / v
    assert spread > 0.05
    assert fitness_components(window(measured(rec)), TARGETS, 500.0, 0.0)["steadiness"] == pytest.approx(
        spread
    )


@pytest.mark.parametrize(
    ("offsets", "duty", "why"),
    [
        ((0.0, 0.5, 0.5, 0.0), 0.45, "trot: diagonal pairs land together"),
        ((0.0, 0.0, 0.5, 0.5), 0.6, "pace: lateral pairs land together"),
        ((0.0, 0.75, 0.5, 0.25), 0.6, "diagonal sequence: the fores in the wrong order"),
    ],
)
def test_other_footfall_patterns_are_not_a_walk(offsets: tuple[float, ...], duty: float, why: str) -> None:
    found = terms(recording(offsets=offsets, duty=duty))
    assert not found["footfalls"], why
    assert found["speed"], why  # the same speed: only the footfalls tell


def test_duty_factor_window() -> None:
    low, high = TARGETS.duty_window
    assert low == 0.55
    assert high == pytest.approx(TARGETS.duty_factor + 0.05)
    assert terms(recording(duty=0.58))["duty_factor"]
    assert not terms(recording(duty=0.5))["duty_factor"]
    assert not terms(recording(duty=0.75))["duty_factor"]


def test_strides_must_be_a_real_horses_at_that_speed() -> None:
    # The revision-3 "walks": 1.85 m/s in quick, short steps at 1.45 Hz (Alexander: 1.84 m, 1 Hz).
    quick = terms(recording(frequency=1.45, speed=1.85))
    assert not quick["stride_length"]
    assert not quick["stride_frequency"]
    assert not quick["speed"]
    # At the target speed but in steps 20 % too short: stride terms fail alone.
    short = terms(recording(frequency=TARGETS.stride_frequency * 1.2))
    assert not short["stride_length"]
    assert not short["stride_frequency"]
    assert short["speed"]


def test_the_trunk_must_stay_level() -> None:
    assert terms(recording(pitch=lambda t: 3 * np.sin(2 * math.pi * t)))["trunk"]  # 6 degrees of range
    assert not terms(recording(pitch=lambda t: 5 * np.sin(2 * math.pi * t)))["trunk"]  # 10 of range
    assert not terms(recording(pitch=lambda t: np.full_like(t, 12.0)))["trunk"]  # nose up 12 degrees


@given(
    first=st.integers(min_value=2, max_value=5),
    extra=st.integers(min_value=1, max_value=5),
    # Clear of the bounds (speed 0.9-1.1 of the target, duty 0.55-0.69), where steps round.
    speed=st.one_of(st.floats(0.8, 0.89), st.floats(0.91, 1.09), st.floats(1.11, 1.2)),
    duty=st.one_of(st.floats(0.45, 0.54), st.floats(0.56, 0.68), st.floats(0.70, 0.8)),
)
def test_more_cycles_of_the_same_gait_never_change_a_verdict(
    first: int, extra: int, speed: float, duty: float
) -> None:
    """Terms hold per cycle, so a window's verdict is the conjunction of its cycles': a walk over
    cycles 2-4 is one over any longer window of the same steady gait, and a failure stays one."""
    rec = recording(speed=TARGETS.velocity * speed, duty=duty, cycles=first + 3 + extra + 1)
    short = terms(rec, first, first + 3)
    longer = terms(rec, first, first + 3 + extra)
    assert short == longer


# ---- fitness --------------------------------------------------------------------------------


def test_components_are_capped_and_stride_is_not_velocity() -> None:
    absurd = window(measured(recording(frequency=3.0, speed=12.0, power=1e9)))
    components = fitness_components(absurd, TARGETS, 500.0, 0.0)
    assert components["velocity"] == components["energy"] == COMPONENT_CAP
    assert components["stride"] == pytest.approx(
        abs(absurd.stride_length - TARGETS.stride_length) / TARGETS.stride_length
    )
    assert components["frequency"] == pytest.approx(
        abs(absurd.stride_frequency - TARGETS.stride_frequency) / TARGETS.stride_frequency
    )


def test_footfalls_measure_how_far_each_hoof_lands_from_the_real_walks_phase() -> None:
    """The walk built on the real walk's phases scores about 0 (the steps' rounding); moving the
    left fore 0.05 earlier costs a third of 0.05 (one hoof of three), under the criterion's 0.10
    (still a walk); a trot's footfalls are far off; a hoof that never lands counts a whole cycle."""
    assert footfall_error(measured(recording())) == pytest.approx(0.0, abs=0.003)
    early = measured(recording(offsets=(0.0, 0.20, 0.5, 0.731)))
    assert footfall_error(early) == pytest.approx(0.05 / 3, abs=0.003)
    assert walk_terms(early, TARGETS)["footfalls"]
    trot = footfall_error(measured(recording(offsets=(0.0, 0.5, 0.5, 0.0))))
    assert trot == pytest.approx((0.25 + 0.0 + 0.731) / 3, abs=0.003)
    dragging = measured(recording(duty=(0.6, 1.0, 0.6, 0.6)))  # the left fore never lifts
    assert footfall_error(dragging) == pytest.approx(1.0 / 3, abs=0.003)


def test_a_speed_margin_moves_the_speed_and_stride_aims_and_nothing_else() -> None:
    """At margin 0 the components are the same bits as without one; at 0.04 a gait 4 % faster on
    4 % longer strides scores 0 on speed and stride, and the other components do not move."""
    fast = window(measured(recording(speed=TARGETS.velocity * 1.04, frequency=TARGETS.stride_frequency)))
    plain = fitness_components(fast, TARGETS, 500.0, 0.01)
    assert fitness_components(fast, TARGETS, 500.0, 0.01, 0.0) == plain
    aimed = fitness_components(fast, TARGETS, 500.0, 0.01, 0.04)
    assert plain["velocity"] == pytest.approx(0.04, abs=1e-3)
    assert aimed["velocity"] == pytest.approx(0.0, abs=1e-3)
    assert aimed["stride"] == pytest.approx(abs(fast.stride_length / (1.04 * TARGETS.stride_length) - 1))
    assert {k: v for k, v in aimed.items() if k not in ("velocity", "stride")} == {
        k: v for k, v in plain.items() if k not in ("velocity", "stride")
    }
    assert aimed["footfalls"] == 0.01


def test_energy_is_a_cost_of_transport_at_the_target_speed() -> None:
    means = window(measured(recording(power=2000.0)))
    energy = fitness_components(means, TARGETS, 500.0, 0.0)["energy"]
    assert energy == pytest.approx(2000.0 / (500.0 * 9.81 * TARGETS.velocity))


def test_an_unviable_gait_scores_worse_than_any_viable_one_yet_finitely() -> None:
    worst = window(measured(recording(frequency=2.0, speed=-30.0, duty=0.1, power=1e12)))
    for weights in (DEFAULT_WEIGHTS, PAPER_WEIGHTS):
        viable = weighted_fitness(fitness_components(worst, TARGETS, 500.0, 0.0), weights)
        assert viable <= COMPONENT_CAP * sum(weights.values())
        assert unviable_fitness(weights) == 2 * COMPONENT_CAP * sum(weights.values()) > viable
    assert unviable_fitness(PAPER_WEIGHTS) == 40.0
    # The pipeline gives every unviable evaluation the backend's penalty under the weights in force.
    fell = honest(
        Evaluation.unviable(GaitStatus.FELL, "trunk down"), BACKEND.unviable_fitness({}, PAPER_WEIGHTS)
    )
    assert (fell.status, fell.fitness) == (GaitStatus.FELL, 40.0)
    nan = honest(Evaluation(1.0, GaitStatus.OK, {"velocity": float("nan")}), 7.0)
    assert (nan.status, nan.fitness) == (GaitStatus.NON_FINITE, 7.0)
    assert BACKEND.unviable_fitness({}, None) == unviable_fitness(DEFAULT_WEIGHTS)


def test_the_backend_declares_its_walk_verdict() -> None:
    verdict = BACKEND.verdict
    assert verdict is not None
    assert verdict.component == "walk"
    assert verdict.terms == WALK_COMPONENTS
    every = dict.fromkeys(WALK_COMPONENTS, 1.0)
    candidate = Evaluation(0.3, GaitStatus.OK, {**every, "walk_sustained": 0.0, "walk": 0.0})
    assert verdict.candidate(candidate)
    assert not verdict.holds(candidate)
    assert verdict.failed_terms(candidate) == ("walk_sustained",)
    walk = Evaluation(0.3, GaitStatus.OK, {**every, "walk": 1.0})
    assert verdict.holds(walk)
    assert not verdict.holds(Evaluation.unviable(GaitStatus.FELL))
    trot = Evaluation(0.3, GaitStatus.OK, {**every, "walk_footfalls": 0.0, "walk": 0.0})
    assert not verdict.candidate(trot)
