"""Text for a syntax tree: the shortest that parses back to the same tree and numbers."""

from __future__ import annotations

import math

from gaitgram.motion.tree import (
    ATOM_PRECEDENCE,
    BINARY_PRECEDENCE,
    UNARY_PRECEDENCE,
    Binary,
    Call,
    Expr,
    Name,
    Number,
    Unary,
    postorder,
)


def format_number(value: float) -> str:
    """The shortest text that reads back as exactly ``value`` (whole numbers without ``.0``).

    Used for phenotype text, so it must stay within the expression language: no ``inf``.
    """
    if math.isinf(value):
        return "1e999" if value > 0 else "-1e999"  # float("1e999") is inf: reads back
    if value.is_integer() and abs(value) < 1e16:
        return str(int(value))
    return repr(value)


def to_text(expr: Expr) -> str:
    """Compact text for a tree, with only the parentheses it needs: it parses back to ``expr``.

    The parser never makes a negative literal (it reads ``-2`` as unary minus applied
    to 2); a tree built by hand with one gets text of the same value, which parses to
    the unary form. NaN has no text.
    """
    stack: list[tuple[str, int]] = []
    for node in postorder(expr):
        match node:
            case Number(value=value):
                text = format_number(value)
                stack.append((text, ATOM_PRECEDENCE if not text.startswith("-") else UNARY_PRECEDENCE))
            case Name(name=name):
                stack.append((name, ATOM_PRECEDENCE))
            case Unary(op=op):
                operand, precedence = stack.pop()
                stack.append((f"{op}{_wrap(operand, precedence < UNARY_PRECEDENCE)}", UNARY_PRECEDENCE))
            case Binary(op=op):
                right, right_precedence = stack.pop()
                left, left_precedence = stack.pop()
                precedence = BINARY_PRECEDENCE[op]
                left = _wrap(left, left_precedence < precedence)
                right = _wrap(right, right_precedence <= precedence)
                stack.append((f"{left}{op}{right}", precedence))
            case Call(name=name, args=args):
                items = [stack.pop()[0] for _ in args][::-1]
                stack.append((f"{name}({','.join(items)})", ATOM_PRECEDENCE))
    return stack[-1][0]


def _wrap(text: str, needed: bool) -> str:
    return f"({text})" if needed else text
