"""Dynamic Structured GE (DSGE; Lourenço et al., Handbook of GE 2018), as sge3 does it.

The reference is Lourenço's own Python 3 code, ``nunolourenco/sge3`` (which is DSGE, though its
name says SGE: its README calls it "an implementation of Dynamic Structured Grammatical
Evolution"): ``sge/sge/grammar.py`` ``_recursive_mapping`` and ``recursive_individual_creation``,
``sge/sge/operators/{mutation,recombination}.py``.

* **Genome**: one gene per rule of the grammar's tables (its order), each a list of choice
  indices, read in order by the rule's expansions; every expansion reads one, a single-choice
  rule's too. Depth-first, leftmost rule first; a value is the choice itself (no modulo).
* **Genes grow as needed.** A gene that runs out is filled, in sge3 during mapping, here by
  :meth:`DSGE.complete` (so that :meth:`DSGE.map` is a function of the genome; a genome that runs
  out maps as invalid, ``codons``): a node no deeper than ``max_depth`` takes any choice, a deeper
  one one of its rule's *shortest-path* choices (those of least minimum depth, sge3's
  ``shortest_path`` table).
* **Initialisation** (``recursive_individual_creation``): any choice down to ``init_depth``, the
  shortest-path ones below it.
* **Variation** (sge3's ``engine``): a child is, with probability ``crossover``, a uniform mask
  over whole genes of two parents, else a copy; then each value its mapping used, in a rule of
  more than one choice, changes with probability ``mutation`` to another choice (to a
  shortest-path one if the tree is already ``max_depth - 1`` deep, sge3's ``tree_depth >=
  MAX_TREE_DEPTH``); then its genes are completed.

Depth limits hold here where sge3's do not: initialisation and completion take only choices
that can still finish within ``max_depth`` (by the minimum-depth analysis), and a child deeper
than ``max_depth`` (crossover and mutation can make one) is made again, up to ``retries`` times,
then is a copy of its first parent. Where sge3's tree stays within the limit, those filters
remove nothing. sge3 counts depth from 0 at the root: its ``MAX_TREE_DEPTH`` m and
``MIN_TREE_DEPTH`` k are ``max_depth = m + 1`` and ``init_depth = k + 1`` here (its defaults, 17
and 5, are 18 and 6).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from gaitgram.analysis.cfg import Cfg
from gaitgram.ge.initialisation import InitialisationError
from gaitgram.ge.registry import RepresentationSpec, Setting, check_fields
from gaitgram.ge.representation import (
    UNLIMITED,
    GrammarTables,
    MappedGenome,
    Plugged,
    check_choices,
    check_genes,
    decode_genes,
    decode_many_genes,
    format_genes,
    grammar_tables,
    json_genes,
    parse_genes,
    result,
)
from gaitgram.language.model import Grammar

__all__ = ["DSGE", "REPRESENTATION", "DSGESettings", "Genes", "compile_dsge"]

Genes = tuple[tuple[int, ...], ...]


@dataclass(frozen=True, slots=True)
class DSGESettings:
    #: Deepest rule node (root 1) of any tree initialisation, completion and variation make.
    max_depth: int = 18
    #: Initialisation takes any choice down to this depth, shortest-path ones below it.
    init_depth: int = 6
    #: Probability that a child is a crossover of two parents (else a copy of one).
    crossover: float = 0.9
    #: Probability that each used value (of a rule with more than one choice) changes.
    mutation: float = 0.1
    #: Attempts at a child within ``max_depth`` before it is a copy of its parent.
    retries: int = 100

    def __post_init__(self) -> None:
        check_fields("dsge", SETTINGS, self)


_DEFAULTS = {f.name: f.default for f in fields(DSGESettings)}
#: DSGE's settings as a run declares them (``[representation_settings]``), the dataclass's defaults.
SETTINGS = (
    Setting(
        "max_depth", _DEFAULTS["max_depth"], "deepest rule node of any tree (sge3's MAX_TREE_DEPTH + 1)", 1
    ),
    Setting(
        "init_depth",
        _DEFAULTS["init_depth"],
        "initialisation takes any choice down to this depth, "
        "shortest-path ones below (sge3's MIN_TREE_DEPTH + 1)",
        1,
    ),
    Setting("crossover", _DEFAULTS["crossover"], "probability that a child crosses two parents", 0.0, 1.0),
    Setting("mutation", _DEFAULTS["mutation"], "probability that each used value changes", 0.0, 1.0),
    Setting("retries", _DEFAULTS["retries"], "attempts at a child within max_depth", 1),
)


def compile_dsge(
    source: Grammar | Cfg, settings: DSGESettings | None = None, *, joints: Mapping[str, str] | None = None
) -> DSGE:
    """DSGE for a grammar (or its tables); ``joints`` as for :func:`~gaitgram.ge.compile_mapper`."""
    return DSGE(grammar_tables(source, joints), settings or DSGESettings())


class DSGE:
    """DSGE over one grammar's tables. Immutable; genomes are tuples of tuples."""

    name = "dsge"
    #: What ``used`` counts: the values the mapping read.
    counts = "values"

    def __init__(self, tables: GrammarTables, settings: DSGESettings) -> None:
        self.tables = tables
        self.settings = settings
        cfg, facts = tables.cfg, tables.facts
        #: The rule each gene belongs to, by name (gene ``i`` is rule ``i`` of the tables).
        self.genes: tuple[str, ...] = cfg.names
        self._n = tuple(len(choices) for choices in cfg.choices)
        #: Per rule, its shortest-path choices (sge3's ``shortest_path`` table): those whose minimum
        #: depth is the rule's, an alternative written twice counted once, as its first (sge3 keeps
        #: the productions and finds each one's index again; PonyGE2's grammars repeat alternatives
        #: to weight them).
        self.shortest: tuple[tuple[int, ...], ...] = tuple(
            tuple(
                c
                for c, d in enumerate(depths)
                if d is not None and d == facts.min_depth[r] and cfg.choices[r].index(cfg.choices[r][c]) == c
            )
            for r, depths in enumerate(facts.choice_min_depth)
        )

    def __repr__(self) -> str:
        return f"DSGE(rules={len(self.genes)}, {self.settings})"

    # ---- mapping ----------------------------------------------------------------------------

    def map(self, genome: Genes) -> MappedGenome:
        """The genome's phenotype. A gene that runs out makes it invalid (``codons``); a value
        that is no choice of its rule raises :class:`~gaitgram.ge.representation.GenomeError`. The
        depth is reported, not limited, as sge3's mapping does (this module's operators keep
        within ``max_depth``)."""
        return self.map_many((genome,))[0]

    def map_many(self, genomes: Sequence[Genes]) -> list[MappedGenome]:
        tables, ops, start, rules = self.tables, self.tables.ops, self.tables.start, len(self.genes)
        names, choices = tables.base.close_names, self.choices
        # Each genome checked as the decoding reaches it (check_genes raises, saying how many genes
        # there should be), so that a batch's first bad genome is the one named.
        checked = (g if len(g) == rules else check_genes(g, self.genes) for g in genomes)
        results = []
        decoded = decode_many_genes(ops, start, checked, UNLIMITED, names)
        for genome, (phenotype, read, depth, reason, texts) in zip(genomes, decoded, strict=True):
            nodes = sum(read)
            results.append(result(tables, phenotype, depth, nodes, nodes, reason, texts, choices, genome))
        return results

    def choices(self, genome: Genes) -> list[int]:
        """The derivation's choices in pre-order, up to where a gene runs out."""
        children = self.tables.children
        cursor = [0] * len(genome)
        found: list[int] = []
        pending = [self.tables.start]
        while pending:
            rule = pending.pop()
            at = cursor[rule]
            if at >= len(genome[rule]) or not children[rule]:
                break
            choice = genome[rule][at]
            cursor[rule] = at + 1
            found.append(choice)
            pending.extend(reversed(children[rule][choice]))
        return found

    def tables_json(self) -> dict[str, Any]:
        """What ``gaitgram compile`` adds to the grammar's tables: each rule's shortest-path choices,
        which completion takes past ``max_depth``."""
        return {"shortest": [list(choices) for choices in self.shortest]}

    def used_per_gene(self, genome: Genes) -> tuple[list[int], int, bool]:
        """How many values of each gene the mapping reads, the tree's depth, and whether it is complete."""
        _, read, depth, reason, _ = decode_genes(
            self.tables.ops, self.tables.start, genome, UNLIMITED, self.tables.base.close_names
        )
        return read, depth, reason is None

    # ---- genes that grow ------------------------------------------------------------------

    def _choose(self, rng: np.random.Generator, rule: int, depth: int, threshold: int, max_depth: int) -> int:
        """sge3's choice for a node with no value yet: any choice down to ``threshold``, a
        shortest-path one below; only those that can still finish within ``max_depth``."""
        facts = self.tables.facts
        room = max_depth - depth + 1
        if depth > threshold:
            options = self.shortest[rule]
        else:
            depths = facts.choice_min_depth[rule]
            options = tuple(c for c, d in enumerate(depths) if d is not None and d <= room)
            if not options:  # the tree is already past the limit: the shortest way out
                options = self.shortest[rule]
        return options[int(rng.integers(len(options)))] if len(options) > 1 else options[0]

    def _derive(
        self, rng: np.random.Generator, genome: Sequence[Sequence[int]], threshold: int, max_depth: int
    ) -> tuple[Genes, list[int], int]:
        """Expand from the start rule reading ``genome`` and choosing (by :meth:`_choose` at
        ``threshold``) where a gene runs out: the completed genome, values used per gene, depth."""
        tables = self.tables
        genes = [list(gene) for gene in genome]
        used = [0] * len(genes)
        deepest = 0
        stack = [(tables.start, 1)]
        while stack:
            rule, depth = stack.pop()
            deepest = max(deepest, depth)
            gene = genes[rule]
            if used[rule] >= len(gene):
                gene.append(self._choose(rng, rule, depth, threshold, max_depth))
            choice = gene[used[rule]]
            used[rule] += 1
            stack.extend((child, depth + 1) for child in reversed(tables.children[rule][choice]))
        return tuple(tuple(gene) for gene in genes), used, deepest

    def complete(self, genome: Genes, rng: np.random.Generator) -> Genes:
        """The genome with every gene that runs out filled as sge3's mapping fills it (values it
        has are kept, used or not)."""
        limit = self.settings.max_depth
        return self._derive(rng, genome, limit, limit)[0]

    # ---- initialisation and variation ----------------------------------------------------------

    def initialise(self, rng: np.random.Generator, n: int, max_depth: int | None = None) -> list[Genes]:
        """``n`` genomes as sge3 creates them, none deeper than ``max_depth`` (default: the
        settings'), which is also the depth past which shortest-path choices are taken."""
        limit = self.settings.max_depth if max_depth is None else max_depth
        shortest = self.tables.facts.min_depth[self.tables.start]
        assert shortest is not None
        if shortest > limit:
            raise InitialisationError(
                f"the shortest derivation is {shortest} levels deep; max depth is {limit}"
            )
        empty: Genes = tuple(() for _ in self.genes)
        return [self._derive(rng, empty, self.settings.init_depth, limit)[0] for _ in range(n)]

    def vary(self, rng: np.random.Generator, parents: Sequence[Genes]) -> list[Genes]:
        """One child per parent: child ``i`` crosses parents ``i`` and ``i + 1`` (sge3 draws two
        tournament winners per crossover; the parents given are such winners)."""
        n = len(parents)
        return [self._child(rng, parents[i], parents[(i + 1) % n]) for i in range(n)]

    def _child(self, rng: np.random.Generator, first: Genes, second: Genes) -> Genes:
        settings = self.settings
        for _ in range(settings.retries):
            if rng.random() < settings.crossover:
                mask = rng.random(len(first)) < 0.5
                child: Genes = tuple(a if m else b for a, b, m in zip(first, second, mask, strict=True))
            else:
                child = first
            limit = settings.max_depth
            child, used, depth = self._derive(rng, child, limit, limit)
            child = self._mutate(rng, child, used, depth)
            child, _, depth = self._derive(rng, child, limit, limit)
            if depth <= settings.max_depth:
                return child
        return first

    def _mutate(self, rng: np.random.Generator, genome: Genes, used: list[int], depth: int) -> Genes:
        """sge3's ``mutate``: each used value of a rule with several choices, with probability
        ``mutation``, to another choice; to a shortest-path one (maybe the same) once the tree is
        ``max_depth - 1`` deep (sge3: ``tree_depth >= MAX_TREE_DEPTH``, counted from 0)."""
        probability, n = self.settings.mutation, self._n
        at_limit = depth >= self.settings.max_depth - 1
        genes = list(genome)
        for g, gene in enumerate(genome):
            if n[g] == 1 or not gene or not used[g]:
                continue
            hits = np.flatnonzero(rng.random(used[g]) < probability)
            if not hits.size:
                continue
            values = list(gene)
            for i in hits:
                if at_limit:
                    options = self.shortest[g]
                    values[i] = options[int(rng.integers(len(options)))]
                else:
                    other = int(rng.integers(n[g] - 1))
                    values[i] = other + (other >= values[i])
            genes[g] = tuple(values)
        return tuple(genes)

    # ---- text and JSON ------------------------------------------------------------------------

    def encode(self, genome: Genes) -> str:
        return format_genes(genome)

    def decode(self, text: str) -> Genes:
        """``[[0, 2], [1], []]``: one list per rule of the grammar, in its order (:attr:`genes`)."""
        genome = parse_genes(text, self.genes)
        check_choices(genome, self._n, self.genes)
        return genome

    def to_json(self, genome: Genes) -> Any:
        return [list(gene) for gene in genome]

    def from_json(self, value: Any) -> Genes:
        genome = json_genes(value, self.genes)
        check_choices(genome, self._n, self.genes)
        return genome


def describe_rule(cfg: Cfg, rule: int) -> str | None:
    """Where a rule's values lie in a DSGE genome."""
    n = len(cfg.choices[rule])
    return (
        f"DSGE gene {rule} of {len(cfg)}: a value per expansion of `<{cfg.names[rule]}>`, each one of its "
        f"{n:,} choice{'s' if n > 1 else ''}, grown as the derivation needs"
    )


REPRESENTATION = RepresentationSpec(
    name="dsge",
    summary="Dynamic structured GE: one gene of choices per rule, grown as needed, shortest-path "
    "choices past max_depth (sge3), uniform-mask crossover and per-value mutation.",
    settings=SETTINGS,
    compile=lambda grammar, facts, settings: Plugged(
        compile_dsge(grammar, DSGESettings(**settings)), grammar, settings
    ),
    genome_syntax="[[0], [2, 1], [], [0, 1, 1]]",
    version="dsge r1",
    describe_rule=describe_rule,
    source="Lourenço's sge3 (nunolourenco/sge3) and alogos' DSGE vectors (tests/data/representations)",
)
