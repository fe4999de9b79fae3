"""Compiling, the third stage: checked postfix nodes to a flat program for the stack machine.

Subexpressions without ``t`` or a sensor are folded to constants here, with float64 arithmetic that
gives exactly the bits the machine's numpy arrays would: Python's float ``+ - * /`` are
the same IEEE 754 operations, and where a result is NaN (whose sign and payload Python
and numpy may pick differently) or a function is applied, numpy computes it. A constant
divided by a constant zero is left unfolded, so every evaluation reports it like any
other zero divisor.
"""

from __future__ import annotations

import operator
from collections.abc import Callable
from dataclasses import dataclass
from enum import IntEnum
from typing import Any

import numpy as np

from gaitgram.motion.parser import NodeKind, Syntax
from gaitgram.motion.vocabulary import BINARY_UFUNCS, CONSTANTS, FUNCTIONS, VARIABLE


class Op(IntEnum):
    T = 0  # push the phases
    PUSH = 1  # push a constant
    UNARY = 2  # top = f(top)
    BINARY = 3  # b = pop; top = f(top, b)
    BINARY_CONST = 4  # top = f(top, c)
    CONST_BINARY = 5  # top = f(c, top)
    SENSOR = 6  # push a sensor's values (the name in the function's place)


#: A division's span and its divisor's, ``(start, end, divisor start, divisor end)``: where a
#: zero divisor is reported.
Division = tuple[int, int, int, int]

#: One step of the machine, ``(op, function, constant, division)``: a plain tuple, which the
#: machine's loop unpacks cheaply. ``division`` is set on divisions only; SENSOR holds the
#: sensor's name where the others hold a function.
Instruction = tuple[Op, Callable[..., Any] | str | None, float, Division | None]


@dataclass(frozen=True, slots=True)
class Program:
    """What the machine runs: its instructions, or (if the expression has no ``t``) its value."""

    instructions: tuple[Instruction, ...]
    #: The value of an expression without ``t`` or a sensor (folded here), else None.
    constant: float | None


_NUMBER, _NAME, _UNARY, _BINARY = NodeKind.NUMBER, NodeKind.NAME, NodeKind.UNARY, NodeKind.BINARY
_T, _PUSH, _UNARY_OP, _BINARY_OP, _BINARY_CONST, _CONST_BINARY, _SENSOR = Op
_FLOAT_OPS: dict[str, Callable[[float, float], float]] = {
    "+": operator.add,
    "-": operator.sub,
    "*": operator.mul,
    "/": operator.truediv,
}
_DYNAMIC: Any = object()  # a stack entry whose value depends on t (its code is already emitted)


def compile_program(syntax: Syntax) -> Program:
    """The program of a checked expression (:func:`gaitgram.motion.checker.check` found no problem)."""
    program: list[Instruction] = []
    emit = program.append
    stack: list[Any] = []  # floats, and _DYNAMIC for what the program computes
    push = stack.append
    ufuncs, float_ops = BINARY_UFUNCS, _FLOAT_OPS
    for kind, value, start, end, a, b in syntax.nodes:
        if kind is _NUMBER:
            push(value)
        elif kind is _BINARY:
            right = stack.pop()
            left = stack[-1]
            func = ufuncs[value]  # type: ignore[index]
            division = (start, end, a, b) if value == "/" else None
            if left is _DYNAMIC:
                if right is _DYNAMIC:
                    emit((_BINARY_OP, func, 0.0, division))
                else:
                    emit((_BINARY_CONST, func, right, division))
            elif right is _DYNAMIC:
                emit((_CONST_BINARY, func, left, division))
                stack[-1] = _DYNAMIC
            elif division is not None and right == 0:
                emit((_PUSH, None, left, None))
                emit((_BINARY_CONST, func, right, division))
                stack[-1] = _DYNAMIC
            else:
                result = float_ops[value](left, right)  # type: ignore[index]
                stack[-1] = result if result == result else _numpy_value(func, left, right)
        elif kind is _NAME:
            if value == VARIABLE:
                emit((_T, None, 0.0, None))
                push(_DYNAMIC)
            elif value in CONSTANTS:
                push(CONSTANTS[value])  # type: ignore[index]
            else:  # a sensor (the checker let it through)
                emit((_SENSOR, value, 0.0, None))
                push(_DYNAMIC)
        elif kind is _UNARY:
            if value == "-":
                if stack[-1] is _DYNAMIC:
                    emit((_UNARY_OP, np.negative, 0.0, None))
                else:
                    stack[-1] = -stack[-1]
        else:  # a call of one argument
            ufunc = FUNCTIONS[value].ufunc  # type: ignore[index]
            if stack[-1] is _DYNAMIC:
                emit((_UNARY_OP, ufunc, 0.0, None))
            else:
                stack[-1] = _numpy_value(ufunc, stack[-1])
    (result,) = stack
    return Program(tuple(program), None if result is _DYNAMIC else result)


def _numpy_value(func: np.ufunc, *args: float) -> float:
    with np.errstate(all="ignore"):
        return float(func(*(np.float64(arg) for arg in args)))
