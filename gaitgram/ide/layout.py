"""What an editor draws beside the text: inlay hints and folding regions.

Inlay hints go after each rule's name: how many choices it has and whether it reads a codon.
In lazy mode (the default, GEVA's) a rule with one choice reads no codon; in eager mode
(PonyGE2's) every expansion reads one. A typed range inside a longer alternative is an
anonymous choice of its own, so it gets a hint too. Folding regions are rules that span
lines, and runs of comment lines.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from enum import StrEnum

from gaitgram.analysis import CheckResult
from gaitgram.language.model import Grammar, RangeSymbol

__all__ = ["Fold", "FoldKind", "InlayHint", "choices_label", "folds", "inlay_hints"]

CHOICE_TOOLTIP = "each choice is one alternative, or one value of a typed range that is one"


@dataclass(frozen=True, slots=True)
class InlayHint:
    offset: int  # shown here, after the text before it
    label: str
    tooltip: str | None = None


def choices_label(choices: int) -> str:
    if choices == 1:
        return "1 choice, no codon (lazy)"
    return f"{choices:,} choices, 1 codon"


def inlay_hints(result: CheckResult, start: int, end: int) -> list[InlayHint]:
    """Hints for the rules that overlap ``[start, end]``."""
    grammar = result.grammar
    hints = []
    for rule in grammar.rules:
        if rule.span.end < start:
            continue
        if rule.span.start > end:
            break
        facts = result.facts.rule(rule.name)
        if facts is not None and grammar.rule(rule.name) is rule and rule.alternatives:
            hints.append(InlayHint(rule.name_span.end, choices_label(facts.choices), CHOICE_TOOLTIP))
        for alternative in rule.alternatives:
            if alternative.range_values is not None:
                continue
            for symbol in alternative.symbols:
                if isinstance(symbol, RangeSymbol):
                    hints.append(InlayHint(rule.span_of(symbol).end, f"{symbol.spec.size:,} values, 1 codon"))
    return hints


class FoldKind(StrEnum):
    RULE = "rule"
    COMMENT = "comment"


@dataclass(frozen=True, slots=True)
class Fold:
    first_line: int  # 0-based
    last_line: int
    kind: FoldKind


_COMMENT_LINE = re.compile(r"^[^\S\n]*#", re.MULTILINE)


def folds(grammar: Grammar) -> list[Fold]:
    source = grammar.source
    found = []
    for rule in grammar.rules:
        first, last = source.location(rule.span.start).line - 1, source.location(rule.span.end).line - 1
        if last > first:
            found.append(Fold(first, last, FoldKind.RULE))
    run_start = previous = -2
    for match in _COMMENT_LINE.finditer(source.text):
        line = source.location(match.start()).line - 1
        if line != previous + 1:
            if previous > run_start >= 0:
                found.append(Fold(run_start, previous, FoldKind.COMMENT))
            run_start = line
        previous = line
    if previous > run_start >= 0:
        found.append(Fold(run_start, previous, FoldKind.COMMENT))
    return sorted(found, key=lambda f: f.first_line)
