"""The horizon: what a run keeps has been checked, and a gait that falls after its scored cycles is
never a run's best, never on its front or in its repertoire, never a walk.

A stand-in evaluator scores gaits from their curves without MuJoCo: every gait looks like a
walk over its scored cycles (every walk term but ``sustained``), and one in three "falls at
cycle 4", which only the check over the horizon (``verify``) finds. The last test plays a short
real run on the horse.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from conftest import GRAMMARS
from gaitgram.analysis import check
from gaitgram.backends.api import Evaluation, GaitStatus, VerifyingEvaluator
from gaitgram.backends.mujoco_horse.targets import DEFAULT_WEIGHTS, WALK_COMPONENTS
from gaitgram.configuration import RunConfig
from gaitgram.evolution.checkpoint import load_checkpoint
from gaitgram.evolution.engine import run_evolution
from gaitgram.language import load
from gaitgram.motion.gait import MotionBatch
from gaitgram.pipeline import Pipeline
from gaitgram.strategies.registry import run_pipeline


def _key(angles: np.ndarray) -> float:
    return float(np.abs(angles).sum())


def falls(angles: np.ndarray) -> bool:
    return int(_key(angles) * 1000) % 3 == 0


class FallsAtCycleFour:
    """Looks like a walk over the scored cycles; one gait in three falls at cycle 4, and only
    ``verify`` simulates that far. The fallers score best, so every search wants them."""

    def __init__(self) -> None:
        self.verified: list[float] = []

    def _score(self, angles: np.ndarray) -> float:
        return (0.1 if falls(angles) else 0.3) + (_key(angles) % 1.0) / 10

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        found = []
        for g in range(len(batch)):
            if batch.problems[g] is not None:
                found.append(Evaluation.unviable(GaitStatus.INVALID_GENOME))
                continue
            components = {
                **dict.fromkeys(WALK_COMPONENTS, 1.0),
                "walk_sustained": 0.0,
                "walk": 0.0,
                **dict.fromkeys(DEFAULT_WEIGHTS, 0.1),
                "velocity": self._score(batch.angles[g]),
                "measured_velocity": 1.5,
                "measured_duty_factor": 0.6,
                "checked_cycles": 5.0,
            }
            found.append(Evaluation(self._score(batch.angles[g]), GaitStatus.OK, components))
        return found

    def verify(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        found = []
        for g, evaluation in enumerate(self.evaluate(batch, generation=generation, weights=weights)):
            self.verified.append(_key(batch.angles[g]))
            if not evaluation.status.viable:
                found.append(evaluation)
            elif falls(batch.angles[g]):
                found.append(
                    Evaluation.unviable(GaitStatus.FELL, "trunk down to 0.60 m at 4.400 s (cycle 4)")
                )
            else:
                components = {
                    **evaluation.components,
                    "walk_sustained": 1.0,
                    "walk": 1.0,
                    "checked_cycles": 20.0,
                }
                found.append(replace(evaluation, components=components))
        return found

    def close(self) -> None:
        pass


def pipeline(strategy: str = "ge", **settings: object) -> Pipeline:
    config = RunConfig(generations=6, population=20, elite=2, seed=3, strategy=strategy, **settings)
    return run_pipeline(check(load(GRAMMARS / "sine-walk.gg")), config)


@pytest.mark.parametrize("strategy", ["ge", "random", "nsga2", "map-elites"])
def test_a_gait_that_falls_at_cycle_four_is_never_kept(tmp_path: Path, strategy: str) -> None:
    evaluator = FallsAtCycleFour()
    assert isinstance(evaluator, VerifyingEvaluator)
    settings: dict[str, object] = {}
    if strategy == "map-elites":
        settings["strategy_settings"] = {
            "descriptors": [{"name": "measured_velocity", "low": 0, "high": 3, "bins": 4}]
        }
    run = pipeline(strategy, **settings)
    bests: list[dict] = []

    def record(_run: int, _stats: object) -> None:
        bests.append(json.loads((tmp_path / "best.json").read_text()))
        kept = [*_members(tmp_path, "front.json", "front"), *_members(tmp_path, "archive.json", "elites")]
        for member in kept:  # every gait a front or repertoire holds was checked and stayed up
            assert member["components"]["checked_cycles"] == 20.0

    state = run_evolution(run, evaluator, 0, tmp_path, fingerprint="test", on_generation=record)
    assert evaluator.verified, "nothing was checked over the horizon"
    fallers_checked = [k for k in evaluator.verified if int(k * 1000) % 3 == 0]
    assert fallers_checked, "the search never wanted a faller: the test proves nothing"
    for best in bests:  # every generation's best was checked and is no faller
        assert best["status"] == "ok"
        assert best["components"]["checked_cycles"] == 20.0
    checkpoint = load_checkpoint(
        tmp_path / "checkpoint.json", run, fingerprint="test", run=0, with_memory=False
    )
    for individual in [*state.population, *checkpoint.population]:
        walk = individual.evaluation.components.get("walk", 0.0)
        if walk:
            assert individual.evaluation.components["checked_cycles"] == 20.0
        if individual.evaluation.status is GaitStatus.FELL:
            assert "cycle 4" in (individual.evaluation.detail or "")


def _members(directory: Path, name: str, key: str) -> list[dict]:
    path = directory / name
    return json.loads(path.read_text())[key] if path.exists() else []
