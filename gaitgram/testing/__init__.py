"""Hypothesis strategies for grammars: test your grammar the way you test code.

::

    from hypothesis import given
    from gaitgram.language import load
    from gaitgram.testing import derivations

    GRAMMAR = load("grammars/hybrid.gg")

    @given(derivations(GRAMMAR, max_depth=8))
    def test_every_curve_is_finite(derivation):
        ...

Derivations are built top-down from drawn choice indices, with the minimum-depth
analysis keeping every tree within ``max_depth``; choices are ordered shallowest
first, so failures shrink toward shallow trees and low choice indices, and the
genome of each derivation is read off its choices (short genomes shrink shorter).

Another representation than GE (``representation="sge"``, with its ``settings``) gives the
derivations of the genomes its own initialisation makes, as a run's first generation, each from a
drawn seed: they keep to the representation's depth limits, but shrink toward one genome (seed
0's) rather than toward small trees.

The properties ``gaitgram test`` checks on them, and the ``PropertyFailed`` a user's own raise, are
in :mod:`gaitgram.testing.properties`.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache
from typing import Any

import numpy as np
from hypothesis import strategies as st

from gaitgram.analysis import GrammarFacts, analyse
from gaitgram.ge import CodonMode, Derivation, compile_mapper
from gaitgram.ge.mapper import Mapper
from gaitgram.ge.registry import DEFAULT_REPRESENTATION, Compiled, Genome, compile_representation
from gaitgram.language.model import FREQUENCY, Grammar
from gaitgram.motion.expression import Motion, compile_motion
from gaitgram.testing.properties import backend_sensors, nominal_curve

__all__ = ["compiled_representation", "derivations", "genomes", "initial_genomes", "motions", "phenotypes"]

#: Codons drawn by ``genomes``: small values shrink best and still select every choice.
DEFAULT_CODON_SIZE = 1_000


@cache
def _facts(grammar: Grammar) -> GrammarFacts:
    return analyse(grammar)


@cache
def _mapper(grammar: Grammar, codons: CodonMode, max_wraps: int, max_depth: int | None) -> Mapper:
    return compile_mapper(grammar, codons=codons, max_wraps=max_wraps, max_depth=max_depth)


def genomes(
    grammar: Grammar | None = None,
    *,
    min_size: int = 1,
    max_size: int = 200,
    codon_size: int = DEFAULT_CODON_SIZE,
) -> st.SearchStrategy[tuple[int, ...]]:
    """Uniform genomes: lists of codons in ``[0, codon_size)``; shrink toward short lists of zeros.

    ``grammar`` is accepted for symmetry with the other strategies; any genome fits any grammar.
    """
    return st.lists(st.integers(0, codon_size - 1), min_size=min_size, max_size=max_size).map(tuple)


def compiled_representation(
    grammar: Grammar, name: str, settings: Mapping[str, Any] | None = None
) -> Compiled:
    """Representation ``name`` compiled for ``grammar`` with ``settings`` (checked; the rest at
    their defaults), for :func:`initial_genomes`."""
    return compile_representation(grammar, _facts(grammar), name, settings or {})


#: ``initial_genomes`` draws a member of a first generation of up to this many: a ramped
#: initialisation reaches its deepest trees only some way into a generation.
FIRST_GENERATION = 32


def initial_genomes(compiled: Compiled) -> st.SearchStrategy[Genome]:
    """Genomes of a compiled representation: a drawn member of the first generation its
    initialisation makes from a drawn seed, what a run starts from. They shrink toward the first
    member of seed 0's."""

    def member(drawn: tuple[int, int]) -> Genome:
        seed, index = drawn
        return compiled.initialise(np.random.default_rng(seed), index + 1)[index]

    return st.tuples(st.integers(0, 2**32 - 1), st.integers(0, FIRST_GENERATION - 1)).map(member)


def derivations(
    grammar: Grammar,
    *,
    max_depth: int = 10,
    codons: CodonMode | str = CodonMode.LAZY,
    max_wraps: int = 0,
    representation: str = DEFAULT_REPRESENTATION,
    settings: Mapping[str, Any] | None = None,
) -> st.SearchStrategy[Derivation]:
    """Valid derivations within ``max_depth``, mapped from the genome that encodes them; of another
    representation than GE, those of its initial genomes, within its ``settings``' depth limits
    (``max_depth``, ``codons`` and ``max_wraps`` are GE's)."""
    if representation != DEFAULT_REPRESENTATION:
        compiled = compiled_representation(grammar, representation, settings)
        return initial_genomes(compiled).map(compiled.derivation).filter(lambda d: d.valid)
    mode = CodonMode(codons)
    facts = _facts(grammar)
    cfg = facts.cfg
    if cfg.start is None or facts.min_depth[cfg.start] is None or facts.min_depth[cfg.start] > max_depth:
        raise ValueError(f"the grammar has no derivation within depth {max_depth}")
    # Per rule, its choices ordered shallowest first: index 0 is what shrinking aims for.
    order = [
        sorted(range(len(depths)), key=lambda c, depths=depths: (depths[c] is None, depths[c] or 0, c))
        for depths in facts.choice_min_depth
    ]

    @st.composite
    def build(draw: st.DrawFn) -> Derivation:
        genome: list[int] = []
        stack = [(cfg.start, 1)]
        while stack:
            rule, level = stack.pop()
            room = max_depth - level + 1
            fitting = [
                c for c in order[rule] if (d := facts.choice_min_depth[rule][c]) is not None and d <= room
            ]
            choice = fitting[draw(st.integers(0, len(fitting) - 1))]
            n = len(cfg.choices[rule])
            if n > 1 or mode is CodonMode.EAGER:
                genome.append(choice)
            children = [item for item in cfg.choices[rule][choice] if isinstance(item, int)]
            stack.extend((child, level + 1) for child in reversed(children))
        return _mapper(grammar, mode, max_wraps, None).map(genome or [0])

    return build()


def phenotypes(grammar: Grammar, **options: object) -> st.SearchStrategy[str]:
    """Phenotype strings of valid derivations (options as for :func:`derivations`)."""
    return derivations(grammar, **options).map(lambda d: d.phenotype)  # type: ignore[arg-type, return-value]


def motions(
    grammar: Grammar, *, samples: int = 128, **options: object
) -> st.SearchStrategy[Mapping[str, np.ndarray]]:
    """Per-joint curves (degrees over one cycle, ``samples`` points) of valid derivations.

    A curve that reads the backend's sensors (a closed loop) is its nominal curve, every sensor at
    rest, as runs and ``gaitgram test`` sample it. A joint whose phenotype does not compile, or is
    not finite, maps to an array of NaN.
    """
    sensors = backend_sensors(grammar)
    names = sensors.names if sensors is not None else frozenset()

    def curves(derivation: Derivation) -> Mapping[str, np.ndarray]:
        result = {}
        for joint, text in derivation.joints.items():
            if joint == FREQUENCY:  # a number, not a curve
                continue
            motion = compile_motion(text, names)
            values = nominal_curve(motion, samples, sensors)[0] if isinstance(motion, Motion) else None
            result[joint] = np.full(samples, np.nan) if values is None else values
        return result

    return derivations(grammar, **options).map(curves)  # type: ignore[arg-type]
