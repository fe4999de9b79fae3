"""Sensible initialisation: random derivation trees within a depth, and the genomes that derive them.

GEVA's RampedFullGrow (the paper's Table 1) and PonyGE2's ramped half-and-half
build *trees*, not genomes: each individual gets a maximum depth from a ramp
and is grown either "full" (prefer recursive choices, so branches reach the
depth) or "grow" (any choice that still fits). The minimum-depth analysis says
which choices fit, so every tree is within its depth and generation never
backtracks. The genome is then read off the tree: for each expansion that reads
a codon, a codon ``c`` with ``c % n_choices == choice``.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import TYPE_CHECKING

from gaitgram.analysis.facts import GrammarFacts
from gaitgram.ge.mapper import CodonMode

if TYPE_CHECKING:  # a generator is passed in: GE's plug-in loads without numpy (``gaitgram map``)
    import numpy as np

#: PonyGE2's default codon size: codons are drawn from [0, CODON_SIZE).
CODON_SIZE = 100_000


class Method(StrEnum):
    GROW = "grow"
    FULL = "full"
    RAMPED = "ramped"


class InitialisationError(ValueError):
    """The grammar cannot produce a tree within the requested depth."""


@dataclass(frozen=True, slots=True)
class Choice:
    """One expansion of a derivation, in depth-first leftmost order."""

    rule: int
    choice: int
    depth: int  # 1 for the root


@dataclass(frozen=True, slots=True)
class GeneratedTree:
    """A random derivation, its genome and how it was made."""

    expansions: tuple[Choice, ...]
    genome: tuple[int, ...]
    used_codons: int  # the genome's first ``used_codons`` codons derive the tree; the rest is tail
    depth: int
    method: Method


def random_tree(
    facts: GrammarFacts,
    rng: np.random.Generator,
    *,
    max_depth: int,
    method: Method = Method.GROW,
    codons: CodonMode = CodonMode.LAZY,
    codon_size: int = CODON_SIZE,
    tail: float | int = 0.5,
) -> GeneratedTree:
    """A random derivation of at most ``max_depth`` levels and a genome that maps to it.

    ``tail`` adds random codons after the used part: a float is a ratio of the
    used length (PonyGE2's tail ratio), an int a count.
    """
    if method is Method.RAMPED:
        raise ValueError("ramped is a population method: use ramped_population")
    cfg = facts.cfg
    if cfg.start is None or facts.min_depth[cfg.start] is None:
        raise InitialisationError("the start rule cannot derive anything")
    start_depth = facts.min_depth[cfg.start]
    assert start_depth is not None
    if start_depth > max_depth:
        raise InitialisationError(
            f"the shortest derivation is {start_depth} levels deep; max depth is {max_depth}"
        )

    expansions: list[Choice] = []
    codon_values: list[int] = []
    deepest = 0
    stack = [(cfg.start, 1)]
    while stack:
        rule, level = stack.pop()
        choice = _pick(facts, rng, rule, level, max_depth, method)
        expansions.append(Choice(rule, choice, level))
        deepest = max(deepest, level)
        n = len(cfg.choices[rule])
        if n > 1 or codons is CodonMode.EAGER:
            codon_values.append(choice + n * int(rng.integers(0, max(1, (codon_size - choice - 1) // n + 1))))
        children = [item for item in cfg.choices[rule][choice] if isinstance(item, int)]
        stack.extend((child, level + 1) for child in reversed(children))

    used = len(codon_values)
    extra = round(used * tail) if isinstance(tail, float) else tail
    codon_values.extend(int(c) for c in rng.integers(0, codon_size, size=max(extra, 0)))
    return GeneratedTree(tuple(expansions), tuple(codon_values), used, deepest, method)


def _pick(
    facts: GrammarFacts, rng: np.random.Generator, rule: int, level: int, max_depth: int, method: Method
) -> int:
    depths = facts.choice_min_depth[rule]
    room = max_depth - level + 1
    fitting = [c for c, d in enumerate(depths) if d is not None and d <= room]
    if not fitting:  # unreachable: the parent's choice guaranteed room for this rule
        raise InitialisationError(f"no choice of rule {facts.cfg.names[rule]} fits in depth {room}")
    if method is Method.FULL:
        recursive = [c for c in fitting if _is_recursive_choice(facts, rule, c)]
        # Prefer choices that can keep growing; among them, keep room for the deepest ones.
        if recursive:
            fitting = recursive
        else:
            deepest = max(depths[c] for c in fitting)  # type: ignore[type-var]
            fitting = [c for c in fitting if depths[c] == deepest]
    return fitting[int(rng.integers(0, len(fitting)))]


def _is_recursive_choice(facts: GrammarFacts, rule: int, choice: int) -> bool:
    return any(isinstance(item, int) and facts.recursive[item] for item in facts.cfg.choices[rule][choice])


def ramped_population(
    facts: GrammarFacts,
    rng: np.random.Generator,
    size: int,
    *,
    max_depth: int,
    grow_probability: float = 0.5,
    min_depth: int | None = None,
    codons: CodonMode = CodonMode.LAZY,
    codon_size: int = CODON_SIZE,
    tail: float | int = 0.5,
) -> list[GeneratedTree]:
    """RampedFullGrow: depths cycle over ``min_depth..max_depth``; each tree is grown with
    probability ``grow_probability``, else built full."""
    cfg = facts.cfg
    shortest = facts.min_depth[cfg.start] if cfg.start is not None else None
    if shortest is None:
        raise InitialisationError("the start rule cannot derive anything")
    low = max(shortest, min_depth or shortest)
    if low > max_depth:
        raise InitialisationError(f"the shortest derivation is {low} levels deep; max depth is {max_depth}")
    depths = list(range(low, max_depth + 1))
    population = []
    for i in range(size):
        method = Method.GROW if rng.random() < grow_probability else Method.FULL
        population.append(
            random_tree(
                facts,
                rng,
                max_depth=depths[i % len(depths)],
                method=method,
                codons=codons,
                codon_size=codon_size,
                tail=tail,
            )
        )
    return population


def random_genomes(
    rng: np.random.Generator, size: int, *, length: int | tuple[int, int], codon_size: int = CODON_SIZE
) -> list[tuple[int, ...]]:
    """Uniform random genomes; ``length`` is fixed or a (low, high) inclusive range."""
    low, high = (length, length) if isinstance(length, int) else length
    lengths = rng.integers(low, high + 1, size=size)
    return [tuple(int(c) for c in rng.integers(0, codon_size, size=int(n))) for n in lengths]
