"""``expression.lark`` parsed by lark: the reference the motion parser is tested against.

Until commit d99e791 gaitgram parsed malformed text with exactly this (lark's LALR parser
with tree-building callbacks) and worded its errors from lark's exceptions as below; the
parser in ``gaitgram/motion/parser.py`` must give the same trees, spans and errors.
"""

from __future__ import annotations

from dataclasses import replace
from functools import cache
from importlib.resources import files

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from gaitgram.motion.results import MotionError, MotionStatus
from gaitgram.motion.tree import Binary, Call, Expr, Name, Number, Unary


@v_args(inline=True)
class _TreeBuilder(Transformer):
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
def lark_parser() -> Lark:
    grammar = files("gaitgram.motion").joinpath("expression.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="lalr", lexer="basic", transformer=_TreeBuilder(), maybe_placeholders=False)


def lark_parse(text: str) -> Expr | MotionError:
    try:
        return lark_parser().parse(text)
    except UnexpectedInput as exc:
        return _syntax_error(text, exc)


_OPERAND = "a number, t, PI, a function call or '('"


def _expected(exc: UnexpectedInput) -> str:
    parser = getattr(exc, "interactive_parser", None)
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
    else:
        offset, length = len(text), 0
        if not text.strip():
            message = "empty motion expression"
        else:
            message = f"unexpected end of text; expected {_expected(exc)}"
    return MotionError(MotionStatus.PARSE_ERROR, message, offset, length, hint)
