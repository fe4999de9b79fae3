"""Typed ranges: the values behind ``int[5..8]``, ``float[0..20 step 0.25]`` and friends.

Arithmetic is decimal, so ``float[0..20 step 0.25]`` derives exactly the texts
``0 0.25 0.5 ... 20`` a user would have written out, and a range and its
written-out list map every genome to the same phenotype.
"""

from __future__ import annotations

from dataclasses import dataclass
from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal, localcontext

from lark import Token, Tree
from lark.exceptions import LarkError, UnexpectedCharacters, UnexpectedEOF, UnexpectedToken

from gaitgram.language.model import RangeKind, RangeSpec
from gaitgram.language.parser import range_parser

#: A range larger than this is almost certainly a typo, and would cost memory.
MAX_RANGE_VALUES = 100_000

#: Larger bounds are a typo; they would also make enormous value texts.
MAX_MAGNITUDE = Decimal("1e12")

#: Extra decimals for ``count`` ranges, whose step rarely terminates.
COUNT_EXTRA_DECIMALS = 2


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
    )


def _evaluate(text: str, tree: Tree) -> tuple[RangeSpec | None, list[RangeProblem]]:
    kind = RangeKind(str(tree.children[0]))
    bounds = next(c for c in tree.children if isinstance(c, Tree) and c.data in ("interval", "relative"))
    option = next((c for c in tree.children if isinstance(c, Tree) and c.data.endswith("_option")), None)
    numbers = [t for t in bounds.children if isinstance(t, Token) and t.type == "RANGE_NUMBER"]
    problems: list[RangeProblem] = []

    def number(token: Token) -> Decimal:
        return Decimal(str(token))

    decimals = max(_decimals(str(t)) for t in numbers)
    if bounds.data == "interval":
        low, high = number(numbers[0]), number(numbers[1])
        center = None
    else:
        center, percent = number(numbers[0]), number(numbers[1])
        if percent < 0:
            return None, [_at(text, numbers[1], "GG302", "a relative range needs a non-negative percentage")]
        delta = abs(center) * percent / 100
        low, high = center - delta, center + delta
        decimals = max(decimals, _decimals(str(low.normalize())), _decimals(str(high.normalize())))

    if max(abs(low), abs(high)) > MAX_MAGNITUDE:
        return None, [RangeProblem("GG304", f"range {text!r} has bounds beyond ±{MAX_MAGNITUDE:g}")]
    if low > high:
        return None, [
            RangeProblem(
                "GG301",
                f"empty range {text!r}: the lower bound {low} is above the upper bound {high}",
                "swap the bounds",
            )
        ]

    step: Decimal | None = None
    count: int | None = None
    if option is not None:
        value_token = option.children[1]
        value = number(value_token)
        if option.data == "step_option":
            if value <= 0:
                return None, [_at(text, value_token, "GG302", f"the step must be positive, not {value}")]
            step = value
            decimals = max(decimals, _decimals(str(value_token)))
        else:
            if value != value.to_integral_value() or value < 1:
                return None, [
                    _at(text, value_token, "GG302", f"the count must be a whole number ≥ 1, not {value}")
                ]
            count = int(value)

    if kind is RangeKind.INT:
        if count is not None:
            return None, [
                _at(
                    text,
                    option.children[0],
                    "GG305",
                    "an int range takes a step, not a count",
                    hint="use float[... count N], or int[LO..HI step S]",
                )
            ]
        step = step if step is not None else Decimal(1)
        if step != step.to_integral_value() or (center is None and decimals > 0):
            return None, [
                RangeProblem(
                    "GG305",
                    f"int range {text!r} has fractional bounds or step",
                    "use float[...] for fractional values",
                )
            ]
        # Relative int ranges round inward, so every value is within the percentage.
        low = low.to_integral_value(ROUND_CEILING)
        high = high.to_integral_value(ROUND_FLOOR)
        decimals = 0
        if low > high:
            return None, [
                RangeProblem("GG301", f"empty range {text!r}: no integer within {center} ± its percentage")
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

    try:
        values = _values(low, high, center, step, count, decimals, problems, text)
    except ArithmeticError:
        return None, [RangeProblem("GG304", f"range {text!r} is out of numeric bounds")]
    if values is None:
        return None, problems
    return RangeSpec(kind, canonical_text(kind, bounds.data, numbers, option), tuple(values)), problems


def _values(
    low: Decimal,
    high: Decimal,
    center: Decimal | None,
    step: Decimal | None,
    count: int | None,
    decimals: int,
    problems: list[RangeProblem],
    text: str,
) -> list[str] | None:
    with localcontext() as ctx:
        ctx.prec = 50
        if count is not None:
            size = count
            if size > MAX_RANGE_VALUES:
                problems.append(_too_large(text, size))
                return None
            if size == 1:
                points = [center if center is not None else low]
            else:
                width = (high - low) / (size - 1)
                points = [low + width * i for i in range(size)]
            places = min(decimals + COUNT_EXTRA_DECIMALS, 12)
        else:
            assert step is not None
            if center is not None and low != high:
                # Relative ranges are centred on their value: it is always one of them.
                k = int(((center - low) / step).to_integral_value(ROUND_FLOOR))
                if 2 * k + 1 > MAX_RANGE_VALUES:
                    problems.append(_too_large(text, 2 * k + 1))
                    return None
                points = [center + step * i for i in range(-k, k + 1)]
            else:
                size = int(((high - low) / step).to_integral_value(ROUND_FLOOR)) + 1
                if size > MAX_RANGE_VALUES:
                    problems.append(_too_large(text, size))
                    return None
                points = [low + step * i for i in range(size)]
                if points[-1] != high:
                    problems.append(
                        RangeProblem(
                            "GG303",
                            f"the upper bound {high} of {text!r} is not on the step grid; "
                            f"the last value is {format_number(points[-1], decimals)}",
                            "make the bounds differ by a whole number of steps",
                        )
                    )
            places = decimals
        return [format_number(p, places) for p in points]


def format_number(value: Decimal, places: int) -> str:
    """Fixed-point text without trailing zeros: 0.25, 20, -3.14."""
    text = f"{value:.{places}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def canonical_text(kind: RangeKind, form: str, numbers: list[Token], option: Tree | None) -> str:
    a, b = (str(n) for n in numbers)
    inner = f"{a}..{b}" if form == "interval" else f"{a} ± {b}%"
    if option is not None:
        inner += f" {option.children[0]} {option.children[1]}"
    return f"{kind}[{inner}]"


def _decimals(number: str) -> int:
    mantissa = number.lower().split("e")[0]
    return len(mantissa.split(".")[1]) if "." in mantissa else 0


def _at(text: str, token: Token, code: str, message: str, hint: str | None = None) -> RangeProblem:
    start = token.start_pos or 0
    return RangeProblem(code, f"{message} in {text!r}", hint, offset=start, length=len(token))


def _too_large(text: str, size: int) -> RangeProblem:
    return RangeProblem(
        "GG304",
        f"range {text!r} has {size:,} values; at most {MAX_RANGE_VALUES:,} are allowed",
        "use a coarser step or a smaller count",
    )
