"""Structured GE (SGE; Lourenço, Pereira and Costa, GPEM 17(3), 2016), as Lourenço's code does it.

The reference is the original SGE, ``nunolourenco/sge`` (Python 2; ``src/core/grammar.py`` and
``src/core/sge.py``), which sge3 replaced by the dynamic variant (:mod:`gaitgram.ge.dsge`).

* **The grammar is unrolled** to a recursion level ``L`` (``read_grammar``/``rewrite_production``):
  a recursive rule ``<e>`` gets versions ``<e>``, ``<e_lvl_0>`` ... ``<e_lvl_L>``; each version's
  recursive references go to the next, and the last one's are replaced by each of the rule's
  non-recursive alternatives in turn (every combination, first reference slowest), so the last
  level cannot recurse. The reference unrolls direct recursion only; here a rule's "recursive"
  references are those into its strongly connected component, which is the same for direct
  recursion and unrolls indirect recursion too (a last-level alternative none of whose recursive
  references has a non-recursive alternative is dropped).
* **One gene per rule of the unrolled grammar**: the grammar's rules in its order, then each
  recursive rule's levels. A gene has one value per time its rule can be expanded at most
  (``compute_count_references_to_non_terminals``: a rule's references summed over the rules that
  use it, each counted where it occurs most, times the largest size among those rules; the start
  rule 1), so the genome never runs out. A value is the choice itself; every expansion reads one.
* **Initialisation**: uniform values; **variation**: with probability ``crossover`` a uniform mask
  over whole genes of two parents, else a copy; then each gene of a rule with several choices, with
  probability ``mutation``, has one value among those the mapping used changed to another choice.

An inlined alternative is a node of the grammar as written: depth, node counts and joint
phenotypes are those of the derivation in the user's grammar. Depth limits: initialisation takes,
where a tree would pass ``max_depth``, only choices that can still finish within it (when the
unrolled grammar cannot go that deep, exactly the reference's uniform genes); with
``settings.max_depth`` set, a deeper genome maps as invalid and variation makes a child again
(up to ``retries`` times, then copies its first parent) rather than pass it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from functools import lru_cache
from typing import Any

import numpy as np

from gaitgram.analysis.cfg import Cfg, Item, RuleKind
from gaitgram.analysis.facts import min_depths, reachable_from
from gaitgram.ge.export import choice_json
from gaitgram.ge.initialisation import InitialisationError
from gaitgram.ge.mapper import MapperError, _join_terminals
from gaitgram.ge.registry import RepresentationSpec, Setting, check_fields
from gaitgram.ge.representation import (
    UNLIMITED,
    GenomeError,
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

__all__ = ["REPRESENTATION", "SGE", "SGESettings", "compile_sge"]

#: The most values a genome may hold, and the most alternatives a last-level rule may get: SGE's
#: genes grow exponentially with the recursion level, and on some grammars past any memory
#: (PonyGE2's ``Word_Stats`` at level 1: 1.4e9 values). PonyGE2's ``Dow`` is within: 2,175 values
#: at level 5, and 659,680 alternatives of its last level (as the reference makes them; 4 s and
#: 340 MB to compile).
MAX_VALUES = 1_000_000
MAX_ALTERNATIVES = 1_000_000

Genes = tuple[tuple[int, ...], ...]


@dataclass(frozen=True, slots=True)
class SGESettings:
    #: Recursion level of the unrolled grammar (the reference's examples use 5).
    recursion: int = 5
    #: Probability that a child is a crossover of two parents (else a copy of one).
    crossover: float = 0.9
    #: Probability that each gene (of a rule with more than one choice) has one value changed.
    mutation: float = 0.05
    #: Deepest rule node (root 1) a valid genome may derive; None: as deep as the unrolled grammar goes.
    max_depth: int | None = None
    #: Attempts at a child within ``max_depth`` before it is a copy of its parent.
    retries: int = 100

    def __post_init__(self) -> None:
        check_fields("sge", SETTINGS, self)


_DEFAULTS = {f.name: f.default for f in fields(SGESettings)}
#: SGE's settings as a run declares them (``[representation_settings]``), the dataclass's defaults.
SETTINGS = (
    Setting("recursion", _DEFAULTS["recursion"], "recursion level of the unrolled grammar", 0),
    Setting("crossover", _DEFAULTS["crossover"], "probability that a child crosses two parents", 0.0, 1.0),
    Setting("mutation", _DEFAULTS["mutation"], "probability that each gene has a value changed", 0.0, 1.0),
    Setting(
        "max_depth", _DEFAULTS["max_depth"], "deepest rule node of a valid genome", 1, optional=True, kind=int
    ),
    Setting("retries", _DEFAULTS["retries"], "attempts at a child within max_depth", 1),
)


def compile_sge(
    source: Grammar | Cfg, settings: SGESettings | None = None, *, joints: Mapping[str, str] | None = None
) -> SGE:
    """SGE for a grammar (or its tables); ``joints`` as for :func:`~gaitgram.ge.compile_mapper`."""
    return SGE(grammar_tables(source, joints), settings or SGESettings())


@dataclass(frozen=True, eq=False)
class Unrolled:
    """The unrolled grammar: entries ``0..len(cfg)-1`` are the grammar's rules (top level), then
    each recursive rule's levels, then the *inlined* entries (a non-recursive alternative put in
    place of a last-level recursive reference: one choice, read from no gene)."""

    names: tuple[str, ...]
    #: Per entry, the grammar rule it stands for.
    origin: tuple[int, ...]
    #: Per entry, its choices; an int is an entry.
    choices: tuple[tuple[tuple[Item, ...], ...], ...]
    #: Entries with a gene (the first ``genes``): all but the inlined ones.
    genes: int
    #: Values per gene (the reference's ``count_references_to_non_terminals``).
    sizes: tuple[int, ...]
    #: Per entry and choice, the choice of the grammar's rule it stands for (a derivation tree in
    #: the grammar as written; not read by the mapping).
    origin_choice: tuple[tuple[int, ...], ...] = ()

    def as_cfg(self, start: int) -> Cfg:
        kinds = tuple(RuleKind.DEFINED if c else RuleKind.UNDEFINED for c in self.choices)
        origins = tuple(tuple(range(len(c))) for c in self.choices)
        return Cfg(self.names, kinds, self.choices, origins, start, {n: i for i, n in enumerate(self.names)})


def unroll(cfg: Cfg, start: int, level: int) -> Unrolled:
    """The grammar unrolled to ``level`` (see the module's docstring), with its gene sizes."""
    n = len(cfg)
    reach = [reachable_from(cfg, cfg.children(r)) for r in range(n)]
    component = [frozenset(s for s in range(n) if reach[r][s] and reach[s][r]) for r in range(n)]
    recursive = [r for r in range(n) if component[r]]
    names = list(cfg.names)
    origin = list(range(n))
    first_level: dict[int, int] = {}
    for r in recursive:
        first_level[r] = len(names)
        names.extend(f"{cfg.names[r]}_lvl_{k}" for k in range(level + 1))
        origin.extend([r] * (level + 1))
    genes = len(names)
    choices: list[tuple[tuple[Item, ...], ...]] = [()] * genes
    origin_choice: list[tuple[int, ...]] = [()] * genes
    inlined: dict[tuple[int, int], int] = {}

    def version(rule: int, k: int) -> int:  # k = -1: the top level
        return rule if k < 0 else first_level[rule] + k

    def inline(rule: int, choice: int) -> int:
        found = inlined.get((rule, choice))
        if found is None:
            found = inlined[rule, choice] = len(names)
            names.append(f"{cfg.names[rule]}/{choice}")
            origin.append(rule)
            choices.append((cfg.choices[rule][choice],))  # its references are all top level
            origin_choice.append((choice,))
        return found

    for r in range(n):
        if not component[r]:
            choices[r] = cfg.choices[r]
            origin_choice[r] = tuple(range(len(cfg.choices[r])))
            continue
        for k in range(-1, level + 1):
            inside = component[r]
            if k < level:
                rule_choices = tuple(
                    tuple(version(i, k + 1) if isinstance(i, int) and i in inside else i for i in choice)
                    for choice in cfg.choices[r]
                )
                origins = tuple(range(len(rule_choices)))
            else:
                last: list[tuple[Item, ...]] = []
                last_origin: list[int] = []
                for written, choice in enumerate(cfg.choices[r]):
                    slots = [j for j, i in enumerate(choice) if isinstance(i, int) and i in inside]
                    plain = [
                        [
                            c
                            for c, alt in enumerate(cfg.choices[choice[j]])
                            if not any(x in inside for x in alt)
                        ]
                        for j in slots
                    ]
                    combinations = math.prod(len(p) for p in plain)
                    if len(last) + combinations > MAX_ALTERNATIVES:
                        raise MapperError(
                            f"sge: at recursion level {level}, the last level of <{cfg.names[r]}> would have "
                            f"more than {MAX_ALTERNATIVES:,} alternatives; lower the recursion level, "
                            "or use dsge"
                        )
                    for picks in itertools.product(*plain):
                        items = list(choice)
                        for j, c in zip(slots, picks, strict=True):
                            items[j] = inline(choice[j], c)  # type: ignore[arg-type]
                        last.append(tuple(items))
                        last_origin.append(written)
                rule_choices, origins = tuple(last), tuple(last_origin)
            choices[version(r, k)] = rule_choices
            origin_choice[version(r, k)] = origins
    # A last level whose every alternative was dropped cannot be expanded (a derivation reaching it
    # is invalid, as at an undefined rule): it needs no values.
    sizes = tuple(size if choices[e] else 0 for e, size in enumerate(_sizes(choices, genes, start)))
    return Unrolled(tuple(names), tuple(origin), tuple(choices), genes, sizes, tuple(origin_choice))


def _sizes(choices: Sequence[Sequence[tuple[Item, ...]]], genes: int, start: int) -> tuple[int, ...]:
    """The reference's gene sizes: for each entry, the sum over the entries that use it of the most
    times one of their alternatives uses it (inlined ones counted in place), times the largest size
    among those entries; the start rule's is 1, an entry nothing uses 0."""

    def flat(items: tuple[Item, ...]) -> list[int]:
        out: list[int] = []
        for i in items:
            if isinstance(i, int):
                if i >= genes:
                    out.extend(flat(choices[i][0]))
                else:
                    out.append(i)
        return out

    most: list[dict[int, int]] = [{} for _ in range(genes)]  # entry -> {user: most uses}
    for user in range(genes):
        for items in choices[user]:
            counts: dict[int, int] = {}
            for i in flat(items):
                counts[i] = counts.get(i, 0) + 1
            for i, count in counts.items():
                most[i][user] = max(most[i].get(user, 0), count)
    # Users before the entries they use: the unrolled grammar's references have no cycle.
    waiting = [len(users) for users in most]
    uses: list[set[int]] = [set() for _ in range(genes)]
    for i, users in enumerate(most):
        for user in users:
            uses[user].add(i)
    sizes = [0] * genes
    ready = [i for i in range(genes) if not waiting[i]]
    while ready:
        i = ready.pop()
        users = most[i]
        if i == start:
            sizes[i] = 1
        elif users:
            sizes[i] = sum(users.values()) * max(sizes[u] for u in users)
        for used in uses[i]:
            waiting[used] -= 1
            if not waiting[used]:
                ready.append(used)
    return tuple(sizes)


class SGE:
    """SGE over one grammar's unrolled tables. Immutable; genomes are tuples of tuples."""

    name = "sge"
    #: What ``used`` counts: the values the mapping read.
    counts = "values"

    def __init__(self, tables: GrammarTables, settings: SGESettings) -> None:
        self.tables = tables
        self.settings = settings
        self.unrolled = unrolled = unroll(tables.cfg, tables.start, settings.recursion)
        #: Each gene's entry of the unrolled grammar, by name (``e``, ``e_lvl_0``, ...).
        self.genes: tuple[str, ...] = unrolled.names[: unrolled.genes]
        self.sizes = unrolled.sizes
        if sum(self.sizes) > MAX_VALUES:
            biggest = max(range(len(self.sizes)), key=self.sizes.__getitem__)
            raise MapperError(
                f"sge: at recursion level {settings.recursion} this grammar's genome would hold "
                f"{sum(self.sizes):,} values (gene <{self.genes[biggest]}> alone {self.sizes[biggest]:,}; "
                f"at most {MAX_VALUES:,}); lower the recursion level, or use dsge"
            )
        self._n = tuple(len(c) for c in unrolled.choices)
        # An inlined entry reads choice 0 every time: a "gene" of zeros as long as it can be needed
        # (inlined entries appear only in last-level choices, whose genes bound their expansions).
        most = sum(
            size
            * max((sum(i >= unrolled.genes for i in items if isinstance(i, int)) for items in c), default=0)
            for size, c in zip(unrolled.sizes, unrolled.choices, strict=False)
        )
        self._inlined: Genes = ((0,) * most,) * (len(unrolled.names) - unrolled.genes)
        self._ops = tuple(
            tuple(tables.op(unrolled.origin[e], _join_terminals(items)) for items in c)
            for e, c in enumerate(unrolled.choices)
        )
        cfg = unrolled.as_cfg(tables.start)
        self._children = tuple(
            tuple(tuple(i for i in c if isinstance(i, int)) for c in cs) for cs in cfg.choices
        )
        self._depth, self._choice_depth = min_depths(cfg)
        self._limit = UNLIMITED if settings.max_depth is None else settings.max_depth

    def __repr__(self) -> str:
        return f"SGE(genes={len(self.genes)}, values={sum(self.sizes)}, {self.settings})"

    # ---- mapping ----------------------------------------------------------------------------

    def map(self, genome: Genes) -> MappedGenome:
        return self.map_many((genome,))[0]

    def map_many(self, genomes: Sequence[Genes]) -> list[MappedGenome]:
        tables, ops, start, limit, inlined = (
            self.tables,
            self._ops,
            self.tables.start,
            self._limit,
            self._inlined,
        )
        genes, names, choices = len(self.genes), self.tables.base.close_names, self.choices
        # Each genome checked as the decoding reaches it (check_genes raises, saying how many genes
        # there should be), so that a batch's first bad genome is the one named.
        laid_out = ((g if len(g) == genes else check_genes(g, self.genes)) + inlined for g in genomes)
        results = []
        decoded = decode_many_genes(ops, start, laid_out, limit, names)
        for genome, (phenotype, read, depth, reason, texts) in zip(genomes, decoded, strict=True):
            nodes = sum(read)
            used = nodes - sum(read[genes:])
            results.append(result(tables, phenotype, depth, nodes, used, reason, texts, choices, genome))
        return results

    def choices(self, genome: Genes) -> list[int]:
        """The derivation's choices in pre-order in the grammar as written (each entry of the
        unrolled grammar stands for one node of it), up to where a gene runs out."""
        unrolled, genes = self.unrolled, genome + self._inlined
        cursor = [0] * len(genes)
        found: list[int] = []
        pending = [self.tables.start]
        while pending:
            entry = pending.pop()
            at = cursor[entry]
            if at >= len(genes[entry]) or not unrolled.choices[entry]:
                break
            choice = genes[entry][at]
            cursor[entry] = at + 1
            found.append(unrolled.origin_choice[entry][choice])
            pending.extend(i for i in reversed(unrolled.choices[entry][choice]) if isinstance(i, int))
        return found

    def tables_json(self) -> dict[str, Any]:
        """The genes for ``gaitgram compile``: each entry of the unrolled grammar with a gene, the rule
        it stands for, its size and its choices (a rule item is an entry: one of the genes, or an
        alternative inlined at the last level, listed after them with its one choice)."""
        unrolled = self.unrolled
        return {
            "genes": [
                {
                    "name": unrolled.names[e],
                    "rule": unrolled.origin[e],
                    "values": unrolled.sizes[e] if e < unrolled.genes else 0,
                    "choices": [choice_json(c) for c in unrolled.choices[e]],
                }
                for e in range(len(unrolled.names))
            ],
            "gene_count": unrolled.genes,
        }

    def used_per_gene(self, genome: Genes) -> list[int]:
        """How many values of each gene the mapping reads (the reference's ``mapping_values``)."""
        read = decode_genes(
            self._ops, self.tables.start, genome + self._inlined, UNLIMITED, self.tables.base.close_names
        )[1]
        return read[: len(self.genes)]

    # ---- initialisation and variation ----------------------------------------------------------

    def initialise(self, rng: np.random.Generator, n: int, max_depth: int | None = None) -> list[Genes]:
        """``n`` genomes of uniform values, but for the values a derivation reads where it would
        pass ``max_depth`` (default: the settings'), which are uniform among the choices that can
        still finish within it."""
        limit = self._limit if max_depth is None else max_depth
        shortest = self._depth[self.tables.start]
        if shortest is None:
            raise InitialisationError(
                f"at recursion level {self.settings.recursion} the unrolled grammar derives nothing from "
                f"<{self.tables.names[self.tables.start]}>; raise the recursion level"
            )
        if shortest > limit:
            raise InitialisationError(
                f"the shortest derivation is {shortest} levels deep; max depth is {limit}"
            )
        return [self._random_genome(rng, limit) for _ in range(n)]

    def _random_genome(self, rng: np.random.Generator, limit: int) -> Genes:
        genes = [
            rng.integers(0, max(k, 1), size=size).tolist()
            for k, size in zip(self._n, self.sizes, strict=False)
        ]
        cursor = [0] * len(genes)
        stack = [(self.tables.start, 1)]
        while stack:
            entry, depth = stack.pop()
            if entry < self.unrolled.genes:
                fitting = [
                    c
                    for c, d in enumerate(self._choice_depth[entry])
                    if d is not None and d <= limit - depth + 1
                ]
                choice = fitting[int(rng.integers(len(fitting)))]
                genes[entry][cursor[entry]] = choice
                cursor[entry] += 1
            else:
                choice = 0
            stack.extend((child, depth + 1) for child in reversed(self._children[entry][choice]))
        return tuple(tuple(gene) for gene in genes)

    def vary(self, rng: np.random.Generator, parents: Sequence[Genes]) -> list[Genes]:
        """One child per parent: child ``i`` crosses parents ``i`` and ``i + 1`` (the reference draws
        two tournament winners per crossover; the parents given are such winners)."""
        n = len(parents)
        used = [self.used_per_gene(p) for p in parents]
        return [
            self._child(rng, parents[i], parents[(i + 1) % n], used[i], used[(i + 1) % n]) for i in range(n)
        ]

    def _child(
        self,
        rng: np.random.Generator,
        first: Genes,
        second: Genes,
        used_first: list[int],
        used_second: list[int],
    ) -> Genes:
        settings = self.settings
        for _ in range(settings.retries):
            if rng.random() < settings.crossover:
                mask = rng.random(len(first)) < 0.5
                child = tuple(a if m else b for a, b, m in zip(first, second, mask, strict=True))
                used = [max(a, b) for a, b in zip(used_first, used_second, strict=True)]  # as the reference
            else:
                child, used = first, used_first
            child = self._mutate(rng, child, used)
            if self.map(child).valid:  # within max_depth, and clear of a last level left empty
                return child
        return first

    def _mutate(self, rng: np.random.Generator, genome: Genes, used: list[int]) -> Genes:
        genes = list(genome)
        hits = np.flatnonzero(rng.random(len(genome)) < self.settings.mutation)
        for g in hits:
            k = self._n[g]
            if k < 2 or not genome[g]:
                continue
            position = int(rng.integers(used[g])) if used[g] > 1 else 0
            values = list(genome[g])
            other = int(rng.integers(k - 1))
            values[position] = other + (other >= values[position])
            genes[g] = tuple(values)
        return tuple(genes)

    # ---- text and JSON ------------------------------------------------------------------------

    def _checked(self, genome: Genes) -> Genes:
        for g, (gene, size) in enumerate(zip(genome, self.sizes, strict=True)):
            if len(gene) != size:
                raise GenomeError(
                    f"gene {g} (<{self.genes[g]}>) has {len(gene)} value(s); SGE's genes have fixed sizes, "
                    f"and this one has {size} at recursion level {self.settings.recursion}"
                )
        check_choices(genome, self._n, self.genes)
        return genome

    def encode(self, genome: Genes) -> str:
        return format_genes(genome)

    def decode(self, text: str) -> Genes:
        """``[[0], [2, 1, 0], ...]``: one list per gene (:attr:`genes`), each of its size (:attr:`sizes`)."""
        return self._checked(parse_genes(text, self.genes))

    def to_json(self, genome: Genes) -> Any:
        return [list(gene) for gene in genome]

    def from_json(self, value: Any) -> Genes:
        return self._checked(json_genes(value, self.genes))


#: The largest grammar (in rules) the editor's hover unrolls: unrolling grows faster than the
#: grammar (a 1,000-rule recursive grammar takes a second), and a hover must answer at once.
MAX_DESCRIBED_RULES = 300


@lru_cache(maxsize=8)
def _unrolled(cfg: Cfg, level: int) -> Unrolled | None:
    """A grammar's unrolled tables for the editor (None: too large to unroll)."""
    try:
        unrolled = unroll(cfg, cfg.start, level) if cfg.start is not None else None
    except MapperError:
        return None
    return unrolled if unrolled is not None and sum(unrolled.sizes) <= MAX_VALUES else None


def describe_rule(cfg: Cfg, rule: int) -> str | None:
    """A rule's genes in an SGE genome at the default recursion level (the editor knows no run's
    settings), each with its size: the most expansions it can take, a value (a choice) each."""
    level = _DEFAULTS["recursion"]
    if len(cfg) > MAX_DESCRIBED_RULES:
        return (
            f"SGE: a grammar of {len(cfg):,} rules is not unrolled here; "
            f"`gaitgram compile G --representation sge -o -` lists its genes"
        )
    unrolled = _unrolled(cfg, level)
    if unrolled is None:
        return f"SGE: at recursion level {level} (the default) this grammar's genome is too large to hold"
    genes = [e for e in range(unrolled.genes) if unrolled.origin[e] == rule and unrolled.sizes[e]]
    if not genes:
        return f"SGE: no gene (no derivation at recursion level {level}, the default, expands it)"
    n = len(cfg.choices[rule])
    listed = "; ".join(
        f"{e} `<{unrolled.names[e]}>`: {unrolled.sizes[e]:,} value{'s' if unrolled.sizes[e] > 1 else ''}"
        for e in genes
    )
    return (
        f"SGE gene{'s' if len(genes) > 1 else ''} (recursion level {level}, the default; "
        f"{unrolled.genes} genes in all): {listed}; each value one of its {n:,} choice{'s' if n > 1 else ''}"
    )


REPRESENTATION = RepresentationSpec(
    name="sge",
    summary="Structured GE: the grammar unrolled to a recursion level, one gene of choices per rule "
    "(Lourenço, Pereira and Costa 2016), uniform-mask crossover and per-gene mutation.",
    settings=SETTINGS,
    compile=lambda grammar, facts, settings: Plugged(
        compile_sge(grammar, SGESettings(**settings)), grammar, settings
    ),
    genome_syntax="[[0], [2, 1], [], [0, 1, 1]]",
    version="sge r1",
    describe_rule=describe_rule,
    source="Lourenço's original SGE (nunolourenco/sge), run here on the bundled and PonyGE2 grammars "
    "(tests/data/representations)",
)
