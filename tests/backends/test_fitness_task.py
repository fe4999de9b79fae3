"""The walking task's formula: capped components, the finite unviable score, the walk criterion."""

from __future__ import annotations

import pytest

from gaitgram.backends.api import Evaluation, GaitStatus
from gaitgram.backends.mujoco_horse import BACKEND
from gaitgram.backends.mujoco_horse.task import (
    COMPONENT_CAP,
    DEFAULT_WEIGHTS,
    PAPER_WEIGHTS,
    GaitMetrics,
    fitness_components,
    is_walk,
    unviable_fitness,
    walk_targets,
    weighted_fitness,
)
from gaitgram.pipeline import honest

TARGETS = walk_targets()


def test_components_are_capped_and_stride_is_not_velocity() -> None:
    absurd = GaitMetrics(
        velocity=100.0, duty_factor=0.6, stride_length=0.5, stride_frequency=3.0, work_per_cycle=1e9
    )
    components = fitness_components(absurd, TARGETS, 500.0)
    assert components["velocity"] == components["energy"] == COMPONENT_CAP
    assert components["stride"] == pytest.approx(abs(0.5 - TARGETS.stride_length) / TARGETS.stride_length)
    assert components["frequency"] == pytest.approx(
        abs(3.0 - TARGETS.stride_frequency) / TARGETS.stride_frequency
    )


def test_an_unviable_gait_scores_worse_than_any_viable_one_yet_finitely() -> None:
    worst_viable = GaitMetrics(-50.0, 0.0, -9.0, 99.0, 1e12)
    for weights in (DEFAULT_WEIGHTS, PAPER_WEIGHTS):
        viable = weighted_fitness(fitness_components(worst_viable, TARGETS, 500.0), weights)
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


def test_a_walk_is_near_the_target_speed_and_duty_factor() -> None:
    v, d = TARGETS.velocity, TARGETS.duty_factor
    assert is_walk(GaitMetrics(v * 1.09, d - 0.049, 1.0, 1.0, 1.0), TARGETS)
    assert not is_walk(GaitMetrics(v * 1.11, d, 1.0, 1.0, 1.0), TARGETS)
    assert not is_walk(GaitMetrics(v, d + 0.06, 1.0, 1.0, 1.0), TARGETS)
