"""The motion expression compiler against a plain reference evaluator, and its error reporting."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from motion_texts import expressions, render

from gaitgram.motion import (
    Curve,
    Motion,
    MotionError,
    MotionStatus,
    compile_motion,
    evaluate_motion,
    parse_expression,
    phase_grid,
    to_text,
)
from gaitgram.motion.expression import (
    Binary,
    Call,
    Expr,
    Name,
    Number,
    Unary,
    postorder,
)

SEED = "6.97+7.7*sin(1*2*PI*t+1.07)+2.56*sin(2*2*PI*t+2.97)"
PHASES = np.concatenate([phase_grid(16), [0.3, 0.999, 1 / 3]])

# ---------------------------------------------------------------------------------------------
# The reference: Python floats and math, one phase at a time.


def reference(node: Expr, t: float, zero_divisions: list[bool]) -> float:
    match node:
        case Number(value=value):
            return value
        case Name(name="t"):
            return t
        case Name():
            return math.pi
        case Unary(op=op, operand=operand):
            value = reference(operand, t, zero_divisions)
            return -value if op == "-" else value
        case Binary(op=op, left=left, right=right):
            a = reference(left, t, zero_divisions)
            b = reference(right, t, zero_divisions)
            if op == "+":
                return a + b
            if op == "-":
                return a - b
            if op == "*":
                return a * b
            if b == 0:  # IEEE 754 division by zero, which Python raises on
                zero_divisions.append(True)
                return (
                    math.nan if a == 0 or math.isnan(a) else math.copysign(math.inf, a) * math.copysign(1, b)
                )
            return a / b
        case Call(name=name, args=(arg,)):
            value = reference(arg, t, zero_divisions)
            try:
                return math.sin(value) if name == "sin" else math.cos(value)
            except ValueError:  # sin(inf)
                return math.nan
    raise AssertionError(node)


def reference_curve(node: Expr, phases: np.ndarray) -> tuple[MotionStatus, np.ndarray]:
    zero_divisions: list[bool] = []
    values = np.array([reference(node, float(t), zero_divisions) for t in phases])
    if zero_divisions:
        return MotionStatus.DIVISION_BY_ZERO, values
    if not np.isfinite(values).all():
        return MotionStatus.NON_FINITE, values
    return MotionStatus.OK, values


def assert_same_values(actual: np.ndarray, expected: np.ndarray) -> None:
    """Equal within 1e-9 where finite; the same infinities; NaN where the reference has NaN."""
    assert actual.shape == expected.shape
    finite = np.isfinite(expected)
    np.testing.assert_array_equal(np.isfinite(actual), finite)
    np.testing.assert_allclose(actual[finite], expected[finite], rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(actual[~finite], expected[~finite])  # inf == inf, nan == nan here


# ---------------------------------------------------------------------------------------------
# Properties


@pytest.mark.filterwarnings("error")
@given(expressions, st.randoms(use_true_random=False))
def test_compiled_evaluation_matches_reference(expr: Expr, rng: random.Random) -> None:
    text = render(expr, rng)
    motion = compile_motion(text)
    assert isinstance(motion, Motion), motion
    curve = motion.evaluate(PHASES)
    status, expected = reference_curve(expr, PHASES)
    assert curve.status is status, (text, curve.error)
    assert_same_values(curve.values, expected)
    assert_same_values(motion(PHASES), expected)
    if status is MotionStatus.OK:
        assert curve.error is None
    else:
        assert curve.error is not None
        assert curve.error.status is status
        assert 0 <= curve.error.offset <= curve.error.offset + curve.error.length <= len(text)
        assert curve.error.phase in PHASES


@given(expressions, st.randoms(use_true_random=False))
def test_parsing_round_trips(expr: Expr, rng: random.Random) -> None:
    assert parse_expression(render(expr, rng)) == expr
    compact = to_text(expr)
    assert parse_expression(compact) == expr
    assert to_text(parse_expression(compact)) == compact  # type: ignore[arg-type]


@given(expressions, st.randoms(use_true_random=False))
def test_every_span_reparses_to_its_node(expr: Expr, rng: random.Random) -> None:
    text = render(expr, rng)
    tree = parse_expression(text)
    assert not isinstance(tree, MotionError)
    for node in postorder(tree):
        assert parse_expression(text[node.start : node.end]) == node


@given(st.lists(st.floats(-360, 360), min_size=0, max_size=4))
def test_curves_keep_the_shape_of_the_phases(values: list[float]) -> None:
    motion = compile_motion("t")
    assert isinstance(motion, Motion)
    phases = np.array(values)
    out = motion(phases)
    np.testing.assert_array_equal(out, phases)
    out[...] = 1.0  # a fresh array, never the caller's phases
    np.testing.assert_array_equal(phases, np.array(values))


@pytest.mark.filterwarnings("error")
@given(st.text(alphabet=st.sampled_from(list("0123456789.eE+-*/() tPIpisncoxa_,'^\n")), max_size=40))
def test_any_text_gives_a_result_never_an_exception(text: str) -> None:
    result = compile_motion(text)
    assert isinstance(result, Motion | MotionError)
    curve = evaluate_motion(text, PHASES)
    assert isinstance(curve, Curve)
    assert curve.values.shape == PHASES.shape
    if isinstance(result, MotionError):
        assert curve.status is result.status
        assert np.isnan(curve.values).all()
        assert 0 <= result.offset <= result.offset + result.length <= len(text)
        assert result.status in (MotionStatus.PARSE_ERROR, MotionStatus.UNKNOWN_NAME)


# ---------------------------------------------------------------------------------------------
# The paper's phenotypes


def test_the_papers_seed_curve() -> None:
    motion = compile_motion(SEED)
    assert isinstance(motion, Motion)
    t = phase_grid(100)
    expected = 6.97 + 7.7 * np.sin(1 * 2 * np.pi * t + 1.07) + 2.56 * np.sin(2 * 2 * np.pi * t + 2.97)
    np.testing.assert_allclose(motion(t), expected, rtol=0, atol=1e-12)
    assert motion.uses_phase


@pytest.mark.parametrize(
    "text",
    [
        # Fig. 2: seed plus concatenated functions, with GE's spacing, signs and a bare amplitude.
        SEED + " + 0.25 * sin( 1 * 2 * PI * t ) - 4 * cos( 6 * 2 * PI * t ) + 0.3",
        SEED + " - 0 * cos( 8 * 2 * PI * t )",
        # A typed range with negative values derives `+-`.
        "7.7*sin(1*2*PI*t+-3.14)",
        # Fig. 5, the free grammar: nested operators, `sin (<expr> * t)` with a space.
        "(t + 3) / sin (2 * t) * cos ((t - 0.5) * t)",
        "((t)) - -t",
    ],
)
def test_grammar_phenotypes_compile(text: str) -> None:
    curve = evaluate_motion(text, phase_grid(64))
    assert curve.ok or curve.status is MotionStatus.DIVISION_BY_ZERO, curve.error


def test_constant_expressions_are_folded() -> None:
    motion = compile_motion("2*PI - 1/4 + cos(0)")
    assert isinstance(motion, Motion)
    assert motion.constant == pytest.approx(2 * math.pi - 0.25 + 1)
    assert not motion.uses_phase
    np.testing.assert_array_equal(motion(np.zeros((2, 3))), np.full((2, 3), motion.constant))


def test_compiling_is_cached() -> None:
    assert compile_motion(SEED) is compile_motion(SEED)


def test_deep_nesting_does_not_overflow_the_stack() -> None:
    for text in [
        "(" * 5000 + "t" + ")" * 5000,
        "-" * 5000 + "t",
        "+".join(["t"] * 5000),
        "sin(" * 3000 + "t" + ")" * 3000,
    ]:
        curve = evaluate_motion(text, PHASES)
        assert curve.ok, curve.error
        assert isinstance(to_text(compile_motion(text).expr), str)  # type: ignore[union-attr]


# ---------------------------------------------------------------------------------------------
# Errors: a status, an offset and a message, never an exception


@pytest.mark.parametrize(
    ("text", "status", "offset", "length", "words"),
    [
        ("__import__('os').system('x')", MotionStatus.PARSE_ERROR, 11, 1, "unexpected character"),
        ("t.__class__", MotionStatus.PARSE_ERROR, 1, 1, "unexpected character '.'"),
        ("eval(t)", MotionStatus.UNKNOWN_NAME, 0, 4, "unknown function 'eval'"),
        ("lambda: 0", MotionStatus.PARSE_ERROR, 6, 1, "unexpected character ':'"),
        ("[t]", MotionStatus.PARSE_ERROR, 0, 1, "unexpected character '['"),
        ("1; 2", MotionStatus.PARSE_ERROR, 1, 1, "unexpected character ';'"),
        ("t\x00", MotionStatus.PARSE_ERROR, 1, 1, "unexpected character"),
        ("", MotionStatus.PARSE_ERROR, 0, 0, "empty"),
        ("   ", MotionStatus.PARSE_ERROR, 3, 0, "empty"),
        ("2 3", MotionStatus.PARSE_ERROR, 2, 1, "unexpected number '3'"),
        ("2 sin(t)", MotionStatus.PARSE_ERROR, 2, 3, "unexpected name 'sin'"),
        ("2*", MotionStatus.PARSE_ERROR, 2, 0, "unexpected end of text; expected a number"),
        ("(t", MotionStatus.PARSE_ERROR, 2, 0, "expected an operator (+ - * /) or ')'"),
        ("t)", MotionStatus.PARSE_ERROR, 1, 1, "unexpected ')'"),
        ("()", MotionStatus.PARSE_ERROR, 1, 1, "unexpected ')'"),
        ("2**t", MotionStatus.PARSE_ERROR, 2, 1, "unexpected '*'"),
        ("2^t", MotionStatus.PARSE_ERROR, 1, 1, "unexpected character '^'"),
        ("1e", MotionStatus.PARSE_ERROR, 1, 1, "unexpected name 'e'"),
        ("٣+t", MotionStatus.PARSE_ERROR, 0, 1, "unexpected character '٣'"),
        ("t + foo", MotionStatus.UNKNOWN_NAME, 4, 3, "unknown name 'foo'"),
        ("t + tan(t)", MotionStatus.UNKNOWN_NAME, 4, 3, "unknown function 'tan'"),
        ("Sin(t) + x", MotionStatus.UNKNOWN_NAME, 0, 3, "unknown function 'Sin'"),
        ("2*time", MotionStatus.UNKNOWN_NAME, 2, 4, "unknown name 'time'"),
        ("sin + 1", MotionStatus.PARSE_ERROR, 0, 3, "sin is a function"),
        ("1 + t(2)", MotionStatus.PARSE_ERROR, 4, 1, "t is not a function"),
        ("PI(2)", MotionStatus.PARSE_ERROR, 0, 2, "PI is not a function"),
        ("1 + sin(t, 2)", MotionStatus.PARSE_ERROR, 4, 9, "sin takes exactly one argument, not 2"),
        ("cos()", MotionStatus.PARSE_ERROR, 0, 5, "cos takes exactly one argument, not 0"),
    ],
)
def test_compile_errors(text: str, status: MotionStatus, offset: int, length: int, words: str) -> None:
    error = compile_motion(text)
    assert isinstance(error, MotionError)
    assert (error.status, error.offset, error.length) == (status, offset, length)
    assert words in error.message
    assert f"offset {offset}" in error.message or offset == len(text)


@pytest.mark.parametrize(
    ("text", "hint"),
    [
        ("__import__('os')", "no strings"),
        ("2**t", "powers"),
        ("2^t", "powers"),
        ("2 t", "'*'"),
        ("Sin(t)", "did you mean 'sin'"),
        ("tan(t)", "only sin and cos"),
        ("time", "'t'"),
    ],
)
def test_compile_errors_have_hints(text: str, hint: str) -> None:
    error = compile_motion(text)
    assert isinstance(error, MotionError)
    assert error.hint is not None
    assert hint in error.hint
    assert hint in str(error)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize(
    ("text", "status", "span", "phase", "words"),
    [
        ("1/(t-0.25)", MotionStatus.DIVISION_BY_ZERO, "1/(t-0.25)", 0.25, "the divisor '(t-0.25)' is 0"),
        ("3 + 1/0", MotionStatus.DIVISION_BY_ZERO, "1/0", 0.0, "division by zero"),
        ("t + 0/(t*0)", MotionStatus.DIVISION_BY_ZERO, "0/(t*0)", 0.0, "division by zero"),
        # The divisor is zero even though the result is finite again.
        ("1/(1/(t-t))", MotionStatus.DIVISION_BY_ZERO, "(1/(t-t))", 0.0, "division by zero"),
        ("t*1e200*1e200", MotionStatus.NON_FINITE, "t*1e200*1e200", 0.125, "is inf"),
        ("1e200*1e200 + t", MotionStatus.NON_FINITE, "1e200*1e200", 0.0, "is inf"),
        ("sin(1e999*t)", MotionStatus.NON_FINITE, "1e999", 0.0, "is inf"),
        ("sin(t + 1e999)", MotionStatus.NON_FINITE, "1e999", 0.0, "is inf"),
        ("sin(1e307*(t+10)*10)", MotionStatus.NON_FINITE, "1e307*(t+10)*10", 0.0, "is inf"),
    ],
)
def test_evaluation_errors(text: str, status: MotionStatus, span: str, phase: float, words: str) -> None:
    motion = compile_motion(text)
    assert isinstance(motion, Motion)
    curve = motion.evaluate(phase_grid(8))
    assert curve.status is status
    assert not curve.ok
    error = curve.error
    assert error is not None
    assert error.status is status
    assert text[error.offset : error.offset + error.length] == span
    assert error.phase == phase
    assert words in error.message
    assert curve.values.shape == (8,)


def test_evaluation_on_no_phases_is_ok() -> None:
    curve = evaluate_motion("1/(t-t)", np.array([]))
    assert curve.ok
    assert curve.values.shape == (0,)


def test_evaluate_motion_reports_compile_errors_as_nan_curves() -> None:
    curve = evaluate_motion("sin(t", np.zeros((2, 5)))
    assert curve.status is MotionStatus.PARSE_ERROR
    assert curve.values.shape == (2, 5)
    assert np.isnan(curve.values).all()
    assert curve.error == compile_motion("sin(t")
