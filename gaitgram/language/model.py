"""The grammar model: what a ``.gg`` document means, with the source span of every part.

Plain data, immutable by convention (the most numerous classes are not frozen
only because frozen dataclasses are slow to build; spans are tuples). The parser
builds it; analyses, the mapper, the formatter's safety check and the language
server read it. Rule names are stored without their angle brackets.

The pieces of a rule (alternatives and symbols) hold ``local_span``: offsets from their
rule's start, which :meth:`Rule.span_of` turns into a document span. So a rule that moves
in an edited document is one new :class:`Rule` (:meth:`Rule.moved`) around the same
pieces, and nothing is shifted in place. Everything else (rules, annotations, joints,
diagnostics) holds document spans.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import StrEnum
from functools import cached_property

from gaitgram.language.diagnostics import Diagnostic
from gaitgram.language.source import SourceText, Span

__all__ = [
    "FREQUENCY",
    "Alternative",
    "Annotation",
    "Argument",
    "ArgumentValue",
    "FrequencyDecl",
    "Grammar",
    "Interval",
    "JointDecl",
    "Name",
    "NonTerminal",
    "RangeKind",
    "RangeSpec",
    "RangeSymbol",
    "Rule",
    "RuleRef",
    "Symbol",
    "Terminal",
]


@dataclass(slots=True, unsafe_hash=True)
class Terminal:
    """Literal text, escapes decoded."""

    text: str
    local_span: Span  # from the rule's start: ``Rule.span_of``


@dataclass(slots=True, unsafe_hash=True)
class NonTerminal:
    """A reference to a rule, ``<name>`` in the source."""

    name: str
    local_span: Span  # from the rule's start: ``Rule.span_of``


class RangeKind(StrEnum):
    INT = "int"
    FLOAT = "float"


@dataclass(frozen=True, slots=True)
class RangeSpec:
    """A typed range: one codon picks one of ``values``.

    ``values`` are the texts the range derives, in codon order; ``text`` is the
    canonical spelling (``float[0..20 step 0.25]``).
    """

    kind: RangeKind
    text: str
    values: tuple[str, ...]

    @property
    def size(self) -> int:
        return len(self.values)


@dataclass(slots=True, unsafe_hash=True)
class RangeSymbol:
    """A typed range inside a longer alternative: an anonymous choice point."""

    spec: RangeSpec
    local_span: Span  # from the rule's start: ``Rule.span_of``


Symbol = Terminal | NonTerminal | RangeSymbol


@dataclass(slots=True, unsafe_hash=True)
class Alternative:
    """One alternative of a rule, as written.

    An alternative that is a typed range on its own contributes one choice per
    value to its rule (as PonyGE2's ``GE_RANGE`` does); any other alternative is
    one choice.
    """

    symbols: tuple[Symbol, ...]
    local_span: Span  # from the rule's start: ``Rule.span_of``

    @property
    def range_values(self) -> RangeSpec | None:
        """The range this alternative expands to, if it is a range on its own."""
        if len(self.symbols) == 1 and isinstance(self.symbols[0], RangeSymbol):
            return self.symbols[0].spec
        return None

    @property
    def choice_count(self) -> int:
        spec = self.range_values
        return spec.size if spec is not None else 1

    def references(self) -> Iterator[NonTerminal]:
        for symbol in self.symbols:
            if isinstance(symbol, NonTerminal):
                yield symbol


# ---- annotations -------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Interval:
    """``lo..hi`` in an annotation argument; either end may be open."""

    low: float | None
    high: float | None

    def __str__(self) -> str:
        def fmt(x: float | None) -> str:
            return "" if x is None else f"{x:g}"

        return f"{fmt(self.low)}..{fmt(self.high)}"


@dataclass(frozen=True, slots=True)
class RuleRef:
    name: str

    def __str__(self) -> str:
        return f"<{self.name}>"


@dataclass(frozen=True, slots=True)
class Name:
    """A bare word such as ``mujoco-horse`` or ``deg``."""

    text: str

    def __str__(self) -> str:
        return self.text


ArgumentValue = int | float | str | Name | RuleRef | Interval


@dataclass(frozen=True, slots=True)
class Argument:
    key: str | None
    value: ArgumentValue | None  # None: a keyword with nothing after ``=``
    span: Span
    raw: str


@dataclass(frozen=True, slots=True)
class Annotation:
    name: str
    arguments: tuple[Argument, ...]
    span: Span
    name_span: Span

    def positional(self) -> tuple[Argument, ...]:
        return tuple(a for a in self.arguments if a.key is None)

    def keyword(self, key: str) -> Argument | None:
        return next((a for a in self.arguments if a.key == key), None)

    def moved(self, delta: int) -> Annotation:
        """The same annotation ``delta`` characters further on."""
        arguments = tuple(Argument(a.key, a.value, a.span.shifted(delta), a.raw) for a in self.arguments)
        return Annotation(self.name, arguments, self.span.shifted(delta), self.name_span.shifted(delta))


@dataclass(frozen=True, slots=True)
class JointDecl:
    """A ``@joint`` annotation, interpreted.

    ``limits`` are in the grammar's units; ``free`` is the range of generations
    in which the joint may move (Table 3 of the paper); ``None`` means always.
    """

    joint: str
    rule: str
    limits: tuple[float, float] | None
    free: tuple[int, int | None] | None
    span: Span

    def is_free(self, generation: int) -> bool:
        if self.free is None:
            return True
        first, last = self.free
        return generation >= first and (last is None or generation <= last)

    def moved(self, delta: int) -> JointDecl:
        """The same declaration ``delta`` characters further on."""
        return JointDecl(self.joint, self.rule, self.limits, self.free, self.span.shifted(delta))


#: The key of the ``@frequency`` rule's phenotype among a derivation's joint phenotypes: not a
#: joint name (those are identifiers), so it never collides with one.
FREQUENCY = "@frequency"


@dataclass(frozen=True, slots=True)
class FrequencyDecl:
    """A ``@frequency`` annotation, interpreted: ``rule`` derives the gait cycle's frequency.

    The rule's phenotype is a constant expression in Hz (the stride frequency), which
    replaces the backend's imposed one; ``limits`` (Hz), if given, bound it.
    """

    rule: str
    limits: tuple[float, float] | None
    span: Span


# ---- rules and grammars ----------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Rule:
    name: str
    alternatives: tuple[Alternative, ...]
    span: Span
    name_span: Span
    annotations: tuple[Annotation, ...] = ()

    @property
    def choice_count(self) -> int:
        return sum(a.choice_count for a in self.alternatives)

    def references(self) -> Iterator[NonTerminal]:
        for alternative in self.alternatives:
            yield from alternative.references()

    def span_of(self, piece: Alternative | Symbol) -> Span:
        """Where one of this rule's alternatives or symbols is in the document."""
        start = self.span.start
        return Span(start + piece.local_span.start, start + piece.local_span.end)

    def moved(self, delta: int, annotations: tuple[Annotation, ...] | None = None) -> Rule:
        """The same rule ``delta`` characters further on: its pieces are shared, not copied.

        ``annotations``: its annotations, already moved (to share them with the grammar's
        list); by default they are moved here.
        """
        if annotations is None:
            annotations = tuple([a.moved(delta) for a in self.annotations])
        span, name_span = self.span, self.name_span
        return Rule(
            self.name,
            self.alternatives,
            Span(span.start + delta, span.end + delta),
            Span(name_span.start + delta, name_span.end + delta),
            annotations,
        )


@dataclass(frozen=True, eq=False)
class Grammar:
    """A parsed document: its rules in source order and what its annotations declare.

    ``diagnostics`` are the problems found while reading (syntax, ranges,
    annotations); the linter adds the rest.
    """

    source: SourceText
    rules: tuple[Rule, ...]
    annotations: tuple[Annotation, ...]
    start: str | None
    backend: str | None
    units: str
    joints: tuple[JointDecl, ...]
    defines: dict[str, int] = field(default_factory=dict)
    diagnostics: tuple[Diagnostic, ...] = ()
    #: The rule that derives the cycle's frequency, if the grammar evolves it.
    frequency: FrequencyDecl | None = None
    #: The annotation that counts for each file setting written (``"start"``, ``"backend"``,
    #: ``"units"``): where ``start``, ``backend`` and ``units`` come from.
    declared: dict[str, Annotation] = field(default_factory=dict)

    @cached_property
    def rules_by_name(self) -> dict[str, Rule]:
        """The first definition of each name; later duplicates are diagnostics."""
        by_name: dict[str, Rule] = {}
        for rule in self.rules:
            by_name.setdefault(rule.name, rule)
        return by_name

    def rule(self, name: str) -> Rule | None:
        return self.rules_by_name.get(name)

    @cached_property
    def rule_starts(self) -> list[int]:
        """Each rule's start offset, in order: to find the rule at an offset by bisection."""
        return [rule.span.start for rule in self.rules]

    def rule_at(self, offset: int) -> Rule | None:
        """The rule whose text (head to last alternative) contains ``offset``."""
        index = bisect_right(self.rule_starts, offset) - 1
        if index >= 0 and offset in self.rules[index].span:
            return self.rules[index]
        return None

    def annotation_at(self, offset: int) -> Annotation | None:
        for annotation in self.annotations:
            if offset in annotation.span:
                return annotation
            if annotation.span.start > offset:
                break
        return None

    @cached_property
    def joints_by_rule(self) -> dict[str, JointDecl]:
        return {j.rule: j for j in self.joints}

    @property
    def has_errors(self) -> bool:
        return any(d.is_error for d in self.diagnostics)
