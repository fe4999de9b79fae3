"""Rule names: what is under the cursor, definitions, references, highlights, rename and symbols."""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Iterable
from dataclasses import dataclass

from lsprotocol import types
from pygls.exceptions import JsonRpcException

from gaitgram.language.model import Annotation, Rule, RuleRef
from gaitgram.language.source import Span
from gaitgram.language.syntax import is_rule_name
from gaitgram_lsp.documents import Snapshot


@dataclass(frozen=True, slots=True)
class Occurrence:
    name: str
    span: Span  # ``<name>``, brackets included
    definition: bool


def rule_at(snapshot: Snapshot, offset: int) -> Rule | None:
    """The rule whose text (head to last alternative) contains ``offset``."""
    rules = snapshot.result.grammar.rules
    index = bisect_right(snapshot.rule_starts, offset) - 1
    if index >= 0 and offset in rules[index].span:
        return rules[index]
    return None


def annotation_at(snapshot: Snapshot, offset: int) -> Annotation | None:
    for annotation in snapshot.result.grammar.annotations:
        if offset in annotation.span:
            return annotation
        if annotation.span.start > offset:
            break
    return None


def name_at(snapshot: Snapshot, offset: int) -> Occurrence | None:
    """The rule name under the cursor: a rule's head, a reference, or ``@start <name>``."""
    rule = rule_at(snapshot, offset)
    if rule is not None:
        if offset in rule.name_span:
            return Occurrence(rule.name, rule.name_span, True)
        for ref in rule.references():
            if offset in ref.span:
                return Occurrence(ref.name, ref.span, False)
        return None
    annotation = annotation_at(snapshot, offset)
    if annotation is not None:
        for argument in annotation.arguments:
            if offset in argument.span and (ref := _rule_argument(annotation.name, argument)) is not None:
                return Occurrence(ref, argument.span, False)
    return None


def _rule_argument(annotation: str, argument) -> str | None:
    value = argument.value
    if annotation == "start" and isinstance(value, RuleRef) and argument.raw == f"<{value.name}>":
        return value.name
    return None


def occurrences(snapshot: Snapshot, name: str) -> list[Occurrence]:
    """Every ``<name>`` in the document, in order: heads, references and ``@start``."""
    grammar = snapshot.result.grammar
    found = []
    for rule in grammar.rules:
        if rule.name == name:
            found.append(Occurrence(name, rule.name_span, True))
        found += [Occurrence(name, ref.span, False) for ref in rule.references() if ref.name == name]
    for annotation in grammar.annotations:
        for argument in annotation.arguments:
            if _rule_argument(annotation.name, argument) == name:
                found.append(Occurrence(name, argument.span, False))
    return sorted(found, key=lambda o: o.span.start)


def definition(snapshot: Snapshot, offset: int) -> list[types.Location] | None:
    found = name_at(snapshot, offset)
    if found is None:
        return None
    heads = [o for o in occurrences(snapshot, found.name) if o.definition]
    return [types.Location(uri=snapshot.uri, range=snapshot.positions.range(o.span)) for o in heads] or None


def references(snapshot: Snapshot, offset: int, include_declaration: bool = True) -> list[types.Location]:
    found = name_at(snapshot, offset)
    if found is None:
        return []
    return [
        types.Location(uri=snapshot.uri, range=snapshot.positions.range(o.span))
        for o in occurrences(snapshot, found.name)
        if include_declaration or not o.definition
    ]


def highlights(snapshot: Snapshot, offset: int) -> list[types.DocumentHighlight]:
    found = name_at(snapshot, offset)
    if found is None:
        return []
    return [
        types.DocumentHighlight(
            range=snapshot.positions.range(o.span),
            kind=types.DocumentHighlightKind.Write if o.definition else types.DocumentHighlightKind.Read,
        )
        for o in occurrences(snapshot, found.name)
    ]


# ---- rename -----------------------------------------------------------------------------------


class RenameRefused(JsonRpcException):
    """Sent to the client as an error response (LSP's RequestFailed), with the reason."""

    CODE = -32803


def prepare_rename(snapshot: Snapshot, offset: int) -> types.PrepareRenamePlaceholder | None:
    found = name_at(snapshot, offset)
    if found is None:
        return None
    inner = Span(found.span.start + 1, found.span.end - 1)
    return types.PrepareRenamePlaceholder(range=snapshot.positions.range(inner), placeholder=found.name)


def rename(snapshot: Snapshot, offset: int, new_name: str) -> types.WorkspaceEdit:
    """Rename the rule under the cursor everywhere (references to an undefined name too)."""
    found = name_at(snapshot, offset)
    if found is None:
        raise RenameRefused("there is no rule name here to rename")
    new_name = new_name.strip()
    if new_name.startswith("<") and new_name.endswith(">"):
        new_name = new_name[1:-1]
    if not is_rule_name(new_name):
        raise RenameRefused(
            f"{new_name!r} is not a rule name: it cannot be empty or contain spaces, <, > or |"
        )
    if new_name != found.name and snapshot.result.grammar.rule(new_name) is not None:
        raise RenameRefused(f"<{new_name}> is already defined; merge the rules by hand")
    edits = [
        types.TextEdit(
            range=snapshot.positions.range(Span(o.span.start + 1, o.span.end - 1)), new_text=new_name
        )
        for o in occurrences(snapshot, found.name)
    ]
    return types.WorkspaceEdit(changes={snapshot.uri: edits})


# ---- symbols ------------------------------------------------------------------------------------


def _detail(snapshot: Snapshot, rule: Rule) -> str:
    joint = snapshot.result.grammar.joints_by_rule.get(rule.name)
    facts = snapshot.result.facts.rule(rule.name)
    choices = facts.choices if facts is not None else rule.choice_count
    text = f"{choices} choice{'' if choices == 1 else 's'}"
    return f"joint {joint.joint}, {text}" if joint is not None and joint.rule == rule.name else text


def _rule_range(rule: Rule) -> Span:
    """The rule with its annotations: what an outline selects."""
    start = rule.annotations[0].span.start if rule.annotations else rule.span.start
    return Span(min(start, rule.span.start), rule.span.end)


def document_symbols(
    snapshot: Snapshot, hierarchical: bool = True
) -> list[types.DocumentSymbol] | list[types.SymbolInformation]:
    """The rules, in order, and the file's annotations (``@start``, ``@backend``, ...)."""
    grammar = snapshot.result.grammar
    positions = snapshot.positions
    symbols: list[tuple[int, str, types.SymbolKind, str, Span, Span]] = []
    rule_annotations = {id(a) for rule in grammar.rules for a in rule.annotations}
    for annotation in grammar.annotations:
        if id(annotation) not in rule_annotations:
            arguments = " ".join(a.raw for a in annotation.arguments)
            symbols.append(
                (
                    annotation.span.start,
                    f"@{annotation.name}",
                    types.SymbolKind.Property,
                    arguments,
                    annotation.span,
                    annotation.name_span,
                )
            )
    for rule in grammar.rules:
        symbols.append(
            (
                rule.span.start,
                f"<{rule.name}>",
                types.SymbolKind.Function,
                _detail(snapshot, rule),
                _rule_range(rule),
                rule.name_span,
            )
        )
    symbols.sort(key=lambda s: s[0])
    if hierarchical:
        return [
            types.DocumentSymbol(
                name=name,
                kind=kind,
                detail=detail or None,
                range=positions.range(whole),
                selection_range=positions.range(selection),
            )
            for _, name, kind, detail, whole, selection in symbols
        ]
    return [
        types.SymbolInformation(
            name=name, kind=kind, location=types.Location(uri=snapshot.uri, range=positions.range(selection))
        )
        for _, name, kind, _detail_text, _whole, selection in symbols
    ]


def matches(query: str, name: str) -> bool:
    """Whether the query's characters appear in the name in order (case-insensitive)."""
    remaining = iter(name.lower())
    return all(ch in remaining for ch in query.lower())


#: Workspace symbol answers are cut here.
MAX_WORKSPACE_SYMBOLS = 1_000


def workspace_symbols(snapshots: Iterable[Snapshot], query: str) -> list[types.WorkspaceSymbol]:
    """Rules of every grammar given (open and on disk) whose names match ``query``."""
    found = []
    for snapshot in snapshots:
        for rule in snapshot.result.grammar.rules_by_name.values():
            if matches(query, rule.name):
                found.append(
                    types.WorkspaceSymbol(
                        name=f"<{rule.name}>",
                        kind=types.SymbolKind.Function,
                        location=types.Location(
                            uri=snapshot.uri, range=snapshot.positions.range(rule.name_span)
                        ),
                        container_name=snapshot.uri.rsplit("/", 1)[-1],
                    )
                )
                if len(found) >= MAX_WORKSPACE_SYMBOLS:
                    return found
    return found
