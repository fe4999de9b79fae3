"""Genomes of the built-in representations drawn as derivation trees, so that they shrink as trees do.

A tree is drawn top-down as GE's derivations always were: a choice index per rule node in
pre-order, among the choices that can still finish within the depth budget (by the minimum-depth
analysis), ordered shallowest first, then by fewest rule children. Hypothesis shrinks the indices
toward 0, so a failing example shrinks toward small, shallow trees and low choices, whatever the
representation. The tree is then written as a genome of the representation (:class:`Plan`):

* GE: a codon per choice (lazy: per rule of more than one choice), the choice itself;
* πGE: a pair of codons per expansion, an order codon (drawn too: 0, what it shrinks to, expands
  the first open rule) and the choice;
* SGE: the tree is drawn over the unrolled grammar, so that it fits the recursion level; each
  entry's choices in order are its gene, the values no expansion reads 0;
* DSGE: each rule's choices in order are its gene;
* CFG-GP: the choices in pre-order are the genome.

A plug-in's representation, whose genomes gaitgram cannot write, has no plan.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property

from hypothesis import assume
from hypothesis import strategies as st

from gaitgram.analysis.cfg import Cfg
from gaitgram.analysis.facts import min_depths
from gaitgram.ge import CodonMode, Derivation
from gaitgram.ge.cfggp import CFGGP
from gaitgram.ge.classic import GE
from gaitgram.ge.dsge import DSGE
from gaitgram.ge.pige import PiGE
from gaitgram.ge.registry import Compiled, Genome
from gaitgram.ge.representation import Layout, Plugged, layout
from gaitgram.ge.sge import SGE

__all__ = [
    "DEFAULT_MAX_DEPTH",
    "DepthTooShallow",
    "Plan",
    "depth_budget",
    "draw_tree",
    "encode_derivation",
    "ge_plan",
    "plan_of",
    "tree_genomes",
]

#: The depth budget of a representation with no depth limit of its own, and GE's default.
DEFAULT_MAX_DEPTH = 10


class DepthTooShallow(ValueError):
    """No tree of the grammar fits the depth asked for; ``shortest`` is the depth its shallowest
    derivation needs (None: the grammar derives no sentence at all)."""

    def __init__(self, max_depth: int, shortest: int | None) -> None:
        reason = f"its shallowest derivation is {shortest} deep" if shortest else "it derives no sentence"
        super().__init__(f"the grammar has no derivation within depth {max_depth}: {reason}")
        self.max_depth, self.shortest = max_depth, shortest


#: Picks the order codon of an expansion among ``n`` open rules (πGE): drawn, or 0.
Pick = Callable[[int], int]


@dataclass(frozen=True, eq=False)
class Plan:
    """How trees are drawn for one compiled representation and written as its genomes.

    ``children`` and ``choice_depth`` are, per rule and choice, its rule children and minimum depth
    (None: it cannot finish) in the grammar trees are drawn over: the grammar's tables, or SGE's
    unrolled grammar. ``write(choices, pick)`` makes the genome of a tree drawn over it (pre-order
    choices); ``from_written(choices)`` turns a tree of the grammar as written into one drawn over
    it (:class:`ValueError` if the representation cannot hold it). ``limit`` is the
    representation's own depth limit; ``max_nodes`` its limit on expansions, if any."""

    start: int
    children: Sequence[Sequence[tuple[int, ...]]]
    choice_depth: Sequence[Sequence[int | None]]
    write: Callable[[Sequence[int], Pick], Genome]
    limit: int | None = None
    max_nodes: int | None = None
    from_written: Callable[[Sequence[int]], Sequence[int]] = list

    @cached_property
    def order(self) -> tuple[tuple[int, ...], ...]:
        """Per rule, its choices that can finish, shallowest first, then those of fewer rule
        children (``(<e>)`` before ``<e>+<e>``): index 0 is what shrinking aims for."""
        return tuple(
            tuple(
                sorted(
                    (c for c, d in enumerate(depths) if d is not None),
                    key=lambda c, ds=depths, kids=kids: (ds[c], len(kids[c]), c),
                )
            )
            for depths, kids in zip(self.choice_depth, self.children, strict=True)
        )

    def shortest(self) -> int | None:
        """The depth of the shallowest tree (None: there is none)."""
        return min((d for d in self.choice_depth[self.start] if d is not None), default=None)


def draw_tree(draw: st.DrawFn, plan: Plan, max_depth: int) -> list[int]:
    """A tree's choices in pre-order, no rule node deeper than ``max_depth`` (root 1)."""
    order, choice_depth, children = plan.order, plan.choice_depth, plan.children
    choices: list[int] = []
    stack = [(plan.start, 1)]
    while stack:
        rule, level = stack.pop()
        room = max_depth - level + 1
        fitting = [c for c in order[rule] if choice_depth[rule][c] <= room]  # type: ignore[operator]
        choice = fitting[draw(st.integers(0, len(fitting) - 1))]
        choices.append(choice)
        stack.extend((child, level + 1) for child in reversed(children[rule][choice]))
    return choices


def depth_budget(compiled: Compiled, max_depth: int | None = None) -> int | None:
    """How deep the drawn trees of ``compiled`` go: ``max_depth`` within the representation's own
    limit, else its own limit, else :data:`DEFAULT_MAX_DEPTH`; for a plug-in's representation,
    ``max_depth`` or its ``max_depth`` setting (None: no limit known)."""
    plan = plan_of(compiled)
    if plan is None:
        return max_depth or getattr(compiled, "settings", {}).get("max_depth")
    if max_depth is None:
        return plan.limit if plan.limit is not None else DEFAULT_MAX_DEPTH
    return max_depth if plan.limit is None else min(max_depth, plan.limit)


def tree_genomes(plan: Plan, max_depth: int) -> st.SearchStrategy[Genome]:
    """Genomes of drawn trees within ``max_depth`` (:class:`ValueError` if no tree fits)."""
    shortest = plan.shortest()
    if shortest is None or shortest > max_depth:
        raise DepthTooShallow(max_depth, shortest)

    @st.composite
    def genome(draw: st.DrawFn) -> Genome:
        choices = draw_tree(draw, plan, max_depth)
        if plan.max_nodes is not None:
            assume(len(choices) <= plan.max_nodes)
        return plan.write(choices, lambda n: draw(st.integers(0, n - 1)))

    return genome()


def _first(n: int) -> int:
    return 0


def encode_derivation(compiled: Compiled, derivation: Derivation) -> Genome:
    """The genome of ``compiled`` that maps to ``derivation``'s tree (a valid derivation of the same
    grammar, e.g. one of :func:`gaitgram.testing.derivations`); πGE's expands the first open rule
    each time. :class:`ValueError` if the representation cannot hold the tree (SGE: it recurses
    deeper than the recursion level) or gaitgram cannot write its genomes (a plug-in's)."""
    if not derivation.valid:
        raise ValueError(f"an invalid derivation ({derivation.reason}) has no genome")
    plan = plan_of(compiled)
    if plan is None:
        raise ValueError(f"gaitgram cannot write genomes of representation {compiled.name!r}")
    written = [node.choice for node, _ in derivation.tree.walk() if not node.is_terminal]
    return plan.write(plan.from_written(written), _first)  # type: ignore[arg-type]


def plan_of(compiled: Compiled) -> Plan | None:
    """The plan of a built-in representation (None: a plug-in's)."""
    if isinstance(compiled, GE):
        settings = compiled.settings
        return ge_plan(
            compiled.facts.cfg, compiled.facts.choice_min_depth, settings["codons"], settings["max_depth"]
        )
    representation = compiled.representation if isinstance(compiled, Plugged) else None
    if isinstance(representation, PiGE):
        return _pige_plan(representation)
    if isinstance(representation, SGE):
        return _sge_plan(representation)
    if isinstance(representation, DSGE | CFGGP):
        tables = representation.tables
        write = _dsge_genome(representation) if isinstance(representation, DSGE) else _cfggp_genome
        return Plan(
            tables.start,
            tables.children,
            tables.facts.choice_min_depth,
            write,
            limit=representation.settings.max_depth,
        )
    return None


def _rule_children(cfg: Cfg) -> tuple[tuple[tuple[int, ...], ...], ...]:
    return tuple(tuple(tuple(i for i in c if isinstance(i, int)) for c in cs) for cs in cfg.choices)


def ge_plan(
    cfg: Cfg, choice_depth: Sequence[Sequence[int | None]], codons: CodonMode | str, limit: int | None
) -> Plan:
    """GE's: a codon per choice, the choice itself; lazy codons skip rules of one choice."""
    assert cfg.start is not None
    children = _rule_children(cfg)
    eager = CodonMode(codons) is CodonMode.EAGER
    counted = tuple(eager or len(cs) > 1 for cs in cfg.choices)

    def write(choices: Sequence[int], pick: Pick) -> Genome:
        rules = layout(children, cfg.start, choices).rules  # type: ignore[arg-type]
        return tuple(c for r, c in zip(rules, choices, strict=True) if counted[r]) or (0,)

    return Plan(cfg.start, children, choice_depth, write, limit=limit)


def _kids(shape: Layout, node: int) -> list[int]:
    """The positions of a node's rule children in a tree's pre-order."""
    kids: list[int] = []
    child = node + 1
    while child < shape.ends[node]:
        kids.append(child)
        child = shape.ends[child]
    return kids


def _cfggp_genome(choices: Sequence[int], pick: Pick) -> Genome:
    return tuple(choices)


def _genes(count: int, rules: Sequence[int], choices: Sequence[int]) -> list[list[int]]:
    """Each rule's (entry's) choices in the order its expansions read them."""
    genes: list[list[int]] = [[] for _ in range(count)]
    for rule, choice in zip(rules, choices, strict=True):
        if rule < count:
            genes[rule].append(choice)
    return genes


def _dsge_genome(dsge: DSGE) -> Callable[[Sequence[int], Pick], Genome]:
    tables = dsge.tables

    def write(choices: Sequence[int], pick: Pick) -> Genome:
        rules = layout(tables.children, tables.start, choices).rules
        return tuple(map(tuple, _genes(len(dsge.genes), rules, choices)))

    return write


def _pige_plan(pige: PiGE) -> Plan:
    tables, settings = pige.tables, pige.settings
    children = tables.children

    def write(choices: Sequence[int], pick: Pick) -> Genome:
        """Expand the tree's nodes in the order the picks give, as πGE's stack holds them (where
        children join the open rules follows the stack mode, as :meth:`PiGE.expand`'s)."""
        shape = layout(children, tables.start, choices)
        codons: list[int] = []
        stack = [0]  # open nodes, by position in pre-order
        while stack:
            i = pick(len(stack))
            node = stack.pop(i)
            codons += (i, choices[node])
            kids = _kids(shape, node)
            if settings.stack == "inplace":
                stack[i:i] = kids
            elif settings.stack == "end":
                stack.extend(kids)
            else:
                stack[0:0] = kids
        return tuple(codons)

    return Plan(
        tables.start,
        children,
        tables.facts.choice_min_depth,
        write,
        limit=settings.max_depth,
        max_nodes=settings.max_expansions,
    )


def _sge_plan(sge: SGE) -> Plan:
    unrolled, start = sge.unrolled, sge.tables.start
    entries = unrolled.as_cfg(start)
    children = _rule_children(entries)
    genes, sizes = unrolled.genes, sge.sizes

    def write(choices: Sequence[int], pick: Pick) -> Genome:
        rules = layout(children, start, choices).rules
        found = _genes(genes, rules, choices)
        for g, gene in enumerate(found):
            if len(gene) > sizes[g]:  # the reference's sizes bound every derivation: never
                raise RuntimeError(f"sge: gene {g} needs {len(gene)} values; it has {sizes[g]}")
            gene.extend([0] * (sizes[g] - len(gene)))
        return tuple(map(tuple, found))

    # Per entry: for each written choice, which of its rule children the entry inlines, and the
    # entry's choice for the written choice with the inlined children's written choices.
    tables: dict[int, tuple[dict[int, tuple[bool, ...]], dict[tuple[int, ...], int]]] = {}

    def table(entry: int) -> tuple[dict[int, tuple[bool, ...]], dict[tuple[int, ...], int]]:
        if entry not in tables:
            slots: dict[int, tuple[bool, ...]] = {}
            found: dict[tuple[int, ...], int] = {}
            for j, items in enumerate(unrolled.choices[entry]):
                written = unrolled.origin_choice[entry][j]
                kids = [i for i in items if isinstance(i, int)]
                slots.setdefault(written, tuple(k >= genes for k in kids))
                key = (written, *(unrolled.origin_choice[k][0] for k in kids if k >= genes))
                found.setdefault(key, j)
            tables[entry] = slots, found
        return tables[entry]

    def from_written(written: Sequence[int]) -> list[int]:
        """A tree of the grammar as written, read as a tree of the unrolled grammar."""
        shape = layout(sge.tables.children, start, written)
        out = [0] * len(written)
        pending = [(0, start)]  # (position in pre-order, entry)
        while pending:
            p, entry = pending.pop()
            kids = _kids(shape, p)
            choice: int | None = 0  # an inlined alternative has one
            if entry < genes:
                slots, found = table(entry)
                inlined = slots.get(written[p])
                choice = (
                    None
                    if inlined is None
                    else found.get(
                        (written[p], *(written[k] for k, i in zip(kids, inlined, strict=True) if i))
                    )
                )
            if choice is None:
                raise ValueError(
                    f"sge: the tree recurses deeper than recursion level {sge.settings.recursion} allows "
                    f"(node {p}, <{unrolled.names[entry]}>)"
                )
            out[p] = choice
            items = [i for i in unrolled.choices[entry][choice] if isinstance(i, int)]
            pending.extend(reversed(list(zip(kids, items, strict=True))))
        return out

    return Plan(
        start,
        children,
        min_depths(entries)[1],
        write,
        limit=sge.settings.max_depth,
        from_written=from_written,
    )
