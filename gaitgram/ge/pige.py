"""Position-independent GE (πGE; O'Neill, Brabazon, Nicolau, Mc Garraghy and Keenan, 2004).

A genome is GE's list of codons read in (order, content) pairs: of the rules not yet expanded,
the order codon picks which (``order % how many``), the content codon its choice (``content %
choices``); every expansion reads both, a single-choice rule's and a single open rule's too. Codons
wrap around the genome; before each expansion, a genome read past ``max_wraps`` wraps (codon index
``// len(genome) > max_wraps``) or ``max_expansions`` expansions is invalid (``codons``), and so is
a tree deeper than ``max_depth`` (``depth``).

Where a chosen rule's children go among the open rules changes the result, and the published
worked examples differ (alogos, the reference here, names the three ``stack_mode`` values; its
``tests/test_system_pige.py`` holds the examples):

* ``"inplace"``: where the expanded rule was, the Handbook of GE's example (2018, p. 82; alogos'
  default and gaitgram's);
* ``"end"``: after all open rules, Fagan et al.'s 2010 example (CEC 2010, its Fig. 3);
* ``"start"``: before all open rules, the partial example of O'Neill et al. 2004.

Initialisation is sensible, as GE's: ramped half-and-half trees
(:func:`~gaitgram.ge.initialisation.ramped_population`) written as πGE genomes in a random order of
expansion (alogos' ``pi_rhh``: each order codon picks a random open rule, each codon a random value
that selects what it must). Variation is GE's (one-point crossover and int-flip mutation,
:mod:`gaitgram.ge.operators`): πGE changes the mapping, not the search, and alogos' two-point
length-preserving crossover needs genomes of one length, which sensible initialisation does not give.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from itertools import cycle, islice
from typing import Any, Literal

import numpy as np

from gaitgram.analysis.cfg import Cfg
from gaitgram.analysis.facts import occurrence_bounds
from gaitgram.ge.derivation import InvalidReason
from gaitgram.ge.initialisation import CODON_SIZE, ramped_population
from gaitgram.ge.mapper import MapperError
from gaitgram.ge.operators import int_flip_mutation, one_point_crossover
from gaitgram.ge.registry import RepresentationSpec, Setting, check_fields
from gaitgram.ge.representation import (
    UNLIMITED,
    GenomeError,
    GrammarTables,
    MappedGenome,
    Plugged,
    grammar_tables,
    json_ints,
    layout,
    parse_flat,
)
from gaitgram.language.model import Grammar

__all__ = ["REPRESENTATION", "PiGE", "PiGESettings", "StackMode", "compile_pige"]

Codons = tuple[int, ...]
StackMode = Literal["inplace", "end", "start"]
STACK_MODES: tuple[StackMode, ...] = ("inplace", "end", "start")


@dataclass(frozen=True, slots=True)
class PiGESettings:
    #: Where an expanded rule's children join the open rules (see the module's docstring).
    stack: StackMode = "inplace"
    #: W wraps allow W + 1 passes over the genome; None: no limit but ``max_expansions``.
    max_wraps: int | None = 3
    #: Most expansions a derivation may take; None: no limit but ``max_wraps``.
    max_expansions: int | None = None
    #: Deepest rule node (root 1) a valid genome may derive; None: no limit.
    max_depth: int | None = None
    #: Top of the initial trees' ramp; None: ``max_depth``, else 10 (a ramp to a deep limit makes
    #: full trees of tens of thousands of nodes on a binary grammar).
    init_max_depth: int | None = None
    #: Codons are drawn from [0, codon_size).
    codon_size: int = CODON_SIZE
    #: GE's variation (gaitgram's defaults, the paper's Table 1).
    crossover: float = 0.9
    fixed_point: bool = True
    crossover_within_used: bool = True
    mutation: float = 0.02
    #: Initialisation: probability of a *grow* tree (else *full*), and random codons appended
    #: after the used ones as a share of them.
    grow_probability: float = 0.5
    tail: float = 0.5

    def __post_init__(self) -> None:
        check_fields("pige", SETTINGS, self)
        if self.max_wraps is None and self.max_expansions is None:
            raise MapperError(
                "pige: max_wraps and max_expansions cannot both be None (a mapping could run forever)"
            )
        deepest, initial = self.max_depth, self.init_max_depth
        if deepest is not None and initial is not None and initial > deepest:
            raise MapperError(
                f"pige: init_max_depth ({initial}) is deeper than max_depth ({deepest}): "
                "lower it, or leave it out to ramp to max_depth"
            )


_DEFAULTS = {f.name: f.default for f in fields(PiGESettings)}
#: πGE's settings as a run declares them (``[representation_settings]``), the dataclass's defaults.
SETTINGS = (
    Setting(
        "stack",
        _DEFAULTS["stack"],
        "where an expanded rule's children join the open rules",
        choices=STACK_MODES,
    ),
    Setting(
        "max_wraps",
        _DEFAULTS["max_wraps"],
        "W wraps allow W + 1 passes over the genome",
        0,
        optional=True,
        kind=int,
    ),
    Setting(
        "max_expansions",
        _DEFAULTS["max_expansions"],
        "most expansions a derivation may take",
        1,
        optional=True,
        kind=int,
    ),
    Setting(
        "max_depth",
        _DEFAULTS["max_depth"],
        "deepest rule node of a valid genome (initial trees: 10 if none)",
        1,
        optional=True,
        kind=int,
    ),
    Setting(
        "init_max_depth",
        _DEFAULTS["init_max_depth"],
        "top of the initial trees' ramp (left out: max_depth, else 10)",
        1,
        optional=True,
        kind=int,
    ),
    Setting("codon_size", _DEFAULTS["codon_size"], "codons are drawn from [0, codon_size)", 2),
    Setting("crossover", _DEFAULTS["crossover"], "probability that a pair of parents is crossed", 0.0, 1.0),
    Setting("fixed_point", _DEFAULTS["fixed_point"], "one cut point for both parents"),
    Setting("crossover_within_used", _DEFAULTS["crossover_within_used"], "cut within the codons used"),
    Setting("mutation", _DEFAULTS["mutation"], "probability that each codon is replaced", 0.0, 1.0),
    Setting("grow_probability", _DEFAULTS["grow_probability"], "share of initial trees grown", 0.0, 1.0),
    Setting("tail", _DEFAULTS["tail"], "random codons after an initial tree's, as a share of them", 0.0),
)


def compile_pige(
    source: Grammar | Cfg, settings: PiGESettings | None = None, *, joints: Mapping[str, str] | None = None
) -> PiGE:
    """πGE for a grammar (or its tables); ``joints`` as for :func:`~gaitgram.ge.compile_mapper`."""
    return PiGE(grammar_tables(source, joints), settings or PiGESettings())


#: Node keys on πGE's stack: a node's number shifted left by this, its depth in the low bits.
_SHIFT = 24
_DEPTH = (1 << _SHIFT) - 1


@dataclass(frozen=True, slots=True)
class Expansion:
    """What πGE's expansions made of a genome. Nodes are numbered as created (the root 0).
    ``nodes[i]`` is node ``i``'s rule until it is expanded as a leaf (a choice without rule
    children), then its text. The log holds each expansion of a node with rule children, in
    order: the node, how many rule children, how its text is made from theirs and its first
    child's number. ``joints`` lists the nodes of joint rules as (rule, node);
    ``reason`` says why it stopped early (None: complete); ``used`` counts the codons read."""

    nodes: list[Any]
    log: list[tuple[int, int, Any, int]]
    joints: list[tuple[int, int]]
    depth: int
    reason: InvalidReason | None
    used: int


class PiGE:
    """πGE over one grammar's tables. Immutable; genomes are tuples of codons."""

    name = "pige"
    #: What ``used`` counts: the codons the mapping read.
    counts = "codons"

    def __init__(self, tables: GrammarTables, settings: PiGESettings) -> None:
        self.tables = tables
        self.settings = settings
        self._n = tuple(len(choices) for choices in tables.cfg.choices)
        joint_rules = set(tables.joint_rules)
        # Per rule and choice: its rule children, how many, how its text is made from theirs (see
        # ``_fill``), which of them (offset, rule) are joint rules, and the span of their keys.
        self._fills = tuple(
            tuple(
                (
                    kids,
                    len(kids),
                    _fill(items),
                    tuple((j, k) for j, k in enumerate(kids) if k in joint_rules),
                    len(kids) << _SHIFT,
                )
                for kids, items in zip(tables.children[r], choices, strict=True)
            )
            for r, choices in enumerate(tables.base.productions)
        )
        cfg, productive = tables.cfg, tables.facts.productive
        #: Joint rules no derivation holds twice: their one node is their first.
        self._once = frozenset(r for r in joint_rules if occurrence_bounds(cfg, r, productive)[1] <= 1)

    def __repr__(self) -> str:
        return f"PiGE(rules={len(self._n)}, {self.settings})"

    # ---- mapping ----------------------------------------------------------------------------

    def expand(self, genome: Codons) -> Expansion:
        """The expansion phase: which open rule each pair of codons expands, and how. A leaf gets
        its text at once; the others are logged for :meth:`map_many` to make their texts from
        their children's.

        The open rules are kept as keys (node number and depth in one int), so that children are
        put on the stack as one ``range`` and no list of depths is kept.
        """
        settings, fills, start = self.settings, self._fills, self.tables.start
        nodes: list[Any] = [start]
        log: list[tuple[int, int, Any, int]] = []
        joints: list[tuple[int, int]] = [(start, 0)] if start in self.tables.joint_rules else []
        if not genome:
            return Expansion(nodes, log, joints, 1, InvalidReason.CODONS, 0)
        # Pairs of codons from the genome read round and round: an expansion may start while
        # fewer than (max_wraps + 1) * len(genome) codons are read (its content codon may be past).
        pairs = UNLIMITED if settings.max_wraps is None else ((settings.max_wraps + 1) * len(genome) + 1) // 2
        if settings.max_expansions is not None:
            pairs = min(pairs, settings.max_expansions)
        max_depth = min(UNLIMITED if settings.max_depth is None else settings.max_depth, _DEPTH)
        codons = cycle(genome)
        mode = settings.stack
        stack = [1]  # the root: node 0 at depth 1
        pop, insert, record = stack.pop, stack.insert, log.append
        deepest = 1
        step = 1 << _SHIFT
        reason: InvalidReason | None = InvalidReason.CODONS  # unless the open rules run out first
        try:
            for order, content in islice(zip(codons, codons, strict=False), pairs):
                i = order % len(stack)
                key = pop(i)
                node = key >> _SHIFT
                options = fills[nodes[node]]
                kids, m, fill, joint_kids, span = options[
                    content % len(options)
                ]  # ZeroDivisionError: no choices
                if not m:
                    nodes[node] = fill
                    if not stack:
                        reason = None
                        break
                    continue
                depth = (key & _DEPTH) + 1
                if depth > deepest:
                    deepest = depth
                    if depth > max_depth:
                        reason = InvalidReason.DEPTH
                        break
                base = len(nodes)
                record((node, m, fill, base))
                nodes.extend(kids)
                if joint_kids:
                    joints.extend((rule, base + j) for j, rule in joint_kids)
                first = (base << _SHIFT) | depth
                if m == 1:
                    if mode == "end":
                        stack.append(first)
                    else:
                        insert(i if mode == "inplace" else 0, first)
                elif mode == "inplace":
                    stack[i:i] = range(first, first + span, step)
                elif mode == "end":
                    stack.extend(range(first, first + span, step))
                else:
                    stack[0:0] = range(first, first + span, step)
        except ZeroDivisionError:
            reason = InvalidReason.UNDEFINED
        # Each node made is expanded but those still open; a node that stopped the loop was popped.
        expanded = len(nodes) - len(stack)
        return Expansion(nodes, log, joints, deepest, reason, 2 * expanded)

    def map(self, genome: Codons) -> MappedGenome:
        return self.map_many((genome,))[0]

    def map_many(self, genomes: Sequence[Codons]) -> list[MappedGenome]:
        """Each genome's phenotype: the expansion phase, then each node's text made from its
        children's, in the reverse order of expansion (children are expanded after their parent)."""
        results = []
        new = tuple.__new__  # a MappedGenome without the NamedTuple's __new__, a Python call
        for genome in genomes:
            expansion = self.expand(genome)
            used = expansion.used
            if expansion.reason is not None:
                results.append(
                    new(MappedGenome, (None, {}, expansion.depth, used // 2, used, expansion.reason))
                )
                continue
            texts = expansion.nodes
            for node, m, fill, first in reversed(expansion.log):
                texts[node] = (
                    fill[0] + texts[first] + fill[1] if m == 1 else fill % tuple(texts[first : first + m])
                )
            joints = self._joints(expansion) if expansion.joints else {}
            results.append(new(MappedGenome, (texts[0], joints, expansion.depth, used // 2, used, None)))
        return results

    def _joints(self, expansion: Expansion) -> dict[str, str]:
        """Each joint rule's text at its first node in pre-order."""
        first: dict[int, int] = {}
        repeated = False
        for rule, node in expansion.joints:
            if rule in first:
                repeated = True
            else:
                first[rule] = node
        if repeated and not self._once.issuperset(first):
            first = self._first_in_preorder(expansion)
        texts = expansion.nodes
        return self.tables.base._name_joints({rule: texts[node] for rule, node in first.items()})

    def _first_in_preorder(self, expansion: Expansion) -> dict[int, int]:
        candidates = {node: rule for rule, node in expansion.joints}
        children = {node: (first, m) for node, m, _, first in expansion.log}
        found: dict[int, int] = {}
        pending = [0]
        while pending:
            node = pending.pop()
            rule = candidates.get(node)
            if rule is not None and rule not in found:
                found[rule] = node
            first, m = children.get(node, (0, 0))
            pending.extend(range(first + m - 1, first - 1, -1))
        return found

    def choices(self, genome: Codons) -> list[int]:
        """The derivation's choices in pre-order (for its tree), up to its first node left
        unexpanded. Each node's choice is found by its text's maker (``_fill``), which is one
        object per choice: a leaf whose text two choices share is given the first."""
        expansion = self.expand(genome)
        internal = {node: (first, m, fill) for node, m, fill, first in expansion.log}
        found: list[int] = []
        pending = [(0, self.tables.start)]
        while pending:
            node, rule = pending.pop()
            options = self._fills[rule]
            if node in internal:
                first, m, fill = internal[node]
                choice = next(c for c, entry in enumerate(options) if entry[2] is fill)
                pending.extend((first + j, options[choice][0][j]) for j in range(m - 1, -1, -1))
            else:
                text = expansion.nodes[node]
                if not isinstance(text, str):
                    break  # never expanded: the derivation stopped before it
                choice = next(c for c, entry in enumerate(options) if not entry[1] and entry[2] is text)
            found.append(choice)
        return found

    def sentential_form(self, genome: Codons) -> str:
        """The derivation as far as it got: terminals, and ``<rule>`` for each rule not expanded
        (a complete derivation gives the phenotype). The 2004 paper's example stops part way."""
        expansion = self.expand(genome)
        names, productions = self.tables.names, self.tables.base.productions
        internal = {node: (first, fill) for node, _, fill, first in expansion.log}
        out: list[str] = []
        pending: list[int | str] = [0]
        while pending:
            item = pending.pop()
            if isinstance(item, str):
                out.append(item)
            elif item in internal:
                child, fill = internal[item]
                rule = expansion.nodes[item]
                choice = next(c for c, entry in enumerate(self._fills[rule]) if entry[2] is fill)
                items: list[int | str] = []
                for x in productions[rule][choice]:
                    items.append(x if isinstance(x, str) else child)
                    child += not isinstance(x, str)
                pending.extend(reversed(items))
            else:
                node = expansion.nodes[item]
                out.append(node if isinstance(node, str) else f"<{names[node]}>")
        return "".join(out)

    # ---- initialisation and variation ----------------------------------------------------------

    def initialise(self, rng: np.random.Generator, n: int, max_depth: int | None = None) -> list[Codons]:
        """Ramped half-and-half trees up to ``max_depth`` (default: the settings' ``init_max_depth``,
        else their ``max_depth``, else 10), each written as a genome in a random order of expansion,
        with a random tail."""
        settings = self.settings
        limit = max_depth if max_depth is not None else settings.init_max_depth or settings.max_depth or 10
        trees = ramped_population(
            self.tables.facts, rng, n, max_depth=limit, grow_probability=settings.grow_probability, tail=0
        )
        return [self._encode_tree(rng, tuple(e.choice for e in tree.expansions)) for tree in trees]

    def _encode_tree(self, rng: np.random.Generator, choices: tuple[int, ...]) -> Codons:
        """A genome that πGE maps to the tree ``choices`` (pre-order), expanding open rules in a
        random order; each codon a random value with the residue it needs (alogos' ``reverse``
        with ``derivation_order="random"``)."""
        shape = layout(self.tables.children, self.tables.start, choices)
        size, mode, n = self.settings.codon_size, self.settings.stack, self._n
        codons: list[int] = []
        stack = [0]
        while stack:
            i = int(rng.integers(len(stack)))
            open_rules = len(stack)
            node = stack.pop(i)
            choice, k = choices[node], n[shape.rules[node]]
            codons.append(i + open_rules * int(rng.integers((size - 1 - i) // open_rules + 1)))
            codons.append(choice + k * int(rng.integers((size - 1 - choice) // k + 1)))
            kids = []
            child = node + 1
            while child < shape.ends[node]:
                kids.append(child)
                child = shape.ends[child]
            if mode == "inplace":
                stack[i:i] = kids
            elif mode == "end":
                stack.extend(kids)
            else:
                stack[0:0] = kids
        tail = round(len(codons) * self.settings.tail)
        codons.extend(int(c) for c in rng.integers(0, size, size=tail))
        return tuple(codons)

    def vary(self, rng: np.random.Generator, parents: Sequence[Codons]) -> list[Codons]:
        """GE's variation: pairs ``(0, 1), (2, 3), ...`` crossed at one point with probability
        ``crossover`` (within the codons each used if ``crossover_within_used``), then every codon
        flipped with probability ``mutation``; an odd last parent pairs with the first."""
        settings = self.settings
        used = [m.used for m in self.map_many(parents)] if settings.crossover_within_used else None
        children: list[Codons] = []
        for i in range(0, len(parents), 2):
            j = (i + 1) % len(parents)
            first, second = parents[i], parents[j]
            if rng.random() < settings.crossover:
                pair = one_point_crossover(
                    first,
                    second,
                    rng,
                    fixed_point=settings.fixed_point,
                    used=(used[i], used[j]) if used is not None else None,
                )
            else:
                pair = (first, second)
            children.extend(
                int_flip_mutation(c, rng, probability=settings.mutation, codon_size=settings.codon_size)
                for c in pair
            )
        return children[: len(parents)]

    # ---- text and JSON ------------------------------------------------------------------------

    def encode(self, genome: Codons) -> str:
        return ",".join(map(str, genome))

    def decode(self, text: str) -> Codons:
        """Codons as GE writes them: ``12,7,301`` (commas and/or spaces; a JSON list works)."""
        return parse_flat(text, "codon")

    def to_json(self, genome: Codons) -> Any:
        return list(genome)

    def from_json(self, value: Any) -> Codons:
        genome = json_ints(value, "a πGE genome")
        if not genome:
            raise GenomeError("a πGE genome needs at least one codon")
        return genome


def _fill(items: tuple[Any, ...]) -> Any:
    """How a choice's text is made from its rule children's: without rule children, the text; with
    one, the (before, after) pair around it; with more, a ``%`` template with a ``%s`` for each."""
    rules = sum(isinstance(i, int) for i in items)
    if not rules:
        return "".join(items)
    if rules == 1:
        at = next(j for j, i in enumerate(items) if isinstance(i, int))
        return "".join(items[:at]), "".join(items[at + 1 :])
    return "".join("%s" if isinstance(i, int) else i.replace("%", "%%") for i in items)


REPRESENTATION = RepresentationSpec(
    name="pige",
    summary="Position-independent GE: an order codon picks which open rule to expand, a content codon "
    "its choice (stack mode as the published examples), GE's initialisation and variation.",
    settings=SETTINGS,
    compile=lambda grammar, facts, settings: Plugged(
        compile_pige(grammar, PiGESettings(**settings)), grammar, settings
    ),
    genome_syntax="12,7,301,4",
    version="pige r1",
    source="O'Neill et al. 2004; alogos' pige (stack modes), checked against the published worked "
    "examples (tests/data/representations)",
)
