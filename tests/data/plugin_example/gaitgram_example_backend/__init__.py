"""An example gaitgram fitness backend: the bigger the neck swings, the better.

A complete plug-in: a joint catalogue (so @joint names and limits are checked),
a settings-taking ``load``, and an evaluator that scores a whole batch at once.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from gaitgram.backends.api import Evaluation, unusable_evaluations
from gaitgram.backends.catalogue import Joint, JointCatalogue
from gaitgram.backends.registry import BackendSpec
from gaitgram.motion.gait import MotionBatch

CATALOGUE = JointCatalogue(
    (
        Joint("neck", "neck", (-40.0, 40.0), "The whole neck, one curve."),
        Joint("tail", "tail", (-60.0, 60.0), "The tail, scored by nothing: free to do anything."),
    )
)


class NeckSwing:
    def __init__(self, target_amplitude: float) -> None:
        self.target_amplitude = target_amplitude

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        done = unusable_evaluations(batch)  # invalid genomes and motions: already scored
        neck = batch.joints.index("neck")
        amplitude = (batch.angles[:, neck].max(axis=1) - batch.angles[:, neck].min(axis=1)) / 2
        return [
            done.get(g)
            or Evaluation(
                fitness=float(abs(self.target_amplitude - amplitude[g])),
                components={"amplitude": float(amplitude[g])},
            )
            for g in range(len(batch))
        ]

    def close(self) -> None:
        pass


def load(settings: Mapping[str, Any] | None = None) -> NeckSwing:
    return NeckSwing(float((settings or {}).get("target_amplitude", 30.0)))


BACKEND = BackendSpec(
    name="neck-swing",
    summary="Example: rewards a neck that swings by target_amplitude degrees.",
    catalogue=CATALOGUE,
    load=load,
)
