"""A backend whose worker dies the first time it evaluates: for testing lost-worker retries.

It kills its own process (as an out-of-memory kill or a lost machine would) on
the first call, when the marker file does not exist yet; afterwards it scores
like ``curve-match``.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from gaitgram.backends.api import Evaluation
from gaitgram.backends.curve_match import CurveMatch
from gaitgram.backends.registry import BackendSpec
from gaitgram.motion.gait import MotionBatch


class CrashOnce:
    def __init__(self, marker: Path, targets: Mapping[str, str]) -> None:
        self.marker = marker
        self.inner = CurveMatch(targets)

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        if not self.marker.exists():
            self.marker.write_text(str(os.getpid()))
            os._exit(1)
        return self.inner.evaluate(batch, generation=generation, weights=weights)

    def close(self) -> None:
        pass


def load(settings: Mapping[str, Any] | None = None) -> CrashOnce:
    settings = settings or {}
    return CrashOnce(Path(settings["marker"]), dict(settings["targets"]))


BACKEND = BackendSpec(
    name="crash-once", summary="Test backend: kills its worker once.", catalogue=None, load=load
)
