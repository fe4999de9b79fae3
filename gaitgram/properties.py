"""Properties every gait grammar should have, checked by ``gaitgram test`` on generated derivations.

A property is a function ``(derivation, context) -> None`` that raises
:class:`PropertyFailed` with a reason. Users add their own in a Python file of
functions named ``property_*`` with the same signature (``gaitgram test --properties FILE``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gaitgram.ge import Derivation
from gaitgram.ge.mapper import Mapper
from gaitgram.language.model import FREQUENCY, Grammar
from gaitgram.motion.expression import Motion, compile_motion, phase_grid
from gaitgram.motion.gait import cycle_frequency


class PropertyFailed(AssertionError):
    """A property does not hold for a derivation; the message says how."""


@dataclass(frozen=True)
class Context:
    grammar: Grammar
    mapper: Mapper
    max_depth: int
    samples: int = 256


Property = Callable[[Derivation, Context], None]


def maps_cleanly(derivation: Derivation, context: Context) -> None:
    """Mapping its genome again gives a valid derivation with a phenotype (no exception, no invalid)."""
    again = context.mapper.map_fast(_genome(derivation))
    if not again.valid or again.phenotype != derivation.phenotype:
        raise PropertyFailed(f"remapping gives {again.phenotype!r} ({again.reason})")


def is_deterministic(derivation: Derivation, context: Context) -> None:
    """The same genome maps to the same phenotype and joints every time."""
    genome = _genome(derivation)
    first, second = context.mapper.map_fast(genome), context.mapper.map_fast(list(genome))
    if first != second:
        raise PropertyFailed("two mappings of the same genome differ")


def within_max_depth(derivation: Derivation, context: Context) -> None:
    if derivation.depth > context.max_depth:
        raise PropertyFailed(f"depth {derivation.depth} exceeds the maximum {context.max_depth}")


def joints_compile(derivation: Derivation, context: Context) -> None:
    """Every @joint phenotype is a motion expression."""
    for joint, text in derivation.joints.items():
        motion = compile_motion(text)
        if not isinstance(motion, Motion):
            raise PropertyFailed(f"{joint}: {motion}")


def curves_finite(derivation: Derivation, context: Context) -> None:
    """Every joint curve is finite over the whole cycle (no division by zero, no overflow)."""
    phases = phase_grid(context.samples)
    for joint, text in derivation.joints.items():
        motion = compile_motion(text)
        if isinstance(motion, Motion):
            curve = motion.evaluate(phases)
            if not curve.ok:
                raise PropertyFailed(f"{joint}: {curve.error}")


def curves_within_limits(derivation: Derivation, context: Context) -> None:
    """Curves stay within their @joint limits; the share of the cycle outside is reported."""
    phases = phase_grid(context.samples)
    for decl in context.grammar.joints:
        text = derivation.joints.get(decl.joint)
        if text is None or decl.limits is None:
            continue
        motion = compile_motion(text)
        if not isinstance(motion, Motion):
            continue
        curve = motion.evaluate(phases)
        if not curve.ok:
            continue
        low, high = decl.limits
        outside = (curve.values < low - 1e-9) | (curve.values > high + 1e-9)
        if outside.any():
            raise PropertyFailed(
                f"{decl.joint}: {outside.mean():.0%} of the cycle outside {low:g}..{high:g} "
                f"(from {np.nanmin(curve.values):.3g} to {np.nanmax(curve.values):.3g})"
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
