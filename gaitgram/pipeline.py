"""From genome to score: the one path that every command takes.

A :class:`Pipeline` is built from a checked grammar and a resolved
:class:`~gaitgram.configuration.RunConfig`, and does, in order:

    genomes --map--> phenotypes --motion--> joint curves --evaluate--> evaluations

with the run's representation (GE's codons by default, :mod:`gaitgram.ge.registry`) and its
settings, its sample count, the joint freedom schedule of the grammar's ``@joint free=``
annotations, the backend and settings of the config and the weights of its schedule. ``evolve``,
``evaluate``, ``render`` and studies all build one, so they cannot disagree
about any of these; a run directory records everything needed to build the
same pipeline again (:mod:`gaitgram.evolution.rundir`).

Building refuses, with a message that names the key and the fix, anything that
would make the numbers mean something other than what they say: a grammar with
errors, backend or representation settings their plug-in does not know, a weight that no
component has, depths the grammar cannot fit in, codons too small to reach every choice.
The pipeline knows no search strategy and no run: a run's strategy is checked
against it one floor up (:func:`gaitgram.strategies.registry.run_pipeline`).
Evaluating checks what comes back: a gait is only ``ok`` if its fitness and
every component are finite.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from gaitgram.analysis import CheckResult
from gaitgram.analysis.facts import GrammarFacts
from gaitgram.analysis.motion_text import sensors_lacking
from gaitgram.backends.api import (
    WORST_FITNESS,
    Evaluation,
    Evaluator,
    GaitStatus,
    SettingsError,
    VerifyingEvaluator,
)
from gaitgram.backends.registry import (
    BackendLoadError,
    BackendNotFound,
    BackendSpec,
    backends_that,
    get_backend,
)
from gaitgram.configuration import RunConfig
from gaitgram.ge.initialisation import InitialisationError
from gaitgram.ge.mapper import MapperError
from gaitgram.ge.registry import (
    Compiled,
    Genome,
    Mapped,
    RepresentationLoadError,
    RepresentationNotFound,
    RepresentationSpec,
    get_representation,
)
from gaitgram.language.model import Grammar
from gaitgram.motion.gait import MotionBatch, Sensors, motion_batch

#: The backend of a grammar that names none and a config that names none.
DEFAULT_BACKEND = "mujoco-horse"


def sensors_of(spec: BackendSpec) -> Sensors | None:
    """A backend's sensors as the motion layer takes them (None: it declares none)."""
    catalogue = spec.sensors
    if catalogue is None or not len(catalogue):
        return None
    return Sensors(catalogue.names, catalogue.periodic, tuple(sorted(catalogue.nominal().items())))


class PipelineError(ValueError):
    """A grammar, config or backend that cannot make a trustworthy pipeline; says why and how to fix."""

    def __init__(self, message: str, *, key: str | None = None) -> None:
        super().__init__(message)
        #: The run.toml key at fault, if one is, dotted from the top (``backend_settings.weights``),
        #: for a file's line and column.
        self.key = key


def settings_error(table: str, error: SettingsError) -> PipelineError:
    """A backend's or strategy's settings error, as the ``[table]`` key at fault."""
    top = error.key.split("[", 1)[0]  # objectives[0] is written as objectives = [...]
    return PipelineError(f"[{table}] {error.key}: {error.message}", key=f"{table}.{top}")


@dataclass(frozen=True)
class Individual:
    """A genome with what the pipeline made of it (``used``: how much of it the mapping read)."""

    genome: Genome
    used: int
    phenotype: str | None
    joints: Mapping[str, str]
    evaluation: Evaluation

    @property
    def fitness(self) -> float:
        return self.evaluation.fitness


@dataclass(frozen=True, eq=False)
class Pipeline:
    """Build with :meth:`build`; immutable, and cheap to keep for a whole run."""

    checked: CheckResult
    #: Resolved: ``backend`` is set and ``backend_settings`` are the backend's normalised settings.
    config: RunConfig
    spec: BackendSpec
    #: The run's representation, compiled for the grammar: maps, initialises and varies genomes.
    representation: Compiled
    #: The curves of a motion batch, in the backend's order (its catalogue's, else the grammar's).
    joints: tuple[str, ...]

    @classmethod
    def build(cls, checked: CheckResult, config: RunConfig) -> Pipeline:
        """Check that ``checked`` and ``config`` make sense together, and resolve the backend."""
        grammar = checked.grammar
        if checked.errors:
            raise PipelineError(_first_error(checked))
        name = config.backend or grammar.backend or DEFAULT_BACKEND
        try:
            spec = _spec(name)
        except PipelineError as error:  # the config's fault where it names the backend
            raise PipelineError(str(error), key="backend" if config.backend else None) from None
        try:
            settings = spec.checked_settings(config.backend_settings)
        except SettingsError as error:
            raise settings_error("backend_settings", error) from None
        config = replace(config, backend=name, backend_settings=settings)
        _check_weights(config, spec)
        _check_joints(grammar, spec)
        _check_frequency(grammar, spec)
        _check_sensors(checked, spec, key="backend" if config.backend else None)
        representation, settings = compile_representation(
            checked, config.representation, config.representation_settings
        )
        config = replace(config, representation_settings=settings)
        joints = (
            spec.catalogue.names if spec.catalogue is not None else tuple(j.joint for j in grammar.joints)
        )
        return cls(checked, config, spec, representation, joints)

    @property
    def grammar(self) -> Grammar:
        return self.checked.grammar

    @property
    def facts(self) -> GrammarFacts:
        return self.checked.facts

    @property
    def backend(self) -> str:
        assert self.config.backend is not None  # resolved by build
        return self.config.backend

    # ---- the stages ------------------------------------------------------------------

    def frozen_at(self, generation: int) -> frozenset[str]:
        """Joints held at neutral in ``generation`` (the paper's Table 3)."""
        return frozenset(j.joint for j in self.grammar.joints if not j.is_free(generation))

    def weights_at(self, generation: int) -> Mapping[str, float] | None:
        """The fitness weights in force in ``generation``; None: the backend's own."""
        return self.config.weights_at(generation) or None

    def scores_change(self, generation: int) -> bool:
        """Whether the same gait scores differently in ``generation`` than in the one before (a joint
        came free or the weights moved), so that individuals carried over must be scored again."""
        return self.frozen_at(generation) != self.frozen_at(generation - 1) or self.weights_at(
            generation
        ) != self.weights_at(generation - 1)

    def map(self, genomes: Sequence[Genome]) -> Sequence[Mapped]:
        return self.representation.map_many(genomes)

    def motion(self, mapped: Sequence[Mapped], generation: int) -> MotionBatch:
        batch = motion_batch(
            [m.joints if m.valid else None for m in mapped],
            self.joints,
            units=self.grammar.units,
            n_samples=self.config.samples,
            frozen=self.frozen_at(generation),
            frequency=self.frequency_limits,
            sensors=self.sensors,
        )
        if self.spec.scores_phenotype:  # the backend reads the texts themselves
            return replace(batch, phenotypes=tuple(m.phenotype if m.valid else None for m in mapped))
        return batch

    @property
    def sensors(self) -> Sensors | None:
        """What the backend lets phenotypes read (None: it senses nothing)."""
        return sensors_of(self.spec)

    @property
    def frequency_limits(self) -> tuple[float, float] | None:
        """The cycle frequencies (Hz) a gait may have, if the grammar evolves its frequency."""
        decl = self.grammar.frequency
        if decl is None:
            return None
        return decl.limits or self.spec.cycle_frequencies

    def evaluate(self, genomes: Sequence[Genome], evaluator: Evaluator, generation: int) -> list[Individual]:
        """Map, build motion, and score ``genomes`` as they would be scored in ``generation``."""
        return self._scored(genomes, evaluator.evaluate, generation)

    def verify(
        self,
        genomes: Sequence[Genome],
        evaluator: Evaluator,
        generation: int,
        *,
        played: Callable[[MotionBatch], MotionBatch] | None = None,
    ) -> list[Individual]:
        """As :meth:`evaluate`, checked over the backend's horizon (``VerifyingEvaluator.verify``):
        the same scores, or unviable for a gait that fails within it. The check the gaits a run
        keeps must pass; a backend whose evaluator cannot verify is trusted with its evaluation.
        ``played`` turns the motion into what is played (a gait retargeted to another body)."""
        score = evaluator.verify if isinstance(evaluator, VerifyingEvaluator) else evaluator.evaluate
        return self._scored(genomes, score, generation, played)

    def _scored(
        self,
        genomes: Sequence[Genome],
        score: Any,
        generation: int,
        played: Callable[[MotionBatch], MotionBatch] | None = None,
    ) -> list[Individual]:
        mapped = self.map(genomes)
        motion = self.motion(mapped, generation)
        evaluations = score(
            motion if played is None else played(motion),
            generation=generation,
            weights=self.weights_at(generation),
        )
        if len(evaluations) != len(genomes):
            raise PipelineError(
                f"backend {self.backend!r} returned {len(evaluations)} evaluations for {len(genomes)} gaits"
            )
        unviable = self.unviable_fitness(generation)
        return [
            Individual(tuple(g), m.used, m.phenotype, m.joints, honest(e, unviable))
            for g, m, e in zip(genomes, mapped, evaluations, strict=True)
        ]

    def unviable_fitness(self, generation: int) -> float:
        """What a gait that cannot be scored scores in ``generation`` (the backend's finite
        penalty under the weights in force, or ``WORST_FITNESS``)."""
        if self.spec.unviable_fitness is None:
            return WORST_FITNESS
        return float(self.spec.unviable_fitness(self.config.backend_settings, self.weights_at(generation)))

    def load_evaluator(
        self, runtime: Mapping[str, Any] | None = None, *, horizon: int | None = None
    ) -> Evaluator:
        """The backend, loaded with the run's settings; ``runtime`` may change only settings that
        change speed, never a score (``threads``); ``horizon`` checks kept gaits over that many
        cycles instead of the run's (the backend's ``horizon_setting``)."""
        extra = dict(runtime or {})
        wrong = sorted(set(extra) - self.spec.runtime_settings)
        if wrong:
            raise PipelineError(
                f"backend {self.backend!r}: {', '.join(wrong)} would change the scores; "
                "only these may differ from the run's settings: "
                f"{', '.join(sorted(self.spec.runtime_settings)) or 'none'}"
            )
        if horizon is not None:
            if self.spec.horizon_setting is None:
                raise PipelineError(f"backend {self.backend!r} checks gaits over no horizon to lengthen")
            extra[self.spec.horizon_setting] = horizon
        if self.spec.load is None:
            raise PipelineError(f"backend {self.backend!r} declares joints but cannot evaluate gaits")
        try:
            return self.spec.load({**self.config.backend_settings, **extra})
        except SettingsError as error:
            raise settings_error("backend_settings", error) from None
        except (ValueError, TypeError, ImportError, LookupError) as error:
            raise PipelineError(f"backend {self.backend!r}: {error}") from None

    def render(
        self,
        batch: MotionBatch,
        *,
        settings: Mapping[str, Any] | None = None,
        cycles: int | None = None,
        fps: int = 25,
        width: int = 480,
        height: int = 360,
    ) -> list[list[Any]]:
        """Each gait of ``batch`` (every one playable) drawn by the backend's render hook as it is
        scored: a list of RGB frames per gait. ``settings`` play it under other backend settings
        than the run's (another body's, from ``retarget``). The hook's
        :class:`~gaitgram.animation.RenderError` (no offscreen OpenGL) passes through."""
        if self.spec.render is None:
            raise PipelineError(f"backend {self.backend!r} draws no gaits")
        played = self.config.backend_settings if settings is None else settings
        try:
            return self.spec.render(played, batch, cycles=cycles, fps=fps, width=width, height=height)
        except SettingsError as error:
            raise settings_error("backend_settings", error) from None
        except (ValueError, TypeError, ImportError, LookupError) as error:
            raise PipelineError(f"backend {self.backend!r}: {error}") from None


def honest(evaluation: Evaluation, unviable: float = WORST_FITNESS) -> Evaluation:
    """An evaluation that says ``ok`` only if everything it measured is a finite number; one that
    is not viable scores ``unviable``."""
    if not evaluation.status.viable:
        return replace(evaluation, fitness=unviable)
    bad = [name for name, value in evaluation.components.items() if not _finite(value)]
    if not _finite(evaluation.fitness):
        bad.insert(0, "fitness")
    if not bad:
        return evaluation
    detail = f"the backend measured a non-finite {', '.join(bad)}"
    return replace(Evaluation.unviable(GaitStatus.NON_FINITE, detail), fitness=unviable)


def _finite(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _first_error(checked: CheckResult) -> str:
    source = checked.grammar.source
    errors = [d for d in checked.diagnostics if d.is_error]
    first = errors[0]
    where = source.location(first.span.start)
    more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
    return (
        f"{source.name}:{where.line}:{where.column}: error[{first.code.code}] {first.message}{more}; "
        f"a grammar with errors is never run: see `gaitgram check {source.name}`"
    )


def _spec(name: str) -> BackendSpec:
    try:
        return get_backend(name)
    except BackendNotFound as error:
        raise PipelineError(str(error)) from None
    except BackendLoadError as error:
        raise PipelineError(str(error)) from None


def _check_weights(config: RunConfig, spec: BackendSpec) -> None:
    if not config.weight_schedule:
        return
    if spec.weight_names is None:
        raise PipelineError(
            f"weight_schedule: backend {spec.name!r} takes no fitness weights, so the schedule would "
            "change nothing; remove it",
            key="weight_schedule",
        )
    known = spec.weight_names(config.backend_settings)
    for i, stage in enumerate(config.weight_schedule):
        for name in stage.weights:
            if name not in known:
                close = difflib.get_close_matches(name, sorted(known), n=1)
                hint = f"did you mean {close[0]}?" if close else f"known: {', '.join(sorted(known))}"
                raise PipelineError(
                    f"weight_schedule[{i}].weights.{name}: backend {spec.name!r} has no fitness component "
                    f"{name!r}; {hint}",
                    key="weight_schedule",
                )


def _check_joints(grammar: Grammar, spec: BackendSpec) -> None:
    if not grammar.joints and not spec.scores_phenotype:
        raise PipelineError(
            "the grammar declares no @joint rule, so no curve would move; mark each joint curve's rule "
            "with @joint NAME (docs/language.md)"
        )
    if spec.catalogue is None:
        return
    missing = [j.joint for j in grammar.joints if spec.catalogue.get(j.joint) is None]
    if missing:
        raise PipelineError(
            f"backend {spec.name!r} has no joint {', '.join(map(repr, missing))}; the grammar was written "
            f"for {grammar.backend or 'another backend'!s}; its joints: {', '.join(spec.catalogue.names)}"
        )


def _check_sensors(checked: CheckResult, spec: BackendSpec, key: str | None) -> None:
    """A grammar whose curves read sensors the backend lacks (the linter's GG509, but the run's
    config may name another backend than the grammar's) would make every closed-loop gait unusable."""
    lacking = sensors_lacking(checked.grammar, checked.facts, spec.sensors)
    if lacking:
        offered = ", ".join(s.name for s in spec.sensors or ())
        raise PipelineError(
            f"the grammar's curves read the sensor{'s' if len(lacking) > 1 else ''} {', '.join(lacking)}, "
            f"which backend {spec.name!r} lacks; "
            + (f"its sensors: {offered}" if offered else "it senses nothing and plays open-loop curves only"),
            key=key,
        )


def _check_frequency(grammar: Grammar, spec: BackendSpec) -> None:
    decl = grammar.frequency
    if decl is None:
        return
    if spec.cycle_frequencies is None:
        raise PipelineError(
            f"backend {spec.name!r} imposes the cycle frequency, so the grammar's @frequency rule "
            f"<{decl.rule}> would change nothing; remove it, or use a backend that plays evolved "
            f"frequencies ({', '.join(backends_that(lambda spec: spec.cycle_frequencies is not None))})"
        )
    low, high = spec.cycle_frequencies
    if decl.limits is not None and not (low <= decl.limits[0] and decl.limits[1] <= high):
        raise PipelineError(
            f"@frequency limits={decl.limits[0]:g}..{decl.limits[1]:g} reach beyond the "
            f"{low:g}..{high:g} Hz backend {spec.name!r} can play; narrow them"
        )


def representation_spec(name: str) -> RepresentationSpec:
    """The installed representation ``name``, or :class:`PipelineError` naming the ones there are."""
    try:
        return get_representation(name)
    except RepresentationNotFound as error:
        raise PipelineError(f"representation: {error}", key="representation") from None
    except RepresentationLoadError as error:
        raise PipelineError(str(error), key="representation") from None


def compile_representation(
    checked: CheckResult, name: str, settings: Mapping[str, Any]
) -> tuple[Compiled, dict[str, Any]]:
    """The representation ``name`` compiled for a checked grammar, and its settings normalised
    (defaults spelt out); :class:`PipelineError` names the setting that cannot be, and why. A first
    genome is drawn, so that depths no initial tree can keep to are refused here, not mid-run."""
    spec = representation_spec(name)
    try:
        normalised = spec.checked_settings(settings)
        compiled = spec.compile(checked.grammar, checked.facts, normalised)
        if spec.check_run is not None:
            spec.check_run(compiled)
    except SettingsError as error:
        raise settings_error("representation_settings", error) from None
    except MapperError as error:
        raise PipelineError(str(error)) from None
    try:
        compiled.initialise(np.random.default_rng(0), 1)
    except InitialisationError as error:
        raise PipelineError(f"representation {name}: {error}", key="representation_settings") from None
    return compiled, normalised
