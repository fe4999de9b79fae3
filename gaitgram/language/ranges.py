"""Typed ranges: the values behind ``int[5..8]``, ``float[0..20 step 0.25]`` and friends.

Numbers are read exactly as written: ``2.5e-1`` is the decimal 0.25, ``1.50`` is
1.5 written to two decimals. Values are computed from them in exact arithmetic,
so ``float[0..20 step 0.25]`` derives exactly the texts ``0 0.25 0.5 ... 20``
a user would have written out, and a range and its written-out list map every
genome to the same phenotype.

A value means the number it prints: every number in a range, and every value
it derives, is within ±:data:`MAX_MAGNITUDE` and has at most
:data:`MAX_DIGITS` significant digits and :data:`MAX_DECIMALS` decimals. A
double holds such a decimal exactly (it reads back unchanged), so distinct
values stay distinct when a gait is evaluated. A range whose values would
collapse, or that would need more, is an error, never a list with duplicates.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from decimal import Decimal, Inexact, Rounded, localcontext
from fractions import Fraction
from itertools import pairwise

from lark import Token, Tree
from lark.exceptions import LarkError, UnexpectedCharacters, UnexpectedEOF, UnexpectedToken

from gaitgram.diagnostics import CODES, Severity
from gaitgram.language.model import RangeKind, RangeSpec
from gaitgram.language.parser import range_parser

#: A range larger than this is almost certainly a typo, and would cost memory.
MAX_RANGE_VALUES = 100_000

#: Larger numbers are a typo; they would also make enormous value texts.
MAX_MAGNITUDE = Decimal("1e12")
_MAGNITUDE = "1e12"

#: Significant digits a double holds exactly (C's ``DBL_DIG``): a decimal with no more
#: reads back from a double unchanged.
MAX_DIGITS = 15

#: Decimals a value may have: below 1e-15 a joint angle or a frequency means nothing.
MAX_DECIMALS = 15

#: Extra decimals for ``count`` ranges, whose step rarely terminates.
COUNT_EXTRA_DECIMALS = 2

NUMBER_LIMITS = (
    f"numbers are within ±{_MAGNITUDE}, with at most {MAX_DIGITS} significant digits "
    f"and {MAX_DECIMALS} decimals"
)


@dataclass(frozen=True, slots=True)
class RangeEdit:
    """Replace ``length`` characters at ``offset`` of a range's text with ``text``."""

    offset: int
    length: int
    text: str


@dataclass(frozen=True, slots=True)
class RangeFix:
    """A fix inside a range's text: the builder turns it into a :class:`~gaitgram.diagnostics.Fix`.

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

    code: str
    message: str
    hint: str | None = None
    offset: int = 0
    length: int | None = None
    fix: RangeFix | None = None


# ---- numbers -------------------------------------------------------------------------------
#
# Everything here works on a Decimal's digits and exponent, never through a decimal
# context: ``1e999999999`` and ``1e-999999999`` are read, measured and refused, not
# rounded, overflowed or turned into a billion-digit integer.


_EXPONENT = re.compile(r"[eE]([+-]?)0*(\d*)$")

#: Exponents are clamped to this (far beyond every limit, within what a Decimal can hold).
_EXTREME_EXPONENT = 10**15


def read_number(text: str) -> Decimal:
    """The exact value of a number's text: ``2.5e-1`` is 0.25 (written to two decimals).

    An exponent too large for a Decimal (``1e9999999999999999999``) is clamped to one that is
    still refused as too large or too small, so every number the syntax allows can be read.
    """
    match = _EXPONENT.search(text)
    if match is not None and len(match.group(2)) > len(str(_EXTREME_EXPONENT)):
        text = f"{text[: match.start()]}e{match.group(1)}{_EXTREME_EXPONENT}"
    return Decimal(text)


def _normal(value: Decimal) -> tuple[int, tuple[int, ...], int]:
    """Sign, digits and exponent with trailing zeros dropped; zero has no digits."""
    sign, digits, exponent = value.as_tuple()
    assert isinstance(exponent, int), value  # finite: the number syntax has no inf or nan
    end = len(digits)
    while end and digits[end - 1] == 0:
        end -= 1
    start = 0
    while start < end and digits[start] == 0:
        start += 1
    return sign, tuple(digits[start:end]), exponent + len(digits) - end


def _compact(value: Decimal) -> Decimal:
    """The same number without trailing zeros, built from its digits (no context, so nothing
    rounds or traps): ``1.000…0`` with a thousand zeros is 1, ``0e-400`` is 0. Arithmetic on a
    checked number's compact form stays within a few dozen digits, so it is exact."""
    sign, digits, exponent = _normal(value)
    return Decimal((sign, digits, exponent)) if digits else Decimal(0)


def significant_digits(value: Decimal) -> int:
    """``0.0250`` has 2 (2 and 5); zero has none."""
    return len(_normal(value)[1])


def decimal_places(value: Decimal) -> int:
    """The decimals the value needs: 0.25 has 2, ``1.50`` 1, ``1e2`` and ``1.5e1`` none."""
    _, digits, exponent = _normal(value)
    return max(0, -exponent) if digits else 0


def written_decimals(value: Decimal) -> int:
    """The decimals the number was written with: ``1.50`` has 2, ``2.5e-1`` 2, ``1e2`` none."""
    exponent = value.as_tuple().exponent
    assert isinstance(exponent, int), value
    return max(0, -exponent)


def number_problem(value: Decimal) -> str | None:
    """Why a number cannot be a value as written (to follow the number in a message), or None."""
    if value.copy_abs() > MAX_MAGNITUDE:
        return f"is beyond ±{_MAGNITUDE}"
    places = decimal_places(value)
    if places > MAX_DECIMALS:
        if value.adjusted() < -MAX_DECIMALS:
            return f"is too small: values keep at most {MAX_DECIMALS} decimals, so it would read as 0"
        return f"has {places} decimals; at most {MAX_DECIMALS} are kept"
    digits = significant_digits(value)
    if digits > MAX_DIGITS:
        return f"has {digits} significant digits; a double holds {MAX_DIGITS}"
    return None


def exact_int(value: Decimal) -> int | None:
    """The value as an int if it is a whole number (``1e3``, ``2.0``) of sane size, else None."""
    sign, digits, exponent = _normal(value)
    if not digits:
        return 0
    if exponent < 0 or exponent + len(digits) > 100:
        return None
    whole = int("".join(map(str, digits))) * 10**exponent
    return -whole if sign else whole


def _units(value: Decimal, places: int) -> int:
    """``value`` times 10**places, which must be a whole number."""
    sign, digits, exponent = _normal(value)
    if not digits:
        return 0
    shift = exponent + places
    assert shift >= 0, (value, places)
    units = int("".join(map(str, digits))) * 10**shift
    return -units if sign else units


def _int_digits(value: Decimal) -> int:
    """Digits before the point: 0 for 0.5, 3 for -123.4."""
    return value.adjusted() + 1 if value.copy_abs() >= 1 else 0


def _plain(value: Decimal) -> str:
    """A checked number as fixed-point text without trailing zeros: 0.25, 20, -3.14."""
    places = decimal_places(value)
    return units_text(_units(value, places), places)


def units_text(units: int, places: int) -> str:
    """The fixed-point text of ``units``·10**-``places`` without trailing zeros: 0.25, 20, -3.14."""
    if places == 0:
        return str(units)
    digits = str(abs(units)).rjust(places + 1, "0")
    whole, fraction = digits[:-places], digits[-places:].rstrip("0")
    return ("-" if units < 0 else "") + whole + ("." + fraction if fraction else "")


def format_number(value: Decimal, places: int) -> str:
    """Fixed-point text without trailing zeros: 0.25, 20, -3.14."""
    text = f"{value:.{places}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


# ---- ranges --------------------------------------------------------------------------------


def parse_range(text: str) -> tuple[RangeSpec | None, list[RangeProblem]]:
    """Read a range's text. Returns the spec (None if unusable) and its problems."""
    try:
        tree = range_parser().parse(text)
    except (UnexpectedCharacters, UnexpectedToken, UnexpectedEOF) as exc:
        return None, [_syntax_problem(text, exc)]
    except LarkError as exc:  # pragma: no cover - defensive: lark's other errors
        return None, [RangeProblem("GG104", f"malformed range: {exc}")]
    return _evaluate(text, tree)


_RANGE_FORMS = "write int[LO..HI], float[LO..HI step S], float[LO..HI count N] or float[X ± P% count N]"


def _syntax_problem(text: str, exc: LarkError) -> RangeProblem:
    position = getattr(exc, "pos_in_stream", None)
    if isinstance(exc, UnexpectedToken) and exc.token.type == "$END":
        position = len(text)
    if position is None:
        position = len(text) - 1
    found = text[position : position + 1] or "the end"
    return RangeProblem(
        "GG104",
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
    if not _PLAIN_REST.fullmatch(after) or not _reads(before + "]"):
        return None
    if not all(_reads(match.group()) for match in _RANGE_SHAPE.finditer(after)):
        return None
    return RangeFix(f"Close the range before the |: {before}]", (RangeEdit(len(before), 0, "]"),), safe=True)


#: What may follow the ``|`` for :func:`_unclosed`: no strings, rules, comments or escapes.
_PLAIN_REST = re.compile(r"[^'\"<#\\]*")
#: The lexer's RANGE token (``gaitgram.lark``).
_RANGE_SHAPE = re.compile(r"(?:int|float)\[[^\]\n]*(?:\.\.|±|\+-)[^\]\n]*\]")


def _reads(text: str) -> bool:
    """Whether a range's text reads without errors."""
    spec, problems = parse_range(text)
    return spec is not None and not any(CODES[p.code].severity is Severity.ERROR for p in problems)


def _evaluate(text: str, tree: Tree) -> tuple[RangeSpec | None, list[RangeProblem]]:
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
                _at(text, token, "GG307", f"{token} in {text!r} {reason}", NUMBER_LIMITS, where=False)
            ]

    # Checked, so each has at most 15 digits; compact, so calculations with them are exact
    # and cheap (``1.000…0`` with a thousand zeros, or ``0e-400``, is written exactly but
    # would round in a decimal context, or cost a thousand-digit fraction).
    first, second = (_compact(read_number(str(token))) for token in numbers)
    center: Decimal | None = None
    if bounds.data == "interval":
        low, high = first, second
        if low > high:
            return None, [
                RangeProblem(
                    "GG301",
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
            return None, [_at(text, numbers[1], "GG302", "a relative range needs a non-negative percentage")]
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
                    "GG307",
                    f"{numbers[0]} ± {numbers[1]}% in {text!r} reaches {_plain(low)}..{_plain(high)}, "
                    f"beyond ±{_MAGNITUDE}",
                    "use a smaller percentage",
                    where=False,
                )
            ]

    step: Decimal | None = None
    count: int | None = None
    if option is not None:
        assert option_token is not None
        value = _compact(read_number(str(option_token)))
        if option.data == "step_option":
            if value <= 0:
                return None, [
                    _at(text, option_token, "GG302", f"the step must be positive, not {option_token}")
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
                        "GG302",
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
                "GG305",
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
                    "GG305",
                    f"int range {text!r} has {what}",
                    "use float[...] for fractional values",
                    fix=to_float(),
                )
            ]
    elif step is None and count is None:
        return None, [
            RangeProblem(
                "GG104",
                f"float range {text!r} needs a step or a count",
                f"for example {text[:-1]} step 0.1] or {text[:-1]} count 11]",
                offset=len(text) - 1,
                length=1,
            )
        ]

    problems: list[RangeProblem] = []
    if count is not None:
        written = [written_decimals(read_number(str(n))) for n in numbers]
        decimals = (
            max(written[0], decimal_places(low), decimal_places(high)) if center is not None else max(written)
        )
        values = _count_values(text, low, high, count, decimals, center is None, problems)
    else:
        assert step is not None
        values = _step_values(text, low, high, center, step, problems, numbers[-1])
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
    start, stride = _units(origin, places), _units(step, places)
    units = [start + stride * i for i in range(first, first + size)]
    if center is None and Fraction(units[-1], 10**places) != Fraction(high):
        last = units_text(units[-1], places)
        problems.append(
            RangeProblem(
                "GG303",
                f"the upper bound {_plain(high)} of {text!r} is not on the step grid; "
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
    if _int_digits(max(low.copy_abs(), high.copy_abs())) + places > MAX_DIGITS:
        for unit in units:
            digits = len(str(abs(unit)).rstrip("0"))
            if digits > MAX_DIGITS:
                problems.append(
                    RangeProblem(
                        "GG307",
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
            return [_plain(low)]
        problems.append(
            RangeProblem(
                "GG306",
                f"the bounds of {text!r} are both {_plain(low)}, so its {count} values would all be equal",
                f"write {_plain(low)} itself, or make the bounds differ",
            )
        )
        return None
    if count == 1:
        problems.append(
            RangeProblem(
                "GG308",
                f"{text!r} asks for one value, but a count range includes both ends, "
                f"{_plain(low)} and {_plain(high)}",
                "use count 2 or more, or write the one value itself",
            )
        )
        return None

    widest = max(low.copy_abs(), high.copy_abs())
    most = min(MAX_DECIMALS, MAX_DIGITS - _int_digits(widest))
    exact = max(decimal_places(low), decimal_places(high))
    if written_bounds and exact > most:
        problems.append(
            RangeProblem(
                "GG307",
                f"the values of {text!r} would need {_int_digits(widest) + exact} significant digits "
                f"to include both bounds; a double holds {MAX_DIGITS}",
                "write the bounds with fewer decimals",
            )
        )
        return None

    # value i = (lo·(n-1) + (hi-lo)·i) / ((n-1)·10**scale), in integers: exact, then rounded once.
    scale = exact
    lo, hi = _units(low, scale), _units(high, scale)
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
            "GG306",
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
    if spec is None or any(CODES[p.code].severity is Severity.ERROR for p in problems):
        return None
    if same_values is not None and list(spec.values) != same_values:
        return None
    return RangeFix(f"{title}: {fixed}", edits, safe=same_values is not None)


def apply_range_edits(text: str, edits: tuple[RangeEdit, ...]) -> str:
    for edit in sorted(edits, key=lambda e: e.offset, reverse=True):
        text = text[: edit.offset] + edit.text + text[edit.offset + edit.length :]
    return text


def _at(
    text: str, token: Token, code: str, message: str, hint: str | None = None, *, where: bool = True
) -> RangeProblem:
    """A problem located at ``token``; ``where``: the message says which range."""
    start = token.start_pos or 0
    shown = f"{message} in {text!r}" if where else message
    return RangeProblem(code, shown, hint, offset=start, length=len(token))


def _too_large(text: str, size: int | None, shown: str | None = None) -> RangeProblem:
    if shown is None:
        shown = f"{size:,}" if size is not None and size < 10**15 else f"about {float(size or 0):.1e}"
    return RangeProblem(
        "GG304",
        f"range {text!r} has {shown} values; at most {MAX_RANGE_VALUES:,} are allowed",
        "use a coarser step or a smaller count",
    )


# ---- text that looks like a range ------------------------------------------------------------
#
# PonyGE2 compatibility keeps ``flaot[0..1 step 0.1]`` and an unclosed ``int[1..5`` as plain
# terminal text (only the exact bracketed shape is a range), so a typo silently turns a
# choice of values into one fixed string. GG309 says so, with the fix.

_N = r"[+-]?(?:\d+(?:\.\d+)?|\.\d+)(?:[eE][+-]?\d+)?"
_S = r"[^\S\n]*"
_LOOK_ALIKE = re.compile(
    rf"(?<![\w\\])(?P<kind>[A-Za-z_]\w*)\[(?P<body>{_S}{_N}{_S}(?:\.\.|±|\+-){_S}{_N}(?:{_S}%)?"
    rf"(?:[^\S\n]+(?:step|count)[^\S\n]+{_N})?)(?P<close>{_S}\])?"
)

#: After a number, more of the same word: ``int[1..5x`` is not an unclosed range.
_WORD_GOES_ON = re.compile(r"[\w.]")

#: Other languages' names for the two kinds.
_KIND_ALIASES = {"integer": "int", "double": "float"}


@dataclass(frozen=True, slots=True)
class LookAlike:
    """Terminal text that looks like a typed range: where (in the text given), why, the fix."""

    offset: int
    length: int
    message: str
    fix: RangeFix | None
    meant: str  # the range it looks like: int or float


LOOK_ALIKE_HINT = "PonyGE2 reads it as plain text too; to keep it as text, quote it ('...')"


def look_alike_ranges(text: str) -> list[LookAlike]:
    """The typed ranges in a run of terminal text that are not ranges: a type name one typo
    (or a letter's case) away from int or float, or no closing ``]``, before ``LO..HI``."""
    if "[" not in text:
        return []
    found = []
    for match in _LOOK_ALIKE.finditer(text):
        word = match["kind"]
        meant = _kind_meant(word)
        closed = match["close"] is not None
        end = match.end() if closed else match.end("body")
        if meant is None or (word == meant and closed) or (not closed and _WORD_GOES_ON.match(text, end)):
            continue
        shown = text[match.start() : end]
        edits = [] if word == meant else [RangeEdit(0, len(word), meant)]
        if not closed:
            edits.append(RangeEdit(end - match.start(), 0, "]"))
        why = [] if word == meant else [f"{word!r} is not int or float"]
        if not closed:
            why.append("it has no closing ]")
        fixed = apply_range_edits(shown, tuple(edits))
        # Once a range ends the text run, a GE_RANGE after it is read as one, not as text.
        usable = _reads(fixed) and "GE_RANGE:" not in text[end:]
        found.append(
            LookAlike(
                match.start(),
                len(shown),
                f"{shown!r} looks like a typed range but is plain text: {' and '.join(why)}",
                RangeFix(f"Make it the range {fixed}", tuple(edits), safe=True) if usable else None,
                meant,
            )
        )
    return found


def _kind_meant(word: str) -> str | None:
    lower = word.lower()
    if lower in _KIND_ALIASES:
        return _KIND_ALIASES[lower]
    if len(lower) < 3:  # `in[1..5]`, `it[0..1]`: too likely to be meant
        return None
    return next((kind for kind in ("int", "float") if _typos(lower, kind) <= 1), None)


def _typos(a: str, b: str) -> int:
    """Edits from ``a`` to ``b`` (insert, delete, replace, swap two neighbours), up to 2."""
    if abs(len(a) - len(b)) > 1:
        return 2
    previous2: list[int] = []
    previous = list(range(len(b) + 1))
    for i, x in enumerate(a, 1):
        current = [i]
        for j, y in enumerate(b, 1):
            cost = min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (x != y))
            if i > 1 and j > 1 and x == b[j - 2] and a[i - 2] == y:
                cost = min(cost, previous2[j - 2] + 1)
            current.append(cost)
        previous2, previous = previous, current
    return min(previous[-1], 2)
