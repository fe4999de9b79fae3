"""The names a grammar's curves read, found without deriving anything: the identifiers in the
terminals of the rules that each ``@joint`` (and the ``@frequency``) rule reaches, and the
backend sensors they are.

One place answers "what does this curve read?" for the linter (GG508 to GG512), the pipeline
(a backend that lacks a sensor the grammar reads), hover, completion and semantic tokens. Names
are split as the motion parser splits them (:func:`gaitgram.motion.names.words`), terminal by
terminal: a name is read where a terminal spells it whole, as every bundled grammar does.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from functools import cached_property

from gaitgram.analysis.cfg import RuleKind
from gaitgram.analysis.facts import GrammarFacts
from gaitgram.backends.catalogue import JointCatalogue
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, backend_names, get_backend
from gaitgram.backends.sensors import Sensor, SensorCatalogue
from gaitgram.language.model import FREQUENCY, Grammar, Rule, Terminal
from gaitgram.language.source import Span
from gaitgram.motion.names import builtin, reads, words

__all__ = [
    "ClosedLoops",
    "LoopTerms",
    "NameUse",
    "SensorScope",
    "closed_loops",
    "motion_rules",
    "name_uses",
    "sensor_uses",
    "sensors_lacking",
]


@dataclass(frozen=True, slots=True)
class NameUse:
    """A name spelt in a terminal of motion text."""

    name: str
    span: Span  # in the document
    rule: str  # the rule whose terminal spells it
    called: bool  # a ``(`` follows it in the terminal
    #: The joints whose curves reach it, and :data:`~gaitgram.language.model.FREQUENCY` if the
    #: frequency rule does, in the grammar's order.
    readers: tuple[str, ...]

    @property
    def builtin(self) -> bool:
        """``t``, a constant or a function: what every phenotype may read."""
        return builtin(self.name)


def motion_rules(grammar: Grammar, facts: GrammarFacts) -> dict[str, tuple[str, ...]]:
    """The rules whose terminals are motion text, in document order, each with its readers: the
    joints (and :data:`~gaitgram.language.model.FREQUENCY`) whose rules, reached from the start
    rule, reach it."""
    cfg = facts.cfg
    roots = [(j.joint, j.rule) for j in grammar.joints]
    if grammar.frequency is not None:
        roots.append((FREQUENCY, grammar.frequency.rule))
    readers: dict[int, dict[str, None]] = {}  # each rule's readers, in order, once each
    successors: list[set[int]] | None = None
    for reader, rule in roots:
        index = cfg.index.get(rule)
        if index is None or cfg.kinds[index] is not RuleKind.DEFINED or not facts.reachable[index]:
            continue
        if successors is None:  # each root's search reads what it reaches, never the whole grammar
            successors = [cfg.children(r) for r in range(len(cfg))]  # (thousands of joint rules)
        reached, frontier = {index}, [index]
        while frontier:
            for child in successors[frontier.pop()]:
                if child not in reached:
                    reached.add(child)
                    frontier.append(child)
        for found in reached:
            if cfg.kinds[found] is RuleKind.DEFINED:
                readers.setdefault(found, {})[reader] = None
    rules = grammar.rules_by_name
    ordered = sorted(readers, key=lambda i: rules[cfg.names[i]].span.start)
    return {cfg.names[i]: tuple(readers[i]) for i in ordered}


def name_uses(grammar: Grammar, facts: GrammarFacts) -> list[NameUse]:
    """Every name in the motion text of ``grammar``, in document order."""
    found: list[NameUse] = []
    for name, who in motion_rules(grammar, facts).items():
        rule = grammar.rules_by_name[name]
        for terminal, span in _terminals(rule):
            for word, at, called in _located(grammar.source.text, terminal.text, span):
                found.append(NameUse(word, at, rule.name, called, who))
    return found


def sensor_uses(grammar: Grammar, facts: GrammarFacts) -> list[tuple[NameUse, Sensor, str]]:
    """The names of motion text that are sensors, each with its sensor and the backend that has
    it: the grammar's backend, or (none declared) the first installed one that does."""
    scope = SensorScope(grammar.backend if grammar.declared.get("backend") is not None else None)
    found = []
    for use in name_uses(grammar, facts):
        if use.builtin or use.called:
            continue
        sensor = scope.sensor(use.name)
        if sensor is not None:
            found.append((use, sensor, scope.backend or scope.offered_by(use.name)[0]))
    return found


def _terminals(rule: Rule) -> Iterator[tuple[Terminal, Span]]:
    for alternative in rule.alternatives:
        for symbol in alternative.symbols:
            if isinstance(symbol, Terminal):
                yield symbol, rule.span_of(symbol)


def _located(text: str, decoded: str, span: Span) -> Iterator[tuple[str, Span, bool]]:
    """The names of a terminal with their spans in the document. The terminal's text has its
    quotes dropped and escapes decoded, so each name is found in the source after the one before
    it, its letters perhaps split by quotes (``'pi'tch``); one spelt through an escape gets the
    whole terminal's span."""
    raw = text[span.start : span.end]
    cursor = 0
    for name, start, end, called in words(decoded):
        if raw == decoded:
            yield name, Span(span.start + start, span.start + end), called
            continue
        found = _spelt(raw, name, cursor)
        if found is None:
            yield name, span, called
            continue
        first, cursor = found
        yield name, Span(span.start + first, span.start + cursor), called


def _spelt(raw: str, name: str, start: int) -> tuple[int, int] | None:
    """Where ``name`` is spelt in ``raw`` from ``start``, quotes allowed between its letters."""
    while (first := raw.find(name[0], start)) >= 0:
        start = first + 1
        if first and (raw[first - 1].isalnum() or raw[first - 1] == "_"):
            continue
        end, letter = first + 1, 1
        while letter < len(name):
            while end < len(raw) and raw[end] in "'\"":
                end += 1
            if end == len(raw) or raw[end] != name[letter]:
                break
            end, letter = end + 1, letter + 1
        if letter == len(name) and not (end < len(raw) and (raw[end].isalnum() or raw[end] == "_")):
            return first, end
    return None


class SensorScope:
    """The sensors a grammar's names are checked against: its backend's, and every installed
    backend's (loaded only when a name is neither built in nor the backend's sensor)."""

    def __init__(self, backend: str | None) -> None:
        #: The declared backend's name, if it is installed and loads; None otherwise.
        self.backend: str | None = None
        #: Its sensors (an empty catalogue: it senses nothing) and joints.
        self.sensors = SensorCatalogue(())
        self.joints: JointCatalogue | None = None
        if backend is not None:
            try:
                spec = get_backend(backend)
            except (BackendNotFound, BackendLoadError):
                return
            self.backend = spec.name
            self.sensors = spec.sensors or SensorCatalogue(())
            self.joints = spec.catalogue

    @cached_property
    def installed(self) -> dict[str, SensorCatalogue]:
        """Every installed backend's sensors, by backend (those that sense nothing left out)."""
        found = {}
        for name in backend_names():
            try:
                catalogue = get_backend(name).sensors
            except (BackendNotFound, BackendLoadError):
                continue
            if catalogue is not None and len(catalogue):
                found[name] = catalogue
        return found

    def sensor(self, name: str) -> Sensor | None:
        """The sensor ``name`` is: the backend's, or else (no backend known) any installed one's."""
        found = self.sensors.get(name)
        if found is None and self.backend is None:
            found = next((c.get(name) for c in self.installed.values() if c.get(name)), None)
        return found

    def offered_by(self, name: str) -> list[str]:
        """The installed backends that have a sensor ``name``."""
        return [backend for backend, catalogue in self.installed.items() if catalogue.get(name)]

    def every_sensor(self) -> list[str]:
        """Every installed backend's sensor names, sorted."""
        return sorted({s.name for catalogue in self.installed.values() for s in catalogue})


def sensors_lacking(grammar: Grammar, facts: GrammarFacts, sensors: SensorCatalogue | None) -> list[str]:
    """The sensors of installed backends that the grammar's curves read and ``sensors`` lacks."""
    scope = SensorScope(None)
    lacking = []
    for use in name_uses(grammar, facts):
        if use.builtin or use.name in lacking or (sensors is not None and sensors.get(use.name)):
            continue
        if scope.offered_by(use.name):
            lacking.append(use.name)
    return lacking


@dataclass(frozen=True, slots=True)
class LoopTerms:
    """A curve that reads sensors, split where that is simple (a sum): the terms that read no
    sensor (what it plays open loop), those that read only a periodic sensor (a limb's oscillator
    ``phase``: a curve of the cycle that touchdown may restart) and those that read the others
    (its feedback)."""

    joint: str
    sensors: tuple[str, ...]  # in the order the curve first reads them
    #: The sum of its terms that read no sensor; None when every term reads one.
    open_loop: str | None
    #: Its terms that read periodic sensors only, each with the sign it is added with.
    phased: tuple[str, ...]
    #: Its terms that read the other sensors, each with its sign (a curve that is no sum is one
    #: term: ``sin(2*PI*t+pitch)``).
    feedback: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class ClosedLoops:
    """The curves of a phenotype that read sensors: what ``gaitgram map`` and ``plot`` say of it."""

    curves: tuple[LoopTerms, ...]

    @property
    def sensors(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys(name for curve in self.curves for name in curve.sensors))

    def summary(self) -> dict[str, object]:
        """The JSON-ready record ``gaitgram map --json`` prints as ``closed_loop``."""
        return {
            "sensors": list(self.sensors),
            "note": self.note(),
            "curves": {
                c.joint: {
                    "sensors": list(c.sensors),
                    "open_loop": c.open_loop,
                    "phased": list(c.phased),
                    "feedback": list(c.feedback),
                }
                for c in self.curves
            },
        }

    def lines(self) -> list[str]:
        """The note, then each curve's open-loop part, phase terms and feedback terms, for people."""
        found = [self.note()]
        for curve in self.curves:
            parts = [f"open loop {curve.open_loop or 'none (every term reads a sensor)'}"]
            if curve.phased:
                parts.append(f"at the limb's phase {' '.join(curve.phased)}")
            if curve.feedback:
                parts.append(f"feedback {' '.join(curve.feedback)}")
            found.append(f"  {curve.joint}: {'; '.join(parts)}")
        return found

    def note(self) -> str:
        """One line for people: which curves read which sensors, and what that means for a plot."""
        joints = [curve.joint for curve in self.curves]
        shown = ", ".join(joints[:4]) + (f" and {len(joints) - 4} more" if len(joints) > 4 else "")
        one = len(joints) == 1
        names = f"sensor{'' if len(self.sensors) == 1 else 's'} {', '.join(self.sensors)}"
        curves = "its curve" if one else "their curves"
        return (
            f"closed loop: {shown} read{'s' if one else ''} the {names}, so {curves} cannot be plotted "
            "as a fixed curve; a plot shows the nominal curve, every sensor at rest"
        )


def closed_loops(grammar: Grammar, facts: GrammarFacts, joints: Mapping[str, str]) -> ClosedLoops | None:
    """The curves of a phenotype (``joints``: each joint's text) that read the grammar's sensors,
    split into open-loop part, phase terms and feedback terms; None for an open-loop phenotype."""
    sensors = {use.name: sensor.periodic for use, sensor, _ in sensor_uses(grammar, facts)}
    if not sensors:
        return None
    curves = []
    for joint, text in joints.items():
        read = reads(text, sensors)
        if read:
            curves.append(LoopTerms(joint, tuple(read), *_terms(text, sensors)))
    return ClosedLoops(tuple(curves)) if curves else None


def _terms(text: str, sensors: Mapping[str, bool]) -> tuple[str | None, tuple[str, ...], tuple[str, ...]]:
    """The sum of the terms of ``text`` that read no sensor, the terms that read only periodic
    ones (``sensors``: each name's ``periodic``), and the terms that read others."""
    from gaitgram.motion.parser import parse  # numpy: only for a phenotype that reads sensors
    from gaitgram.motion.tree import Binary, Name, postorder

    syntax = parse(text)
    if not hasattr(syntax, "tree"):  # not an expression: nothing to split
        return None, (), (text,)
    plain: list[str] = []
    phased: list[str] = []
    feedback: list[str] = []
    work = [(syntax.tree(), "+")]
    while work:
        node, sign = work.pop()
        if isinstance(node, Binary) and node.op in "+-":
            work.append((node.right, sign if node.op == "+" else "-" if sign == "+" else "+"))
            work.append((node.left, sign))
            continue
        read = {n.name for n in postorder(node) if isinstance(n, Name) and n.name in sensors}
        kind = feedback if any(not sensors[r] for r in read) else phased if read else plain
        kind.append(_signed(sign, text[node.start : node.end]))
    return "".join(plain).removeprefix("+") or None, tuple(phased), tuple(feedback)


def _signed(sign: str, term: str) -> str:
    """``term`` added (``+``) or subtracted (``-``), its own leading minus folded in."""
    if term.startswith("-"):
        return term if sign == "+" else "+" + term[1:]
    return sign + term
