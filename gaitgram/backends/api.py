"""The fitness backend plug-in API: what a backend receives and what it returns.

A backend evaluates a whole generation at once (a :class:`MotionBatch`) and
returns one :class:`Evaluation` per gait: a fitness (lower is better), its named
components, and a status. A bad gait is a status, never an exception that takes
the batch down. Backends are registered as :class:`~gaitgram.backends.registry.BackendSpec`
entry points; ``spec.load(settings)`` returns an :class:`Evaluator`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

from gaitgram.motion.problems import MotionProblem

if TYPE_CHECKING:
    from gaitgram.motion.gait import MotionBatch

#: The score of a gait that cannot be judged (fell, flipped, no motion): worse than any real one.
WORST_FITNESS = 1.0e9


class GaitStatus(StrEnum):
    OK = "ok"
    FELL = "fell"  # the trunk came down too low
    FLIPPED = "flipped"  # the trunk rolled or pitched over
    UNSTABLE = "unstable"  # the simulation diverged (MuJoCo warnings, non-finite state)
    INVALID_GENOME = "invalid-genome"
    INVALID_MOTION = "invalid-motion"
    NON_FINITE = "non-finite"

    @property
    def viable(self) -> bool:
        return self is GaitStatus.OK


_FROM_PROBLEM = {
    MotionProblem.INVALID_GENOME: GaitStatus.INVALID_GENOME,
    MotionProblem.INVALID_MOTION: GaitStatus.INVALID_MOTION,
    MotionProblem.NON_FINITE: GaitStatus.NON_FINITE,
}


@dataclass(frozen=True)
class Evaluation:
    """One gait's score. ``components`` are named numbers (the fitness terms, measurements,
    verdicts); ``cycles`` are measures with one value per scored cycle, for backends that score
    cycles one by one (a report shows their spread)."""

    fitness: float
    status: GaitStatus = GaitStatus.OK
    components: Mapping[str, float] = field(default_factory=dict)
    detail: str | None = None
    cycles: Mapping[str, tuple[float, ...]] = field(default_factory=dict)

    @classmethod
    def unviable(cls, status: GaitStatus, detail: str | None = None) -> Evaluation:
        return cls(WORST_FITNESS, status, {}, detail)

    def as_record(self) -> dict[str, Any]:
        record = {
            "fitness": self.fitness,
            "status": self.status.value,
            "components": dict(self.components),
            "detail": self.detail,
        }
        if self.cycles:  # absent for backends that do not measure cycles: their records are unchanged
            record["cycles"] = {name: list(values) for name, values in self.cycles.items()}
        return record


def unusable_evaluations(batch: MotionBatch) -> dict[int, Evaluation]:
    """The gaits a backend need not simulate, already scored: index -> evaluation."""
    return {
        g: Evaluation.unviable(_FROM_PROBLEM[problem], batch.details[g])
        for g, problem in enumerate(batch.problems)
        if problem is not None
    }


@dataclass(frozen=True)
class Verdict:
    """A yes/no judgement a backend makes of each viable gait ("is it a walk?"), declared so that
    generic layers (runs, reports) can select and count such gaits without knowing the backend.

    ``component`` is the 0/1 component that holds it; ``terms`` are the 0/1 components it is the
    conjunction of, in the order a report lists them (so a report can say *why* a gait fails it);
    ``pending`` is the term only a check over the horizon can establish (the evaluator's
    ``verify``): a gait with every other term is a *candidate*, worth that check. ``version``
    names the judgement's revision (``"v2"``), which a report records beside the counts it made
    with it: a revised criterion counts differently.
    """

    component: str
    label: str
    terms: tuple[str, ...] = ()
    pending: str | None = None
    version: str = ""

    def holds(self, evaluation: Evaluation) -> bool:
        return self.holds_in(evaluation.components, viable=evaluation.status.viable)

    def holds_in(self, components: Mapping[str, float], *, viable: bool) -> bool:
        """The verdict read from recorded components (a run's files), for a gait ``viable`` or not."""
        return viable and components.get(self.component, 0.0) >= 0.5

    def candidate(self, evaluation: Evaluation) -> bool:
        """Viable, with every term but the pending one: a verdict that a check could make hold."""
        return evaluation.status.viable and all(
            evaluation.components.get(term, 0.0) >= 0.5 for term in self.terms if term != self.pending
        )

    def failed_terms(self, evaluation: Evaluation) -> tuple[str, ...]:
        return tuple(term for term in self.terms if evaluation.components.get(term, 0.0) < 0.5)

    def sentence(self, evaluation: Evaluation) -> str:
        """The verdict for people, in the backend's words: "a walk by criterion v2", or "not a walk
        by criterion v2: fails walk_footfalls, walk_sustained" (or why it was not judged), so that
        a command can say what its gait is without knowing the backend."""
        by = f" by criterion {self.version}" if self.version else ""
        article = "an" if self.label[:1].lower() in "aeiou" else "a"
        if self.holds(evaluation):
            return f"{article} {self.label}{by}"
        if not evaluation.status.viable:
            return f"not {article} {self.label}{by}: the gait is not viable ({evaluation.status})"
        failed = self.failed_terms(evaluation)
        return f"not {article} {self.label}{by}" + (f": fails {', '.join(failed)}" if failed else "")


@dataclass(frozen=True)
class ReferenceMeasure:
    """One row of a report's realism table: a measure an assessment keeps (``key``: its name in the
    kept ``measures``, or ``CURVE_max`` / ``CURVE_min``, the extreme of a kept curve) as people
    read it (``label``), beside the reference's value (None: the reference does not measure it)
    and what that value is (its spread, or why there is none)."""

    key: str
    label: str
    value: float | None
    spread: str


@dataclass(frozen=True)
class ReferenceCurve:
    """A curve an assessment keeps over one cycle, its title in figures, and the reference's mean
    and SD at as many evenly spaced phases."""

    name: str
    title: str
    mean: tuple[float, ...]
    sd: tuple[float, ...]


@dataclass(frozen=True)
class Assessment:
    """What a backend's ``assess`` keeps of each gait, declared (``BackendSpec.assessment``) so
    that a report reads it as data, without knowing the backend.

    A kept assessment's ``realism`` holds ``measures`` (named numbers), ``scores`` (one per name
    of ``scored``: how far the gait is from the reference in that measure, in its spread), their
    mean ``distance``, and ``curves`` (one per :class:`ReferenceCurve`); its ``trials`` and
    ``graded`` rungs say what each disturbance did. The report's realism section is titled
    ``title`` and opens with ``text`` (what the reference is, how the gaits are measured, what
    the distance means; Markdown); ``measures`` are its table's rows and ``figure`` titles the
    figure of the curves on the reference's band. A trial's ``detail`` lists, comma-separated
    after ``failed_terms``, the verdict's terms a gait failed under it (empty: details are not
    counted).
    """

    title: str
    text: str
    measures: tuple[ReferenceMeasure, ...]
    scored: tuple[str, ...]
    curves: tuple[ReferenceCurve, ...]
    figure: str
    failed_terms: str = ""


@runtime_checkable
class Evaluator(Protocol):
    """A loaded backend. ``evaluate`` is called once per generation with the whole population.

    ``weights`` (component name -> weight) are the fitness weights in force this
    generation (the paper's Table 2); None means the backend's defaults.
    """

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]: ...

    def close(self) -> None: ...


@runtime_checkable
class VerifyingEvaluator(Evaluator, Protocol):
    """An evaluator that can also check gaits over a longer horizon than ``evaluate`` scores: the
    check the gaits a run keeps must pass. ``verify`` returns the same evaluation as ``evaluate``
    (the same fitness), or an unviable one if the gait fails within the horizon, with what the
    check established (the backend's ``Verdict.pending`` term)."""

    def verify(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]: ...


@runtime_checkable
class CountingEvaluator(Evaluator, Protocol):
    """An evaluator that counts the simulation steps it has run (by ``evaluate`` and ``verify``,
    summed over gaits): a physics backend's unit of work. A run records them beside its time in
    the backend (``gaitgram.evolution.usage``), so its cost against the raw simulation comes from
    the run itself. Optional: a run of another backend records its time alone."""

    @property
    def simulated_steps(self) -> int: ...


class SettingsError(ValueError):
    """A backend setting that cannot be used: ``key`` names it (dotted for nested tables)."""

    def __init__(self, key: str, message: str) -> None:
        super().__init__(f"{key}: {message}")
        self.key = key
        self.message = message
