"""Numbers as written: the exact value of a number's text, and the limits a value keeps to.

A number's syntax is the grammar's (``RANGE_NUMBER`` and ``ARG_NUMBER`` in ``gaitgram.lark``,
both its ``NUMBER``); this module reads the text that syntax allows. ``2.5e-1`` is the decimal
0.25, ``1.50`` is 1.5 written to two decimals.

A value means the number it prints: every number in a range or an annotation, and every value
a range derives, is within ±:data:`MAX_MAGNITUDE` and has at most :data:`MAX_DIGITS`
significant digits and :data:`MAX_DECIMALS` decimals. A double holds such a decimal exactly (it
reads back unchanged), so distinct values stay distinct when a gait is evaluated.

Everything here works on a Decimal's digits and exponent, never through a decimal context:
``1e999999999`` and ``1e-999999999`` are read, measured and refused, not rounded, overflowed or
turned into a billion-digit integer.
"""

from __future__ import annotations

import re
from decimal import Decimal

__all__ = [
    "MAX_DECIMALS",
    "MAX_DIGITS",
    "MAX_MAGNITUDE",
    "NUMBER_LIMITS",
    "compact",
    "decimal_places",
    "exact_int",
    "in_units",
    "int_digits",
    "number_problem",
    "plain",
    "read_number",
    "significant_digits",
    "units_text",
    "written_decimals",
]

#: Larger numbers are a typo; they would also make enormous value texts.
MAX_MAGNITUDE = Decimal("1e12")
MAGNITUDE_TEXT = "1e12"

#: Significant digits a double holds exactly (C's ``DBL_DIG``): a decimal with no more
#: reads back from a double unchanged.
MAX_DIGITS = 15

#: Decimals a value may have: below 1e-15 a joint angle or a frequency means nothing.
MAX_DECIMALS = 15

NUMBER_LIMITS = (
    f"numbers are within ±{MAGNITUDE_TEXT}, with at most {MAX_DIGITS} significant digits "
    f"and {MAX_DECIMALS} decimals"
)

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


def compact(value: Decimal) -> Decimal:
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
        return f"is beyond ±{MAGNITUDE_TEXT}"
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


def in_units(value: Decimal, places: int) -> int:
    """``value`` times 10**places, which must be a whole number."""
    sign, digits, exponent = _normal(value)
    if not digits:
        return 0
    shift = exponent + places
    assert shift >= 0, (value, places)
    whole = int("".join(map(str, digits))) * 10**shift
    return -whole if sign else whole


def int_digits(value: Decimal) -> int:
    """Digits before the point: 0 for 0.5, 3 for -123.4."""
    return value.adjusted() + 1 if value.copy_abs() >= 1 else 0


def plain(value: Decimal) -> str:
    """A checked number as fixed-point text without trailing zeros: 0.25, 20, -3.14."""
    places = decimal_places(value)
    return units_text(in_units(value, places), places)


def units_text(count: int, places: int) -> str:
    """The fixed-point text of ``count``·10**-``places`` without trailing zeros: 0.25, 20, -3.14."""
    if places == 0:
        return str(count)
    digits = str(abs(count)).rjust(places + 1, "0")
    whole, fraction = digits[:-places], digits[-places:].rstrip("0")
    return ("-" if count < 0 else "") + whole + ("." + fraction if fraction else "")
