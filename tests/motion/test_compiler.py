"""Compile-time folding gives the bits numpy's arrays would, for any operands.

The compiler folds ``+ - * /`` of constants with Python floats (several times cheaper than
numpy scalars) and hands NaN results and function calls to numpy: these tests hold it to
numpy's float64 bits over every kind of double, NaNs of either sign and any payload included.
"""

from __future__ import annotations

import math
import struct

import numpy as np
from hypothesis import example, given
from hypothesis import strategies as st

from gaitgram.motion.compiler import Op, compile_program
from gaitgram.motion.parser import NodeKind, Syntax
from gaitgram.motion.vocabulary import BINARY_UFUNCS, FUNCTIONS

NAN_PAYLOADS = [
    struct.unpack(">d", bytes.fromhex(h))[0]
    for h in ("7ff8000000000001", "fff8000000000000", "7ff4000000000000")
]
doubles = st.one_of(
    st.floats(),
    st.sampled_from([0.0, -0.0, math.inf, -math.inf, 5e-324, -5e-324, 1.7976931348623157e308, *NAN_PAYLOADS]),
)


def bits(value: float) -> bytes:
    return struct.pack(">d", value)


def constant(*nodes: tuple) -> float | None:
    return compile_program(Syntax("", tuple((*node, 0, 0, 0, 0) for node in nodes))).constant


@given(doubles, doubles, st.sampled_from("+-*/"))
@example(math.inf, -math.inf, "+")
@example(0.0, math.inf, "*")
@example(-NAN_PAYLOADS[0], NAN_PAYLOADS[1], "-")
def test_folding_a_binary_operation_gives_numpys_bits(left: float, right: float, op: str) -> None:
    folded = constant((NodeKind.NUMBER, left), (NodeKind.NUMBER, right), (NodeKind.BINARY, op))
    if op == "/" and right == 0:
        assert folded is None  # left for the machine, which reports the zero divisor
        return
    with np.errstate(all="ignore"):
        expected = BINARY_UFUNCS[op](np.float64(left), np.float64(right))
    assert folded is not None
    assert bits(folded) == bits(float(expected))


@given(doubles, st.sampled_from(sorted(FUNCTIONS)))
def test_folding_a_call_gives_numpys_bits(argument: float, name: str) -> None:
    folded = constant((NodeKind.NUMBER, argument), (NodeKind.CALL, name))
    with np.errstate(all="ignore"):
        expected = FUNCTIONS[name].ufunc(np.float64(argument))
    assert folded is not None
    assert bits(folded) == bits(float(expected))


def test_a_constant_zero_divisor_stays_in_the_program() -> None:
    program = compile_program(
        Syntax(
            "",
            (
                (NodeKind.NUMBER, 1.0, 0, 1, 0, 0),
                (NodeKind.NUMBER, 0.0, 2, 3, 0, 0),
                (NodeKind.BINARY, "/", 0, 3, 2, 3),
            ),
        )
    )
    assert [step[0] for step in program.instructions] == [Op.PUSH, Op.BINARY_CONST]
    assert program.instructions[-1][3] == (0, 3, 2, 3)  # the division's span and its divisor's
