"""CFG-GP (Whigham, "Grammatically-based genetic programming", 1995): the derivation tree is the genome.

There is no code of Whigham's to run; alogos' ``systems/cfggp`` quotes the paper and implements it,
and is the reference for what the paper leaves open.

* **Genome**: a derivation tree, held as the sequence of its choices in pre-order (each node's
  rule follows from the grammar and the choices before it), so a subtree is a slice. Its text is
  the tree, ``<e>0(<e>1(<v>0) <o>1 <e>1(<v>1))``; its JSON the flat list of choices.
* **Initialisation**: ramped half-and-half (:func:`~gaitgram.ge.initialisation.ramped_population`,
  GE's): *grow* or *full* trees of depths ramped up to ``max_depth``.
* **Crossover** (Whigham's Fig. 3): a random node of the first tree whose rule the second tree
  has, a random node of that rule in the second, and the subtrees swapped; if either child is
  deeper than ``max_depth`` the operation is aborted and begun again from the first step (up to
  ``retries`` times; then the parents are kept).
* **Mutation**: a random node's subtree replaced by a tree grown from its rule within
  ``max_depth`` ("in an operation similar to creating the initial population").

No tree any of these makes is deeper than ``max_depth``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from gaitgram.analysis.cfg import Cfg
from gaitgram.ge.initialisation import ramped_population
from gaitgram.ge.mapper import MapperError
from gaitgram.ge.registry import RepresentationSpec, Setting, check_fields
from gaitgram.ge.representation import (
    GenomeError,
    GrammarTables,
    Layout,
    MappedGenome,
    Plugged,
    decode_sequence,
    grammar_tables,
    grow_subtree,
    json_ints,
    layout,
    parse_flat,
    result,
    text_position,
)
from gaitgram.language.model import Grammar

__all__ = ["CFGGP", "REPRESENTATION", "CFGGPSettings", "Tree", "compile_cfggp"]

#: A derivation tree: its choices in pre-order.
Tree = tuple[int, ...]


@dataclass(frozen=True, slots=True)
class CFGGPSettings:
    #: Whigham's MAX-TREE-DEPTH: the deepest rule node (root 1) of any tree.
    max_depth: int = 17
    #: Probability that a pair of parents is crossed (else copied).
    crossover: float = 0.9
    #: Probability that a child has one subtree regrown.
    mutation: float = 0.1
    #: Initialisation: probability of a *grow* tree (else *full*).
    grow_probability: float = 0.5
    #: Crossover attempts within ``max_depth`` before the parents are kept.
    retries: int = 100
    #: Top of the initial trees' ramp; None: ``max_depth`` (a ramp to 17 makes full trees of tens
    #: of thousands of nodes on a binary grammar).
    init_max_depth: int | None = None

    def __post_init__(self) -> None:
        check_fields("cfg-gp", SETTINGS, self)
        if self.init_max_depth is not None and self.init_max_depth > self.max_depth:
            raise MapperError(
                f"cfg-gp: init_max_depth ({self.init_max_depth}) is deeper than max_depth "
                f"({self.max_depth}): lower it, or leave it out to ramp to max_depth"
            )


_DEFAULTS = {f.name: f.default for f in fields(CFGGPSettings)}
#: CFG-GP's settings as a run declares them (``[representation_settings]``), the dataclass's defaults.
SETTINGS = (
    Setting(
        "max_depth", _DEFAULTS["max_depth"], "deepest rule node of any tree (Whigham's MAX-TREE-DEPTH)", 1
    ),
    Setting("crossover", _DEFAULTS["crossover"], "probability that a pair of parents is crossed", 0.0, 1.0),
    Setting("mutation", _DEFAULTS["mutation"], "probability that a child has a subtree regrown", 0.0, 1.0),
    Setting("grow_probability", _DEFAULTS["grow_probability"], "share of initial trees grown", 0.0, 1.0),
    Setting("retries", _DEFAULTS["retries"], "crossover attempts within max_depth", 1),
    Setting(
        "init_max_depth",
        _DEFAULTS["init_max_depth"],
        "top of the initial trees' ramp (left out: max_depth)",
        1,
        optional=True,
        kind=int,
    ),
)


def compile_cfggp(
    source: Grammar | Cfg, settings: CFGGPSettings | None = None, *, joints: Mapping[str, str] | None = None
) -> CFGGP:
    """CFG-GP for a grammar (or its tables); ``joints`` as for :func:`~gaitgram.ge.compile_mapper`."""
    return CFGGP(grammar_tables(source, joints), settings or CFGGPSettings())


class CFGGP:
    """CFG-GP over one grammar's tables. Immutable; genomes are tuples of choices in pre-order."""

    name = "cfg-gp"
    #: What ``used`` counts: the nodes the mapping read.
    counts = "nodes"

    def __init__(self, tables: GrammarTables, settings: CFGGPSettings) -> None:
        self.tables = tables
        self.settings = settings

    def __repr__(self) -> str:
        return f"CFGGP(rules={len(self.tables.names)}, {self.settings})"

    # ---- mapping ----------------------------------------------------------------------------

    def map(self, genome: Tree) -> MappedGenome:
        return self.map_many((genome,))[0]

    def map_many(self, genomes: Sequence[Tree]) -> list[MappedGenome]:
        """Each tree's phenotype (a tree deeper than ``max_depth`` maps as invalid, ``depth``). A
        sequence that is not one tree of the grammar raises
        :class:`~gaitgram.ge.representation.GenomeError`."""
        tables, ops, start, limit = self.tables, self.tables.ops, self.tables.start, self.settings.max_depth
        names, choices = tables.base.close_names, self.choices
        results = []
        for genome in genomes:
            out, nodes, depth, reason, texts = decode_sequence(ops, start, genome, limit, names)
            if reason is None and nodes < len(genome):
                raise GenomeError(
                    f"the tree ends after {nodes} nodes; {len(genome) - nodes} value(s) left over"
                )
            phenotype = "".join(out) if reason is None else None
            results.append(result(tables, phenotype, depth, nodes, nodes, reason, texts, choices, genome))
        return results

    def choices(self, genome: Tree) -> list[int]:
        """The derivation's choices in pre-order: the genome itself."""
        return list(genome)

    def layout(self, genome: Tree) -> Layout:
        """Each node's rule, depth and subtree end (:class:`~gaitgram.ge.representation.Layout`)."""
        return layout(self.tables.children, self.tables.start, genome)

    # ---- initialisation and variation ----------------------------------------------------------

    def initialise(self, rng: np.random.Generator, n: int, max_depth: int | None = None) -> list[Tree]:
        """Ramped half-and-half trees, depths ramped up to ``max_depth`` (default: the settings'
        ``init_max_depth``, else their ``max_depth``)."""
        settings = self.settings
        limit = max_depth if max_depth is not None else settings.init_max_depth or settings.max_depth
        trees = ramped_population(
            self.tables.facts,
            rng,
            n,
            max_depth=limit,
            grow_probability=self.settings.grow_probability,
            tail=0,
        )
        return [tuple(e.choice for e in tree.expansions) for tree in trees]

    def vary(self, rng: np.random.Generator, parents: Sequence[Tree]) -> list[Tree]:
        """Children of parents ``(0, 1), (2, 3), ...``: crossed with probability ``crossover``, each
        then mutated with probability ``mutation``; an odd last parent pairs with the first."""
        settings = self.settings
        children: list[Tree] = []
        for i in range(0, len(parents), 2):
            first, second = parents[i], parents[(i + 1) % len(parents)]
            pair = (
                self.crossover(rng, first, second) if rng.random() < settings.crossover else (first, second)
            )
            children.extend(self.mutate(rng, c) if rng.random() < settings.mutation else c for c in pair)
        return children[: len(parents)]

    def crossover(self, rng: np.random.Generator, first: Tree, second: Tree) -> tuple[Tree, Tree]:
        """Whigham's subtree crossover within ``max_depth`` (the parents if no attempt fits)."""
        a, b = self.layout(first), self.layout(second)
        in_second = set(b.rules)
        sites = [p for p, r in enumerate(a.rules) if r in in_second]
        for _ in range(self.settings.retries):
            i = sites[int(rng.integers(len(sites)))]
            matching = [q for q, r in enumerate(b.rules) if r == a.rules[i]]
            j = matching[int(rng.integers(len(matching)))]
            limit = self.settings.max_depth
            if _swapped_depth(a, i, b, j) <= limit and _swapped_depth(b, j, a, i) <= limit:
                end_a, end_b = a.ends[i], b.ends[j]
                child_a = first[:i] + second[j:end_b] + first[end_a:]
                child_b = second[:j] + first[i:end_a] + second[end_b:]
                return child_a, child_b
        return first, second

    def mutate(self, rng: np.random.Generator, tree: Tree) -> Tree:
        """A random node's subtree regrown by *grow* within ``max_depth``."""
        shape = self.layout(tree)
        p = int(rng.integers(len(tree)))
        rule, depth = shape.rules[p], shape.depths[p]
        shortest = self.tables.facts.min_depth[rule]
        if shortest is None or depth + shortest - 1 > self.settings.max_depth:
            return tree  # a tree already past the limit (not one of ours): nothing fits here
        grown = grow_subtree(self.tables, rng, rule, depth, self.settings.max_depth)
        return tree[:p] + tuple(grown) + tree[shape.ends[p] :]

    # ---- text and JSON ------------------------------------------------------------------------

    def encode(self, tree: Tree) -> str:
        """The tree: each node ``<rule>choice``, its rule children in parentheses."""
        shape = self.layout(tree)
        names, children = self.tables.names, self.tables.children
        parts: list[str] = []
        closes: list[int] = []  # ends of the subtrees still open, innermost last
        for p, c in enumerate(tree):
            if p and parts[-1] != "(":
                parts.append(" ")
            parts.append(f"<{names[shape.rules[p]]}>{c}")
            if children[shape.rules[p]][c]:
                parts.append("(")
                closes.append(shape.ends[p])
            while closes and closes[-1] == p + 1:
                parts.append(")")
                closes.pop()
        return "".join(parts)

    def decode(self, text: str) -> Tree:
        """A tree as :meth:`encode` writes it, each ``<rule>`` the rule the grammar puts there; or
        its JSON, the choices in pre-order (``[0, 1, 0, 1, 1, 1]``)."""
        if text.lstrip().startswith("["):
            return self.from_json(parse_flat(text))
        roots = _parse_tree(text)
        if len(roots) != 1:
            raise GenomeError(f"the text holds {len(roots)} trees; a genome is one tree, e.g. <e>0(<v>1)")
        names, children = self.tables.names, self.tables.children
        choices: list[int] = []
        pending: list[tuple[int, _Node]] = [(self.tables.start, roots[0])]
        while pending:
            rule, (name, choice, kids, at) = pending.pop()
            where = text_position(text, at)
            if name != names[rule]:
                raise GenomeError(
                    f"{where}: <{name}> here, but the grammar expands <{names[rule]}> at this node"
                )
            options = children[rule]
            if choice >= len(options):
                raise GenomeError(
                    f"{where}: <{name}> has {len(options)} choice(s) (0 to {len(options) - 1}), not {choice}"
                )
            if len(kids) != len(options[choice]):
                raise GenomeError(
                    f"{where}: choice {choice} of <{name}> has {len(options[choice])} rule child(ren); "
                    f"the text gives {len(kids)}"
                )
            choices.append(choice)
            pending.extend(zip(reversed(options[choice]), reversed(kids), strict=True))
        return tuple(choices)

    def to_json(self, tree: Tree) -> Any:
        return list(tree)

    def from_json(self, value: Any) -> Tree:
        tree = json_ints(value, "a CFG-GP genome (its choices in pre-order)")
        self.layout(tree)  # one whole tree of the grammar, or GenomeError
        return tree


_TREE = re.compile(
    r"[\s,]*(?:(?P<node><(?P<name>[^<>]*)>\s*(?P<choice>[0-9]+))|(?P<open>\()|(?P<close>\))|(?P<bad>\S))"
)

#: A node as written: rule name, choice, children, offset in the text.
_Node = tuple[str, int, list[Any], int]


def _parse_tree(text: str) -> list[_Node]:
    """The nodes of a tree's text, nested as written (checked against the grammar by the caller)."""
    top: list[_Node] = []
    levels: list[list[_Node]] = [top]
    last: _Node | None = None
    position = 0
    for match in _TREE.finditer(text):
        if match.start() != position:
            break
        position = match.end()
        kind = match.lastgroup
        at = match.start(kind) if kind else match.start()
        if kind == "node":
            last = (match.group("name"), int(match.group("choice")), [], at)
            levels[-1].append(last)
        elif kind == "open":
            if last is None:
                raise GenomeError(f"{text_position(text, at)}: '(' must follow a node, e.g. <e>0(<v>1)")
            levels.append(last[2])
            last = None
        elif kind == "close":
            if len(levels) == 1:
                raise GenomeError(f"{text_position(text, at)}: ')' closes nothing")
            levels.pop()
            last = None
        else:
            raise GenomeError(
                f"{text_position(text, at)}: cannot read {text[at : at + 20]!r}; a node is <rule>choice, "
                "its rule children in parentheses, e.g. <e>0(<v>1)"
            )
    if text[position:].strip():
        raise GenomeError(f"{text_position(text, position)}: cannot read {text[position:].strip()[:20]!r}")
    if len(levels) > 1:
        raise GenomeError(f"the tree's text ends with {len(levels) - 1} '(' left open")
    return top


def _swapped_depth(into: Layout, at: int, source: Layout, at_source: int) -> int:
    """The depth of ``into`` with its subtree at ``at`` replaced by ``source``'s at ``at_source``."""
    outside = max(max(into.depths[:at], default=0), max(into.depths[into.ends[at] :], default=0))
    height = max(source.depths[at_source : source.ends[at_source]]) - source.depths[at_source]
    return max(outside, into.depths[at] + height)


REPRESENTATION = RepresentationSpec(
    name="cfg-gp",
    summary="CFG-GP: the derivation tree is the genome (Whigham 1995), ramped half-and-half, subtree "
    "crossover and mutation within max_depth.",
    settings=SETTINGS,
    compile=lambda grammar, facts, settings: Plugged(
        compile_cfggp(grammar, CFGGPSettings(**settings)), grammar, settings
    ),
    genome_syntax="<e>0(<e>1(<v>0) <o>1 <e>1(<v>1))",
    version="cfg-gp r1",
    source="Whigham 1995, and alogos' cfggp for what the paper leaves open",
)
