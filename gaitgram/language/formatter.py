"""``gaitgram fmt``: one layout for every grammar, without changing what it means.

Only whitespace that PonyGE2's reading ignores is touched: the space around
``::=`` and ``|``, the indentation of continuation lines, blank lines between
rules, indentation of annotations and the space before comments. Text inside an
alternative, including a line break inside one (which is terminal text), is
kept byte for byte. Rules are laid out as::

    <expr> ::= <expr> <op> <expr>
             | <var>  # comment

Safety is checked, not assumed: the result is parsed again and must give the
same rules, alternatives, annotations and diagnostics, or nothing is written.
"""

from __future__ import annotations

from dataclasses import dataclass

from lark import Token, Tree

from gaitgram.language import parse
from gaitgram.language.diagnostics import Diagnostic
from gaitgram.language.lexer import Piece
from gaitgram.language.model import Grammar
from gaitgram.language.parser import parse_tree, scanner, tree_end, tree_start
from gaitgram.language.source import SourceText

__all__ = ["FormatError", "FormatRefused", "format_text"]


class FormatRefused(Exception):
    """The document has syntax errors, so its layout cannot be trusted to carry meaning."""

    def __init__(self, diagnostics: tuple[Diagnostic, ...]) -> None:
        super().__init__(f"{len(diagnostics)} syntax error(s); fix them before formatting")
        self.diagnostics = diagnostics


class FormatError(Exception):
    """The formatter would have changed the grammar's meaning: a bug in gaitgram, never written."""


# Layout elements: what the formatter may move around, and the verbatim text between.
@dataclass(frozen=True, slots=True)
class _Head:
    text: str


@dataclass(frozen=True, slots=True)
class _Line:
    """A whole line that is laid out at column 0 (an annotation)."""

    text: str


@dataclass(frozen=True, slots=True)
class _Content:
    text: str  # verbatim: from the first to the last non-blank piece of an alternative


@dataclass(frozen=True, slots=True)
class _Pipe:
    pass


@dataclass(frozen=True, slots=True)
class _Comment:
    text: str
    top_level: bool  # after a rule's last alternative: laid out at column 0


@dataclass(frozen=True, slots=True)
class _Break:
    newlines: int


_Element = _Head | _Line | _Content | _Pipe | _Comment | _Break


def format_text(text: str | SourceText, *, name: str = "<text>") -> str:
    """The formatted text. Raises :class:`FormatRefused` on syntax errors."""
    source = text if isinstance(text, SourceText) else SourceText(text, name)
    before = parse(source)
    syntax = tuple(d for d in before.diagnostics if d.code.syntax)
    if syntax:
        raise FormatRefused(syntax)
    formatted = _render(_elements(source))
    after = parse(formatted, name=source.name, defines=before.defines)
    if _meaning(before) != _meaning(after):
        raise FormatError(f"{source.name}: formatting would change the grammar; the file is left as it is")
    return formatted


def _meaning(grammar: Grammar) -> tuple[object, ...]:
    """Everything the layout must not change; spans excluded."""
    rules = tuple(
        (
            rule.name,
            tuple(tuple(_symbol_value(s) for s in alt.symbols) for alt in rule.alternatives),
            tuple(_annotation_value(a) for a in rule.annotations),
        )
        for rule in grammar.rules
    )
    annotations = tuple(_annotation_value(a) for a in grammar.annotations)
    # Messages may quote layout (a bad argument's trailing spaces), so compare what and where.
    codes = tuple(sorted((d.code.code, d.rule) for d in grammar.diagnostics))
    return rules, annotations, codes


def _symbol_value(symbol: object) -> tuple[str, object]:
    kind = type(symbol).__name__
    if hasattr(symbol, "spec"):
        return kind, symbol.spec  # type: ignore[attr-defined]
    if hasattr(symbol, "name"):
        return kind, symbol.name  # type: ignore[attr-defined]
    return kind, symbol.text  # type: ignore[attr-defined]


def _annotation_value(annotation: object) -> tuple[object, ...]:
    return (
        annotation.name,  # type: ignore[attr-defined]
        tuple((a.key, a.value) for a in annotation.arguments),  # type: ignore[attr-defined]
    )


# ---- source -> layout elements --------------------------------------------------------


def _elements(source: SourceText) -> list[_Element]:
    text = source.text
    tree = parse_tree(text)
    elements: list[_Element] = []
    for item in tree.children:
        if isinstance(item, Token):  # comments and blank lines before the first item
            elements += _between(text, _pieces(text, item))
        elif item.data == "rule":
            head: Token = item.children[0]
            elements.append(_Head(head[: head.index(">") + 1] + " ::="))
            if len(item.children) > 1:
                elements += _right_hand_side(text, _pieces(text, item.children[1]))
        else:
            elements += _annotation(text, item)
    return elements


def _pieces(text: str, token: Token) -> list[Piece]:
    return scanner().pieces(text, token.start_pos, token.end_pos)


def _annotation(text: str, tree: Tree) -> list[_Element]:
    head: Token = tree.children[0]
    parts = [head.strip()]
    comment = None
    tail: list[_Element] = []
    for child in tree.children[1:]:
        if isinstance(child, Tree):
            parts.append(text[tree_start(child) : tree_end(child)])
        elif child.type == "COMMENT":
            comment = str(child).rstrip()
        elif child.type == "NEWLINE":
            tail.append(_Break(1))
        elif child.type == "PIECES":
            tail += _between(text, _pieces(text, child))
    line = " ".join(parts) + (f"  {comment}" if comment else "")
    return [_Line(line), *_merge_breaks(tail)]


def _between(text: str, pieces: list[Piece]) -> list[_Element]:
    """Comments and blank lines outside rules (stray text is a syntax error, refused earlier)."""
    found: list[_Element] = []
    for kind, start, end in pieces:
        if kind == "NEWLINE":
            found.append(_Break(1))
        elif kind == "COMMENT":
            found.append(_Comment(text[start:end].rstrip(), top_level=True))
    return _merge_breaks(found)


def _right_hand_side(text: str, pieces: list[Piece]) -> list[_Element]:
    """Split at ``|`` and comments like the model builder, keeping each alternative verbatim."""
    found: list[_Element] = []
    segment: list[Piece] = []

    def flush() -> None:
        nonblank = [i for i, p in enumerate(segment) if p[0] not in ("WS", "NEWLINE")]
        if not nonblank:
            found.extend(_Break(1) for p in segment if p[0] == "NEWLINE")
            return
        first, last = nonblank[0], nonblank[-1]
        found.extend(_Break(1) for p in segment[:first] if p[0] == "NEWLINE")
        content = text[segment[first][1] : segment[last][2]]
        found.append(_Content(content.rstrip()))
        found.extend(_Break(1) for p in segment[last + 1 :] if p[0] == "NEWLINE")

    for piece in pieces:
        kind = piece[0]
        if kind in ("PIPE", "COMMENT"):
            flush()
            segment = []
            found.append(_Pipe() if kind == "PIPE" else _Comment(text[piece[1] : piece[2]].rstrip(), False))
        else:
            segment.append(piece)
    flush()
    last_alternative = max((i for i, e in enumerate(found) if isinstance(e, _Content | _Pipe)), default=-1)
    found = [
        _Comment(e.text, True) if isinstance(e, _Comment) and i > last_alternative else e
        for i, e in enumerate(found)
    ]
    return _merge_breaks(found)


def _merge_breaks(elements: list[_Element]) -> list[_Element]:
    merged: list[_Element] = []
    for element in elements:
        if isinstance(element, _Break) and merged and isinstance(merged[-1], _Break):
            merged[-1] = _Break(merged[-1].newlines + element.newlines)
        else:
            merged.append(element)
    return merged


# ---- layout elements -> text ----------------------------------------------------------------


def _render(elements: list[_Element]) -> str:
    """The lines, each written as a list of its pieces: a rule of 100,000 alternatives on one line
    is one line, and extending it piece by piece as a string would copy it at every piece."""
    lines: list[str] = []
    line: list[str] = []  # the pieces of the line being written
    filled = False  # whether it has more than spaces
    blank_pending = False
    pipe_indent = content_indent = 0  # of the current rule

    def start_line(indent: int) -> None:
        nonlocal line, filled, blank_pending
        if any(line):
            lines.append("".join(line))
        if blank_pending and lines:
            lines.append("")
        blank_pending = False
        line, filled = [" " * indent], False

    def add(*pieces: str) -> None:
        nonlocal filled
        line.extend(pieces)
        filled = filled or any(piece.strip() for piece in pieces)

    for element in elements:
        match element:
            case _Head(text):
                start_line(0)
                add(text)
                pipe_indent, content_indent = len(text) - 1, len(text) + 1
            case _Line(text):
                start_line(0)
                add(text)
                pipe_indent = content_indent = 0
            case _Break(newlines):
                if filled:
                    lines.append("".join(line))
                    line, filled = [], False
                blank_pending = blank_pending or newlines >= 2
            case _Pipe():
                if filled:
                    add(" |")
                else:
                    start_line(pipe_indent)
                    add("|")
            case _Content(text):
                if filled:
                    add(" ", text)
                else:
                    start_line(content_indent)
                    add(text)
            case _Comment(text, top_level):
                if filled:
                    add("  ", text)
                else:
                    start_line(0 if top_level else content_indent)
                    add(text)
                    if top_level:
                        pipe_indent = content_indent = 0
    if filled:
        lines.append("".join(line))
    return "".join(ln.rstrip(" \t") + "\n" for ln in lines)
