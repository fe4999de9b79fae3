"""Completion that knows where the cursor is.

It never waits for an analysis: the names it offers come from the last one (a
:class:`CompletionModel`, plain values only), and what is being typed comes from the
current line. Contexts:

* ``@`` at the start of a line: annotation names;
* an annotation's arguments: its keyword names, and its parameters' values by what they
  refer to (``Parameter.refers``): rules, installed backends, the declared backend's joints,
  a joint's limits (the backend's) and freedom (the paper's Table 3), or the choices;
* a right-hand side: rule references (their first production as detail), nearest rules
  first and filtered by what is typed, and typed-range snippets; in a curve's text (a rule that
  a ``@joint`` rule reaches), the backend's sensors that its joints may read, with their units;
* ``<`` at the start of a line, where a new rule's name is typed: no rule names, only the
  names used but not defined yet, and the new-rule snippet;
* nothing inside a comment or a string.
"""

from __future__ import annotations

import re
from bisect import bisect_left, bisect_right
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from decimal import Decimal
from enum import Enum, StrEnum

from gaitgram.analysis import CheckResult
from gaitgram.analysis.cfg import Cfg, RuleKind
from gaitgram.analysis.motion_text import SensorScope, motion_rules
from gaitgram.backends.catalogue import Joint
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, backend_names, get_backend
from gaitgram.ide.hover import annotation_doc, describe_sensor
from gaitgram.language.annotations import ANNOTATIONS, AnnotationKind, Parameter, Refers
from gaitgram.language.model import FREQUENCY, Rule

__all__ = [
    "MAX_ITEMS",
    "RANGE_SNIPPETS",
    "TRIGGER_CHARACTERS",
    "Completion",
    "CompletionKind",
    "CompletionModel",
    "Completions",
    "Context",
    "RuleEntry",
    "Where",
    "complete",
    "context",
    "joints_of",
    "readable_sensors",
]

#: Lists are cut here; the client asks again as more is typed.
MAX_ITEMS = 200
TRIGGER_CHARACTERS = ["<", "@", " ", "="]

_DETAIL_WIDTH = 60


@dataclass(frozen=True, slots=True)
class RuleEntry:
    name: str
    detail: str  # its first production
    line: int  # where it is defined: nearer rules rank first


@dataclass(frozen=True)
class CompletionModel:
    """What completion needs from an analysis, as plain values that stay valid after it.

    Per rule (first definitions, in document order) there are parallel tuples; the detail
    shown with a rule (its first production) is read from ``text`` only for the rules a
    completion offers, since building it for thousands of rules on every change costs more
    than the rest of the model."""

    names: tuple[str, ...] = ()
    lines: tuple[int, ...] = ()
    #: Each rule's first production: offsets into ``text``, and whether more follow.
    firsts: tuple[tuple[int, int, bool], ...] = ()
    text: str = ""
    #: Names used but not defined, with a rule that uses each.
    undefined: tuple[tuple[str, str], ...] = ()
    backend: str | None = None
    units: str = "deg"
    #: Joint name -> the rule that drives it.
    driven: dict[str, str] = field(default_factory=dict)
    #: Per rule (parallel to ``names``; empty if no rule is a curve's text): the sensors its text
    #: may read, and each sensor's (unit, Markdown description).
    readable: tuple[tuple[str, ...], ...] = ()
    sensors: dict[str, tuple[str, str]] = field(default_factory=dict)
    #: The rules' names in lower case: what ranking reads.
    folded: tuple[str, ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "folded", tuple(name.lower() for name in self.names))

    @classmethod
    def of(cls, result: CheckResult) -> CompletionModel:
        grammar = result.grammar
        firsts = list(grammar.rules_by_name.values())
        return cls(
            names=tuple(rule.name for rule in firsts),
            lines=tuple(grammar.source.line_indices(r.span.start for r in firsts)),
            firsts=tuple(_first_alternative(rule) for rule in firsts),
            text=grammar.source.text,
            undefined=_undefined(result.facts.cfg),
            backend=grammar.backend,
            units=grammar.units,
            driven={j.joint: j.rule for j in grammar.joints},
            **readable_sensors(result),
        )

    def entry(self, index: int) -> RuleEntry:
        start, end, more = self.firsts[index] if self.firsts else (0, 0, False)
        return RuleEntry(self.names[index], _production(self.text, start, end, more), self.lines[index])

    @property
    def rules(self) -> list[RuleEntry]:
        return [self.entry(i) for i in range(len(self.names))]


def readable_sensors(result: CheckResult) -> dict[str, object]:
    """``readable`` and ``sensors`` of a :class:`CompletionModel`: per rule, the sensors its text may
    read (none in the @frequency rule's, only those its joints' groups may read), and what each is."""
    grammar = result.grammar
    rules = motion_rules(grammar, result.facts) if grammar.joints else {}
    if not rules:
        return {}
    scope = SensorScope(grammar.backend if grammar.declared.get("backend") is not None else None)
    offered = (
        {s.name: (s, scope.backend) for s in scope.sensors}
        if scope.backend is not None
        else {s.name: (s, b) for b, c in reversed(scope.installed.items()) for s in c}
    )
    described = {name: (s.unit, describe_sensor(s, b)) for name, (s, b) in offered.items()}

    def readable(readers: tuple[str, ...]) -> tuple[str, ...]:
        if FREQUENCY in readers:
            return ()
        groups = {j.group for r in readers if scope.joints and (j := scope.joints.get(r)) is not None}
        return tuple(n for n, (s, _) in offered.items() if all(s.readable_by(g) for g in groups))

    return {
        "readable": tuple(readable(rules[name]) if name in rules else () for name in grammar.rules_by_name),
        "sensors": described,
    }


def _undefined(cfg: Cfg) -> tuple[tuple[str, str], ...]:
    """Each undefined name with the first rule that uses it; the scan stops once all are found."""
    missing = {i for i, kind in enumerate(cfg.kinds) if kind is RuleKind.UNDEFINED}
    users: dict[int, str] = {}
    for rule, choices in enumerate(cfg.choices):
        if len(users) == len(missing) or cfg.kinds[rule] is not RuleKind.DEFINED:
            break
        for choice in choices:
            for item in choice:
                if item in missing and item not in users:  # ints only: strings are never in it
                    users[item] = cfg.names[rule]
    return tuple((cfg.names[i], user) for i, user in users.items())


def _first_alternative(rule: Rule) -> tuple[int, int, bool]:
    """Where the rule's first alternative is, and whether more follow: what ``entry`` shows."""
    if not rule.alternatives:
        return 0, 0, False
    span = rule.span_of(rule.alternatives[0])
    return span.start, span.end, len(rule.alternatives) > 1


def _production(text: str, start: int, end: int, more: bool) -> str:
    shown = " ".join(text[start : min(end, start + 4 * _DETAIL_WIDTH)].split())
    if len(shown) > _DETAIL_WIDTH:
        shown = shown[: _DETAIL_WIDTH - 1] + "…"
    return shown + (" | …" if more else "")


# ---- the context at the cursor ------------------------------------------------------------


class Where(Enum):
    ANNOTATION = "annotation"  # the name after @
    ARGUMENT = "argument"  # an annotation argument's value
    KEYWORD = "keyword"  # an annotation's key=
    RULE = "rule"  # a reference on a right-hand side
    HEAD = "head"  # a new rule's name
    NOTHING = "nothing"


@dataclass(frozen=True)
class Context:
    where: Where
    typed: str = ""  # what is typed of the word being completed
    start: int = 0  # code-point columns of the text an item replaces
    end: int = 0
    annotation: AnnotationKind | None = None
    parameter: Parameter | None = None
    words: tuple[str, ...] = ()  # the annotation's arguments before the cursor
    bracket: bool = False  # RULE: a < was typed
    closed: bool = False  # HEAD: the name's > and ::= are already there


_ANNOTATION_LINE = re.compile(r"[^\S\n]*@([A-Za-z_][\w-]*)?(.*)", re.DOTALL)
_NAME_CHARS = re.compile(r"[^<>|\s]*")
_WORD, _NOT_BLANK, _NAME = re.compile(r"[\w-]*"), re.compile(r"\S*"), re.compile(r"\w*")


def _ending(run: re.Pattern[str], text: str) -> str:
    """The longest run of ``run``'s characters that ends ``text``, matched on it reversed:
    ``re.search(run + "$")`` tries every start on the line, quadratic in a long word."""
    return run.match(text[::-1]).group()[::-1]  # type: ignore[union-attr]  # the empty run matches


def context(before: str, after: str) -> Context:
    """What is being typed, from the line's text before and after the cursor."""
    annotation = _ANNOTATION_LINE.fullmatch(before)
    if annotation is not None:
        name, rest = annotation.group(1) or "", annotation.group(2)
        if not rest:
            at = before.index("@") + 1
            tail = len(re.match(r"[\w-]*", after).group())  # type: ignore[union-attr]
            return Context(Where.ANNOTATION, name, at, len(before) + tail)
        if rest[0].isspace():
            return _argument_context(ANNOTATIONS.get(name), before, rest, after)
        return Context(Where.NOTHING)
    if _in_comment_or_string(before):
        return Context(Where.NOTHING)
    head = re.fullmatch(r"<([^<>|\s]*)", before)
    if head is not None:  # a line that starts with a name: a new rule, unless more follows it
        tail = _NAME_CHARS.match(after).group()  # type: ignore[union-attr]
        rest = after[len(tail) :]
        closed = re.match(r">\s*::=", rest) is not None
        if closed or rest.strip() in ("", ">"):
            end = len(before) + len(tail) + (1 if rest.startswith(">") else 0)
            return Context(Where.HEAD, head.group(1), 0, end, closed=closed)
    reference = re.search(r"<([^<>|\s]*)$", before)
    if reference is not None:
        tail = _NAME_CHARS.match(after).group()  # type: ignore[union-attr]
        end = len(before) + len(tail) + (1 if after[len(tail) :].startswith(">") else 0)
        return Context(Where.RULE, reference.group(1), reference.start(), end, bracket=True)
    word = _ending(_WORD, before)
    tail = re.match(r"[\w-]*", after).group()  # type: ignore[union-attr]
    return Context(Where.RULE, word, len(before) - len(word), len(before) + len(tail))


def _argument_context(kind: AnnotationKind | None, before: str, rest: str, after: str) -> Context:
    if kind is None:
        return Context(Where.NOTHING)
    current = _ending(_NOT_BLANK, rest)
    words = tuple(rest[: len(rest) - len(current)].split())
    tail = re.match(r"[^\s#]*", after).group()  # type: ignore[union-attr]
    end = len(before) + len(tail)
    if "#" in rest:
        return Context(Where.NOTHING)
    if "=" in current:
        key, _, typed = current.partition("=")
        parameter = kind.keywords.get(key)
        if parameter is None:
            return Context(Where.NOTHING)
        return Context(Where.ARGUMENT, typed, end - len(typed) - len(tail), end, kind, parameter, words)
    start = len(before) - len(current)
    positional = [w for w in words if "=" not in w]
    if len(positional) < len(kind.positional):
        parameter = kind.positional[len(positional)]
        return Context(Where.ARGUMENT, current, start, end, kind, parameter, words)
    return Context(Where.KEYWORD, current, start, end, kind, None, words)


def _in_comment_or_string(before: str) -> bool:
    quote = None
    for ch in before:
        if quote is not None:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "#":
            return True
    return quote is not None


# ---- items -----------------------------------------------------------------------------------


class CompletionKind(StrEnum):
    ANNOTATION = "annotation"
    RULE = "rule"
    KEYWORD = "keyword"  # an annotation's ``key=``
    CHOICE = "choice"  # one of a parameter's fixed choices, or a joint
    BACKEND = "backend"
    VALUE = "value"  # a suggested value (a joint's limits, its freedom)
    SNIPPET = "snippet"
    SENSOR = "sensor"  # a backend's sensor, in a curve's text


@dataclass(frozen=True, slots=True)
class Completion:
    label: str
    kind: CompletionKind
    text: str  # what replaces the word being typed
    detail: str | None = None
    documentation: str | None = None  # Markdown
    #: The same text with LSP snippet tab stops, for clients that take snippets.
    snippet: str | None = None
    filter_text: str | None = None
    sort_text: str | None = None


@dataclass(frozen=True, slots=True)
class Completions:
    items: list[Completion]
    #: More matched than were given: ask again as more is typed.
    incomplete: bool
    #: Code-point columns of the line that an item's text replaces.
    start: int
    end: int


def complete(
    model: CompletionModel, line: int, line_text: str, column: int, trigger: str | None = None
) -> Completions:
    """Completions at code-point ``column`` of ``line`` (whose text is ``line_text``)."""
    found = context(line_text[:column], line_text[column:])
    items: list[Completion] = []
    incomplete = False
    sensors = _sensors_here(model, line) if found.where is Where.RULE and not found.bracket else ()
    if sensors:  # a curve's text: the word is a name of motion text (``0.2*pi`` types ``pi``)
        typed = _ending(_NAME, line_text[:column])
        tail = re.match(r"\w*", line_text[column:]).group()  # type: ignore[union-attr]
        found = replace(found, typed=typed, start=column - len(typed), end=column + len(tail))
    if (trigger == " " and found.where not in (Where.ARGUMENT, Where.KEYWORD)) or (
        trigger == "@" and found.where is not Where.ANNOTATION
    ):  # a space in a rule is not a request; nor is an @ that starts no annotation
        return Completions(items, incomplete, found.start, found.end)
    if found.where is Where.ANNOTATION:
        items = [
            Completion(kind.name, CompletionKind.ANNOTATION, kind.name, kind.summary, annotation_doc(kind))
            for kind in ANNOTATIONS.values()
        ]
    elif found.where is Where.ARGUMENT and found.parameter and found.parameter.refers is Refers.RULE:
        matches, incomplete = _rank(model, found.typed.lstrip("<").rstrip(">"), line)
        items = [
            Completion(
                f"<{e.name}>", CompletionKind.RULE, f"<{e.name}>", e.detail or None, sort_text=f"{rank:07d}"
            )
            for rank, e in enumerate(matches)
        ]
    elif found.where is Where.ARGUMENT:
        items = _values(model, found)
    elif found.where is Where.KEYWORD:
        assert found.annotation is not None
        given = {w.partition("=")[0] for w in found.words if "=" in w}
        items = [
            Completion(f"{p.name}=", CompletionKind.KEYWORD, f"{p.name}=", p.help)
            for p in found.annotation.keywords.values()
            if p.name not in given
        ]
    elif found.where is Where.HEAD:
        suffix = "" if found.closed else " ::= "
        items = [
            Completion(
                f"<{name}>",
                CompletionKind.RULE,
                f"<{name}>{suffix}",
                f"used in <{user}>, not defined yet",
                filter_text=f"<{name}>",
            )
            for name, user in model.undefined
        ]
        if not found.closed:
            items.append(
                Completion(
                    "new rule",
                    CompletionKind.SNIPPET,
                    "<name> ::= a | b",
                    "a new rule",
                    snippet="<${1:name}> ::= ${2:a} | ${3:b}",
                )
            )
    elif found.where is Where.RULE:
        matches, incomplete = _rank(model, found.typed, line)
        items = [
            Completion(
                f"<{e.name}>",
                CompletionKind.RULE,
                f"<{e.name}>",
                e.detail or None,
                filter_text=f"<{e.name}>" if found.bracket else e.name,
                sort_text=f"{rank:07d}",
            )
            for rank, e in enumerate(matches)
        ]
        if not found.bracket:
            items += [
                Completion(
                    label,
                    CompletionKind.SNIPPET,
                    plain,
                    "typed range: one codon picks one value",
                    snippet=body,
                    sort_text=f"9{i}",
                )
                for i, (label, body, plain) in enumerate(RANGE_SNIPPETS)
            ]
            items += [
                Completion(
                    name,
                    CompletionKind.SENSOR,
                    name,
                    model.sensors[name][0],
                    model.sensors[name][1],
                    filter_text=name,
                    sort_text=f"!{name}",  # in a curve's text, before the rules
                )
                for name in sensors
            ]
    return Completions(items, incomplete, found.start, found.end)


def _sensors_here(model: CompletionModel, line: int) -> tuple[str, ...]:
    """The sensors the text of the rule at ``line`` may read (none outside a curve's text)."""
    if not model.readable:
        return ()
    index = bisect_right(model.lines, line) - 1
    return model.readable[index] if index >= 0 else ()


def _rank(model: CompletionModel, typed: str, line: int) -> tuple[list[RuleEntry], bool]:
    """Rules matching what is typed (exactly, by prefix, then inside), nearest first; at most
    MAX_ITEMS, and whether more matched. One pass over the names and then only as many steps
    as items: it runs on every keystroke, on the event loop."""
    wanted = typed.lower()
    if wanted:
        tiers: list[Sequence[int]] = [[], [], []]
        for index, name in enumerate(model.folded):
            if wanted in name:
                tiers[0 if name == wanted else 1 if name.startswith(wanted) else 2].append(index)
    else:
        tiers = [range(len(model.names))]
    chosen: list[int] = []
    for tier in tiers:
        chosen += _nearest(tier, model.lines, line, MAX_ITEMS - len(chosen))
    return [model.entry(i) for i in chosen], sum(map(len, tiers)) > MAX_ITEMS


def _nearest(indices: Sequence[int], lines: Sequence[int], line: int, count: int) -> list[int]:
    """The ``count`` indices whose lines are nearest ``line`` (the earlier on a tie), nearest
    first; ``indices`` ascend, and so do their lines."""
    right = bisect_left(indices, line, key=lines.__getitem__)
    left = right - 1
    found: list[int] = []
    while len(found) < count and (left >= 0 or right < len(indices)):
        if right >= len(indices) or (
            left >= 0 and line - lines[indices[left]] <= lines[indices[right]] - line
        ):
            found.append(indices[left])
            left -= 1
        else:
            found.append(indices[right])
            right += 1
    return found


#: (label, snippet body, plain text) of the typed-range snippets.
RANGE_SNIPPETS = (
    ("int[lo..hi]", "int[${1:0}..${2:10}]", "int[0..10]"),
    ("float[lo..hi step s]", "float[${1:0}..${2:20} step ${3:0.25}]", "float[0..20 step 0.25]"),
    ("float[lo..hi count n]", "float[${1:-3.14}..${2:3.14} count ${3:64}]", "float[-3.14..3.14 count 64]"),
    ("float[x ± p% count n]", "float[${1:7.7} ± ${2:25}% count ${3:21}]", "float[7.7 ± 25% count 21]"),
)


def _values(model: CompletionModel, found: Context) -> list[Completion]:
    """Values for ``found.parameter``, by what it refers to."""
    assert found.annotation is not None
    assert found.parameter is not None
    parameter = found.parameter
    if parameter.choices:
        return [Completion(c, CompletionKind.CHOICE, c, parameter.help) for c in parameter.choices]
    refers = parameter.refers
    if refers is Refers.BACKEND:
        return [Completion(n, CompletionKind.BACKEND, n, _backend_summary(n)) for n in backend_names()]
    if refers is Refers.JOINT:
        ordered = sorted(joints_of(model.backend), key=lambda bj: (bj[1].name in model.driven, bj[0]))
        return [
            Completion(joint.name, CompletionKind.CHOICE, joint.name, _joint_detail(joint, backend, model))
            for backend, joint in ordered
        ]
    if refers in (Refers.JOINT_LIMITS, Refers.JOINT_FREEDOM):
        joint = _joint_named(model, found)
        if joint is None:
            return []
        if refers is Refers.JOINT_LIMITS:
            scale = Decimal(1) if model.units == "deg" else Decimal("0.017453292519943295")
            low, high = (_number(Decimal(str(v)) * scale) for v in joint.limits)
            return [
                Completion(f"{low}..{high}", CompletionKind.VALUE, f"{low}..{high}", "the backend's limits")
            ]
        return [
            Completion(
                f"{joint.free_from}..",
                CompletionKind.VALUE,
                f"{joint.free_from}..",
                "as in Table 3 of the paper",
            ),
            Completion("0..", CompletionKind.VALUE, "0..", "from the start"),
        ]
    return []


def _joint_named(model: CompletionModel, found: Context) -> Joint | None:
    """The joint that the annotation's joint parameter names, among the words typed so far."""
    assert found.annotation is not None
    positional = [w for w in found.words if "=" not in w]
    keyword = {k: v for k, _, v in (w.partition("=") for w in found.words if "=" in w)}
    for index, parameter in enumerate(found.annotation.positional):
        if parameter.refers is Refers.JOINT and index < len(positional):
            wanted = positional[index]
            break
    else:
        wanted = next(
            (keyword.get(p.name) for p in found.annotation.keywords.values() if p.refers is Refers.JOINT),
            None,
        )
    return next((j for _, j in joints_of(model.backend) if j.name == wanted), None)


def _number(value: Decimal) -> str:
    text = f"{value:.4f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def joints_of(backend: str | None) -> list[tuple[str, Joint]]:
    """(backend, joint) for the declared backend, or for every installed one if none is."""
    names = [backend] if backend else list(backend_names())
    found = []
    for name in names:
        try:
            catalogue = get_backend(name).catalogue
        except (BackendNotFound, BackendLoadError):
            continue
        if catalogue is not None:
            found += [(name, joint) for joint in catalogue.joints]
    return found


def _joint_detail(joint: Joint, backend: str, model: CompletionModel) -> str:
    limits = f"{joint.limits[0]:g}..{joint.limits[1]:g}°"
    driven = model.driven.get(joint.name)
    where = "" if model.backend else f" ({backend})"
    return f"{joint.group}, {limits}, free from generation {joint.free_from}{where}" + (
        f"; driven by <{driven}>" if driven else ""
    )


def _backend_summary(name: str) -> str:
    try:
        return get_backend(name).summary
    except (BackendNotFound, BackendLoadError) as error:
        return str(error)
