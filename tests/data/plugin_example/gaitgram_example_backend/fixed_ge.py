"""An example representation: fixed-length codon strings, varied by uniform crossover.

A complete plug-in in one module: every genome holds ``length`` codons drawn uniformly, mapped by
GE's mapper with PonyGE2's eager codons and no wraps (a derivation that does not finish within its
codons is invalid, and a run scores it so); children take each codon from either parent and redraw
it with probability ``mutation``. All its randomness is the ``rng`` it is given, so runs resume.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from gaitgram.analysis.facts import GrammarFacts
from gaitgram.ge import Derivation, Mapped, MappingOptions, compile_mapper
from gaitgram.ge.classic import parse_codons
from gaitgram.ge.export import mapper_tables
from gaitgram.ge.registry import Genome, GenomeError, Parent, RepresentationSpec, Setting
from gaitgram.language.model import Grammar

CODON_SIZE = 256

SETTINGS = (
    Setting("length", 60, "codons in every genome", 1, 100_000),
    Setting("mutation", 0.05, "probability that each codon is redrawn", 0.0, 1.0),
)


class FixedGE:
    """The representation compiled for one grammar (``gaitgram.ge.registry.Compiled``)."""

    name = "fixed-ge"
    counts = "codons"  # what a mapping's ``used`` counts: best.json records ``used_codons``

    def __init__(self, grammar: Grammar, facts: GrammarFacts, settings: Mapping[str, Any]) -> None:
        self.grammar = grammar
        self.length, self.mutation = settings["length"], settings["mutation"]
        self.options = MappingOptions("eager", 0, None)
        self.mapper = compile_mapper(grammar, codons="eager", max_wraps=0)

    def initialise(self, rng: np.random.Generator, n: int) -> list[Genome]:
        return [tuple(int(c) for c in rng.integers(CODON_SIZE, size=self.length)) for _ in range(n)]

    def vary(self, rng: np.random.Generator, parents: Sequence[Parent], count: int) -> list[Genome]:
        children = []
        for k in range(count):
            first = np.array(parents[k % len(parents)].genome)
            second = np.array(parents[(k + 1) % len(parents)].genome)
            child = np.where(rng.random(self.length) < 0.5, first, second)
            redraw = rng.random(self.length) < self.mutation
            child[redraw] = rng.integers(CODON_SIZE, size=int(redraw.sum()))
            children.append(tuple(int(c) for c in child))
        return children

    def map_many(self, genomes: Sequence[Genome]) -> list[Mapped]:
        return self.mapper.map_many(genomes)

    def derivation(self, genome: Genome) -> Derivation:
        return self.mapper.map(genome)

    def encode(self, genome: Genome) -> str:
        return ",".join(map(str, genome))

    def decode(self, text: str) -> Genome:
        return self.from_json(list(parse_codons(text)))

    def to_json(self, genome: Genome) -> Any:
        return list(genome)

    def from_json(self, value: Any) -> Genome:
        if not isinstance(value, list) or len(value) != self.length:
            raise GenomeError(f"a fixed-ge genome is a list of exactly {self.length} codons (setting length)")
        if not all(isinstance(c, int) and not isinstance(c, bool) and 0 <= c < CODON_SIZE for c in value):
            raise GenomeError(f"a fixed-ge codon is an integer in [0, {CODON_SIZE})")
        return tuple(value)

    def tables(self) -> dict[str, Any]:
        """What ``gaitgram compile`` writes: GE's tables, and the length."""
        return {"length": self.length, **mapper_tables(self.grammar, self.options)}


REPRESENTATION = RepresentationSpec(
    name="fixed-ge",
    summary="Example: fixed-length codon strings, eager GE mapping, uniform crossover.",
    settings=SETTINGS,
    compile=FixedGE,  # (grammar, facts, checked settings) -> the compiled representation
    genome_syntax="12,7,201",
    version="fixed-ge r1",  # change it whenever the same genome could map or vary differently
)
