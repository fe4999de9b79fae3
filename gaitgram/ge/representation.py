"""What the grammar-guided representations beside GE share: the typed API, the result of mapping a
genome, the decoding loop over a grammar's tables, and genome text.

Each representation (:mod:`~gaitgram.ge.pige`, :mod:`~gaitgram.ge.sge`, :mod:`~gaitgram.ge.dsge`,
:mod:`~gaitgram.ge.cfggp`) compiles a grammar's integer rule tables
(:class:`~gaitgram.analysis.cfg.Cfg`) once, so a typed range is one choice set and ``@joint``
rules give joint phenotypes exactly as they do for GE. A compiled representation is immutable and
offers the same five things, which a plug-in can wrap as they are:

* ``initialise(rng, n, max_depth)``: ``n`` genomes whose trees are no deeper than ``max_depth``;
* ``vary(rng, parents)``: as many children, by the crossover and mutation of the reference code;
* ``map(genome)`` / ``map_many(genomes)``: :class:`MappedGenome`, the phenotype and its summary;
* ``encode(genome)`` / ``decode(text)``: genome text; ``to_json`` / ``from_json``: JSON values.

Depth is counted as everywhere in gaitgram: the root rule node has depth 1, terminals add none.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from operator import length_hint
from typing import Any, NamedTuple, Protocol, TypeVar

import numpy as np

from gaitgram import __version__
from gaitgram.analysis.cfg import Cfg, Item
from gaitgram.analysis.facts import GrammarFacts, min_depths, reachable_from
from gaitgram.ge.derivation import Derivation, InvalidReason
from gaitgram.ge.export import grammar_tables_json
from gaitgram.ge.initialisation import Method, _pick
from gaitgram.ge.mapper import CodonMode, Mapper, MapperError, compile_mapper, joint_op
from gaitgram.ge.registry import GenomeError
from gaitgram.language.model import Grammar

__all__ = [
    "GenomeError",
    "GrammarTables",
    "MappedGenome",
    "Representation",
    "grammar_tables",
]

G = TypeVar("G")

#: No depth limit, as a number: the decoding loop compares without a None test.
UNLIMITED = 1 << 62
#: Bottom-of-stack and level-close sentinels of the decoding loop (as the GE mapper's).
_DONE = -1
_UP = -2


class MappedGenome(NamedTuple):
    """A genome's phenotype and what a run records of it.

    ``used`` counts what the mapping read (codons for πGE, gene values for SGE and DSGE, tree
    nodes for CFG-GP); ``depth`` and ``nodes`` describe the derivation tree in the grammar as
    written (rule nodes; the root has depth 1). An invalid genome has no phenotype and no joints,
    and ``reason`` says why.
    """

    phenotype: str | None
    joints: dict[str, str]
    depth: int
    nodes: int
    used: int
    reason: InvalidReason | None

    @property
    def valid(self) -> bool:
        return self.reason is None


#: How the decoding loops build a :class:`MappedGenome`: its fields as one tuple, without the
#: NamedTuple's ``__new__``, a Python call per genome.
_new = tuple.__new__


class Representation(Protocol[G]):
    """The typed API every representation offers (``G`` is its genome type)."""

    name: str

    def initialise(self, rng: np.random.Generator, n: int, max_depth: int) -> list[G]: ...

    def vary(self, rng: np.random.Generator, parents: Sequence[G]) -> list[G]: ...

    def map(self, genome: G) -> MappedGenome: ...

    def map_many(self, genomes: Sequence[G]) -> list[MappedGenome]: ...

    def encode(self, genome: G) -> str: ...

    def decode(self, text: str) -> G: ...

    def to_json(self, genome: G) -> Any: ...

    def from_json(self, value: Any) -> G: ...


@dataclass(frozen=True, eq=False)
class GrammarTables:
    """A grammar compiled once for every representation: per rule and choice the decoding loops'
    operation (see :func:`make_op`), the rule facts initialisation needs, and the joints."""

    cfg: Cfg
    facts: GrammarFacts
    start: int
    #: The GE mapper on the same tables: terminals joined, joints found, the grammar checked.
    base: Mapper
    #: Per rule and choice, the decoding loops' operation.
    ops: tuple[tuple[Any, ...], ...]
    #: Per rule and choice, the rules it uses, in order.
    children: tuple[tuple[tuple[int, ...], ...], ...]
    #: The joint rules, numbered as their markers number them (the GE mapper's ``joint_list``).
    joint_rules: tuple[int, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return self.cfg.names

    def op(self, rule: int, items: tuple[Item, ...]) -> Any:
        """The operation of a choice of ``rule`` with ``items`` (terminals joined): for tables
        built on this grammar, as SGE's unrolled rules are."""
        return make_op(items, _marker(self.base, rule))

    def joints_of(
        self, texts: dict[str, str], choices: Callable[[Any], Sequence[int]], genome: Any
    ) -> dict[str, str]:
        """A valid derivation's joints, from the texts :func:`decode_genes` and :func:`decode_sequence`
        join at each joint's closing marker, as the GE mapper's loops do
        (:meth:`Mapper.joints_in_order`; ``choices(genome)``: the derivation's choices in pre-order)."""
        return self.base.joints_in_order(texts, choices, genome)


def make_op(items: tuple[Item, ...], joint: int | None) -> Any:
    """A choice as the decoding loops apply it (``items``: terminals joined, as the GE mapper's
    ``productions``).

    * a *leaf* (no rule among the items), not of a joint rule: its text, a ``str``;
    * otherwise ``(lead, head, rest)``: emit the leading terminals, continue with the first rule
      (saving a push and a pop), push the rest reversed. A joint rule's items go between markers,
      ints: the loops record the output's length at the first and join the joint's text at the
      second.
    """
    if joint is not None:
        return joint_op(joint, items)
    if not any(isinstance(i, int) for i in items):
        return "".join(items)  # type: ignore[arg-type]
    rest = list(items)
    lead = rest.pop(0) if isinstance(rest[0], str) else ""
    head = rest.pop(0)
    return lead, head, tuple(reversed(rest))


def grammar_tables(source: Grammar | Cfg, joints: Mapping[str, str] | None = None) -> GrammarTables:
    """Compile ``source`` (refused with :class:`MapperError` as :func:`compile_mapper` refuses it)."""
    base = compile_mapper(source, codons=CodonMode.EAGER, max_wraps=0, joints=joints)
    cfg = base.cfg
    depth, choice_depth = min_depths(cfg)
    facts = GrammarFacts(
        cfg=cfg,
        productive=tuple(d is not None for d in depth),
        reachable=reachable_from(cfg, [base.start]),
        min_depth=depth,
        choice_min_depth=choice_depth,
        joint_reach={},
    )
    if depth[base.start] is None:
        raise MapperError(f"the start rule <{cfg.names[base.start]}> derives no finite phenotype")
    children = tuple(
        tuple(tuple(i for i in choice if isinstance(i, int)) for choice in choices) for choices in cfg.choices
    )
    ops = tuple(
        tuple(make_op(items, _marker(base, r)) for items in choices)
        for r, choices in enumerate(base.productions)
    )
    return GrammarTables(cfg, facts, base.start, base, ops, children, base.joint_list)


def _marker(base: Mapper, rule: int) -> int | None:
    """The number of ``rule``'s joint markers; None for a rule without, and for every rule of a
    grammar whose joints are cut from the phenotype (``base.joints_from_phenotype``)."""
    if rule not in base.joint_list or base.joints_from_phenotype is not None:
        return None
    return base.joint_list.index(rule)


def decode_genes(
    ops: Sequence[Any],
    start: int,
    genes: Sequence[Sequence[int]],
    max_depth: int,
    names: Mapping[int, str],
) -> tuple[str | None, list[int], int, InvalidReason | None, dict[str, str]]:
    """One genome's :func:`decode_many_genes`."""
    return next(decode_many_genes(ops, start, (genes,), max_depth, names))


def decode_many_genes(
    ops: Sequence[Any],
    start: int,
    genomes: Iterable[Sequence[Sequence[int]]],
    max_depth: int,
    names: Mapping[int, str],
) -> Iterator[tuple[str | None, list[int], int, InvalidReason | None, dict[str, str]]]:
    """Expand each genome from ``start`` depth-first, leftmost rule first, each rule ``r`` taking
    as its choice the next value of ``genes[r]`` (SGE and DSGE: a gene per rule, each read with its
    own cursor).

    Yields, per genome, the phenotype (None if invalid), the values read from each gene (their
    sum: the rule nodes expanded), the depth reached, why the derivation stopped early (None: it
    is complete; ``codons`` when a gene runs out, ``depth`` past ``max_depth``, ``undefined`` at a
    rule with no choices) and the joints' texts, by name (``names``: the GE mapper's
    ``close_names``), joined where each joint's closing marker is met. A value that names no
    choice raises :class:`GenomeError`.

    The loop is the GE mapper's depth-tracking fast loop (``_run_depth``), with the codon
    arithmetic replaced by the gene cursors: an expansion emits its leading terminals, pushes a
    level-close sentinel and the rest of its items, and continues with its first rule; a leaf
    emits its text and goes on. Written out again in :func:`decode_sequence` on purpose: a shared
    step would cost a call per node. A generator over the genomes, so that the output list, the
    stack and their bound methods are set up once, not per genome (on a small grammar, a dozen
    nodes a genome, that setup was a sixth of the time); a derivation's end leaves the loops
    through ``while`` ... ``else``.
    """
    out: list[str] = []
    append, clear, join = out.append, out.clear, "".join
    starts: list[int] = []  # the output's length at each open joint's marker
    mark, unmark = starts.append, starts.pop
    stack: list[Any] = []
    pop, push, extend = stack.pop, stack.append, stack.extend
    depth_reason, codons, undefined = InvalidReason.DEPTH, InvalidReason.CODONS, InvalidReason.UNDEFINED
    for genes in genomes:
        texts: dict[str, str] = {}  # each joint's text, joined at its closing marker, by name
        read = [0] * len(genes)
        depth = deepest = 0
        reason = None
        push(_DONE)
        item = start
        try:
            while True:
                at = read[item]
                op = ops[item][genes[item][at]]  # IndexError: no value left, or no such choice
                read[item] = at + 1
                if op.__class__ is str:  # a leaf, one level down
                    if depth >= deepest:
                        deepest = depth + 1
                        if deepest > max_depth:
                            reason = depth_reason
                            break
                    append(op)
                else:
                    lead, head, rest = op
                    depth += 1
                    if depth > deepest:
                        deepest = depth
                        if depth > max_depth:
                            reason = depth_reason
                            break
                    if lead:
                        append(lead)
                    push(_UP)
                    if rest:
                        extend(rest)
                    if head is not None:
                        item = head
                        continue
                item = pop()
                while type(item) is not int:  # terminals
                    append(item)
                    item = pop()
                while item < 0:
                    if item == _UP:
                        depth -= 1
                    elif item == _DONE:
                        break
                    elif item & 1:  # a joint's opening marker
                        mark(len(out))
                    else:
                        texts[names[item]] = join(out[unmark() :])
                    item = pop()
                    while type(item) is not int:
                        append(item)
                        item = pop()
                else:
                    continue  # the next rule to expand
                break  # the derivation is complete
        except IndexError:
            if not ops[item]:
                reason = undefined
            elif read[item] >= len(genes[item]):
                reason = codons
            else:
                raise GenomeError(
                    f"value {read[item]} of gene {item}, {genes[item][read[item]]}, is no choice of its "
                    f"rule (it has {len(ops[item])})"
                ) from None
        if reason is None:
            phenotype: str | None = join(out)
        else:
            phenotype = None
            stack.clear()
            starts.clear()
        clear()
        yield phenotype, read, deepest, reason, texts


def decode_sequence(
    ops: Sequence[Any], start: int, sequence: Sequence[int], max_depth: int, names: Mapping[int, str]
) -> tuple[list[str], int, int, InvalidReason | None, dict[str, str]]:
    """As :func:`decode_genes`, the choices read in order from one sequence (a tree's choices in
    pre-order: CFG-GP). Returns the pieces, the values read (the rule nodes), the depth, why it
    stopped early (``codons``: the sequence ran out) and the joints' texts."""
    out: list[str] = []
    append = out.append
    texts: dict[str, str] = {}  # each joint's text, joined at its closing marker, by name
    starts: list[int] = []  # the output's length at each open joint's marker
    mark, unmark, join = starts.append, starts.pop, "".join
    stack: list[Any] = [_DONE]
    pop, push, extend = stack.pop, stack.append, stack.extend
    depth = deepest = 0
    item = start
    values = iter(sequence)
    n = len(sequence)
    try:
        # One expansion per value, so the values drive the loop (as in GE's eager loop).
        for choice in values:
            op = ops[item][choice]  # IndexError: no such choice
            if op.__class__ is str:  # a leaf, one level down
                if depth >= deepest:
                    deepest = depth + 1
                    if deepest > max_depth:
                        return out, n - length_hint(values), deepest, InvalidReason.DEPTH, texts
                append(op)
            else:
                lead, head, rest = op
                depth += 1
                if depth > deepest:
                    deepest = depth
                    if depth > max_depth:
                        return out, n - length_hint(values), deepest, InvalidReason.DEPTH, texts
                if lead:
                    append(lead)
                push(_UP)
                if rest:
                    extend(rest)
                if head is not None:
                    item = head
                    continue
            item = pop()
            while True:
                while type(item) is not int:  # terminals
                    append(item)
                    item = pop()
                if item >= 0:
                    break
                if item == _UP:
                    depth -= 1
                elif item == _DONE:
                    return out, n - length_hint(values), deepest, None, texts
                elif item & 1:  # a joint's opening marker
                    mark(len(out))
                else:
                    texts[names[item]] = join(out[unmark() :])
                item = pop()
    except IndexError:
        if not ops[item]:
            return out, n - length_hint(values) - 1, deepest, InvalidReason.UNDEFINED, texts
        raise GenomeError(
            f"value {n - length_hint(values) - 1} of the sequence is no choice of its rule "
            f"(it has {len(ops[item])})"
        ) from None
    return out, n, deepest, InvalidReason.CODONS, texts


def result(
    tables: GrammarTables,
    phenotype: str | None,
    depth: int,
    nodes: int,
    used: int,
    reason: InvalidReason | None,
    texts: dict[str, str],
    choices: Callable[[Any], Sequence[int]],
    genome: Any,
) -> MappedGenome:
    """What a decoding loop returned, as a :class:`MappedGenome` (``choices(genome)``: the
    derivation's choices in pre-order, asked only for a grammar whose joints come from the tree)."""
    # Built with tuple.__new__, not the NamedTuple's own __new__ (a Python call): on a small grammar
    # (a dozen nodes a genome) that call was a tenth of the decoding.
    if reason is not None:
        return _new(MappedGenome, (None, {}, depth, nodes, used, reason))
    if texts:
        joints = tables.joints_of(texts, choices, genome)
    else:
        cut = tables.base.joints_from_phenotype
        joints = texts if cut is None else cut(phenotype)  # type: ignore[arg-type]  # valid, so a str
    return _new(MappedGenome, (phenotype, joints, depth, nodes, used, None))


# ---- derivation trees in pre-order ------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Layout:
    """A derivation as the pre-order sequence of its choices (the rules follow from the grammar):
    each node's rule, depth and the end (exclusive) of its subtree in the sequence."""

    rules: tuple[int, ...]
    depths: tuple[int, ...]
    ends: tuple[int, ...]

    @property
    def depth(self) -> int:
        return max(self.depths, default=0)


def layout(children: Sequence[Sequence[tuple[int, ...]]], start: int, choices: Sequence[int]) -> Layout:
    """The :class:`Layout` of ``choices`` read as a derivation from ``start``.

    Raises :class:`GenomeError` if a choice does not exist or the sequence is not exactly one tree.
    """
    n = len(choices)
    rules: list[int] = []
    depths: list[int] = []
    ends = [0] * n
    pending: list[tuple[int, int]] = [(start, 1)]
    open_nodes: list[list[int]] = []  # [position, children still to complete]
    for p, c in enumerate(choices):
        if not pending:
            raise GenomeError(f"the tree ends after {p} nodes; {n - p} value(s) left over")
        rule, d = pending.pop()
        options = children[rule]
        if not 0 <= c < len(options):
            raise GenomeError(f"node {p}: {c} is not a choice of its rule (it has {len(options)})")
        kids = options[c]
        rules.append(rule)
        depths.append(d)
        if kids:
            pending.extend((k, d + 1) for k in reversed(kids))
            open_nodes.append([p, len(kids)])
            continue
        ends[p] = p + 1
        while open_nodes:
            top = open_nodes[-1]
            top[1] -= 1
            if top[1]:
                break
            ends[top[0]] = p + 1
            open_nodes.pop()
    if pending:
        raise GenomeError(f"the tree is incomplete: {len(pending)} rule(s) left unexpanded after {n} nodes")
    return Layout(tuple(rules), tuple(depths), tuple(ends))


def grow_subtree(
    tables: GrammarTables, rng: np.random.Generator, rule: int, depth: int, max_depth: int
) -> list[int]:
    """A random subtree from ``rule`` at ``depth`` within ``max_depth``, by *grow* (any choice that
    can still finish in time, by the minimum-depth analysis, GE's), as pre-order choices."""
    choices: list[int] = []
    stack = [(rule, depth)]
    while stack:
        r, d = stack.pop()
        c = _pick(tables.facts, rng, r, d, max_depth, Method.GROW)
        choices.append(c)
        stack.extend((k, d + 1) for k in reversed(tables.children[r][c]))
    return choices


# ---- genome text --------------------------------------------------------------------------------

_TOKEN = re.compile(r"\s*(?:(?P<open>\[)|(?P<close>\])|(?P<comma>,)|(?P<word>[^\s,\[\]]+))")


def text_position(text: str, offset: int) -> str:
    """``line:column`` of an offset, for messages."""
    line = text.count("\n", 0, offset) + 1
    column = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return f"{line}:{column}"


def _tokens(text: str) -> Iterator[tuple[str, str, int]]:
    position = 0
    while True:
        match = _TOKEN.match(text, position)
        if match is None or match.end() == position:
            rest = text[position:]
            if rest.strip():
                raise GenomeError(f"{text_position(text, position)}: cannot read {rest.strip()[:20]!r}")
            return
        kind = match.lastgroup
        assert kind is not None
        yield kind, match.group(kind), match.start(kind)
        position = match.end()


def _value(text: str, token: str, offset: int, example: str, noun: str = "value") -> int:
    if not token.isdigit() or not token.isascii():
        raise GenomeError(
            f"{text_position(text, offset)}: {token!r} is not a {noun}; {noun}s are non-negative "
            f"integers, e.g. {example}"
        )
    return int(token)


def parse_flat(text: str, noun: str = "value") -> tuple[int, ...]:
    """Values separated by commas and/or whitespace, optionally in [brackets] (JSON works);
    ``noun`` is what messages call them (a πGE genome's are codons)."""
    values = [
        _value(text, token, at, "12,7,301", noun) for kind, token, at in _tokens(text) if kind == "word"
    ]
    if not values:
        raise GenomeError(f"the genome is empty; write its {noun}s separated by commas, e.g. 12,7,301")
    return tuple(values)


def parse_genes(text: str, genes: Sequence[str]) -> tuple[tuple[int, ...], ...]:
    """A list of genes, each a list of values: ``[[0, 2], [1], []]`` (JSON works; commas optional).
    ``genes`` names the genes expected, in order."""
    example = "[[0, 2], [1], []]"
    found: list[tuple[int, ...]] = []
    gene: list[int] | None = None
    level = 0
    closed = False
    for kind, token, at in _tokens(text):
        if closed and kind != "comma":
            raise GenomeError(f"{text_position(text, at)}: text after the genome's closing ']'")
        if kind == "open":
            level += 1
            if level == 2:
                gene = []
            elif level > 2:
                raise GenomeError(f"{text_position(text, at)}: lists nest two deep at most, e.g. {example}")
        elif kind == "close":
            if level == 0:
                raise GenomeError(f"{text_position(text, at)}: ']' closes nothing")
            if level == 2:
                assert gene is not None
                found.append(tuple(gene))
                gene = None
            level -= 1
            closed = level == 0
        elif kind == "word":
            if level != 2:
                raise GenomeError(
                    f"{text_position(text, at)}: a value outside a gene; write one list per gene, "
                    f"e.g. {example}"
                )
            assert gene is not None
            gene.append(_value(text, token, at, example))
    if level:
        raise GenomeError(f"the genome's text ends inside a list: {level} ']' missing")
    return check_genes(found, genes)


def check_genes(genome: Sequence[Sequence[int]], genes: Sequence[str]) -> tuple[tuple[int, ...], ...]:
    if len(genome) != len(genes):
        raise GenomeError(
            f"the genome has {len(genome)} gene(s); this grammar needs {len(genes)}, one per rule, "
            f"in this order: {', '.join(genes[:12])}{', ...' if len(genes) > 12 else ''}"
        )
    return tuple(tuple(gene) for gene in genome)


def format_genes(genome: Sequence[Sequence[int]]) -> str:
    return "[" + ", ".join("[" + ", ".join(map(str, gene)) + "]" for gene in genome) + "]"


def json_ints(value: Any, what: str) -> tuple[int, ...]:
    """A JSON list of non-negative integers (bools are not integers here)."""
    if not isinstance(value, list | tuple):
        raise GenomeError(f"{what} must be a list of non-negative integers, not {type(value).__name__}")
    for i, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise GenomeError(f"{what}[{i}] must be a non-negative integer, not {v!r}")
    return tuple(value)


def json_genes(value: Any, genes: Sequence[str]) -> tuple[tuple[int, ...], ...]:
    if not isinstance(value, list | tuple):
        raise GenomeError(f"a genome must be a list of genes (lists of integers), not {type(value).__name__}")
    return check_genes(
        [
            json_ints(gene, f"gene {i} (<{genes[i]}>)" if i < len(genes) else f"gene {i}")
            for i, gene in enumerate(value)
        ],
        genes,
    )


def check_choices(genome: Sequence[Sequence[int]], n_choices: Sequence[int], genes: Sequence[str]) -> None:
    """Every value of gene ``g`` names one of the ``n_choices[g]`` choices of its rule."""
    for g, (gene, n) in enumerate(zip(genome, n_choices, strict=False)):
        for i, v in enumerate(gene):
            if v >= n:
                has = f"it has {n} (0 to {n - 1})" if n else "it has none"
                raise GenomeError(
                    f"gene {g} (<{genes[g]}>), value {i}: {v} is not a choice of the rule; {has}"
                )


# ---- as a plug-in ---------------------------------------------------------------------------------


class Plugged:
    """One of this module's representations as the registry's compiled representation
    (:class:`gaitgram.ge.registry.Compiled`): the typed API above, and what runs and commands
    need beside it (a count of children from tournament winners, the derivation tree, the tables).

    ``representation`` offers :class:`Representation`'s methods and ``choices(genome)``: the
    derivation's choices in pre-order in the grammar as written, as far as it got."""

    def __init__(self, representation: Any, grammar: Grammar, settings: Mapping[str, Any]) -> None:
        self.representation = representation
        self.name: str = representation.name
        self.counts: str = representation.counts
        self.grammar = grammar
        self.settings = dict(settings)
        self.map_many = representation.map_many
        self.encode = representation.encode
        self.decode = representation.decode
        self.to_json = representation.to_json
        self.from_json = representation.from_json

    def __repr__(self) -> str:
        return f"Plugged({self.representation!r})"

    def initialise(self, rng: np.random.Generator, n: int) -> list[Any]:
        return list(self.representation.initialise(rng, n))

    def vary(self, rng: np.random.Generator, parents: Sequence[Any], count: int) -> list[Any]:
        """The representation's variation of the parents' genomes (its own pairing), the first
        ``count`` children."""
        return list(self.representation.vary(rng, [p.genome for p in parents]))[:count]

    def derivation(self, genome: Any) -> Derivation:
        """The tree of the genome's derivation in the grammar as written (each node numbered in
        pre-order and labelled with its choice), with this representation's summary: what it used,
        why it is invalid."""
        mapped = self.representation.map(genome)
        tables: GrammarTables = self.representation.tables
        tree = tables.base.map(self.representation.choices(genome) or [0])
        reads_codons = self.counts == "codons" and len(genome) > 0
        tree.used_codons, tree.wraps = (
            mapped.used,
            max(mapped.used - 1, 0) // len(genome) if reads_codons else 0,
        )
        tree.genome_length = len(genome) if reads_codons else 0
        if not mapped.valid:
            tree.phenotype, tree.joints, tree.reason = None, {}, mapped.reason
        return tree

    def tables(self) -> dict[str, Any]:
        tables: GrammarTables = self.representation.tables
        extra = getattr(self.representation, "tables_json", None)
        return {
            "format": "gaitgram-representation",
            "version": 1,
            "generator": f"gaitgram {__version__}",
            "source": self.grammar.source.name,
            "representation": self.name,
            "settings": self.settings,
            **grammar_tables_json(self.grammar, tables.cfg),
            **(extra() if extra is not None else {}),
        }
