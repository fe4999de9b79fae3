"""Properties every gait grammar should have, checked by ``gaitgram test`` on generated derivations.

A property is a function ``(derivation, context) -> None`` that raises
:class:`PropertyFailed` with a reason. Users add their own in a Python file of
functions named ``property_*`` with the same signature (``gaitgram test --properties FILE``).

A curve that reads the backend's sensors (a closed loop) compiles with them, and its *nominal*
curve (every sensor at rest, as runs and plots sample it) is the one checked for finiteness and
limits: what it does under other readings depends on the body.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitgram.backends.registry import get_backend
from gaitgram.ge import Derivation
from gaitgram.ge.mapper import Mapper
from gaitgram.ge.registry import Compiled, Genome
from gaitgram.language.model import FREQUENCY, Grammar
from gaitgram.motion.expression import Motion, compile_motion, phase_grid
from gaitgram.motion.gait import Sensors, cycle_frequency, sensed_curve
from gaitgram.pipeline import DEFAULT_BACKEND, sensors_of


class PropertyFailed(AssertionError):
    """A property does not hold for a derivation; the message says how."""


@dataclass(frozen=True)
class Context:
    grammar: Grammar
    mapper: Mapper
    max_depth: int
    samples: int = 256
    #: The backend's sensors, which curves may read (None: it senses nothing).
    sensors: Sensors | None = None
    #: Another representation than GE whose genomes are tested, and the genome of the derivation
    #: at hand (None: GE's, read off the derivation's codons).
    representation: Compiled | None = None
    genome: Genome | None = None

    @classmethod
    def of(cls, grammar: Grammar, mapper: Mapper, max_depth: int) -> Context:
        """The context of a checked grammar, with its backend's sensors."""
        return cls(grammar, mapper, max_depth, sensors=backend_sensors(grammar))

    def motion(self, text: str) -> Motion | object:
        """``text`` compiled, reading the backend's sensors."""
        return compile_motion(text, self.sensors.names if self.sensors is not None else frozenset())

    def curve(self, motion: Motion) -> tuple[np.ndarray | None, str | None]:
        """Its values over one cycle (a closed loop's nominal curve), or why it has none."""
        return nominal_curve(motion, self.samples, self.sensors)


def backend_sensors(grammar: Grammar) -> Sensors | None:
    """The sensors of the grammar's backend, which its curves may read (None: it senses nothing)."""
    return sensors_of(get_backend(grammar.backend or DEFAULT_BACKEND))


def nominal_curve(
    motion: Motion, samples: int, sensors: Sensors | None
) -> tuple[np.ndarray | None, str | None]:
    """A compiled curve's values at ``samples`` phases of one cycle, or why it has none: a closed
    loop's nominal curve (every sensor at rest, as runs and plots sample it), whose values under
    other readings depend on the body."""
    if motion.sensors and sensors is not None:
        values, _, problem, detail = sensed_curve(motion.text, samples, sensors)
        return (None, detail) if problem is not None else (values, None)
    curve = motion.evaluate(phase_grid(samples))
    return (curve.values, None) if curve.ok else (None, str(curve.error))


Property = Callable[[Derivation, Context], None]


def _mapped(derivation: Derivation, context: Context, *, copy: bool = False) -> Any:
    """The derivation's genome mapped again: through its representation's mapping where it is not
    GE's, else GE's codons read off the tree (``copy``: as a new list)."""
    if context.representation is not None and context.genome is not None:
        return context.representation.map_many([context.genome])[0]
    genome = _genome(derivation)
    return context.mapper.map_fast(list(genome) if copy else genome)


def maps_cleanly(derivation: Derivation, context: Context) -> None:
    """Mapping its genome again gives a valid derivation with a phenotype (no exception, no invalid)."""
    again = _mapped(derivation, context)
    if not again.valid or again.phenotype != derivation.phenotype:
        raise PropertyFailed(f"remapping gives {again.phenotype!r} ({again.reason})")


def is_deterministic(derivation: Derivation, context: Context) -> None:
    """The same genome maps to the same phenotype and joints every time."""
    if _mapped(derivation, context) != _mapped(derivation, context, copy=True):
        raise PropertyFailed("two mappings of the same genome differ")


def within_max_depth(derivation: Derivation, context: Context) -> None:
    if derivation.depth > context.max_depth:
        raise PropertyFailed(f"depth {derivation.depth} exceeds the maximum {context.max_depth}")


def joints_compile(derivation: Derivation, context: Context) -> None:
    """Every @joint phenotype is a motion expression."""
    for joint, text in derivation.joints.items():
        motion = context.motion(text)
        if not isinstance(motion, Motion):
            raise PropertyFailed(f"{joint}: {motion}")


def curves_finite(derivation: Derivation, context: Context) -> None:
    """Every joint curve is finite over the whole cycle (no division by zero, no overflow)."""
    for joint, text in derivation.joints.items():
        motion = context.motion(text)
        if isinstance(motion, Motion):
            _, problem = context.curve(motion)
            if problem is not None:
                raise PropertyFailed(f"{joint}: {problem}")


def curves_within_limits(derivation: Derivation, context: Context) -> None:
    """Curves stay within their @joint limits; the share of the cycle outside is reported."""
    for decl in context.grammar.joints:
        text = derivation.joints.get(decl.joint)
        if text is None or decl.limits is None:
            continue
        motion = context.motion(text)
        if not isinstance(motion, Motion):
            continue
        values, _ = context.curve(motion)
        if values is None:
            continue
        low, high = decl.limits
        outside = (values < low - 1e-9) | (values > high + 1e-9)
        if outside.any():
            raise PropertyFailed(
                f"{decl.joint}: {outside.mean():.0%} of the cycle outside {low:g}..{high:g} "
                f"(from {np.nanmin(values):.3g} to {np.nanmax(values):.3g})"
            )


def frequency_valid(derivation: Derivation, context: Context) -> None:
    """A @frequency rule derives a constant, finite frequency within its limits."""
    decl = context.grammar.frequency
    if decl is None:
        return
    limits = decl.limits or (0.0, math.inf)
    _, problem, detail = cycle_frequency(derivation.joints.get(FREQUENCY), limits)
    if problem is not None:
        raise PropertyFailed(str(detail))


BUILT_IN: dict[str, Property] = {
    "maps-cleanly": maps_cleanly,
    "deterministic": is_deterministic,
    "within-max-depth": within_max_depth,
    "joints-compile": joints_compile,
    "curves-finite": curves_finite,
    "curves-within-limits": curves_within_limits,
    "frequency-valid": frequency_valid,
}


def _genome(derivation: Derivation) -> list[int]:
    """The codons the derivation read, in order (its genome without the unused tail)."""
    codons = [(n.codon_index, n.codon) for n, _ in derivation.tree.walk() if n.codon_index is not None]
    return [codon for _, codon in sorted(codons)] or [0]
