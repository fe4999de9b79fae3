"""Rewrites of a rule that keep its meaning exactly, as :class:`~gaitgram.language.diagnostics.Fix` data:
the editor's refactorings, made by the library so that any front end offers the same ones.

* collapse a written-out list of evenly spaced numbers (``0 | 0.25 | 0.5 | ... | 2``) into the
  typed range that derives exactly the same texts in the same order (``float[0..2 step 0.25]``),
  so every genome keeps its phenotype;
* expand a typed range that is a whole alternative back into its values.
"""

from __future__ import annotations

from decimal import Decimal, InvalidOperation
from itertools import pairwise

from gaitgram.language.diagnostics import Applicability, Fix, TextEdit
from gaitgram.language.model import Alternative, Rule, Terminal
from gaitgram.language.parser import terminal
from gaitgram.language.ranges import parse_range
from gaitgram.language.source import SourceText, Span

__all__ = ["MAX_EXPANDED", "collapses", "expansions", "range_for", "rewrites"]

#: A typed range is expanded only up to this many values.
MAX_EXPANDED = 200


def rewrites(source: SourceText, rule: Rule) -> list[Fix]:
    """Every rewrite of ``rule``: collapses of its number lists, then expansions of its ranges."""
    return collapses(source, rule) + expansions(rule)


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


def collapses(source: SourceText, rule: Rule) -> list[Fix]:
    """Each maximal run of plain-number alternatives that is exactly a typed range's values."""
    text = source.text
    found = []
    for i, j in _runs(rule):
        alternatives = rule.alternatives[i:j]
        spans = [rule.span_of(a) for a in alternatives]
        span = Span(spans[0].start, spans[-1].end)
        between = [text[a.end : b.start] for a, b in pairwise(spans)]
        if any(gap.strip() != "|" for gap in between):  # comments in between would be lost
            continue
        spec = range_for([_number_text(a) or "" for a in alternatives])
        if spec is not None:
            title = f"Collapse {len(alternatives)} values into {spec}"
            found.append(Fix(title, (TextEdit(span, spec),), Applicability.SAFE))
    return found


def expansions(rule: Rule) -> list[Fix]:
    """Each typed range that is a whole alternative, with at most :data:`MAX_EXPANDED` values."""
    found = []
    for alternative in rule.alternatives:
        spec = alternative.range_values
        if spec is not None and spec.size <= MAX_EXPANDED:
            title = f"Expand {spec.text} into its {spec.size} values"
            values = TextEdit(rule.span_of(alternative), " | ".join(spec.values))
            found.append(Fix(title, (values,), Applicability.SAFE))
    return found


def _number_text(alternative: Alternative) -> str | None:
    if len(alternative.symbols) == 1 and isinstance(alternative.symbols[0], Terminal):
        value = alternative.symbols[0].text
        # A plain decimal: a number of the grammar without an exponent.
        if "e" not in value.lower() and terminal("RANGE_NUMBER").fullmatch(value):
            return value
    return None


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
