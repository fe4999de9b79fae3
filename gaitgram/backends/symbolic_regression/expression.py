"""PonyGE2's regression phenotypes as data: parsed and compiled to numpy, never ``eval``-ed.

PonyGE2 scores a regression phenotype by ``eval``-ing it as Python with ``x`` the data's inputs,
under ``np.seterr(all="raise")``. Its grammars (``supervised_learning/*.bnf``) derive a small
subset of Python, and only that subset is accepted here: numbers (``12.34``, ``-1.5``), inputs
``x[:, i]``, ``+``, ``-`` and ``*`` with Python's precedence and left associativity, unary minus,
parentheses, PonyGE2's protected operators ``pdiv``, ``aq``, ``psqrt`` and ``plog``, and
``np.sin``, ``np.tanh`` and ``np.exp``. Anything else is a :class:`ExpressionError`, never run.

A compiled expression applies the same operations to the same kinds of object as Python would:
numbers stay Python floats (so ``99.99*99.99`` is Python's float product, and PonyGE2's ``pdiv``
of two numbers meets Python's ``ZeroDivisionError``), inputs are float64 columns. So a value,
and whether numpy raises a floating-point error on the way, is what PonyGE2's ``eval`` gives.
"""

from __future__ import annotations

import operator
import re
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np


def pdiv(x: Any, y: Any) -> Any:
    """Koza's protected division as PonyGE2 defines it: ``x / y``, or 1 where ``y`` is 0."""
    try:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(y == 0, np.ones_like(x), x / y)
    except ZeroDivisionError:  # two Python numbers, the divisor 0
        return 1.0


def aq(a: Any, b: Any) -> Any:
    """The analytic quotient (Ni, Drieberg and Rockett 2013), as PonyGE2 defines it."""
    return a / np.sqrt(1.0 + b**2.0)


def psqrt(x: Any) -> Any:
    """PonyGE2's protected square root: of the absolute value."""
    return np.sqrt(np.abs(x))


def plog(x: Any) -> Any:
    """PonyGE2's protected logarithm: ``log(1 + |x|)``."""
    return np.log(1.0 + np.abs(x))


#: The functions PonyGE2's regression grammars call, by the name they call them, with their arity.
FUNCTIONS: dict[str, tuple[int, Callable[..., Any]]] = {
    "pdiv": (2, pdiv),
    "aq": (2, aq),
    "psqrt": (1, psqrt),
    "plog": (1, plog),
    "np.sin": (1, np.sin),
    "np.tanh": (1, np.tanh),
    "np.exp": (1, np.exp),
}

#: Python's additive operators (left associative, below ``*``).
_ADDITIVE: dict[str, Callable[[Any, Any], Any]] = {"+": operator.add, "-": operator.sub}

_TOKEN = re.compile(
    r"\s*(?:"
    r"(?P<number>\d+\.\d*|\.\d+|\d+)"
    r"|(?P<input>x\[\s*:\s*,\s*(?P<index>\d+)\s*\])"
    r"|(?P<name>[A-Za-z_][A-Za-z_0-9]*(?:\.[A-Za-z_][A-Za-z_0-9]*)*)"
    r"|(?P<symbol>[-+*(),])"
    r")"
)

Node = Callable[[tuple[Any, ...]], Any]


class ExpressionError(ValueError):
    """A phenotype outside the subset PonyGE2's regression grammars derive; says where and why."""


@dataclass(frozen=True)
class Expression:
    """A compiled phenotype: call it with the input columns (``columns[i]`` is ``x[:, i]``)."""

    text: str
    #: The input indices it reads, ascending.
    inputs: tuple[int, ...]
    _run: Node

    def __call__(self, columns: tuple[Any, ...]) -> Any:
        return self._run(columns)


@lru_cache(maxsize=65_536)
def compile_expression(text: str) -> Expression:
    """``text`` compiled, cached: a population hands the same phenotypes on for generations.
    Raises :class:`ExpressionError` for text outside the subset."""
    parser = _Parser(text)
    node = parser.expression()
    if not parser.at_end():
        parser.fail(f"unexpected {parser.shown()!r}")
    return Expression(text, tuple(sorted(parser.inputs)), node)


class _Parser:
    """Recursive descent over Python's precedence for the subset: sums of products of unary terms.

    Tokens are parallel lists: ``keys[k]`` is the symbol itself (``+``, ``(``...) or the kind of
    token (``number``, ``input``, ``name``), closed by an ``end`` key; ``values[k]`` its text (an
    input's index), ``spans[k]`` where the text spells it."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.keys: list[str] = []
        self.values: list[str] = []
        self.spans: list[tuple[int, int]] = []
        self.inputs: set[int] = set()
        position, stop = 0, len(text.rstrip())
        while position < stop:
            match = _TOKEN.match(text, position)
            if match is None:
                offset = len(text) - len(text[position:].lstrip())
                raise ExpressionError(f"column {offset + 1}: unexpected {text[offset]!r} in {text!r}")
            kind = match.lastgroup  # the outer group: number, input, name or symbol
            assert kind is not None
            value = match.group("index") if kind == "input" else match.group(kind)
            self.keys.append(value if kind == "symbol" else kind)
            self.values.append(value)
            self.spans.append(match.span(kind))
            position = match.end()
        self.keys.append("end")
        self.spans.append((len(text), len(text)))
        self.at = 0

    def at_end(self) -> bool:
        return self.keys[self.at] == "end"

    def shown(self) -> str:
        """The current token as the text spells it."""
        start, end = self.spans[self.at]
        return self.text[start:end]

    def fail(self, message: str) -> None:
        raise ExpressionError(f"column {self.spans[self.at][0] + 1}: {message} in {self.text!r}")

    def take(self, symbol: str) -> None:
        if self.keys[self.at] != symbol:
            found = "the end" if self.at_end() else repr(self.shown())
            self.fail(f"expected {symbol!r}, found {found}")
        self.at += 1

    def expression(self) -> Node:
        node = self.product()
        while (apply := _ADDITIVE.get(self.keys[self.at])) is not None:
            self.at += 1
            node = _binary(apply, node, self.product())
        return node

    def product(self) -> Node:
        node = self.unary()
        while self.keys[self.at] == "*":
            self.at += 1
            node = _binary(operator.mul, node, self.unary())
        return node

    def unary(self) -> Node:
        if self.keys[self.at] == "-":
            self.at += 1
            operand = self.unary()
            return lambda columns: -operand(columns)
        return self.atom()

    def atom(self) -> Node:
        key, text = self.keys[self.at], self.values[self.at] if not self.at_end() else ""
        if key == "number":
            if "." not in text and len(text) > 1 and text.startswith("0"):
                self.fail(f"{text} is not a Python number (leading zeros)")
            self.at += 1
            value = float(text) if "." in text else int(text)
            return lambda columns: value
        if key == "input":
            self.at += 1
            index = int(text)
            self.inputs.add(index)
            return lambda columns: columns[index]
        if key == "name":
            return self.call(text)
        if key == "(":
            self.at += 1
            node = self.expression()
            self.take(")")
            return node
        self.fail("the expression ends too early" if key == "end" else f"unexpected {self.shown()!r}")
        raise AssertionError  # fail raised

    def call(self, name: str) -> Node:
        if name not in FUNCTIONS:
            known = ", ".join(FUNCTIONS)
            self.fail(f"{name} is not one of PonyGE2's regression functions ({known})")
        arity, function = FUNCTIONS[name]
        self.at += 1
        self.take("(")
        arguments = [self.expression()]
        while self.keys[self.at] == ",":
            self.at += 1
            arguments.append(self.expression())
        self.take(")")
        if len(arguments) != arity:
            self.at -= 1
            self.fail(f"{name} takes {arity} argument{'s' if arity > 1 else ''}, not {len(arguments)}")
        if arity == 1:
            (only,) = arguments
            return lambda columns: function(only(columns))
        first, second = arguments
        return lambda columns: function(first(columns), second(columns))


def _binary(apply: Callable[[Any, Any], Any], left: Node, right: Node) -> Node:
    return lambda columns: apply(left(columns), right(columns))
