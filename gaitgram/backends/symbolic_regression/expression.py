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

_OPERATORS: dict[str, Callable[[Any, Any], Any]] = {"+": operator.add, "-": operator.sub, "*": operator.mul}

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
    if parser.peek() is not None:
        parser.fail(f"unexpected {parser.shown()!r}")
    return Expression(text, tuple(sorted(parser.inputs)), node)


class _Parser:
    """Recursive descent over Python's precedence for the subset: sums of products of unary terms."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.tokens: list[tuple[str, str, int, int]] = []  # (kind, value, start, end)
        self.inputs: set[int] = set()
        position = 0
        while text[position:].strip():
            match = _TOKEN.match(text, position)
            if match is None:
                offset = len(text) - len(text[position:].lstrip())
                raise ExpressionError(f"column {offset + 1}: unexpected {text[offset]!r} in {text!r}")
            kind = match.lastgroup  # the outer group: number, input, name or symbol
            assert kind is not None
            value = match.group("index") if kind == "input" else match.group(kind)
            self.tokens.append((kind, value, match.start(kind), match.end(kind)))
            position = match.end()
        self.at = 0

    def peek(self) -> str | None:
        return self.tokens[self.at][1] if self.at < len(self.tokens) else None

    def shown(self) -> str:
        """The current token as the text spells it."""
        _, _, start, end = self.tokens[self.at]
        return self.text[start:end]

    def fail(self, message: str) -> None:
        offset = self.tokens[self.at][2] if self.at < len(self.tokens) else len(self.text)
        raise ExpressionError(f"column {offset + 1}: {message} in {self.text!r}")

    def take(self, symbol: str) -> None:
        if self.peek() != symbol or self.tokens[self.at][0] != "symbol":
            found = "the end" if self.peek() is None else repr(self.shown())
            self.fail(f"expected {symbol!r}, found {found}")
        self.at += 1

    def expression(self) -> Node:
        node = self.product()
        while self.at < len(self.tokens) and self.tokens[self.at][:2] in (("symbol", "+"), ("symbol", "-")):
            node = _binary(_OPERATORS[self.tokens[self.at][1]], node, self._next(self.product))
        return node

    def product(self) -> Node:
        node = self.unary()
        while self.at < len(self.tokens) and self.tokens[self.at][:2] == ("symbol", "*"):
            node = _binary(operator.mul, node, self._next(self.unary))
        return node

    def _next(self, parse: Callable[[], Node]) -> Node:
        self.at += 1
        return parse()

    def unary(self) -> Node:
        if self.at < len(self.tokens) and self.tokens[self.at][:2] == ("symbol", "-"):
            operand = self._next(self.unary)
            return lambda columns: -operand(columns)
        return self.atom()

    def atom(self) -> Node:
        if self.at == len(self.tokens):
            self.fail("the expression ends too early")
        kind, text, _, _ = self.tokens[self.at]
        if kind == "number":
            if "." not in text and len(text) > 1 and text.startswith("0"):
                self.fail(f"{text} is not a Python number (leading zeros)")
            self.at += 1
            value = float(text) if "." in text else int(text)
            return lambda columns: value
        if kind == "input":
            self.at += 1
            index = int(text)
            self.inputs.add(index)
            return lambda columns: columns[index]
        if kind == "name":
            return self.call(text)
        if text == "(":
            self.at += 1
            node = self.expression()
            self.take(")")
            return node
        self.fail(f"unexpected {self.shown()!r}")
        raise AssertionError  # fail raised

    def call(self, name: str) -> Node:
        if name not in FUNCTIONS:
            known = ", ".join(FUNCTIONS)
            self.fail(f"{name} is not one of PonyGE2's regression functions ({known})")
        arity, function = FUNCTIONS[name]
        self.at += 1
        self.take("(")
        arguments = [self.expression()]
        while self.peek() == "," and self.tokens[self.at][0] == "symbol":
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
