"""Typed ranges: the values behind ``int[5..8]``, ``float[0..20 step 0.25]`` and friends.

A range's syntax is the grammar's (``range_spec`` and the ``RANGE`` token of ``gaitgram.lark``);
:func:`parse_range` reads it with the parser generated from that grammar and works out its
values. Numbers are read exactly as written (:mod:`~gaitgram.language.numbers`), and values are
computed from them in exact arithmetic, so ``float[0..20 step 0.25]`` derives exactly the texts
``0 0.25 0.5 ... 20`` a user would have written out, and a range and its written-out list map
every genome to the same phenotype. A range whose values would collapse, or that would need
more digits than a double holds, is an error, never a list with duplicates.

The problems a range can have are declared here, each with what to do about it and what its
fix does, and reported by :func:`parse_range` as :class:`RangeProblem` s that the builder turns
into diagnostics.
"""

from __future__ import annotations

import re
import threading
from bisect import bisect_left
from dataclasses import dataclass, replace
from decimal import Decimal, Inexact, Rounded, localcontext
from fractions import Fraction
from functools import cache
from itertools import pairwise

from lark import Token, Tree
from lark.exceptions import LarkError, UnexpectedCharacters, UnexpectedEOF, UnexpectedToken

from gaitgram.language.diagnostics import Applicability, Code, Severity
from gaitgram.language.model import RangeKind, RangeSpec
from gaitgram.language.numbers import (
    MAGNITUDE_TEXT,
    MAX_DECIMALS,
    MAX_DIGITS,
    MAX_MAGNITUDE,
    NUMBER_LIMITS,
    compact,
    decimal_places,
    exact_int,
    in_units,
    int_digits,
    number_problem,
    plain,
    read_number,
    units_text,
    written_decimals,
)
from gaitgram.language.parser import range_parser, terminal
from gaitgram.language.source import SourceText

__all__ = [
    "CODES",
    "MAX_GRAMMAR_RANGE_VALUES",
    "MAX_RANGE_VALUES",
    "OpenRanges",
    "RangeEdit",
    "RangeFix",
    "RangeProblem",
    "apply_range_edits",
    "over_budget_problem",
    "parse_range",
    "range_reads",
    "range_token",
]

#: A range larger than this is almost certainly a typo, and would cost memory.
MAX_RANGE_VALUES = 100_000
#: The values all of a grammar's typed ranges may hold together (one range's for each place it
#: is written). Each value is a string in the model and a choice in the analyses, so without a
#: bound a few hundred bytes of large ranges would take gigabytes and minutes; the bundled
#: grammars hold about 1,500.
MAX_GRAMMAR_RANGE_VALUES = 1_000_000

#: Extra decimals for ``count`` ranges, whose step rarely terminates.
COUNT_EXTRA_DECIMALS = 2

E, W = Severity.ERROR, Severity.WARNING
SAFE, UNSAFE = Applicability.SAFE, Applicability.UNSAFE

MALFORMED_RANGE = Code(
    "GG104",
    "malformed-range",
    E,
    "a typed range that does not parse",
    "A typed range is int[LO..HI], int[LO..HI step S], float[LO..HI step S], float[LO..HI count N] "
    "or float[X ± P% count N]; a float range needs a step or a count. A range left unclosed before a | "
    "reads as one malformed range up to the next ]; the fix closes it before the |.",
    syntax=True,
    fix=SAFE,
    fix_help="Closes a range left open before a `|` (`int[1..5 | int[7..9]`), when both ranges then read "
    "without errors and only plain text follows the `|`.",
)
EMPTY_RANGE = Code(
    "GG301",
    "empty-range",
    E,
    "a typed range with no values",
    "The lower bound of a typed range is above its upper bound. Swap the bounds.",
    fix=UNSAFE,
    fix_help="Swaps the bounds, when the range then reads without errors.",
)
BAD_STEP = Code(
    "GG302",
    "bad-range-step",
    E,
    "a typed range whose step or count is not positive",
    "A step must be positive, a count a whole number of at least 1, a percentage not negative.",
)
OFF_GRID = Code(
    "GG303",
    "range-off-grid",
    W,
    "a range bound that is not on its step grid",
    "The upper bound is not a whole number of steps above the lower one, so the last value is "
    "below it. Make the upper bound the last value (the values stay the same), or change the step.",
    fix=SAFE,
    fix_help="Makes the upper bound the last value: the range derives exactly the same values.",
)
TOO_LARGE = Code(
    "GG304",
    "range-too-large",
    E,
    "a typed range with too many values",
    "A typed range has more than 100,000 values, or takes a grammar's typed ranges past 1,000,000 values "
    "in all (counted where each is written). Use a coarser step or a smaller count, or write a range "
    "used in many places once, in a rule of its own.",
)
KIND_MISMATCH = Code(
    "GG305",
    "range-kind-mismatch",
    E,
    "an int range with fractional bounds or step",
    "An int range has whole bounds and steps, and no count. Use float[...] for fractional values or a count.",
    fix=UNSAFE,
    fix_help="Makes it a float range, when that reads without errors.",
)
VALUES_COLLAPSE = Code(
    "GG306",
    "range-values-collapse",
    E,
    "a typed range whose values would not all be distinct",
    "The values of the range would round to the same text, so some choices would be equal. Use "
    "a smaller count or bounds further apart.",
)
UNREPRESENTABLE_NUMBER = Code(
    "GG307",
    "unrepresentable-range-number",
    E,
    "a range number or value a double cannot hold exactly",
    "Numbers in ranges are within ±1e12 with at most 15 significant digits and 15 decimals, so a "
    "double holds each value exactly. Write fewer digits.",
)
COUNT_TOO_SMALL = Code(
    "GG308",
    "range-count-too-small",
    E,
    "count 1 over a range whose two ends differ",
    "A count range includes both ends, so count 1 cannot cover two different ends. Use count 2 "
    "or more, or write the one value itself.",
)

CODES = (
    MALFORMED_RANGE,
    EMPTY_RANGE,
    BAD_STEP,
    OFF_GRID,
    TOO_LARGE,
    KIND_MISMATCH,
    VALUES_COLLAPSE,
    UNREPRESENTABLE_NUMBER,
    COUNT_TOO_SMALL,
)


@dataclass(frozen=True, slots=True)
class RangeEdit:
    """Replace ``length`` characters at ``offset`` of a range's text with ``text``."""

    offset: int
    length: int
    text: str


@dataclass(frozen=True, slots=True)
class RangeFix:
    """A fix inside a range's text: the builder turns it into a :class:`~gaitgram.language.diagnostics.Fix`.

    Only made when the fixed range reads without errors (:func:`_fixed`), so applying it
    never trades one error for another.
    """

    title: str
    edits: tuple[RangeEdit, ...]
    safe: bool = False


@dataclass(frozen=True, slots=True)
class RangeProblem:
    """What is wrong with a range: a diagnostic code, a message, a hint, and where.

    ``offset`` and ``length`` locate the problem inside the range text.
    """

    code: Code
    message: str
    hint: str | None = None
    offset: int = 0
    length: int | None = None
    fix: RangeFix | None = None
    #: Refused for the values its grammar has left (:data:`MAX_GRAMMAR_RANGE_VALUES`), not for
    #: itself: read alone, it may be fine.
    over_budget: bool = False


# ---- ranges --------------------------------------------------------------------------------


#: Ranges read lately, by text: a grammar repeats its ranges (one per joint and term), and an
#: editor re-reads them at every keystroke. Only small ones are kept, so memory stays small.
_RECENT: dict[str, tuple[RangeSpec | None, tuple[RangeProblem, ...]]] = {}
_RECENT_SIZE = 512
_RECENT_VALUES = 1_000
_RECENT_LOCK = threading.Lock()  # the language server reads documents on worker threads


class _OverBudget(Exception):
    """A range with more values than its grammar has left (``budget``): it is not made."""

    def __init__(self, size: int) -> None:
        self.size = size


def parse_range(text: str, budget: int = MAX_RANGE_VALUES) -> tuple[RangeSpec | None, list[RangeProblem]]:
    """Read a range's text. Returns the spec (None if unusable) and its problems. A range of more
    than ``budget`` values (what its grammar has left of :data:`MAX_GRAMMAR_RANGE_VALUES`) is
    refused before its values are made."""
    found = _RECENT.get(text)
    if found is not None and found[0] is not None and found[0].size > budget:
        return None, [over_budget_problem(text, found[0].size)]
    if found is None:
        try:
            spec, problems = _read_range(text, budget)
        except _OverBudget as over:
            return None, [over_budget_problem(text, over.size)]
        found = spec, tuple(problems)
        if spec is None or spec.size <= _RECENT_VALUES:
            with _RECENT_LOCK:
                if len(_RECENT) >= _RECENT_SIZE:
                    del _RECENT[next(iter(_RECENT))]  # the oldest
                _RECENT[text] = found
    return found[0], list(found[1])


def _read_range(text: str, budget: int = MAX_RANGE_VALUES) -> tuple[RangeSpec | None, list[RangeProblem]]:
    try:
        tree = range_parser().parse(text)
    except (UnexpectedCharacters, UnexpectedToken, UnexpectedEOF) as exc:
        return None, [_syntax_problem(text, exc)]
    except LarkError as exc:  # pragma: no cover - defensive: lark's other errors
        return None, [RangeProblem(MALFORMED_RANGE, f"malformed range: {exc}")]
    return _evaluate(text, tree, budget)


_RANGE_FORMS = "write int[LO..HI], float[LO..HI step S], float[LO..HI count N] or float[X ± P% count N]"


def _syntax_problem(text: str, exc: LarkError) -> RangeProblem:
    position = getattr(exc, "pos_in_stream", None)
    if isinstance(exc, UnexpectedToken) and exc.token.type == "$END":
        position = len(text)
    if position is None:
        position = len(text) - 1
    found = text[position : position + 1] or "the end"
    return RangeProblem(
        MALFORMED_RANGE,
        f"malformed range {text!r}: unexpected {found!r}",
        _RANGE_FORMS,
        offset=position,
        length=1,
        fix=_unclosed(text, position) if found == "|" else None,
    )


def _unclosed(text: str, position: int) -> RangeFix | None:
    """``int[1..5 | int[7..9]`` is one bracketed token, so one malformed range; the first range
    was evidently meant to end before the ``|``. The fix closes it there, if that reads, and if
    what follows the ``|`` is plain text and ranges that read too (so no new error appears)."""
    before, after = text[:position].rstrip(), text[position + 1 :]
    if not _PLAIN_REST.fullmatch(after) or not range_reads(before + "]"):
        return None
    if not all(range_reads(match.group()) for match in range_token().finditer(after)):
        return None
    return RangeFix(f"Close the range before the |: {before}]", (RangeEdit(len(before), 0, "]"),), safe=True)


#: What may follow the ``|`` for :func:`_unclosed`: no strings, rules, comments or escapes.
_PLAIN_REST = re.compile(r"[^'\"<#\\]*")


def _evaluate(
    text: str, tree: Tree, budget: int = MAX_RANGE_VALUES
) -> tuple[RangeSpec | None, list[RangeProblem]]:
    kind = RangeKind(str(tree.children[0]))
    bounds = next(c for c in tree.children if isinstance(c, Tree) and c.data in ("interval", "relative"))
    option = next((c for c in tree.children if isinstance(c, Tree) and c.data.endswith("_option")), None)
    numbers = [t for t in bounds.children if isinstance(t, Token) and t.type == "RANGE_NUMBER"]
    option_token: Token | None = option.children[1] if option is not None else None
    by_count = option is not None and option.data == "count_option"

    # Every number is read exactly, and must be one a value can be (a count is checked below).
    for token in (*numbers, *([] if by_count or option_token is None else [option_token])):
        reason = number_problem(read_number(str(token)))
        if reason is not None:
            return None, [
                _at(
                    text,
                    token,
                    UNREPRESENTABLE_NUMBER,
                    f"{token} in {text!r} {reason}",
                    NUMBER_LIMITS,
                    where=False,
                )
            ]

    # Checked, so each has at most 15 digits; compact, so calculations with them are exact
    # and cheap (``1.000…0`` with a thousand zeros, or ``0e-400``, is written exactly but
    # would round in a decimal context, or cost a thousand-digit fraction).
    first, second = (compact(read_number(str(token))) for token in numbers)
    center: Decimal | None = None
    if bounds.data == "interval":
        low, high = first, second
        if low > high:
            return None, [
                RangeProblem(
                    EMPTY_RANGE,
                    f"empty range {text!r}: the lower bound {numbers[0]} is above the upper bound "
                    f"{numbers[1]}",
                    "swap the bounds",
                    fix=_fixed(
                        text,
                        "Swap the bounds",
                        (_replace(numbers[0], str(numbers[1])), _replace(numbers[1], str(numbers[0]))),
                    ),
                )
            ]
    else:
        center, percent = first, second
        if percent < 0:
            return None, [_at(text, numbers[1], BAD_STEP, "a relative range needs a non-negative percentage")]
        with localcontext() as context:
            context.prec = 100  # exact: both numbers are compact, with at most 15 digits
            context.traps[Inexact] = context.traps[Rounded] = True
            delta = center.copy_abs() * percent / 100
            low, high = center - delta, center + delta
        if high.copy_abs() > MAX_MAGNITUDE or low.copy_abs() > MAX_MAGNITUDE:
            return None, [
                _at(
                    text,
                    numbers[1],
                    UNREPRESENTABLE_NUMBER,
                    f"{numbers[0]} ± {numbers[1]}% in {text!r} reaches {plain(low)}..{plain(high)}, "
                    f"beyond ±{MAGNITUDE_TEXT}",
                    "use a smaller percentage",
                    where=False,
                )
            ]

    step: Decimal | None = None
    count: int | None = None
    if option is not None:
        assert option_token is not None
        value = compact(read_number(str(option_token)))
        if option.data == "step_option":
            if value <= 0:
                return None, [
                    _at(text, option_token, BAD_STEP, f"the step must be positive, not {option_token}")
                ]
            step = value
        else:
            if decimal_places(value) == 0 and value > MAX_RANGE_VALUES:
                shown = f"{int(value):,}" if value.adjusted() < MAX_DIGITS else str(option_token)
                return None, [_too_large(text, None, shown)]
            whole = exact_int(value)
            if whole is None or whole < 1:
                return None, [
                    _at(
                        text,
                        option_token,
                        BAD_STEP,
                        f"the count must be a whole number ≥ 1, not {option_token}",
                    )
                ]
            count = whole

    def to_float() -> RangeFix | None:
        return _fixed(text, "Make it a float range", (_replace(tree.children[0], "float"),))

    if kind is RangeKind.INT:
        if count is not None:
            problem = _at(
                text,
                option.children[0],  # type: ignore[union-attr]
                KIND_MISMATCH,
                "an int range takes a step, not a count",
                hint="use float[... count N], or int[LO..HI step S]",
            )
            return None, [replace(problem, fix=to_float())]
        step = step if step is not None else Decimal(1)
        written = (low, high) if center is None else (center,)
        if any(decimal_places(x) for x in (*written, step)):
            what = "fractional bounds or step" if center is None else "a fractional centre or step"
            return None, [
                RangeProblem(
                    KIND_MISMATCH,
                    f"int range {text!r} has {what}",
                    "use float[...] for fractional values",
                    fix=to_float(),
                )
            ]
    elif step is None and count is None:
        return None, [
            RangeProblem(
                MALFORMED_RANGE,
                f"float range {text!r} needs a step or a count",
                f"for example {text[:-1]} step 0.1] or {text[:-1]} count 11]",
                offset=len(text) - 1,
                length=1,
            )
        ]

    problems: list[RangeProblem] = []
    if count is not None:
        if count > budget:
            raise _OverBudget(count)
        written = [written_decimals(read_number(str(n))) for n in numbers]
        decimals = (
            max(written[0], decimal_places(low), decimal_places(high)) if center is not None else max(written)
        )
        values = _count_values(text, low, high, count, decimals, center is None, problems)
    else:
        assert step is not None
        values = _step_values(text, low, high, center, step, problems, numbers[-1], budget)
    if values is None:
        return None, problems
    return RangeSpec(kind, canonical_text(kind, bounds.data, numbers, option), tuple(values)), problems


def _step_values(
    text: str,
    low: Decimal,
    high: Decimal,
    center: Decimal | None,
    step: Decimal,
    problems: list[RangeProblem],
    high_token: Token | None = None,
    budget: int = MAX_RANGE_VALUES,
) -> list[str] | None:
    """``low, low+step, ...`` up to ``high``; or, centred, ``center ± k·step`` within the bounds.

    Exact: every value has the decimals of the origin or the step, whichever has more.
    """
    origin = low if center is None else center
    places = max(decimal_places(origin), decimal_places(step))
    if center is None:
        size = int((Fraction(high) - Fraction(low)) // Fraction(step)) + 1
        first = 0
    else:
        k = int((Fraction(high) - Fraction(center)) // Fraction(step))
        size, first = 2 * k + 1, -k
    if size > MAX_RANGE_VALUES:
        problems.append(_too_large(text, size))
        return None
    if size > budget:
        raise _OverBudget(size)
    start, stride = in_units(origin, places), in_units(step, places)
    units = [start + stride * i for i in range(first, first + size)]
    if center is None and Fraction(units[-1], 10**places) != Fraction(high):
        last = units_text(units[-1], places)
        problems.append(
            RangeProblem(
                OFF_GRID,
                f"the upper bound {plain(high)} of {text!r} is not on the step grid; "
                f"the last value is {last}",
                "make the bounds differ by a whole number of steps",
                fix=None
                if high_token is None
                else _fixed(
                    text,
                    f"Make the upper bound {last}",
                    (_replace(high_token, last),),
                    same_values=[units_text(u, places) for u in units],
                ),
            )
        )
    if int_digits(max(low.copy_abs(), high.copy_abs())) + places > MAX_DIGITS:
        for unit in units:
            digits = len(str(abs(unit)).rstrip("0"))
            if digits > MAX_DIGITS:
                problems.append(
                    RangeProblem(
                        UNREPRESENTABLE_NUMBER,
                        f"{text!r} derives {units_text(unit, places)}, which has {digits} significant "
                        f"digits; a double holds {MAX_DIGITS}",
                        "write the bounds and the step with fewer decimals",
                    )
                )
                return None
    return [units_text(u, places) for u in units]


def _count_values(
    text: str,
    low: Decimal,
    high: Decimal,
    count: int,
    decimals: int,
    written_bounds: bool,
    problems: list[RangeProblem],
) -> list[str] | None:
    """``count`` evenly spaced values from ``low`` to ``high``, both included, rounded (half to
    even) to two more decimals than the bounds are written with, or to as many more as keep
    them apart, within the limits a double holds exactly."""
    if low == high:
        if count == 1:
            return [plain(low)]
        problems.append(
            RangeProblem(
                VALUES_COLLAPSE,
                f"the bounds of {text!r} are both {plain(low)}, so its {count} values would all be equal",
                f"write {plain(low)} itself, or make the bounds differ",
            )
        )
        return None
    if count == 1:
        problems.append(
            RangeProblem(
                COUNT_TOO_SMALL,
                f"{text!r} asks for one value, but a count range includes both ends, "
                f"{plain(low)} and {plain(high)}",
                "use count 2 or more, or write the one value itself",
            )
        )
        return None

    widest = max(low.copy_abs(), high.copy_abs())
    most = min(MAX_DECIMALS, MAX_DIGITS - int_digits(widest))
    exact = max(decimal_places(low), decimal_places(high))
    if written_bounds and exact > most:
        problems.append(
            RangeProblem(
                UNREPRESENTABLE_NUMBER,
                f"the values of {text!r} would need {int_digits(widest) + exact} significant digits "
                f"to include both bounds; a double holds {MAX_DIGITS}",
                "write the bounds with fewer decimals",
            )
        )
        return None

    # value i = (lo·(n-1) + (hi-lo)·i) / ((n-1)·10**scale), in integers: exact, then rounded once.
    scale = exact
    lo, hi = in_units(low, scale), in_units(high, scale)
    gaps = count - 1
    width, denominator = hi - lo, gaps * 10**scale
    places = min(decimals + COUNT_EXTRA_DECIMALS, most)
    # Three neighbours closer than one unit of the last place cannot round to three numbers.
    while places <= most and count >= 3 and 2 * width * 10**places < denominator:
        places += 1
    while places <= most:
        units = _rounded(lo * gaps, width, gaps, denominator, 10**places)
        if all(a != b for a, b in pairwise(units)):
            return [units_text(u, places) for u in units]
        places += 1
    apart = float(Fraction(width, denominator))
    problems.append(
        RangeProblem(
            VALUES_COLLAPSE,
            f"the {count:,} values of {text!r} are {apart:.3g} apart: closer than the "
            f"{most} decimals a value keeps here, so some would be equal",
            "use a smaller count, or bounds further apart",
        )
    )
    return None


def _rounded(base: int, width: int, gaps: int, denominator: int, factor: int) -> list[int]:
    """Round ``(base + width·i)·factor / denominator`` half to even, for i in 0..gaps."""
    units = []
    for i in range(gaps + 1):
        quotient, remainder = divmod((base + width * i) * factor, denominator)
        twice = 2 * remainder
        if twice > denominator or (twice == denominator and quotient & 1):
            quotient += 1
        units.append(quotient)
    return units


def canonical_text(kind: RangeKind, form: str, numbers: list[Token], option: Tree | None) -> str:
    a, b = (str(n) for n in numbers)
    inner = f"{a}..{b}" if form == "interval" else f"{a} ± {b}%"
    if option is not None:
        inner += f" {option.children[0]} {option.children[1]}"
    return f"{kind}[{inner}]"


def _replace(token: Token, text: str) -> RangeEdit:
    return RangeEdit(token.start_pos or 0, len(token), text)


def _fixed(
    text: str, title: str, edits: tuple[RangeEdit, ...], *, same_values: list[str] | None = None
) -> RangeFix | None:
    """The fix, if the range it makes reads without errors (else None: it would not fix it).

    With ``same_values``, a fix whose range derives exactly those values, which keeps every
    phenotype, so it is safe; else None. Titled with the fixed range, to show the result.
    """
    fixed = apply_range_edits(text, edits)
    spec, problems = parse_range(fixed)
    if spec is None or any(p.code.severity is Severity.ERROR for p in problems):
        return None
    if same_values is not None and list(spec.values) != same_values:
        return None
    return RangeFix(f"{title}: {fixed}", edits, safe=same_values is not None)


def apply_range_edits(text: str, edits: tuple[RangeEdit, ...]) -> str:
    for edit in sorted(edits, key=lambda e: e.offset, reverse=True):
        text = text[: edit.offset] + edit.text + text[edit.offset + edit.length :]
    return text


def _at(
    text: str, token: Token, code: Code, message: str, hint: str | None = None, *, where: bool = True
) -> RangeProblem:
    """A problem located at ``token``; ``where``: the message says which range."""
    start = token.start_pos or 0
    shown = f"{message} in {text!r}" if where else message
    return RangeProblem(code, shown, hint, offset=start, length=len(token))


def _too_large(text: str, size: int | None, shown: str | None = None) -> RangeProblem:
    if shown is None:
        shown = f"{size:,}" if size is not None and size < 10**15 else f"about {float(size or 0):.1e}"
    return RangeProblem(
        TOO_LARGE,
        f"range {text!r} has {shown} values; at most {MAX_RANGE_VALUES:,} are allowed",
        "use a coarser step or a smaller count",
    )


def over_budget_problem(text: str, size: int) -> RangeProblem:
    """A range (or a ``GE_RANGE``) of ``size`` values, more than its grammar has left."""
    return RangeProblem(
        TOO_LARGE,
        f"range {text!r} has {size:,} values, more than the grammar's typed ranges have left: "
        f"they may hold {MAX_GRAMMAR_RANGE_VALUES:,} in all, counted where each is written",
        "use coarser steps or smaller counts, or write a range once in a rule of its own",
        over_budget=True,
    )


# ---- the range syntax of the grammar ----------------------------------------------------------


def range_token() -> re.Pattern[str]:
    """The scanner's ``RANGE`` token: the bracketed shape that makes text a range."""
    return terminal("RANGE")


_CLOSING = re.compile(r"\]")


@cache
def _range_opening() -> re.Pattern[str]:
    """A range's kind and ``[``: where a range may start."""
    return re.compile(rf"(?:{terminal('RANGE_KIND').pattern})\[")


class OpenRanges:
    """Whether an ``int[``/``float[`` is left open before an offset, for many offsets of one
    text: else a ``]`` that a fix writes could close that one instead, and swallow everything
    in between. Every ``]`` and every opening are found once, on the first question, so a line
    of thousands of malformed ranges costs a search per range, not a read of the line."""

    def __init__(self, source: SourceText) -> None:
        self.source = source
        self._closings: list[int] | None = None
        self._openings: list[tuple[int, int]] = []

    def none_before(self, start: int) -> bool:
        """Whether no opening before ``start`` on its line lacks a ``]`` after it (up to ``start``)."""
        text = self.source.text
        if self._closings is None:
            self._openings = [(m.start(), m.end()) for m in _range_opening().finditer(text)]
            self._closings = [m.start() for m in _CLOSING.finditer(text)]
        line_start = self.source.line_start_of(start)
        last = bisect_left(self._closings, start) - 1  # the last ] before start
        after = max(line_start, self._closings[last] + 1 if last >= 0 else 0)
        first = bisect_left(self._openings, (after, after))
        return first == len(self._openings) or self._openings[first][1] > start


def range_reads(text: str) -> bool:
    """Whether a range's text reads without errors."""
    spec, problems = parse_range(text)
    return spec is not None and not any(p.code.severity is Severity.ERROR for p in problems)
