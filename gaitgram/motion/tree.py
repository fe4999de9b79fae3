"""The syntax tree of a motion expression, for tools that work on its structure.

The compiler itself never needs it (it reads the parser's postfix nodes, see
:mod:`gaitgram.motion.parser`); the tree is built on request, by
:func:`~gaitgram.motion.parser.parse_expression` or a motion's ``expr``. Spans
(``start``, ``end``: offsets into the text) do not take part in equality, so a tree parsed
from differently spaced or parenthesised text compares equal.
"""

from __future__ import annotations

from dataclasses import dataclass, field

#: Binding strength of the binary operators, loosest first (all left-associative); unary
#: ``-`` and ``+`` bind tighter than any of them, and atoms tightest of all.
BINARY_PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2}
UNARY_PRECEDENCE = 3
ATOM_PRECEDENCE = 4


@dataclass(frozen=True, slots=True)
class Number:
    value: float
    start: int = field(default=0, compare=False)
    end: int = field(default=0, compare=False)


@dataclass(frozen=True, slots=True)
class Name:
    name: str
    start: int = field(default=0, compare=False)
    end: int = field(default=0, compare=False)


@dataclass(frozen=True, slots=True)
class Unary:
    op: str  # "-" or "+"
    operand: Expr
    start: int = field(default=0, compare=False)
    end: int = field(default=0, compare=False)


@dataclass(frozen=True, slots=True)
class Binary:
    op: str  # "+", "-", "*" or "/"
    left: Expr
    right: Expr
    start: int = field(default=0, compare=False)
    end: int = field(default=0, compare=False)


@dataclass(frozen=True, slots=True)
class Call:
    name: str
    args: tuple[Expr, ...]
    start: int = field(default=0, compare=False)
    end: int = field(default=0, compare=False)


Expr = Number | Name | Unary | Binary | Call


def children(node: Expr) -> tuple[Expr, ...]:
    match node:
        case Unary(operand=operand):
            return (operand,)
        case Binary(left=left, right=right):
            return (left, right)
        case Call(args=args):
            return args
        case _:
            return ()


def postorder(root: Expr) -> list[Expr]:
    """Every node, children before parents, left to right; iterative, for any depth."""
    # Pre-order with the children pushed left to right visits node, right, left; reversed,
    # that is left, right, node.
    order: list[Expr] = []
    stack: list[Expr] = [root]
    while stack:
        node = stack.pop()
        order.append(node)
        kind = type(node)
        if kind is Binary:
            stack.append(node.left)  # type: ignore[union-attr]
            stack.append(node.right)  # type: ignore[union-attr]
        elif kind is Unary:
            stack.append(node.operand)  # type: ignore[union-attr]
        elif kind is Call:
            stack.extend(node.args)  # type: ignore[union-attr]
    order.reverse()
    return order
