"""Motion expressions: a joint curve's phenotype text, parsed and evaluated over the gait phase.

A phenotype is untrusted text that GE assembled from grammar pieces, so it is
read by our own parser and never reaches ``eval``. The language is the paper's:
numbers, the phase ``t`` in [0, 1), ``PI`` (or ``pi``), ``+ - * /``, unary minus
and plus, parentheses, ``sin`` and ``cos``; that is everything its grammars
(Fig. 2 and the free grammar of Fig. 5) derive. ``expression.lark`` defines the
syntax; a hand-written operator-precedence parser accepts exactly that language
several times faster, and lark itself reports the errors.

Everything that can go wrong with a phenotype is a value, not an exception:
:func:`compile_motion` returns a :class:`Motion` or a :class:`MotionError`, and
:meth:`Motion.evaluate` returns a :class:`Curve` whose :class:`MotionStatus` says
whether the values are usable (a division by zero, or a non-finite value, at
some phase of the grid). A fitness backend can score any status without a
``try``.

Evaluation is a small stack machine over whole numpy arrays: one pass over a
flat program per evaluation, however many phases, and no recursion, so deeply
nested phenotypes cannot overflow the Python stack. Subexpressions without
``t`` are folded to constants at compile time with the same float64 arithmetic.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from enum import IntEnum, StrEnum
from functools import cache, lru_cache
from importlib.resources import files
from typing import Any, NamedTuple

import numpy as np
from lark import Lark, Token, Transformer, v_args
from lark.exceptions import LarkError, UnexpectedCharacters, UnexpectedInput, UnexpectedToken
from numpy.typing import ArrayLike, NDArray

# ---------------------------------------------------------------------------------------------
# Results


class MotionStatus(StrEnum):
    """Whether a phenotype gives a usable curve, and if not, why."""

    OK = "ok"
    #: The text is not a motion expression (syntax, a function called with the wrong arity, a
    #: constant called as a function). Adversarial text such as ``__import__('os')`` lands here.
    PARSE_ERROR = "parse-error"
    #: A name that is not ``t``, ``PI``, ``pi``, ``sin`` or ``cos``.
    UNKNOWN_NAME = "unknown-name"
    #: Some divisor is exactly zero at some phase of the evaluation grid.
    DIVISION_BY_ZERO = "division-by-zero"
    #: The curve is infinite or NaN at some phase (overflow, ``sin`` of infinity, ...).
    NON_FINITE = "non-finite"
    #: From :func:`gaitgram.motion.fourier.fourier_coefficients`: the curve is not a finite sum of
    #: sines of whole harmonics up to the requested one.
    NOT_A_SUM_OF_SINES = "not-a-sum-of-sines"


@dataclass(frozen=True, slots=True)
class MotionError:
    """What is wrong with a phenotype, and where: ``text[offset:offset + length]``.

    ``phase`` is the first grid phase where an evaluation problem shows, if any.
    """

    status: MotionStatus
    message: str
    offset: int = 0
    length: int = 0
    hint: str | None = None
    phase: float | None = None

    def __str__(self) -> str:
        return self.message if self.hint is None else f"{self.message} ({self.hint})"


@dataclass(frozen=True, slots=True, eq=False)
class Curve:
    """A motion evaluated at some phases: always has values, usable only if ``ok``.

    The values are kept even when the status is not OK (NaN everywhere if the text
    did not compile), so a plot can still show what went wrong.
    """

    status: MotionStatus
    values: NDArray[np.float64]
    error: MotionError | None = None

    @property
    def ok(self) -> bool:
        return self.status is MotionStatus.OK


# ---------------------------------------------------------------------------------------------
# Syntax tree. Spans (``start``, ``end``: offsets into the text) do not take part in equality,
# so a tree parsed from differently spaced or parenthesised text compares equal.


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


# ---------------------------------------------------------------------------------------------
# The vocabulary


@dataclass(frozen=True, slots=True)
class Function:
    """A function a phenotype may call: its numpy ufunc, and why it is in the language."""

    name: str
    ufunc: np.ufunc
    doc: str


#: Functions, each of one argument in radians. Only what the paper's grammars derive: a wider
#: vocabulary (tan, exp, log, sqrt, powers) would add singularities and domain errors that no
#: gait needs. Add an entry here to extend the language; nothing else needs to change.
FUNCTIONS: dict[str, Function] = {
    "sin": Function("sin", np.sin, "the sum-of-sines representation (Eq. 1, Fig. 2)"),
    "cos": Function("cos", np.cos, "cosine terms of the concatenating grammar (Fig. 2) and Fig. 5"),
}

#: Named constants. The paper writes ``PI``; ``pi`` is accepted as well.
CONSTANTS: dict[str, float] = {"PI": math.pi, "pi": math.pi}

#: The phase of the gait cycle, in [0, 1).
VARIABLE = "t"

_UNSUPPORTED = {"tan", "exp", "log", "ln", "sqrt", "abs", "pow", "min", "max", "asin", "acos", "atan"}


def phase_grid(n_samples: int) -> NDArray[np.float64]:
    """``n_samples`` equally spaced phases ``k / n`` over one cycle, the end excluded."""
    if n_samples < 1:
        raise ValueError(f"a phase grid needs at least one sample, not {n_samples}")
    return np.arange(n_samples, dtype=np.float64) / n_samples


# ---------------------------------------------------------------------------------------------
# Parsing


@v_args(inline=True)
class _TreeBuilder(Transformer):
    """LALR callbacks that build the syntax tree while parsing (no lark Tree in between)."""

    def start(self, expr: Expr) -> Expr:
        return expr

    def number(self, token: Token) -> Number:
        return Number(float(token), token.start_pos, token.end_pos)

    def name(self, token: Token) -> Name:
        return Name(str(token), token.start_pos, token.end_pos)

    def unary(self, op: Token, operand: Expr) -> Unary:
        return Unary(str(op), operand, op.start_pos, operand.end)

    def binary(self, left: Expr, op: Token, right: Expr) -> Binary:
        return Binary(str(op), left, right, left.start, right.end)

    def group(self, lpar: Token, expr: Expr, rpar: Token) -> Expr:
        return replace(expr, start=lpar.start_pos, end=rpar.end_pos)

    def arguments(self, *items: Expr | Token) -> tuple[Expr, ...]:
        return tuple(item for item in items if not isinstance(item, Token))

    def call(self, name: Token, _lpar: Token, *rest: tuple[Expr, ...] | Token) -> Call:
        args = rest[0] if len(rest) == 2 else ()
        rpar = rest[-1]
        assert isinstance(args, tuple)
        assert isinstance(rpar, Token)
        return Call(str(name), args, name.start_pos, rpar.end_pos)


@cache
def _parser() -> Lark:
    grammar = files("gaitgram.motion").joinpath("expression.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="lalr", lexer="basic", transformer=_TreeBuilder(), maybe_placeholders=False)


def parse_expression(text: str) -> Expr | MotionError:
    """The syntax tree of ``text``, or a PARSE_ERROR. Names are not checked here.

    Well-formed text takes a fast path (:func:`_fast_parse`); anything it rejects is
    parsed again by lark from ``expression.lark``, which either reports the error
    or, should the two ever disagree, has the final word.
    """
    tree = _fast_parse(text)
    if tree is not None:
        return tree
    return _lark_parse(text)


def _lark_parse(text: str) -> Expr | MotionError:
    try:
        return _parser().parse(text)
    except UnexpectedInput as exc:
        return _syntax_error(text, exc)
    except (LarkError, RecursionError) as exc:  # pragma: no cover - defensive
        return MotionError(MotionStatus.PARSE_ERROR, f"malformed motion expression: {exc}", 0, len(text))


# The terminals of expression.lark in one pattern; `bad` is anything else (lark's error).
_TOKENS = re.compile(
    r"(?P<ws>[ \t\r\n]+)"
    r"|(?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>[-+*/(),])"
    r"|(?P<bad>[\s\S])"
)
_BINARY_PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2}
_UNARY, _BINARY, _LPAR, _CALL = "unary", "binary", "(", "call"


def _fast_parse(text: str) -> Expr | None:
    """Operator-precedence parsing of ``expression.lark``'s language, or None if malformed.

    lark's LALR parser with tree-building callbacks costs about 9 microseconds a token
    here; this loop is three to four times faster, which matters when every generation
    maps hundreds of phenotypes of hundreds of tokens. It builds exactly the trees (and
    spans) of the lark callbacks, which the tests check on random text. Iterative, so
    nesting depth is unlimited.
    """
    tokens = [
        (kind, match.group(), match.start(), match.end())
        for match in _TOKENS.finditer(text)
        if (kind := match.lastgroup) != "ws"
    ]
    operands: list[Expr] = []
    # (kind, text, start, end, argument count): binary operators, unary operators, "(" and calls
    operators: list[list] = []

    def reduce_one() -> None:
        kind, op, start, _, _ = operators.pop()
        right = operands.pop()
        if kind == _UNARY:
            operands.append(Unary(op, right, start, right.end))
        else:
            left = operands.pop()
            operands.append(Binary(op, left, right, left.start, right.end))

    def reduce_while(precedence: int) -> None:
        # Unary operators bind tighter than any binary one; "(" and calls are barriers.
        while operators:
            kind, op = operators[-1][0], operators[-1][1]
            if kind in (_LPAR, _CALL) or (kind == _BINARY and _BINARY_PRECEDENCE[op] < precedence):
                return
            reduce_one()

    expect_operand = True
    index, count = 0, len(tokens)
    while index < count:
        kind, value, start, end = tokens[index]
        index += 1
        if kind == "bad":
            return None
        if expect_operand:
            if kind == "number":
                operands.append(Number(float(value), start, end))
                expect_operand = False
            elif kind == "name":
                if index < count and tokens[index][1] == "(":
                    index += 1
                    if index < count and tokens[index][1] == ")":
                        operands.append(Call(value, (), start, tokens[index][3]))
                        index += 1
                        expect_operand = False
                    else:
                        operators.append([_CALL, value, start, end, 1])
                else:
                    operands.append(Name(value, start, end))
                    expect_operand = False
            elif value in ("+", "-"):
                operators.append([_UNARY, value, start, end, 0])
            elif value == "(":
                operators.append([_LPAR, value, start, end, 0])
            else:
                return None
        elif value in _BINARY_PRECEDENCE:
            reduce_while(_BINARY_PRECEDENCE[value])
            operators.append([_BINARY, value, start, end, 0])
            expect_operand = True
        elif value == ")":
            reduce_while(0)
            if not operators:
                return None
            opener, name, open_start, _, n_args = operators.pop()
            if opener == _LPAR:
                operands.append(replace(operands.pop(), start=open_start, end=end))
            else:
                args = tuple(operands[len(operands) - n_args :])
                del operands[len(operands) - n_args :]
                operands.append(Call(name, args, open_start, end))
        elif value == ",":
            reduce_while(0)
            if not operators or operators[-1][0] != _CALL:
                return None
            operators[-1][4] += 1
            expect_operand = True
        else:
            return None
    if expect_operand:
        return None
    reduce_while(0)
    if operators:
        return None
    (tree,) = operands
    return tree


_OPERAND = "a number, t, PI, a function call or '('"


def _expected(exc: UnexpectedInput) -> str:
    """What may come next, in words: an operand, or an operator and what may close."""
    parser = getattr(exc, "interactive_parser", None)
    # lark's ``expected`` is the LALR state's set, which may list tokens that cannot follow;
    # the interactive parser knows exactly.
    terminals = parser.accepts() if parser is not None else getattr(exc, "expected", set())
    if "NUMBER" in terminals or "NAME" in terminals:
        return _OPERAND
    closers = [word for name, word in (("RPAR", "')'"), ("$END", "the end")) if name in terminals]
    return " or ".join(["an operator (+ - * /)", *closers])


def _syntax_error(text: str, exc: UnexpectedInput) -> MotionError:
    hint = None
    if isinstance(exc, UnexpectedCharacters):
        offset, length = exc.pos_in_stream, 1
        char = text[offset : offset + 1]
        message = f"unexpected character {char!r} at offset {offset}"
        if char and char in "'\"":
            hint = "a motion expression has no strings"
        elif char == "^":
            hint = "powers are not supported: multiply instead"
        elif char.isdigit():
            hint = "write numbers with ASCII digits"
    elif isinstance(exc, UnexpectedToken) and exc.token.type != "$END":
        token = exc.token
        offset, length = token.start_pos, len(token)
        kind = {"NUMBER": "number ", "NAME": "name "}.get(token.type, "")
        message = f"unexpected {kind}{str(token)!r} at offset {offset}; expected {_expected(exc)}"
        if token.type == "STAR" and text[:offset].rstrip().endswith("*"):
            hint = "powers (**) are not supported: multiply instead"
        elif token.type in ("NUMBER", "NAME", "LPAR"):
            hint = "write '*' for a product"
    else:  # the end of the text came too early
        offset, length = len(text), 0
        if not text.strip():
            message = "empty motion expression"
        else:
            message = f"unexpected end of text; expected {_expected(exc)}"
    return MotionError(MotionStatus.PARSE_ERROR, message, offset, length, hint)


# ---------------------------------------------------------------------------------------------
# Rendering


_UNARY_PRECEDENCE = 3
_ATOM_PRECEDENCE = 4


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
                stack.append((text, _ATOM_PRECEDENCE if not text.startswith("-") else _UNARY_PRECEDENCE))
            case Name(name=name):
                stack.append((name, _ATOM_PRECEDENCE))
            case Unary(op=op):
                operand, precedence = stack.pop()
                stack.append((f"{op}{_wrap(operand, precedence < _UNARY_PRECEDENCE)}", _UNARY_PRECEDENCE))
            case Binary(op=op):
                right, right_precedence = stack.pop()
                left, left_precedence = stack.pop()
                precedence = _BINARY_PRECEDENCE[op]
                left = _wrap(left, left_precedence < precedence)
                right = _wrap(right, right_precedence <= precedence)
                stack.append((f"{left}{op}{right}", precedence))
            case Call(name=name, args=args):
                items = [stack.pop()[0] for _ in args][::-1]
                stack.append((f"{name}({','.join(items)})", _ATOM_PRECEDENCE))
    return stack[-1][0]


def _wrap(text: str, needed: bool) -> str:
    return f"({text})" if needed else text


# ---------------------------------------------------------------------------------------------
# Compiling


class _Op(IntEnum):
    T = 0  # push the phases
    PUSH = 1  # push a constant
    UNARY = 2  # top = f(top)
    BINARY = 3  # b = pop; top = f(top, b)
    BINARY_CONST = 4  # top = f(top, c)
    CONST_BINARY = 5  # top = f(c, top)


class _Instruction(NamedTuple):
    """One step of the stack machine (a tuple: the evaluation loop unpacks it cheaply)."""

    op: _Op
    func: Callable[..., Any] | None = None
    const: float = 0.0
    node: Binary | None = None  # the operation, for locating a zero divisor


_BINARY_UFUNCS = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.true_divide}


@dataclass(frozen=True, slots=True)
class _Dynamic:
    """A compile-time stack entry whose value depends on ``t`` (its code is already emitted)."""


_DYNAMIC = _Dynamic()


def _compile(tree: Expr) -> tuple[tuple[_Instruction, ...], float | None] | MotionError:
    """Resolve names and emit the program; a fully constant tree gives its value instead.

    Constant subtrees are folded with numpy's float64 arithmetic, exactly as the array
    evaluation would compute them (the caller holds ``np.errstate``).
    """
    problems: list[MotionError] = []
    program: list[_Instruction] = []
    stack: list[float | _Dynamic] = []

    def materialise(index: int) -> None:
        # Only a constant division by zero needs a constant on the runtime stack: it is left
        # unfolded so every evaluation reports it, like any other zero divisor.
        value = stack[index]
        assert not isinstance(value, _Dynamic)
        program.append(_Instruction(_Op.PUSH, const=value))
        stack[index] = _DYNAMIC

    for node in postorder(tree):
        kind = type(node)
        if kind is Number:
            stack.append(node.value)
        elif kind is Binary:
            op = node.op
            func = _BINARY_UFUNCS[op]
            right = stack.pop()
            left = stack[-1]
            if left is _DYNAMIC:
                if right is _DYNAMIC:
                    program.append(_Instruction(_Op.BINARY, func, node=node))
                else:
                    program.append(_Instruction(_Op.BINARY_CONST, func, right, node))
            elif right is _DYNAMIC:
                program.append(_Instruction(_Op.CONST_BINARY, func, left, node))
                stack[-1] = _DYNAMIC
            elif op == "/" and right == 0:
                materialise(-1)
                program.append(_Instruction(_Op.BINARY_CONST, func, right, node))
            else:
                stack[-1] = float(func(np.float64(left), np.float64(right)))
        elif kind is Name:
            name = node.name
            if name == VARIABLE:
                program.append(_Instruction(_Op.T))
                stack.append(_DYNAMIC)
            elif name in CONSTANTS:
                stack.append(CONSTANTS[name])
            else:
                problems.append(_name_problem(node, called=False))
                stack.append(0.0)
        elif kind is Unary:
            if node.op == "-":
                if stack[-1] is _DYNAMIC:
                    program.append(_Instruction(_Op.UNARY, np.negative))
                else:
                    stack[-1] = -stack[-1]
        else:  # Call
            name, n_args = node.name, len(node.args)
            function = FUNCTIONS.get(name)
            arguments = stack[len(stack) - n_args :]
            del stack[len(stack) - n_args :]
            if function is None:
                problems.append(_name_problem(node, called=True))
                stack.append(0.0)
            elif n_args != 1:
                problems.append(
                    MotionError(
                        MotionStatus.PARSE_ERROR,
                        f"{name} takes exactly one argument, not {n_args}, at offset {node.start}",
                        node.start,
                        node.end - node.start,
                        f"write {name}(x)",
                    )
                )
                stack.append(0.0)
            elif arguments[0] is _DYNAMIC:
                program.append(_Instruction(_Op.UNARY, function.ufunc))
                stack.append(_DYNAMIC)
            else:
                stack.append(float(function.ufunc(np.float64(arguments[0]))))
    if problems:
        return min(problems, key=lambda p: p.offset)
    (result,) = stack
    return tuple(program), (None if isinstance(result, _Dynamic) else result)


def _name_problem(node: Name | Call, *, called: bool) -> MotionError:
    name = node.name
    offset, length = node.start, len(name)
    if called and (name == VARIABLE or name in CONSTANTS):
        return MotionError(
            MotionStatus.PARSE_ERROR,
            f"{name} is not a function, at offset {offset}",
            offset,
            length,
            f"write '*' for a product: {name}*(...)",
        )
    if not called and name in FUNCTIONS:
        return MotionError(
            MotionStatus.PARSE_ERROR,
            f"{name} is a function, at offset {offset}",
            offset,
            length,
            f"call it: {name}(...)",
        )
    kind = "function" if called else "name"
    known = sorted(FUNCTIONS) if called else [VARIABLE, *CONSTANTS]
    message = f"unknown {kind} {name!r} at offset {offset}; known: {', '.join(known)}"
    close = [k for k in (*FUNCTIONS, VARIABLE, *CONSTANTS) if k.lower() == name.lower()]
    if close:
        hint = f"did you mean {close[0]!r}? names are case-sensitive"
    elif name.lower() in ("time", "phase"):
        hint = f"the phase variable is {VARIABLE!r}"
    elif name.lower() in _UNSUPPORTED:
        hint = f"motion expressions support only {' and '.join(FUNCTIONS)}"
    else:
        hint = None
    return MotionError(MotionStatus.UNKNOWN_NAME, message, offset, length, hint)


# ---------------------------------------------------------------------------------------------
# Motions


@dataclass(frozen=True, slots=True, eq=False)
class Motion:
    """A compiled phenotype: a vectorised function of the phase ``t``.

    Build one with :func:`compile_motion`. Calling it gives raw values (NaN and inf
    included, never a warning); :meth:`evaluate` adds the status a fitness needs.
    """

    text: str
    expr: Expr
    program: tuple[_Instruction, ...] = field(repr=False)
    #: The value of an expression without ``t`` (folded at compile time), else None.
    constant: float | None = field(repr=False)

    @property
    def uses_phase(self) -> bool:
        """Whether the curve moves at all: a phenotype without ``t`` is a fixed angle."""
        return any(isinstance(node, Name) and node.name == VARIABLE for node in postorder(self.expr))

    def __call__(self, phases: ArrayLike) -> NDArray[np.float64]:
        t = np.asarray(phases, dtype=np.float64)
        with np.errstate(all="ignore"):
            return self._run(t)[0]

    def evaluate(self, phases: ArrayLike) -> Curve:
        """The curve at ``phases`` (any shape), with DIVISION_BY_ZERO or NON_FINITE if it fails."""
        t = np.asarray(phases, dtype=np.float64)
        with np.errstate(all="ignore"):
            values, zero = self._run(t)
        if zero is not None:
            node, index = zero
            phase = float(t.flat[index]) if t.size else 0.0
            divisor = node.right
            snippet = self.text[divisor.start : divisor.end]
            error = MotionError(
                MotionStatus.DIVISION_BY_ZERO,
                f"division by zero at t={phase:.6g}: the divisor {snippet!r} is 0",
                node.start,
                node.end - node.start,
                phase=phase,
            )
            return Curve(MotionStatus.DIVISION_BY_ZERO, values, error)
        finite = np.isfinite(values)
        if not finite.all():
            index = int(np.argmin(finite.reshape(-1)))
            return Curve(MotionStatus.NON_FINITE, values, self._non_finite(float(t.flat[index])))
        return Curve(MotionStatus.OK, values)

    def sample(self, n_samples: int) -> Curve:
        """The curve on :func:`phase_grid` of ``n_samples``: one cycle, the end excluded."""
        return self.evaluate(phase_grid(n_samples))

    def _run(self, t: NDArray[np.float64]) -> tuple[NDArray[np.float64], tuple[Binary, int] | None]:
        if self.constant is not None:
            return np.full(t.shape, self.constant), None
        stack: list = []
        zero: tuple[Binary, int] | None = None
        T, PUSH, UNARY, BINARY, BINARY_CONST = _Op.T, _Op.PUSH, _Op.UNARY, _Op.BINARY, _Op.BINARY_CONST  # noqa: N806
        divide = np.true_divide
        for op, func, const, node in self.program:
            if op == BINARY_CONST:
                left, right = stack[-1], const
            elif op == UNARY:
                stack[-1] = func(stack[-1])
                continue
            elif op == T:
                stack.append(t)
                continue
            elif op == BINARY:
                right = stack.pop()
                left = stack[-1]
            elif op == PUSH:
                stack.append(np.float64(const))
                continue
            else:  # CONST_BINARY
                left, right = const, stack[-1]
            if func is divide and zero is None:
                hits = np.equal(right, 0)
                if hits.any():
                    index = int(np.argmax(np.broadcast_to(hits, t.shape).reshape(-1))) if t.size else 0
                    zero = (node, index)
            stack[-1] = func(left, right)
        (result,) = stack
        if isinstance(result, np.ndarray) and result is not t and result.shape == t.shape:
            return result, zero
        return np.array(np.broadcast_to(result, t.shape), dtype=np.float64), zero

    def _non_finite(self, phase: float) -> MotionError:
        """Find the smallest subexpression that turns finite values into a non-finite one."""
        values: list[np.float64] = []
        with np.errstate(all="ignore"):
            for node in postorder(self.expr):
                arity = len(children(node))
                inputs = values[len(values) - arity :]
                del values[len(values) - arity :]
                value = _scalar_node(node, inputs, phase)
                values.append(value)
                if not np.isfinite(value) and all(np.isfinite(v) for v in inputs):
                    snippet = self.text[node.start : node.end]
                    return MotionError(
                        MotionStatus.NON_FINITE,
                        f"{snippet!r} is {float(value)} at t={phase:.6g}",
                        node.start,
                        node.end - node.start,
                        phase=phase,
                    )
        return MotionError(  # pragma: no cover - the scalar replay disagrees with the array run
            MotionStatus.NON_FINITE,
            f"the curve is not finite at t={phase:.6g}",
            0,
            len(self.text),
            phase=phase,
        )


def _scalar_node(node: Expr, inputs: list[np.float64], phase: float) -> np.float64:
    match node:
        case Number(value=value):
            return np.float64(value)
        case Name(name=name):
            return np.float64(phase if name == VARIABLE else CONSTANTS[name])
        case Unary(op=op):
            return -inputs[0] if op == "-" else inputs[0]
        case Binary(op=op):
            return _BINARY_UFUNCS[op](inputs[0], inputs[1])
        case Call(name=name):
            return FUNCTIONS[name].ufunc(inputs[0])
    raise AssertionError(node)  # pragma: no cover


@lru_cache(maxsize=4096)
def compile_motion(text: str) -> Motion | MotionError:
    """Compile phenotype text to a :class:`Motion`, or say why it is not one.

    Never raises for any string. Results are cached: GE re-evaluates elites and
    duplicate phenotypes, and both results are immutable.
    """
    tree = parse_expression(text)
    if isinstance(tree, MotionError):
        return tree
    with np.errstate(all="ignore"):
        compiled = _compile(tree)
    if isinstance(compiled, MotionError):
        return compiled
    program, constant = compiled
    return Motion(text, tree, program, constant)


def evaluate_motion(motion: Motion | str, phases: ArrayLike) -> Curve:
    """Compile (if text) and evaluate: a total function for batches, one :class:`Curve` per call.

    Text that does not compile gives a curve of NaN with the compile error.
    """
    if isinstance(motion, str):
        compiled = compile_motion(motion)
        if isinstance(compiled, MotionError):
            shape = np.shape(phases)
            return Curve(compiled.status, np.full(shape, np.nan), compiled)
        motion = compiled
    return motion.evaluate(phases)
