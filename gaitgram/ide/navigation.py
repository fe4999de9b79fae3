"""Rule names: what is under the cursor, where it is defined and used, renaming, and outlines.

A rule is named by its head, by ``<name>`` references on right-hand sides, and by every
annotation argument whose parameter refers to a rule (``Refers.RULE``, such as
``@start <prog>``): the annotation table says which, so a new annotation that names rules is
found and renamed with no change here.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from enum import StrEnum

from gaitgram.analysis import CheckResult
from gaitgram.language.annotations import rule_references
from gaitgram.language.diagnostics import TextEdit
from gaitgram.language.model import Grammar, Rule
from gaitgram.language.source import Span
from gaitgram.language.syntax import is_rule_name

__all__ = [
    "Occurrence",
    "RenameRefused",
    "Symbol",
    "SymbolKind",
    "matches",
    "name_at",
    "occurrences",
    "rename",
    "rename_target",
    "rules_matching",
    "symbols",
]


@dataclass(frozen=True, slots=True)
class Occurrence:
    name: str
    span: Span  # ``<name>``, brackets included
    definition: bool


def name_at(grammar: Grammar, offset: int) -> Occurrence | None:
    """The rule name under the cursor: a rule's head, a reference, or an annotation's ``<name>``."""
    rule = grammar.rule_at(offset)
    if rule is not None:
        if offset in rule.name_span:
            return Occurrence(rule.name, rule.name_span, True)
        for ref in rule.references():
            if offset in (span := rule.span_of(ref)):
                return Occurrence(ref.name, span, False)
        return None
    annotation = grammar.annotation_at(offset)
    if annotation is not None:
        for name, span in rule_references(annotation):
            if offset in span:
                return Occurrence(name, span, False)
    return None


def occurrences(grammar: Grammar, name: str) -> list[Occurrence]:
    """Every ``<name>`` in the document, in order: heads, references and annotation arguments."""
    found = []
    for rule in grammar.rules:
        if rule.name == name:
            found.append(Occurrence(name, rule.name_span, True))
        found += [Occurrence(name, rule.span_of(ref), False) for ref in rule.references() if ref.name == name]
    for annotation in grammar.annotations:
        found += [
            Occurrence(name, span, False) for named, span in rule_references(annotation) if named == name
        ]
    return sorted(found, key=lambda o: o.span.start)


class RenameRefused(ValueError):
    """A rename that cannot be done, with the reason to show."""


def rename_target(grammar: Grammar, offset: int) -> tuple[str, Span] | None:
    """The name a rename at ``offset`` would change, and the span of its text (no brackets)."""
    found = name_at(grammar, offset)
    if found is None:
        return None
    return found.name, Span(found.span.start + 1, found.span.end - 1)


def rename(grammar: Grammar, offset: int, new_name: str) -> list[TextEdit]:
    """Edits renaming the rule under the cursor everywhere (references to an undefined name too)."""
    found = name_at(grammar, offset)
    if found is None:
        raise RenameRefused("there is no rule name here to rename")
    new_name = new_name.strip()
    if new_name.startswith("<") and new_name.endswith(">"):
        new_name = new_name[1:-1]
    if not is_rule_name(new_name):
        raise RenameRefused(
            f"{new_name!r} is not a rule name: it cannot be empty or contain spaces, <, > or |"
        )
    if new_name != found.name and grammar.rule(new_name) is not None:
        raise RenameRefused(f"<{new_name}> is already defined; merge the rules by hand")
    return [
        TextEdit(Span(o.span.start + 1, o.span.end - 1), new_name) for o in occurrences(grammar, found.name)
    ]


# ---- outlines -------------------------------------------------------------------------------


class SymbolKind(StrEnum):
    RULE = "rule"
    SETTING = "setting"  # a file annotation: @start, @backend, ...


@dataclass(frozen=True, slots=True)
class Symbol:
    name: str  # ``<rule>`` or ``@annotation``
    kind: SymbolKind
    detail: str
    span: Span  # the whole item: a rule with its annotations
    selection: Span  # its name


def symbols(result: CheckResult) -> list[Symbol]:
    """The rules, in order, and the file's annotations (``@start``, ``@backend``, ...)."""
    grammar = result.grammar
    found: list[Symbol] = []
    rule_annotations = {id(a) for rule in grammar.rules for a in rule.annotations}
    for annotation in grammar.annotations:
        if id(annotation) not in rule_annotations:
            arguments = " ".join(a.raw for a in annotation.arguments)
            found.append(
                Symbol(
                    f"@{annotation.name}",
                    SymbolKind.SETTING,
                    arguments,
                    annotation.span,
                    annotation.name_span,
                )
            )
    for rule in grammar.rules:
        found.append(
            Symbol(f"<{rule.name}>", SymbolKind.RULE, _detail(result, rule), _extent(rule), rule.name_span)
        )
    return sorted(found, key=lambda s: s.selection.start)


def _detail(result: CheckResult, rule: Rule) -> str:
    joint = result.grammar.joints_by_rule.get(rule.name)
    facts = result.facts.rule(rule.name)
    choices = facts.choices if facts is not None else rule.choice_count
    text = f"{choices} choice{'' if choices == 1 else 's'}"
    return f"joint {joint.joint}, {text}" if joint is not None and joint.rule == rule.name else text


def _extent(rule: Rule) -> Span:
    """The rule with its annotations: what an outline selects."""
    start = rule.annotations[0].span.start if rule.annotations else rule.span.start
    return Span(min(start, rule.span.start), rule.span.end)


def matches(query: str, name: str) -> bool:
    """Whether the query's characters appear in the name in order (case-insensitive)."""
    remaining = iter(name.lower())
    return all(ch in remaining for ch in query.lower())


def rules_matching(grammars: Iterable[Grammar], query: str, limit: int) -> list[tuple[Grammar, Rule]]:
    """Rules of the grammars whose names match ``query``, at most ``limit``."""
    found = []
    for grammar in grammars:
        for rule in grammar.rules_by_name.values():
            if matches(query, rule.name):
                found.append((grammar, rule))
                if len(found) >= limit:
                    return found
    return found
