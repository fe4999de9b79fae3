"""What a run spent in its backend, recorded by the run itself: per generation, the wall seconds
inside the evaluator's ``evaluate`` and ``verify`` and, from a backend that counts them
(:class:`~gaitgram.backends.api.CountingEvaluator`), the simulation steps it ran.

So a run's cost against the raw simulation (``python -m benchmarks evolve``'s ratio) comes from
the run, not from running it again. The figures are kept in ``backend.json`` beside the run's
checkpoint, one entry per generation, and summed where a run directory's ``summary.json`` and a
study's report show them. They are measurements, not results: a resumed run keeps the entries of
the generations its checkpoint holds and adds its own, so its steps are the uninterrupted run's
(the evaluations are deterministic) and its seconds are what this machine took. A generation's
entry is written before its checkpoint: a kill between the two leaves an entry that the resume
redoes and replaces. The totals say how many generations they cover (a run resumed from a
checkpoint made before runs recorded their usage counts only the generations after it).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gaitgram import jsonio
from gaitgram.backends.api import CountingEvaluator, Evaluation, Evaluator, VerifyingEvaluator
from gaitgram.fileio import write_atomically
from gaitgram.runlayout import USAGE as USAGE_FILE

if TYPE_CHECKING:
    from gaitgram.motion.gait import MotionBatch

__all__ = [
    "USAGE_FILE",
    "GenerationUsage",
    "Meter",
    "RunUsage",
    "UsageError",
    "metered",
    "read_usage",
    "recorded",
    "write_usage",
]

_FORMAT = 1


class UsageError(ValueError):
    """A ``backend.json`` that cannot be read; the message names it and says what to do."""


@dataclass(frozen=True)
class GenerationUsage:
    """One generation's time inside the backend (wall seconds) and steps simulated (None: the
    backend does not count them)."""

    generation: int
    seconds: float
    steps: int | None

    def as_record(self) -> dict[str, Any]:
        return {"generation": self.generation, "backend_seconds": self.seconds, "simulated_steps": self.steps}


@dataclass(frozen=True)
class RunUsage:
    """The generations of a run whose usage is recorded, in order."""

    generations: tuple[GenerationUsage, ...]

    @property
    def seconds(self) -> float:
        return math.fsum(g.seconds for g in self.generations)

    @property
    def steps(self) -> int | None:
        """Steps over the recorded generations; None if the backend does not count them."""
        if not self.generations or any(g.steps is None for g in self.generations):
            return None
        return sum(g.steps for g in self.generations)  # type: ignore[misc]

    def as_record(self) -> dict[str, Any]:
        """Totals, as a run directory's ``summary.json`` shows them."""
        return {
            "simulated_steps": self.steps,
            "backend_seconds": self.seconds,
            "generations_counted": len(self.generations),
        }


def read_usage(run_dir: Path) -> RunUsage | None:
    """The usage ``run_dir`` records, None if it records none (a run made before runs recorded
    it); UsageError if the file is damaged."""
    path = run_dir / USAGE_FILE
    try:
        data = jsonio.read_object(path, _EXPECTED)
    except jsonio.ObjectError as error:
        if error.missing:
            return None
        raise UsageError(f"{error}; {_FIX}") from None
    return RunUsage(_entries(data, path))


_EXPECTED = f'a gaitgram usage record (expected {{"format": {_FORMAT}, "generations": [...]}})'
_FIX = "delete it to go on without the run's backend time and steps (they are measurements, not results)"


def _entries(data: dict[str, Any], path: Path) -> tuple[GenerationUsage, ...]:
    def bad(what: str) -> UsageError:
        return UsageError(f"{path}: {what}; {_FIX}")

    if data.get("format") != _FORMAT or not isinstance(data.get("generations"), list):
        raise bad(f"not {_EXPECTED}")
    found: list[GenerationUsage] = []
    for k, entry in enumerate(data["generations"]):
        if not isinstance(entry, Mapping):
            raise bad(f"generations[{k}] is not a record")
        generation, seconds, steps = (
            entry.get(key) for key in ("generation", "backend_seconds", "simulated_steps")
        )
        if not _count(generation) or (found and generation <= found[-1].generation):
            raise bad(
                f"generations[{k}].generation must be a whole number after the one before, not {generation!r}"
            )
        if isinstance(seconds, bool) or not isinstance(seconds, int | float) or seconds < 0:
            raise bad(f"generations[{k}].backend_seconds must be a number >= 0, not {seconds!r}")
        if steps is not None and not _count(steps):
            raise bad(f"generations[{k}].simulated_steps must be a whole number >= 0 or null, not {steps!r}")
        found.append(GenerationUsage(generation, float(seconds), steps))
    return tuple(found)


def _count(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def write_usage(run_dir: Path, usage: RunUsage) -> None:
    record = {"format": _FORMAT, "generations": [g.as_record() for g in usage.generations]}
    write_atomically(run_dir / USAGE_FILE, jsonio.dumps(record, indent=1) + "\n")


class Meter:
    """A run's evaluator with its time inside ``evaluate`` (and ``verify``) and its steps metered:
    :meth:`take` hands what was spent since the last take."""

    def __init__(self, inner: Evaluator) -> None:
        self.inner = inner
        self._seconds = 0.0
        self._steps = self._count()

    def _count(self) -> int | None:
        return self.inner.simulated_steps if isinstance(self.inner, CountingEvaluator) else None

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        start = time.perf_counter()
        try:
            return self.inner.evaluate(batch, generation=generation, weights=weights)
        finally:
            self._seconds += time.perf_counter() - start

    def take(self, generation: int) -> GenerationUsage:
        """What was spent since the last take (or since metering began), as ``generation``'s."""
        steps = self._count()
        spent = None if steps is None or self._steps is None else steps - self._steps
        taken = GenerationUsage(generation, self._seconds, spent)
        self._seconds, self._steps = 0.0, steps
        return taken

    def close(self) -> None:
        self.inner.close()


class _VerifyingMeter(Meter):
    """A meter of an evaluator that can verify: verifies too, metered (the run checks what it keeps)."""

    def verify(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        assert isinstance(self.inner, VerifyingEvaluator)
        start = time.perf_counter()
        try:
            return self.inner.verify(batch, generation=generation, weights=weights)
        finally:
            self._seconds += time.perf_counter() - start


def metered(evaluator: Evaluator) -> Meter:
    """``evaluator`` metered, verifying where it verifies (so the run checks what it checked)."""
    return _VerifyingMeter(evaluator) if isinstance(evaluator, VerifyingEvaluator) else Meter(evaluator)


def recorded(entries: Sequence[GenerationUsage], generation: int) -> list[GenerationUsage]:
    """The entries of generations ``0..generation`` (a resumed run redoes the ones after)."""
    return [entry for entry in entries if entry.generation <= generation]
