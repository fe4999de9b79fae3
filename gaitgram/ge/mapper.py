"""The GE mapper: a grammar compiled once into flat tables, then genomes mapped many times.

Semantics (docs/ge.md, Mapping): depth-first, leftmost non-terminal first;
``choice = codon % n_choices``; a typed range is one choice set. Codons are read
in order and wrap around the genome; with ``max_wraps = W`` at most
``len(genome) * (W + 1)`` can be read. In ``eager`` mode (PonyGE2) every
expansion reads a codon; in ``lazy`` mode (GEVA, the paper's tool) a rule with a
single choice reads none.

Two ways to map:

* :meth:`Mapper.map` builds the full :class:`~gaitgram.ge.derivation.Derivation`
  (tree, depth, node count, joint phenotypes);
* :meth:`Mapper.map_fast` / :meth:`Mapper.map_many` give phenotype, used codons,
  wraps and joint phenotypes only, several times faster: the evolution loop's path.

Both are loops over explicit stacks (no recursion limit on deep derivations)
and agree on every genome (a property test checks it against a recursive
reference). The fast loops lean on CPython specifics for speed, each noted where
it is used: the stack holds ``int`` rule indices and ``str`` terminals, codons
come from a ``for`` loop over the genome (a pass per wrap), and a rule that
must not be expanded has a choice count of 0, so that the modulo raises.
A joint rule's items go between two negative ints, markers that the loops meet
where they meet the bottom of the stack (no test on the common path): the opening
one records the output's length, the closing one joins the joint's text from there,
so that a joint's phenotype is one slice of the output, joined once, not a scan of
every piece. Where the start rule is ``<j1>;<j2>;...`` and nothing else derives a
separator's character (every bundled gait grammar: :func:`_cutter` decides it once),
the joint rules get no markers and the finished phenotype is cut at the separators:
one ``str.split`` a genome, not two markers and a join per joint.
``map_many`` maps a whole batch in one loop, set up once.
``python -m benchmarks map`` measures both paths.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from operator import length_hint
from typing import Any, NamedTuple

from gaitgram.analysis.cfg import Cfg, Item, RuleKind, build_cfg
from gaitgram.analysis.facts import Occurrences, min_depths
from gaitgram.ge.derivation import Derivation, InvalidReason, Node
from gaitgram.language.model import FREQUENCY, Grammar

__all__ = [
    "CodonMode",
    "Mapped",
    "Mapper",
    "MapperError",
    "MappingOptions",
    "compile_mapper",
]


class CodonMode(StrEnum):
    #: A single-choice rule reads no codon (GEVA; the paper's runs). The default.
    LAZY = "lazy"
    #: Every expansion reads a codon, unit rules included (PonyGE2).
    EAGER = "eager"


class MapperError(ValueError):
    """The grammar or the options cannot make a mapper (a genome never raises this)."""


@dataclass(frozen=True, slots=True)
class MappingOptions:
    codons: CodonMode = CodonMode.LAZY
    #: W wraps allow W + 1 passes over the genome (the paper: 3).
    max_wraps: int = 3
    #: Deepest allowed rule node (root at depth 1); None: no limit.
    max_depth: int | None = None

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "codons", CodonMode(self.codons))
        except ValueError:
            raise MapperError(f"codons must be 'lazy' or 'eager', not {self.codons!r}") from None
        if isinstance(self.max_wraps, bool) or not isinstance(self.max_wraps, int) or self.max_wraps < 0:
            raise MapperError(f"max_wraps must be an integer >= 0, not {self.max_wraps!r}")
        if self.max_depth is not None and (
            isinstance(self.max_depth, bool) or not isinstance(self.max_depth, int) or self.max_depth < 1
        ):
            raise MapperError(f"max_depth must be an integer >= 1 or None, not {self.max_depth!r}")

    @property
    def passes(self) -> int:
        return self.max_wraps + 1


class Mapped(NamedTuple):
    """A genome's phenotype without its tree: what the fast path returns."""

    phenotype: str | None
    used_codons: int
    wraps: int
    joints: dict[str, str]
    reason: InvalidReason | None

    @property
    def valid(self) -> bool:
        return self.reason is None

    @property
    def used(self) -> int:
        """What the mapping read, as every representation's result names it."""
        return self.used_codons


#: Bottom-of-stack sentinel in the fast loops: an int, so that the terminal loop stops at it.
_DONE = -1
#: Level-close sentinel in the depth-tracking loops.
_UP = -2
#: Joint ``k`` (of :attr:`Mapper.joint_list`) opens with the marker ``_OPEN - 2k`` and closes with
#: ``_OPEN - 2k - 1``: negative ints, met by the loops where they meet ``_DONE``.
_OPEN = -3


def joint_op(joint: int, items: tuple[Item, ...]) -> _Op:
    """A choice of joint ``joint``'s rule as the fast loops apply it: its items between markers."""
    return "", None, (_OPEN - 2 * joint - 1, *reversed(items), _OPEN - 2 * joint)


#: How many copies of the genome the depth-limited loop lays out before extending on demand.
_PREFETCH_PASSES = 4

_Op = tuple[str, int | None, tuple[Any, ...]]  # (leading terminals, first rule, the rest reversed)
#: The depth-limited loop's result: output pieces, codons used, why invalid (None: valid), the texts of
#: the joints closed, by name.
_Run = tuple[list[str], int, "InvalidReason | None", dict[str, str]]


def compile_mapper(
    source: Grammar | Cfg,
    *,
    codons: CodonMode | str = CodonMode.LAZY,
    max_wraps: int = 3,
    max_depth: int | None = None,
    joints: Mapping[str, str] | None = None,
) -> Mapper:
    """Compile a grammar (or its :class:`Cfg`) into a :class:`Mapper`.

    ``joints`` (joint name -> rule name) defaults to the grammar's ``@joint``
    declarations, and its ``@frequency`` rule under the key ``"@frequency"``
    (:data:`~gaitgram.language.model.FREQUENCY`); pass it to get joint phenotypes
    from a bare ``Cfg``.

    A grammar that carries an error diagnostic (a syntax error, a malformed
    range or annotation: the text does not say what it means) raises
    :class:`MapperError` rather than map what the parser could salvage. Rules
    the linter reports (undefined, unproductive) have a defined meaning for the
    mapper: a genome that reaches one is invalid.
    """
    options = MappingOptions(codons, max_wraps, max_depth)  # type: ignore[arg-type]  # validated there
    if isinstance(source, Grammar):
        errors = [d for d in source.diagnostics if d.is_error]
        if errors:
            first = errors[0]
            where = source.source.location(first.span.start)
            raise MapperError(
                f"{source.source.name}:{where.line}:{where.column}: error[{first.code.code}] "
                f"{first.message}: a grammar with errors is not compiled "
                f"({len(errors)} error{'s' if len(errors) > 1 else ''}; see `gaitgram check`)"
            )
        cfg = build_cfg(source)
        if joints is None:
            joints = {decl.joint: decl.rule for decl in source.joints}
            if source.frequency is not None:
                joints[FREQUENCY] = source.frequency.rule
    else:
        cfg = source
    return Mapper(cfg, options, joints)


def _as_list(genome: Sequence[int]) -> list[int] | tuple[int, ...]:
    if genome.__class__ is list or genome.__class__ is tuple:
        return genome  # type: ignore[return-value]
    tolist = getattr(genome, "tolist", None)  # numpy: plain ints index and divide far faster
    return tolist() if tolist is not None else list(genome)


def _wraps(used: int, length: int) -> int:
    return (used - 1) // length if used > 0 and length > 0 else 0


class Mapper:
    """A grammar's production tables for one set of :class:`MappingOptions`.

    Build with :func:`compile_mapper`. Immutable after construction and safe to
    share between threads; one mapper maps any number of genomes.
    """

    def __init__(self, cfg: Cfg, options: MappingOptions, joints: Mapping[str, str] | None = None) -> None:
        if cfg.start is None:
            raise MapperError("the grammar has no (defined) start rule")
        self.cfg = cfg
        self.options = options
        self.start: int = cfg.start
        self.rule_names: tuple[str, ...] = cfg.names
        #: Choices per rule as written (typed ranges expanded), whatever the mode.
        self.n_choices: tuple[int, ...] = tuple(len(choices) for choices in cfg.choices)
        eager = options.codons is CodonMode.EAGER
        #: Choices per rule, terminals joined and empty ones dropped.
        self.productions: tuple[tuple[tuple[Item, ...], ...], ...] = tuple(
            tuple(_join_terminals(choice) for choice in choices) for choices in cfg.choices
        )
        #: Whether expanding each rule reads a codon.
        self.reads: tuple[bool, ...] = tuple(eager or k != 1 for k in self.n_choices)

        # Rules the mapper refuses to expand, and why. Without a depth limit a lazy
        # derivation can loop through single-choice rules forever without reading a
        # codon; those rules are found here, once, rather than hanging at map time.
        # With a limit such a derivation simply runs into it, as it would anywhere.
        self.stops: dict[int, InvalidReason] = {
            r: InvalidReason.UNDEFINED for r, k in enumerate(self.n_choices) if k == 0
        }
        if not eager and options.max_depth is None:
            for r in _silent_divergent(self.productions, self.n_choices):
                self.stops[r] = InvalidReason.NONTERMINATING
        #: Effective choice counts: 0 for a rule in ``stops`` (division by it ends the fast loops).
        self._k: tuple[int, ...] = tuple(0 if r in self.stops else k for r, k in enumerate(self.n_choices))

        # Joints: rule index -> joint names (a rule may, oddly, carry several).
        by_rule: dict[int, list[str]] = {}
        for joint, rule in (joints or {}).items():
            r = cfg.index.get(rule)
            if r is not None and cfg.kinds[r] is not RuleKind.UNDEFINED:
                by_rule.setdefault(r, []).append(joint)
        self.joint_rules: dict[int, tuple[str, ...]] = {r: tuple(names) for r, names in by_rule.items()}
        named = {name for names in by_rule.values() for name in names}
        self._joint_order: tuple[str, ...] = tuple(j for j in (joints or {}) if j in named)
        #: The joint rules, numbered as their markers number them.
        self.joint_list: tuple[int, ...] = tuple(self.joint_rules)
        #: The fast loops' naming of a joint's text (GE's and the other representations'): its rule's
        #: closing marker -> its (first) name.
        self.close_names: dict[int, str] = {
            _OPEN - 2 * k - 1: names[0] for k, names in enumerate(self.joint_rules.values())
        }
        # Where a joint rule can occur twice in a derivation (or carries several names: rare
        # grammars), the loops' texts do not tell which occurrence came first: the tree does.
        self._joints_by_tree = any(len(names) > 1 for names in self.joint_rules.values())
        if self.joint_list and not self._joints_by_tree:
            occurrences = Occurrences(cfg, tuple(d is not None for d in min_depths(cfg)[0]))
            self._joints_by_tree = any(occurrences.bounds(r)[1] > 1 for r in self.joint_list)
        #: The joints' order when the loops' texts can be taken as they are (in that order); None
        #: where they come from the tree (a repeated rule's later text may stand under its name).
        self._loop_order: tuple[str, ...] | None = None if self._joints_by_tree else self._joint_order
        #: Where every joint is one item of a start rule ``<j1>;<j2>;...`` (the gait grammars), a
        #: function that cuts a valid phenotype into its joints, in order (:func:`_cutter`): the
        #: fast loops then map with no markers. None: the markers give the joints.
        self.joints_from_phenotype: Callable[[str], dict[str, str]] | None = (
            _cutter(self.productions, self.start, self.joint_rules, self._joint_order)
            if self.joint_list and not self._joints_by_tree
            else None
        )

        self._ops: tuple[tuple[_Op, ...], ...] = tuple(
            tuple(self._op(r, choice) for choice in choices) for r, choices in enumerate(self.productions)
        )
        #: Each single-choice rule's op, Nones for the others: what the lazy loop expands on the spot.
        self._unit_ops: tuple[_Op | tuple[None, None, None], ...] = tuple(
            ops[0] if self._k[r] == 1 else (None, None, None) for r, ops in enumerate(self._ops)
        )
        self._passes = options.passes
        self._prefetch = min(options.passes, _PREFETCH_PASSES)
        if options.max_depth is not None:
            self._many = self._many_depth
        elif eager:
            self._many = self._many_eager
        else:
            self._many = self._many_lazy

    def _op(self, rule: int, items: tuple[Item, ...]) -> _Op:
        """A choice as the fast loops apply it: emit the leading terminals, continue with
        the first rule directly (saving a push and a pop), push the rest reversed."""
        if rule in self.joint_rules and self.joints_from_phenotype is None:
            return joint_op(self.joint_list.index(rule), items)
        lead = ""
        rest = list(items)
        if rest and isinstance(rest[0], str):
            lead = rest.pop(0)
        head = rest.pop(0) if rest else None
        assert head is None or isinstance(head, int)
        return lead, head, tuple(reversed(rest))

    def __repr__(self) -> str:
        o = self.options
        return (
            f"Mapper(start=<{self.rule_names[self.start]}>, rules={len(self.rule_names)}, "
            f"codons={o.codons.value}, max_wraps={o.max_wraps}, max_depth={o.max_depth})"
        )

    # ---- the fast path ---------------------------------------------------------------
    #
    # The mapper's hot loops: ``_many_eager``, ``_many_lazy`` and ``_run_depth`` repeat one
    # expansion step (emit the lead, push the rest, go on with the head, pop terminals) written
    # out in each on purpose: a shared helper would cost a call per codon, the step that every
    # evaluation pays. The tree mapper (``map``) is the reference they are tested against.
    #
    # ``_many_eager`` and ``_many_lazy`` map a whole batch in one call: the tables, the output
    # list, the stack and their bound methods are set up once per batch, not once per genome, and
    # each result is built in place. On a small grammar (PonyGE2's letter.bnf: a dozen codons a
    # genome) that per-genome setup was a third of the time. A derivation's end is met deep
    # inside the loops; it leaves them through ``for``/``while`` ... ``else`` clauses, which cost
    # nothing on the common path (no flag tested per codon).
    #
    # A joint's text is joined where its closing marker is met, from the output's length
    # recorded at its opening marker, and stored under its name: no second pass over markers.
    # Where ``joints_from_phenotype`` is set there are no markers: the phenotype is cut instead.

    def map_fast(self, genome: Sequence[int]) -> Mapped:
        """Phenotype, used codons, wraps and joint phenotypes, without building the tree."""
        return self._many((genome,))[0]

    def map_many(self, genomes: Iterable[Sequence[int]]) -> list[Mapped]:
        """:meth:`map_fast` over many genomes, mapped in one loop (set up once per batch)."""
        return self._many(genomes)

    def phenotype(self, genome: Sequence[int]) -> str | None:
        """Just the phenotype (None if invalid)."""
        return self._many((genome,))[0].phenotype

    def _joints(self, texts: dict[str, str], genome: Sequence[int]) -> dict[str, str]:
        """A valid genome's joints in the grammar's order, from the texts its loop joined (in the
        order their rules closed). Where a joint rule can occur twice in a derivation, or carries
        several joint names (rare grammars), the loops' texts do not say which occurrence is the
        first: the tree mapper gives them."""
        if self._joints_by_tree:
            return self.map(genome).joints
        return {name: texts[name] for name in self._joint_order if name in texts}

    def joints_in_order(
        self, texts: dict[str, str], choices: Callable[[Any], Sequence[int]], genome: Any
    ) -> dict[str, str]:
        """:meth:`_joints` for another representation's decoding loop (the same markers, named by
        :attr:`close_names`): ``choices(genome)`` gives the derivation's choices in pre-order,
        which this (eager) mapper maps to the same tree; asked only where the texts come from the
        tree."""
        if not texts or tuple(texts) == self._loop_order:
            return texts
        return self._joints(texts, choices(genome) if self._joints_by_tree else ())

    def _many_eager(self, genomes: Iterable[Sequence[int]]) -> list[Mapped]:
        ks, ops, stops, start, allowed = self._k, self._ops, self.stops, self.start, self._passes
        passes_range = range(allowed)
        joint_name, order, ordered = self.close_names, self._loop_order, self._joints
        cut = self.joints_from_phenotype
        new, invalid, join, remaining = tuple.__new__, InvalidReason.CODONS, "".join, length_hint
        results: list[Mapped] = []
        keep = results.append
        out: list[str] = []
        append, clear = out.append, out.clear
        stack: list[Any] = []
        push, pop, extend = stack.append, stack.pop, stack.extend
        starts: list[int] = []  # the output's length at each open joint's marker
        mark, unmark = starts.append, starts.pop
        for genome in genomes:
            codons = genome if genome.__class__ is list else _as_list(genome)
            n = len(codons)
            texts: dict[str, str] = {}
            push(_DONE)
            item = start
            # One expansion per codon, so the codons drive the loop: a pass per genome wrap,
            # and the iterator's remaining length tells how many were used.
            for passes in passes_range:
                codon_iter = iter(codons)
                try:
                    for codon in codon_iter:
                        # ZeroDivisionError at a rule in ``stops``, after fetching a codon it does not use.
                        lead, head, rest = ops[item][codon % ks[item]]
                        if lead:
                            append(lead)
                        if rest:
                            extend(rest)
                        if head is not None:
                            item = head
                            continue
                        item = pop()
                        while type(item) is not int:  # terminals
                            append(item)
                            item = pop()
                        if item >= 0:
                            continue
                        while item != _DONE:  # a joint's marker: odd opens, even closes
                            if item & 1:
                                mark(len(out))
                            else:
                                texts[joint_name[item]] = join(out[unmark() :])
                            item = pop()
                            while type(item) is not int:
                                append(item)
                                item = pop()
                            if item >= 0:
                                break
                        else:
                            break  # the derivation is complete
                    else:
                        continue  # this pass's codons are used up: wrap
                except ZeroDivisionError:
                    reason, used = stops[item], (passes + 1) * n - remaining(codon_iter) - 1
                else:
                    reason, used = None, (passes + 1) * n - remaining(codon_iter)
                break
            else:
                reason, used = stops.get(item, invalid), allowed * n
            wraps = (used - 1) // n if used else 0
            if reason is None:
                if texts:
                    if tuple(texts) != order:
                        texts = ordered(texts, codons)
                    keep(new(Mapped, (join(out), used, wraps, texts, None)))
                elif cut is None:
                    keep(new(Mapped, (join(out), used, wraps, texts, None)))
                else:
                    phenotype = join(out)
                    keep(new(Mapped, (phenotype, used, wraps, cut(phenotype), None)))
            else:
                keep(new(Mapped, (None, used, wraps, {}, reason)))
                stack.clear()
                starts.clear()
            clear()
        return results

    def _many_lazy(self, genomes: Iterable[Sequence[int]]) -> list[Mapped]:
        ks, ops, unit_ops, stops, start = self._k, self._ops, self._unit_ops, self.stops, self.start
        allowed = self._passes
        passes_range = range(allowed)
        joint_name, order, ordered = self.close_names, self._loop_order, self._joints
        cut = self.joints_from_phenotype
        new, invalid, join, remaining = tuple.__new__, InvalidReason.CODONS, "".join, length_hint
        results: list[Mapped] = []
        keep = results.append
        out: list[str] = []
        append, clear = out.append, out.clear
        stack: list[Any] = []
        push, pop, extend = stack.append, stack.pop, stack.extend
        starts: list[int] = []
        mark, unmark = starts.append, starts.pop
        for genome in genomes:
            codons = genome if genome.__class__ is list else _as_list(genome)
            n = len(codons)
            texts: dict[str, str] = {}
            push(_DONE)
            item = start
            reason, used = None, 0
            # As _many_eager, except that after each expansion the single-choice rules that
            # follow are expanded on the spot (``unit_ops``: Nones for a rule that reads), so
            # that the codon loop sees only rules that read. First those before any codon:
            lead, head, rest = unit_ops[item]
            while lead is not None:
                if lead:
                    append(lead)
                if rest:
                    extend(rest)
                if head is not None:
                    item = head
                else:
                    item = pop()
                    while type(item) is not int:
                        append(item)
                        item = pop()
                    if item < 0:
                        while item != _DONE:
                            if item & 1:
                                mark(len(out))
                            else:
                                texts[joint_name[item]] = join(out[unmark() :])
                            item = pop()
                            while type(item) is not int:
                                append(item)
                                item = pop()
                            if item >= 0:
                                break
                        else:
                            break  # the derivation is complete without reading a codon
                lead, head, rest = unit_ops[item]
            else:
                for passes in passes_range:
                    codon_iter = iter(codons)
                    try:
                        for codon in codon_iter:
                            lead, head, rest = ops[item][codon % ks[item]]
                            while lead is not None:
                                if lead:
                                    append(lead)
                                if rest:
                                    extend(rest)
                                if head is not None:
                                    item = head
                                else:
                                    item = pop()
                                    while type(item) is not int:
                                        append(item)
                                        item = pop()
                                    if item < 0:
                                        while item != _DONE:
                                            if item & 1:
                                                mark(len(out))
                                            else:
                                                texts[joint_name[item]] = join(out[unmark() :])
                                            item = pop()
                                            while type(item) is not int:
                                                append(item)
                                                item = pop()
                                            if item >= 0:
                                                break
                                        else:
                                            break  # the derivation is complete
                                lead, head, rest = unit_ops[item]
                            else:
                                continue  # the next rule reads a codon
                            break
                        else:
                            continue  # this pass's codons are used up: wrap
                    except ZeroDivisionError:
                        reason, used = stops[item], (passes + 1) * n - remaining(codon_iter) - 1
                    else:
                        reason, used = None, (passes + 1) * n - remaining(codon_iter)
                    break
                else:
                    reason, used = stops.get(item, invalid), allowed * n
            wraps = (used - 1) // n if used else 0
            if reason is None:
                if texts:
                    if tuple(texts) != order:
                        texts = ordered(texts, codons)
                    keep(new(Mapped, (join(out), used, wraps, texts, None)))
                elif cut is None:
                    keep(new(Mapped, (join(out), used, wraps, texts, None)))
                else:
                    phenotype = join(out)
                    keep(new(Mapped, (phenotype, used, wraps, cut(phenotype), None)))
            else:
                keep(new(Mapped, (None, used, wraps, {}, reason)))
                stack.clear()
                starts.clear()
            clear()
        return results

    def _many_depth(self, genomes: Iterable[Sequence[int]]) -> list[Mapped]:
        """Both modes with a depth limit, a genome at a time (``_run_depth``)."""
        run, order, ordered, cut = self._run_depth, self._loop_order, self._joints, self.joints_from_phenotype
        new = tuple.__new__
        results: list[Mapped] = []
        keep = results.append
        for genome in genomes:
            codons = _as_list(genome)
            out, used, reason, texts = run(codons)
            n = len(codons)
            wraps = (used - 1) // n if used else 0
            if reason is None:
                phenotype = "".join(out)
                if cut is not None:
                    texts = cut(phenotype)
                elif texts and tuple(texts) != order:
                    texts = ordered(texts, codons)
                keep(new(Mapped, (phenotype, used, wraps, texts, None)))
            else:
                keep(new(Mapped, (None, used, wraps, {}, reason)))
        return results

    def _run_depth(self, codons: Sequence[int]) -> _Run:
        """Both modes with a depth limit: a level-close sentinel under each expansion's children."""
        ks, ops, reads, stops = self._k, self._ops, self.reads, self.stops
        max_depth = self.options.max_depth
        assert max_depth is not None
        limit = len(codons) * self._passes
        g = codons * self._prefetch if codons.__class__ is list else list(codons) * self._prefetch
        out: list[str] = []
        append = out.append
        joint_name = self.close_names
        texts: dict[str, str] = {}
        starts: list[int] = []
        stack: list[Any] = [_DONE]
        pop, push, extend = stack.pop, stack.append, stack.extend
        used = 0
        depth = 0  # rule nodes open above ``item``
        item = self.start
        while True:
            try:
                while True:
                    if depth >= max_depth:
                        return out, used, InvalidReason.DEPTH, texts
                    if reads[item]:
                        # IndexError when the codons laid out so far run out, ZeroDivisionError
                        # at a rule in ``stops``: both before any state changes, so a retry is exact.
                        lead, head, rest = ops[item][g[used] % ks[item]]
                        used += 1
                    else:
                        lead, head, rest = ops[item][0]
                    depth += 1
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
                        while type(item) is not int:
                            append(item)
                            item = pop()
                        if item >= 0:
                            break
                        if item == _UP:
                            depth -= 1
                        elif item == _DONE:
                            return out, used, None, texts
                        elif item & 1:  # a joint's opening marker
                            starts.append(len(out))
                        else:
                            texts[joint_name[item]] = "".join(out[starts.pop() :])
                        item = pop()
            except IndexError:
                if ks[item] == 0:
                    return out, used, stops[item], texts
                if len(g) >= limit:
                    return out, used, InvalidReason.CODONS, texts
                g.extend(codons)
            except ZeroDivisionError:
                return out, used, stops[item], texts

    def _name_joints(self, texts: dict[int, str]) -> dict[str, str]:
        by_joint = {name: texts[r] for r, names in self.joint_rules.items() if r in texts for name in names}
        return {name: by_joint[name] for name in self._joint_order if name in by_joint}

    # ---- the full derivation ------------------------------------------------------------

    def map(self, genome: Sequence[int]) -> Derivation:
        """Map a genome to its full derivation: tree, statistics and joint phenotypes."""
        codons = _as_list(genome)
        n = len(codons)
        limit = n * self.options.passes
        max_depth = self.options.max_depth
        ks, productions, reads, stops = self._k, self.productions, self.reads, self.stops
        joint_rules = self.joint_rules
        out: list[str] = []
        append = out.append
        root = Node(self.start)
        # Entries: terminal text, (unexpanded rule node, its depth), or (joint rule, output offset)
        # where the subtree of that rule's first occurrence ends.
        stack: list[Any] = [(root, 1)]
        pop, push = stack.pop, stack.append
        claimed: set[int] = set()
        texts: dict[int, str] = {}
        used = depth = nodes = 0
        reason: InvalidReason | None = None
        while stack:
            entry = pop()
            if entry.__class__ is str:
                append(entry)
                continue
            node, level = entry
            if node.__class__ is int:  # the first subtree of a joint rule is complete
                texts[node] = "".join(out[level:])
                continue
            item = node.symbol
            nodes += 1
            if level > depth:
                depth = level
                if max_depth is not None and level > max_depth:
                    reason = InvalidReason.DEPTH
                    break
            k = ks[item]
            if k == 0:
                reason = stops[item]
                break
            if reads[item]:
                if used >= limit:
                    reason = InvalidReason.CODONS
                    break
                codon = codons[used % n]
                node.codon_index = used
                node.codon = codon
                node.choice = choice = codon % k
                used += 1
            else:
                node.choice = choice = 0
            if item in joint_rules and item not in claimed:
                claimed.add(item)
                push((item, len(out)))
            children = node.children = [Node(x) for x in productions[item][choice]]
            level += 1
            for child in reversed(children):
                push(child.symbol if child.symbol.__class__ is str else (child, level))
        valid = reason is None
        return Derivation(
            phenotype="".join(out) if valid else None,
            used_codons=used,
            wraps=_wraps(used, n),
            depth=depth,
            nodes=nodes,
            tree=root,
            joints=self._name_joints(texts) if valid else {},
            reason=reason,
            rule_names=self.rule_names,
            genome_length=n,
        )


def _cutter(
    productions: Sequence[Sequence[tuple[Item, ...]]],
    start: int,
    joint_rules: Mapping[int, tuple[str, ...]],
    order: tuple[str, ...],
) -> Callable[[str], dict[str, str]] | None:
    """How to cut a valid phenotype into its joints, in ``order``, where the grammar's shape allows
    it; None where it does not (the loops' markers then give them).

    The shape: the start rule has one choice, its items rules separated by literal terminals
    (``<j1>;<j2>;...;<frequency>``, terminals joined), each joint rule one of those items, once,
    and used by no rule they reach (so every derivation holds each joint exactly once, there), and
    no terminal they reach holds a character of any separator. The phenotype is then the items'
    texts between the separators, and the first occurrence of each separator after an item's text
    is the one that ends it: one ``str.split`` (or a partition per separator) finds every joint.
    Anything else (a terminal before the first rule or after the last, two rules side by side, a
    joint rule used twice or inside another item, the start rule reached again) keeps the markers.
    """
    if start in joint_rules or len(productions[start]) != 1:
        return None
    items = productions[start][0]
    rules, seps = items[0::2], items[1::2]
    if (
        len(items) % 2 == 0
        or not all(isinstance(r, int) for r in rules)
        or not all(isinstance(s, str) for s in seps)
    ):
        return None
    jointed = [r for r in rules if r in joint_rules]
    if len(jointed) != len(set(jointed)) or set(jointed) != set(joint_rules):
        return None
    banned = set("".join(seps))
    seen: set[Any] = set(rules)
    todo = list(seen)
    while todo:
        for choice in productions[todo.pop()]:
            for item in choice:
                if isinstance(item, str):
                    if not banned.isdisjoint(item):
                        return None
                elif item == start or item in joint_rules:
                    return None
                elif item not in seen:
                    seen.add(item)
                    todo.append(item)
    at = {names[0]: rules.index(r) for r, names in joint_rules.items()}
    places = tuple(at[name] for name in order)
    pairs = tuple(zip(order, places, strict=True))
    if len(set(seps)) == 1:
        sep = seps[0]
        if places == tuple(range(len(rules))):  # every item a joint, in order: all in C
            # zip without strict=: the keyword takes zip off its fast call path (0.2 us a genome);
            # the shape gives exactly one part per joint.
            return lambda phenotype: dict(zip(order, phenotype.split(sep)))  # noqa: B905

        def cut(phenotype: str) -> dict[str, str]:
            parts = phenotype.split(sep)
            return {name: parts[i] for name, i in pairs}

        return cut

    def partition(phenotype: str) -> dict[str, str]:
        parts = []
        for sep in seps:
            text, _, phenotype = phenotype.partition(sep)
            parts.append(text)
        parts.append(phenotype)
        return {name: parts[i] for name, i in pairs}

    return partition


def _join_terminals(choice: tuple[Item, ...]) -> tuple[Item, ...]:
    items: list[Item] = []
    for item in choice:
        if isinstance(item, str):
            if not item:
                continue
            if items and isinstance(items[-1], str):
                items[-1] += item
                continue
        items.append(item)
    return tuple(items)


def _silent_divergent(
    productions: Sequence[Sequence[tuple[Item, ...]]], n_choices: Sequence[int]
) -> set[int]:
    """Single-choice rules whose lazy expansion recurses forever before reading a codon.

    A single-choice rule is *silent* if it finishes without reading a codon (all
    its rules silent: a least fixed point). Expanding a non-silent single-choice
    rule passes its leading silent items and then expands the first non-silent
    one: a rule that reads a codon or has no choices (the chain ends), or another
    single-choice rule. That "next" map is a function; the rules from which it
    cycles are the divergent ones. Linear in the grammar's size.
    """
    n = len(n_choices)
    unit = [k == 1 for k in n_choices]
    silent = [False] * n
    waiting = [0] * n
    users: list[list[int]] = [[] for _ in range(n)]
    ready = []
    for r in range(n):
        if not unit[r]:
            continue
        needed = {item for item in productions[r][0] if isinstance(item, int)}
        waiting[r] = len(needed)
        for child in needed:
            users[child].append(r)
        if not needed:
            ready.append(r)
    while ready:
        r = ready.pop()
        silent[r] = True
        for u in users[r]:
            waiting[u] -= 1
            if waiting[u] == 0:
                ready.append(u)

    following: dict[int, int] = {}
    for r in range(n):
        if unit[r] and not silent[r]:
            following[r] = next(i for i in productions[r][0] if isinstance(i, int) and not silent[i])
    divergent: set[int] = set()
    settled: set[int] = set()
    for r in following:
        path: list[int] = []
        on_path: set[int] = set()
        x = r
        while x in following and x not in settled and x not in on_path:
            path.append(x)
            on_path.add(x)
            x = following[x]
        # The walk stopped at a cycle of its own, at a rule already settled, or at a
        # rule that reads a codon or has no choices (the end of the chain).
        if x in on_path or x in divergent:
            divergent.update(path)
        settled.update(path)
    return divergent
