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
first (then fewest rule children first), so failures shrink toward small, shallow
trees and low choice indices, and the
genome of each derivation is read off its choices (short genomes shrink shorter).

The genomes of every built-in representation (``representation="sge"``, with its ``settings``;
:func:`representation_genomes` of a compiled one) are drawn the same way: a tree drawn within the
representation's depth limits, written as its genome (:mod:`gaitgram.testing.trees`), so that they
shrink toward small trees too.

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
from gaitgram.testing.trees import (
    DEFAULT_MAX_DEPTH,
    DepthTooShallow,
    depth_budget,
    encode_derivation,
    ge_plan,
    plan_of,
    tree_genomes,
)

__all__ = [
    "DepthTooShallow",
    "compiled_representation",
    "derivations",
    "encode_derivation",
    "genomes",
    "initial_genomes",
    "motions",
    "phenotypes",
    "representation_genomes",
]

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
    member of seed 0's, not toward small trees: :func:`representation_genomes` does."""

    def member(drawn: tuple[int, int]) -> Genome:
        seed, index = drawn
        return compiled.initialise(np.random.default_rng(seed), index + 1)[index]

    return st.tuples(st.integers(0, 2**32 - 1), st.integers(0, FIRST_GENERATION - 1)).map(member)


def representation_genomes(compiled: Compiled, *, max_depth: int | None = None) -> st.SearchStrategy[Genome]:
    """Genomes of a compiled representation (:func:`compiled_representation`), each the genome of a
    tree drawn as :func:`derivations` draws GE's, so that they shrink toward small trees and low
    choices: every one maps to a valid derivation no deeper than ``max_depth`` and the
    representation's own depth limits (without either, 10 deep). A plug-in's representation,
    whose genomes gaitgram cannot write from a tree, gets :func:`initial_genomes`."""
    plan = plan_of(compiled)
    if plan is None:
        return initial_genomes(compiled)
    budget = depth_budget(compiled, max_depth)
    assert budget is not None
    return tree_genomes(plan, budget)


def derivations(
    grammar: Grammar,
    *,
    max_depth: int | None = None,
    codons: CodonMode | str = CodonMode.LAZY,
    max_wraps: int = 0,
    representation: str = DEFAULT_REPRESENTATION,
    settings: Mapping[str, Any] | None = None,
) -> st.SearchStrategy[Derivation]:
    """Valid derivations within ``max_depth`` (GE's default 10), mapped from the genome that encodes
    them; of another representation than GE, the derivations of its
    :func:`representation_genomes`, within ``max_depth`` and its ``settings``' depth limits
    (``codons`` and ``max_wraps`` are GE's)."""
    if representation != DEFAULT_REPRESENTATION:
        compiled = compiled_representation(grammar, representation, settings)
        drawn = representation_genomes(compiled, max_depth=max_depth).map(compiled.derivation)
        # A plug-in's initial genomes may map as invalid; drawn trees never do.
        return drawn if plan_of(compiled) is not None else drawn.filter(lambda d: d.valid)
    facts = _facts(grammar)
    depth = DEFAULT_MAX_DEPTH if max_depth is None else max_depth
    if facts.cfg.start is None:
        raise DepthTooShallow(depth, None)
    mode = CodonMode(codons)
    mapper = _mapper(grammar, mode, max_wraps, None)
    plan = ge_plan(facts.cfg, facts.choice_min_depth, mode, None)
    return tree_genomes(plan, depth).map(lambda genome: mapper.map(list(genome)))


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
