"""Code actions.

Quick fixes, for the diagnostics under the cursor:

* GG201 (undefined rule): define it, after the rule that uses it; or replace the name with
  the nearest defined ones (difflib);
* GG204 (unreachable rule): remove it, with its annotations (and, when there are several,
  remove them all);
* GG401/GG502 (unknown annotation or joint): replace with the nearest known name.

Refactorings, for the rule under the cursor:

* collapse (anywhere in the rule) a written-out list of evenly spaced numbers
  (``0 | 0.25 | 0.5 | ... | 2``) into the typed range that derives exactly the same texts in the same order
  (``float[0..2 step 0.25]``), so every genome keeps its phenotype;
* expand a typed range that is a whole alternative back into its values.
"""

from __future__ import annotations

import re
from decimal import Decimal, InvalidOperation
from difflib import get_close_matches
from itertools import pairwise

from lsprotocol import types

from gaitgram.diagnostics import Diagnostic
from gaitgram.language.annotations import ANNOTATIONS
from gaitgram.language.model import Alternative, Rule, Terminal
from gaitgram.language.ranges import parse_range
from gaitgram.language.source import Span
from gaitgram_lsp.documents import Snapshot
from gaitgram_lsp.features.completion import joints_of
from gaitgram_lsp.features.diagnostics import to_lsp, wire_diagnostic
from gaitgram_lsp.features.navigation import rule_at

QUICK_FIX = types.CodeActionKind.QuickFix
REWRITE = types.CodeActionKind.RefactorRewrite
KINDS = [QUICK_FIX, REWRITE]

#: A typed range is expanded only up to this many values.
MAX_EXPANDED = 200
_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d+)?|\.\d+)")


def code_actions(
    snapshot: Snapshot, start: int, end: int, only: list[str] | None = None
) -> list[types.CodeAction]:
    """Actions for the text between offsets ``start`` and ``end``."""
    actions: list[types.CodeAction] = []
    if _wanted(QUICK_FIX, only):
        for found in snapshot.result.diagnostics:
            if found.span.start <= end and start <= found.span.end:
                actions += _fixes(snapshot, found)
    if _wanted(REWRITE, only):
        rule = rule_at(snapshot, start)
        if rule is not None:
            actions += _collapse(snapshot, rule) + _expand(snapshot, rule)
    return actions


def _wanted(kind: str, only: list[str] | None) -> bool:
    return only is None or any(kind == o or kind.startswith(o + ".") for o in only)


def _action(
    snapshot: Snapshot,
    title: str,
    edits: list[tuple[Span, str]],
    kind: str,
    fixes: Diagnostic | None = None,
    preferred: bool = False,
) -> types.CodeAction:
    positions = snapshot.positions
    return types.CodeAction(
        title=title,
        kind=kind,
        diagnostics=[_lsp(snapshot, fixes)] if fixes is not None else None,
        is_preferred=preferred or None,
        edit=types.WorkspaceEdit(
            changes={
                snapshot.uri: [
                    types.TextEdit(range=positions.range(span), new_text=text) for span, text in edits
                ]
            }
        ),
    )


def _lsp(snapshot: Snapshot, found: Diagnostic) -> types.Diagnostic:
    return to_lsp([wire_diagnostic(found, snapshot.positions)])[0]


# ---- quick fixes ---------------------------------------------------------------------------------


def _fixes(snapshot: Snapshot, found: Diagnostic) -> list[types.CodeAction]:
    code = found.code.code
    grammar = snapshot.result.grammar
    text = snapshot.text
    if code == "GG201":
        raw = text[found.span.start : found.span.end]
        if not (raw.startswith("<") and raw.endswith(">")):
            return []
        name = raw[1:-1]
        user = grammar.rule(found.rule) if found.rule else None
        where = _line_end(text, user.span.end) if user is not None else len(text)
        newline = "\n" if where == len(text) and text and not text.endswith("\n") else ""
        insert = f"{newline}<{name}> ::= ''\n" if where == len(text) else f"\n<{name}> ::= ''"
        actions = [_action(snapshot, f"Define <{name}>", [(Span(where, where), insert)], QUICK_FIX, found)]
        nearest = get_close_matches(name, list(grammar.rules_by_name), n=3, cutoff=0.6)
        actions += [
            _action(snapshot, f"Replace with <{n}>", [(found.span, f"<{n}>")], QUICK_FIX, found, i == 0)
            for i, n in enumerate(nearest)
        ]
        return actions
    if code == "GG204" and found.rule:
        rule = grammar.rule(found.rule)
        if rule is None:
            return []
        actions = [
            _action(
                snapshot,
                f"Remove unreachable <{rule.name}>",
                [(_removal(snapshot, rule), "")],
                QUICK_FIX,
                found,
            )
        ]
        unreachable = [d for d in snapshot.result.diagnostics if d.code.code == "GG204" and d.rule]
        if len(unreachable) > 1:
            spans = [
                _removal(snapshot, r) for d in unreachable if (r := grammar.rule(d.rule or "")) is not None
            ]
            actions.append(
                _action(
                    snapshot,
                    f"Remove all {len(spans)} unreachable rules",
                    [(span, "") for span in _disjoint(spans)],
                    QUICK_FIX,
                )
            )
        return actions
    if code == "GG401":
        name = text[found.span.start + 1 : found.span.end]
        nearest = get_close_matches(name, list(ANNOTATIONS), n=1, cutoff=0.6)
        return [
            _action(snapshot, f"Replace with @{n}", [(found.span, f"@{n}")], QUICK_FIX, found, True)
            for n in nearest
        ]
    if code == "GG502":
        joint = next((j for j in grammar.joints if j.span == found.span), None)
        if joint is None:
            return []
        annotation = next(a for a in grammar.annotations if a.span == joint.span)
        argument = next((a for a in annotation.positional()), None)
        names = [j.name for _, j in joints_of(grammar.backend)]
        nearest = get_close_matches(joint.joint, names, n=1, cutoff=0.5)
        if argument is None:
            return []
        return [
            _action(snapshot, f"Replace with {n}", [(argument.span, n)], QUICK_FIX, found, True)
            for n in nearest
        ]
    return []


def _line_end(text: str, offset: int) -> int:
    end = text.find("\n", offset)
    return len(text) if end == -1 else end


def _removal(snapshot: Snapshot, rule: Rule) -> Span:
    """The rule, its annotations, and its lines if nothing else is on them."""
    text = snapshot.text
    start = min([rule.span.start, *(a.span.start for a in rule.annotations)])
    line_start = text.rfind("\n", 0, start) + 1
    if not text[line_start:start].strip():
        start = line_start
    end = rule.span.end
    line_end = _line_end(text, end)
    rest = text[end:line_end]
    if not rest.strip() or rest.lstrip().startswith("#"):
        end = min(line_end + 1, len(text))
    else:  # another item follows on the same line
        end += len(rest) - len(rest.lstrip())
    return Span(start, end)


def _disjoint(spans: list[Span]) -> list[Span]:
    merged: list[Span] = []
    for span in sorted(spans, key=lambda s: s.start):
        if merged and span.start <= merged[-1].end:
            merged[-1] = Span(merged[-1].start, max(merged[-1].end, span.end))
        else:
            merged.append(span)
    return merged


# ---- value lists and typed ranges -----------------------------------------------------------


def _number_text(alternative: Alternative) -> str | None:
    if len(alternative.symbols) == 1 and isinstance(alternative.symbols[0], Terminal):
        value = alternative.symbols[0].text
        if _NUMBER.fullmatch(value):
            return value
    return None


def range_for(values: list[str]) -> str | None:
    """The typed range whose values are exactly ``values``, in order, if there is one."""
    if len(values) < 3:
        return None
    try:
        numbers = [Decimal(v) for v in values]
    except InvalidOperation:
        return None
    step = numbers[1] - numbers[0]
    if step <= 0 or any(b - a != step for a, b in pairwise(numbers)):
        return None
    low, high, step_text = (_plain(n) for n in (numbers[0], numbers[-1], step))
    integral = all("." not in v for v in values)
    if integral:
        spec = f"int[{low}..{high}]" if step == 1 else f"int[{low}..{high} step {step_text}]"
    else:
        spec = f"float[{low}..{high} step {step_text}]"
    parsed, problems = parse_range(spec)
    if parsed is None or problems or list(parsed.values) != values:
        return None  # e.g. 0.50 is written where the range would derive 0.5
    return spec


def _plain(number: Decimal) -> str:
    text = format(number.normalize(), "f")
    return "0" if text in ("-0", "") else text


def _runs(rule: Rule) -> list[tuple[int, int]]:
    """Maximal runs [i, j) of consecutive alternatives that are plain numbers."""
    runs, i = [], 0
    alternatives = rule.alternatives
    while i < len(alternatives):
        if _number_text(alternatives[i]) is None:
            i += 1
            continue
        j = i
        while j < len(alternatives) and _number_text(alternatives[j]) is not None:
            j += 1
        runs.append((i, j))
        i = j
    return runs


def _collapse(snapshot: Snapshot, rule: Rule) -> list[types.CodeAction]:
    text = snapshot.text
    actions = []
    for i, j in _runs(rule):
        alternatives = rule.alternatives[i:j]
        span = Span(alternatives[0].span.start, alternatives[-1].span.end)
        between = [text[a.span.end : b.span.start] for a, b in pairwise(alternatives)]
        if any(gap.strip() != "|" for gap in between):  # comments in between would be lost
            continue
        spec = range_for([_number_text(a) or "" for a in alternatives])
        if spec is not None:
            actions.append(
                _action(snapshot, f"Collapse {len(alternatives)} values into {spec}", [(span, spec)], REWRITE)
            )
    return actions


def _expand(snapshot: Snapshot, rule: Rule) -> list[types.CodeAction]:
    actions = []
    for alternative in rule.alternatives:
        spec = alternative.range_values
        if spec is None:
            continue
        if spec.size <= MAX_EXPANDED:
            actions.append(
                _action(
                    snapshot,
                    f"Expand {spec.text} into its {spec.size} values",
                    [(alternative.span, " | ".join(spec.values))],
                    REWRITE,
                )
            )
    return actions
