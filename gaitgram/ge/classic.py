"""``ge``: grammatical evolution as the paper ran it, as a representation plug-in (the default).

A genome is a tuple of codons, mapped by :mod:`gaitgram.ge.mapper` (lazy, GEVA's, or eager,
PonyGE2's, codon consumption; wraps; an optional depth limit). A first generation is
RampedFullGrow's trees written as genomes with a random tail (:mod:`gaitgram.ge.initialisation`),
varied by one-point crossover and int-flip mutation (:mod:`gaitgram.ge.operators`), all with the
paper's Table 1 settings by default. Its settings are the run.toml keys older configs write at
the top level (``max_wraps = 3``); they belong in ``[representation_settings]`` now, and a run
directory's fingerprint holds them as it always did, so every GE run resumes as it was.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from gaitgram.analysis.facts import GrammarFacts
from gaitgram.backends.api import SettingsError
from gaitgram.ge.derivation import Derivation
from gaitgram.ge.export import mapper_tables
from gaitgram.ge.initialisation import CODON_SIZE, ramped_population
from gaitgram.ge.mapper import CodonMode, Mapped, Mapper, MappingOptions, compile_mapper
from gaitgram.ge.registry import Compiled, Genome, GenomeError, Parent, RepresentationSpec, Setting
from gaitgram.language.model import Grammar

if TYPE_CHECKING:  # the operators (numpy) are imported when genomes are varied: `gaitgram map` needs none
    import numpy as np

    from gaitgram.ge.operators import Codons

__all__ = ["GE", "REPRESENTATION", "SETTINGS", "Variation", "parse_codons"]

#: GE's settings, the paper's Table 1 by default (in the order older run.toml files wrote them).
SETTINGS = (
    Setting("max_wraps", 3, "W wraps allow W + 1 passes over the genome", 0, 1_000),
    Setting(
        "codons",
        CodonMode.LAZY.value,
        "codon consumption: lazy (GEVA, the paper) or eager (PonyGE2)",
        choices=tuple(m.value for m in CodonMode),
    ),
    Setting("codon_size", CODON_SIZE, "codons are drawn from [0, codon_size)", 2, 2**31 - 1),
    Setting("init_max_depth", 10, "deepest rule node of an initial tree (the ramp's top)", 1, 1_000),
    Setting("grow_probability", 0.5, "share of initial trees grown (else built full)", 0.0, 1.0),
    Setting("tail", 0.5, "random codons after an initial tree's, as a share of them", 0.0, 100.0),
    Setting("crossover", 0.9, "probability that a pair of parents is crossed", 0.0, 1.0),
    Setting("fixed_point", True, "one cut point for both parents (GEVA), else one each (PonyGE2)"),
    Setting("crossover_within_used", True, "cut within the codons each parent's mapping used"),
    Setting("mutation", 0.02, "probability that each codon is replaced", 0.0, 1.0),
    Setting("mutation_within_used", False, "mutate only the codons the mapping used"),
    Setting(
        "max_depth",
        None,
        "deepest rule node of a valid genome (left out: no limit)",
        1,
        100_000,
        optional=True,
        kind=int,
    ),
)


class Variation:
    """GE's crossover and mutation with a run's settings (Table 1). The mapper, needed to know the
    codons a genome uses, is attached by its owner and never pickled (``nsga2`` and ``map-elites``
    keep one in their pickled state, as ``gaitgram.strategies.common.GEVariation``)."""

    def __init__(self, settings: Mapping[str, Any]) -> None:
        self.crossover = settings["crossover"]
        self.fixed_point = settings["fixed_point"]
        self.crossover_within_used = settings["crossover_within_used"]
        self.mutation = settings["mutation"]
        self.mutation_within_used = settings["mutation_within_used"]
        self.codon_size = settings["codon_size"]
        self.mapper: Mapper | None = None

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "mapper": None}

    def _used(self, genomes: Sequence[Codons]) -> list[int]:
        if self.mapper is None:
            raise RuntimeError("GEVariation.mapper is not attached")
        return [m.used_codons for m in self.mapper.map_many(genomes)]

    def cross(
        self,
        first: Codons,
        second: Codons,
        rng: np.random.Generator,
        used: tuple[int, int] | None = None,
    ) -> tuple[Codons, Codons]:
        """One-point crossover of two parents (whether to cross at all is the caller's draw);
        ``used``, the codons each parent's mapping reads, when the caller knows them."""
        if not self.crossover_within_used:
            used = None
        elif used is None:
            used = tuple(self._used([first, second]))  # type: ignore[assignment]
        from gaitgram.ge.operators import one_point_crossover

        return one_point_crossover(first, second, rng, fixed_point=self.fixed_point, used=used)

    def mutate(self, genomes: Sequence[Codons], rng: np.random.Generator) -> list[Codons]:
        """Int-flip mutation of each genome (within the codons it uses, if the run says so)."""
        from gaitgram.ge.operators import int_flip_mutation

        used: Sequence[int | None] = (
            self._used(genomes) if self.mutation_within_used else [None] * len(genomes)
        )
        return [
            int_flip_mutation(g, rng, probability=self.mutation, codon_size=self.codon_size, used=u)
            for g, u in zip(genomes, used, strict=True)
        ]


class GE:
    """GE compiled for one grammar and one set of settings (:data:`SETTINGS`, checked)."""

    name = "ge"
    #: What ``used`` counts: the codons the mapping read.
    counts = "codons"

    def __init__(self, grammar: Grammar, facts: GrammarFacts, settings: Mapping[str, Any]) -> None:
        self.grammar = grammar
        self.facts = facts
        self.settings = dict(settings)
        self.options = MappingOptions(settings["codons"], settings["max_wraps"], settings["max_depth"])
        self.mapper = compile_mapper(
            grammar,
            codons=settings["codons"],
            max_wraps=settings["max_wraps"],
            max_depth=settings["max_depth"],
        )
        self.variation = Variation(settings)
        self.variation.mapper = self.mapper

    def __repr__(self) -> str:
        return f"GE({self.mapper!r})"

    def map_many(self, genomes: Sequence[Genome]) -> list[Mapped]:
        return self.mapper.map_many(genomes)

    def derivation(self, genome: Genome) -> Derivation:
        return self.mapper.map(genome)

    def initialise(self, rng: np.random.Generator, n: int) -> list[Genome]:
        """RampedFullGrow's trees (Table 1), each written as a genome with a random tail."""
        settings = self.settings
        trees = ramped_population(
            self.facts,
            rng,
            n,
            max_depth=settings["init_max_depth"],
            grow_probability=settings["grow_probability"],
            codons=CodonMode(settings["codons"]),
            codon_size=settings["codon_size"],
            tail=settings["tail"],
        )
        return [t.genome for t in trees]

    def vary(self, rng: np.random.Generator, parents: Sequence[Parent], count: int) -> list[Genome]:
        """Parents paired in order (an odd last one with the first), each pair crossed at one point
        with probability ``crossover`` (the draw made for every pair), then the first ``count``
        children mutated: the paper's GE, draw for draw."""
        variation, probability = self.variation, self.settings["crossover"]
        children: list[Codons] = []
        for i in range(0, len(parents), 2):
            first, second = parents[i], parents[(i + 1) % len(parents)]
            if rng.random() < probability:
                children += variation.cross(first.genome, second.genome, rng, used=(first.used, second.used))
            else:
                children += [first.genome, second.genome]
        return list(variation.mutate(children[:count], rng))

    def encode(self, genome: Genome) -> str:
        return ",".join(map(str, genome))

    def decode(self, text: str) -> Genome:
        return parse_codons(text)

    def to_json(self, genome: Genome) -> Any:
        return list(genome)

    def from_json(self, value: Any) -> Genome:
        size = self.settings["codon_size"]
        if not isinstance(value, list) or not value:
            raise GenomeError("a GE genome is a non-empty list of codons")
        if not all(isinstance(c, int) and not isinstance(c, bool) and 0 <= c < size for c in value):
            raise GenomeError(f"has codons outside [0, {size})")
        return tuple(value)

    def tables(self) -> dict[str, Any]:
        return mapper_tables(self.grammar, self.options, self.mapper.cfg)


_CODON = re.compile(r"[^\s,\[\]]+")


def parse_codons(text: str) -> Codons:
    """Codons separated by commas and/or whitespace, optionally in [brackets] (JSON works)."""
    codons = []
    for match in _CODON.finditer(text):
        token = match.group()
        if not (token.isdigit() and token.isascii()):
            line = text.count("\n", 0, match.start()) + 1
            column = match.start() - (text.rfind("\n", 0, match.start()) + 1) + 1
            raise GenomeError(
                f"{line}:{column}: {token!r} is not a codon; codons are non-negative integers separated "
                "by commas or spaces, e.g. 12,7,301"
            )
        codons.append(int(token))
    if not codons:
        raise GenomeError("the genome is empty; write its codons separated by commas, e.g. 12,7,301")
    return tuple(codons)


def check_run(compiled: Compiled) -> None:
    """What a run needs of GE's settings that this grammar cannot give (:class:`SettingsError`
    naming the setting): depths its shortest derivation cannot fit in, codons too small to reach
    every choice. Commands that only map genomes do without."""
    assert isinstance(compiled, GE)
    settings, facts = compiled.settings, compiled.facts
    start = facts.cfg.start
    shortest = facts.min_depth[start] if start is not None else None
    init, limit = settings["init_max_depth"], settings["max_depth"]
    if shortest is not None:  # a start rule that derives nothing is the linter's error (GG205)
        if init < shortest:
            raise SettingsError(
                "init_max_depth",
                f"{init} is below the {shortest} levels of the grammar's shortest derivation, so no "
                f"initial tree fits; make it at least {shortest}",
            )
        if limit is not None and limit < shortest:
            raise SettingsError(
                "max_depth",
                f"{limit} is below the {shortest} levels of the grammar's shortest derivation, so every "
                f"genome would be invalid; make it at least {shortest}",
            )
    if limit is not None and limit < init:
        raise SettingsError(
            "max_depth",
            f"{limit} is below init_max_depth {init}, so some initial trees would be invalid at once; "
            "raise max_depth or lower init_max_depth",
        )
    widest = max(compiled.mapper.n_choices, default=0)
    if settings["codon_size"] < widest:
        raise SettingsError(
            "codon_size",
            f"{settings['codon_size']} is smaller than the {widest} choices of the grammar's widest rule, "
            f"so some of its choices could never be picked; make codon_size at least {widest}",
        )


REPRESENTATION = RepresentationSpec(
    name="ge",
    summary="Grammatical evolution: codons pick choices modulo their count (GEVA's lazy or PonyGE2's "
    "eager reading, wraps), RampedFullGrow, one-point crossover, int-flip mutation.",
    settings=SETTINGS,
    compile=GE,
    check_run=check_run,
    genome_syntax="12,7,301",
    source="O'Neill and Ryan 2001; GEVA (the paper's tool) and PonyGE2 (tests/data/ponyge2, "
    "tests/data/representations: GEVA's vectors via alogos)",
)
