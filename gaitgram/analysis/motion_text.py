"""The names a grammar's curves read, found without deriving anything: the identifiers in the
terminals of the rules that each ``@joint`` (and the ``@frequency``) rule reaches, and the
backend sensors they are.

One place answers "what does this curve read?" for the linter (GG508 to GG512), the pipeline
(a backend that lacks a sensor the grammar reads), hover, completion and semantic tokens. Names
are split as the motion parser splits them (:func:`gaitgram.motion.names.words`), terminal by
terminal: a name is read where a terminal spells it whole, as every bundled grammar does.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property

from gaitgram.analysis.cfg import RuleKind
from gaitgram.analysis.facts import GrammarFacts, reachable_from
from gaitgram.backends.catalogue import JointCatalogue
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, backend_names, get_backend
from gaitgram.backends.sensors import Sensor, SensorCatalogue
from gaitgram.language.model import FREQUENCY, Grammar, Rule, Terminal
from gaitgram.language.source import Span
from gaitgram.motion.names import builtin, words

__all__ = ["NameUse", "SensorScope", "motion_rules", "name_uses", "sensor_uses", "sensors_lacking"]


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
    readers: dict[int, list[str]] = {}
    for reader, rule in roots:
        index = cfg.index.get(rule)
        if index is None or cfg.kinds[index] is not RuleKind.DEFINED or not facts.reachable[index]:
            continue
        for reached, yes in enumerate(reachable_from(cfg, [index])):
            if yes and cfg.kinds[reached] is RuleKind.DEFINED and reader not in readers.get(reached, ()):
                readers.setdefault(reached, []).append(reader)
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
