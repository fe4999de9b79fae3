"""From the lark tree to the grammar model, reading right-hand sides as PonyGE2 does.

PonyGE2's reading rules (``vectors/ponyge2/README.md``), which every PonyGE2
grammar must keep under gaitgram:

* an alternative is trimmed at both ends; whitespace inside it is terminal text;
* a line break inside an alternative is terminal text too, and the spaces right
  after it are dropped (as are spaces alone before it);
* a comment ends an alternative, so text on the lines after a comment starts a
  new alternative even without ``|`` (gaitgram warns about it: GG107);
* empty alternatives are dropped; ``''`` is the way to write an empty string;
* escapes are decoded in quoted and unquoted text alike;
* adjacent pieces of terminal text form one terminal.
"""

from __future__ import annotations

import unicodedata
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import NamedTuple

from lark import Token, Tree

from gaitgram.language.annotations import CheckedAnnotation, Target, check_annotation, unreadable_argument
from gaitgram.language.diagnostics import Applicability, Diagnostic, Fix, TextEdit
from gaitgram.language.escapes import unescape
from gaitgram.language.lexer import Piece
from gaitgram.language.look_alikes import HINT as LOOK_ALIKE_HINT
from gaitgram.language.look_alikes import RANGE_LOOK_ALIKE, look_alike_ranges
from gaitgram.language.meaning import read_defines, read_document, read_rule
from gaitgram.language.model import (
    Alternative,
    Annotation,
    Argument,
    ArgumentValue,
    Grammar,
    Interval,
    JointDecl,
    Name,
    NonTerminal,
    RangeKind,
    RangeSpec,
    RangeSymbol,
    Rule,
    RuleRef,
    Symbol,
    Terminal,
)
from gaitgram.language.numbers import exact_int, read_number
from gaitgram.language.parser import scanner, tree_end, tree_start
from gaitgram.language.problems import (
    comment_splits_alternative,
    dangling_annotation,
    empty_alternative,
    empty_rule,
    ge_range_bad_size,
    ge_range_not_whole,
    ge_range_unreadable,
    invalid_escape,
    stray_text,
    undefined_define,
    unencodable_text,
    unterminated_string,
)
from gaitgram.language.ranges import (
    MALFORMED_RANGE,
    MAX_GRAMMAR_RANGE_VALUES,
    MAX_RANGE_VALUES,
    OpenRanges,
    RangeFix,
    over_budget_problem,
    parse_range,
)
from gaitgram.language.source import SourceText, Span

_BLANK = frozenset({"WS", "NEWLINE", "COMMENT"})
_TEXTUAL = frozenset({"TEXT", "WS"})
SAFE, UNSAFE = Applicability.SAFE, Applicability.UNSAFE


class Parts(NamedTuple):
    """What a text reads as before the document-wide settings are decided: each rule with
    its own annotations' meaning (``meaning.read_rule``). A part of a document reads the
    same alone as in place, which is what the incremental parser keeps (a tuple: thousands
    are rebuilt when an edit moves the segments after it, see ``moved``)."""

    rules: tuple[Rule, ...]
    annotations: tuple[Annotation, ...]
    joints: tuple[JointDecl, ...]
    problems: tuple[Diagnostic, ...]
    #: Its own ``@define`` values.
    defines: dict[str, int]
    #: The values of its typed ranges, counted where each is written (see
    #: ``ranges.MAX_GRAMMAR_RANGE_VALUES``), and whether one was refused for that limit.
    range_values: int = 0
    over_budget: bool = False

    def moved(self, delta: int) -> Parts:
        """The same parts ``delta`` characters further on (the incremental parser's segment
        that moved): new rules, annotations, joints and problems, none changed in place."""
        if delta == 0:
            return self
        annotations = {id(a): a.moved(delta) for a in self.annotations}  # shared with their rules
        return Parts(
            tuple(
                [
                    rule.moved(delta, tuple([annotations[id(a)] for a in rule.annotations]))
                    for rule in self.rules
                ]
            ),
            tuple(annotations.values()),
            tuple([joint.moved(delta) for joint in self.joints]),
            tuple([problem.moved(delta) for problem in self.problems]),
            self.defines,
            self.range_values,
            self.over_budget,
        )


def read_parts(
    tree: Tree,
    source: SourceText,
    defines: Mapping[str, int] | None = None,
    window: tuple[int, int] | None = None,
) -> Parts:
    """Read a parse tree; ``defines`` are the values ``GE_RANGE:name`` may take from outside it.
    With ``window`` (start, end), the tree is of that part of ``source`` only (``parse_tree``'s
    ``start`` and ``end``), which reads the same alone as in place when it starts and ends where
    items do (``incremental.segment_starts``)."""
    return _Builder(source, dict(defines or {}), window or (0, len(source.text))).build(tree)


def build_grammar(tree: Tree, source: SourceText, defines: Mapping[str, int] | None = None) -> Grammar:
    parts = read_parts(tree, source, defines)
    return assemble_grammar(source, [parts], {**parts.defines, **(defines or {})})


def assemble_grammar(source: SourceText, parts: Sequence[Parts], defines: dict[str, int]) -> Grammar:
    """The grammar of a document read as ``parts`` (in order), finished with what only the
    whole document decides (``meaning.read_document``)."""
    rules = [rule for p in parts for rule in p.rules]
    annotations = [a for p in parts for a in p.annotations]
    joints = [j for p in parts for j in p.joints]
    problems = [d for p in parts for d in p.problems]
    settings = read_document(source.text, rules, annotations, joints, has_problems=bool(problems))
    start = settings.values["start"]
    return Grammar(
        source=source,
        rules=tuple(rules),
        annotations=tuple(annotations),
        start=start if start is not None else (rules[0].name if rules else None),
        backend=settings.values["backend"],
        units=settings.values["units"] or "deg",
        joints=tuple(joints),
        defines=defines,
        diagnostics=tuple(sorted([*problems, *settings.problems], key=lambda d: d.span)),
        frequency=settings.frequency,
        declared=settings.declared,
    )


@dataclass
class _Builder:
    source: SourceText
    external_defines: dict[str, int]
    window: tuple[int, int]
    problems: list[Diagnostic] = field(default_factory=list)
    defines: dict[str, int] = field(default_factory=dict)
    #: Values of the typed ranges read so far, and whether one was refused for the grammar's limit.
    range_values: int = 0
    over_budget: bool = False

    @cached_property
    def open_ranges(self) -> OpenRanges:
        return OpenRanges(self.source)

    # ---- document ------------------------------------------------------------

    def build(self, tree: Tree) -> Parts:
        self.problems.extend(unencodable_text(self.source, *self.window))
        items = tree.children
        annotations = [
            self._annotation(item) for item in items if isinstance(item, Tree) and item.data == "annotation"
        ]
        checked = [check_annotation(a, self.problems) for a in annotations]
        own_defines = read_defines(c for c in checked if c.kind is not None and c.kind.target is Target.FILE)
        self.defines = {**own_defines, **self.external_defines}

        rules: list[Rule] = []
        joints: list[JointDecl] = []
        pending: list[CheckedAnnotation] = []
        annotation_iter = iter(checked)
        for item in items:
            if isinstance(item, Token):
                self._stray(self._pieces(item))
            elif item.data == "rule":
                rule = self._rule(item, [c.annotation for c in pending])
                rules.append(rule)
                joint, problems = read_rule(self.source.text, rule, pending)
                self.problems.extend(problems)
                if joint is not None:
                    joints.append(joint)
                pending = []
            else:
                c = next(annotation_iter)
                self._stray_after_annotation(item)
                if c.kind is None or c.kind.target is Target.RULE:
                    pending.append(c)
        for c in pending:
            if c.kind is not None:
                self.problems.append(dangling_annotation(self.source, c.annotation))
        return Parts(
            tuple(rules),
            tuple(annotations),
            tuple(joints),
            tuple(self.problems),
            own_defines,
            self.range_values,
            self.over_budget,
        )

    def _pieces(self, token: Token) -> list[Piece]:
        return scanner().pieces(self.source.text, token.start_pos, token.end_pos)

    # ---- stray text ---------------------------------------------------------------

    def _stray(self, pieces: list[Piece]) -> None:
        """Report runs of non-blank pieces outside any rule, one diagnostic per line."""
        text = self.source.text
        run: list[Piece] = []
        for piece in (*pieces, ("NEWLINE", -1, -1)):
            if piece[0] == "NEWLINE" or piece[0] == "COMMENT":
                if run:
                    span = Span(run[0][1], run[-1][2])
                    self.problems.append(stray_text(span, text[span.start : span.end].strip()))
                    run = []
            elif piece[0] != "WS":
                run.append(piece)

    def _stray_after_annotation(self, tree: Tree) -> None:
        for child in tree.children:
            if isinstance(child, Token) and child.type == "PIECES":
                self._stray(self._pieces(child))

    # ---- annotations ----------------------------------------------------------------

    def _annotation(self, tree: Tree) -> Annotation:
        head: Token = tree.children[0]
        at = head.start_pos + head.index("@")
        name_span = Span(at, head.end_pos)
        arguments: list[Argument] = []
        end = head.end_pos
        for child in tree.children[1:]:
            if isinstance(child, Tree):
                argument = self._argument(child)
                if argument is not None:
                    arguments.append(argument)
                end = tree_end(child)
            elif child.type not in ("WS", "NEWLINE", "COMMENT", "PIECES"):
                end = child.end_pos
        return Annotation(head[head.index("@") + 1 :], tuple(arguments), Span(at, end), name_span)

    def _argument(self, tree: Tree) -> Argument | None:
        span = Span(tree_start(tree), tree_end(tree))
        raw = self.source.text[span.start : span.end]
        if tree.data == "bad_argument":
            self.problems.append(unreadable_argument(raw, span))
            return None
        if tree.data == "keyword_argument":
            key = str(tree.children[0])
            value_tree = tree.children[2] if len(tree.children) > 2 else None
            value = self._value(value_tree) if value_tree is not None else None
            return Argument(key, value, span, raw)
        return Argument(None, self._value(tree), span, raw)

    def _value(self, tree: Tree) -> ArgumentValue:
        if tree.data == "span_value":
            low = high = None
            seen_dots = False
            for token in tree.children:
                if token.type == "DOTS":
                    seen_dots = True
                elif seen_dots:
                    high = _number(token)
                else:
                    low = _number(token)
            return Interval(low, high)
        token: Token = tree.children[0]
        if tree.data == "name_value":
            return Name(str(token))
        if tree.data == "number_value":
            return _number(token)
        if tree.data == "rule_value":
            return RuleRef(token[1:-1])
        text, errors = unescape(token[1:-1])
        self.problems.extend(invalid_escape(self.source, token.start_pos + 1, e) for e in errors)
        return text

    # ---- rules ---------------------------------------------------------------------------

    def _rule(self, tree: Tree, annotations: list[Annotation]) -> Rule:
        head: Token = tree.children[0]
        close = head.index(">")
        name = head[1:close]
        name_span = Span(head.start_pos, head.start_pos + close + 1)
        pieces = self._pieces(tree.children[1]) if len(tree.children) > 1 else []
        alternatives = self._alternatives(name, pieces, head.start_pos)
        end = _content_end(pieces, head.end_pos)
        rule_span = Span(head.start_pos, end)
        if not alternatives:
            self.problems.append(empty_rule(name, name_span, end))
        return Rule(name, tuple(alternatives), rule_span, name_span, tuple(annotations))

    def _alternatives(self, rule: str, pieces: list[Piece], base: int) -> list[Alternative]:
        """Split a right-hand side at ``|`` and comments, then read each part (spans from ``base``,
        the rule's start)."""
        alternatives: list[Alternative] = []
        groups: list[list[list[Piece]]] = [[[]]]  # pipe groups -> comment segments -> pieces
        segment = groups[0][0]
        pipes: list[Piece] = []
        for piece in pieces:
            kind = piece[0]
            if kind == "PIPE":
                segment = []
                groups.append([segment])
                pipes.append(piece)
            elif kind == "COMMENT":
                segment = []
                groups[-1].append(segment)
            else:
                segment.append(piece)

        text = self.source.text
        for index, group in enumerate(groups):
            nonblank = 0
            for segment in group:
                trimmed = _trim(segment, text)
                if not trimmed:
                    continue
                nonblank += 1
                alternative = self._alternative(rule, trimmed, base)
                if nonblank > 1:
                    where = alternative.local_span.shifted(base)
                    self.problems.append(comment_splits_alternative(where, rule))
                alternatives.append(alternative)
            if nonblank == 0 and pipes:
                where = pipes[index] if index < len(pipes) else pipes[index - 1]
                self.problems.append(empty_alternative(text, Span(where[1], where[2]), rule))
        return alternatives

    def _alternative(self, rule: str, pieces: list[Piece], base: int) -> Alternative:
        text = self.source.text
        symbols: list[Symbol] = []
        parts: list[str] = []  # terminal text waiting to be one Terminal
        parts_start = parts_end = 0
        after_newline = False
        i, count = 0, len(pieces)
        while i < count:
            kind, start, end = pieces[i]
            i += 1
            if kind == "NONTERMINAL":
                if parts:
                    symbols.append(Terminal("".join(parts), Span(parts_start - base, parts_end - base)))
                    parts = []
                symbols.append(NonTerminal(text[start + 1 : end - 1], Span(start - base, end - base)))
                after_newline = False
                continue
            if kind in _TEXTUAL:
                # A run of text and spaces is one piece of PonyGE2 text.
                while i < count and pieces[i][0] in _TEXTUAL:
                    end = pieces[i][2]
                    i += 1
                value = text[start:end]
                if after_newline:
                    stripped = value.lstrip(" ")
                    start += len(value) - len(stripped)
                    value = stripped
                    after_newline = False
                if not value or (i < count and pieces[i][0] == "NEWLINE" and not value.strip(" ")):
                    continue  # spaces next to a line break are not text
                if "[" in value:
                    self._look_alikes(rule, value, start)
                if "\\" in value:
                    value = self._decode(value, start)
            elif kind == "STRING":
                value = text[start + 1 : end - 1]
                if "\\" in value:
                    value = self._decode(value, start + 1)
                after_newline = False
            elif kind == "NEWLINE":
                value = "\n"
                after_newline = True
            else:
                after_newline = False
                value = self._special(rule, kind, start, end, whole=count == 1)
                if not isinstance(value, str):
                    if parts:
                        symbols.append(Terminal("".join(parts), Span(parts_start - base, parts_end - base)))
                        parts = []
                    symbols.append(RangeSymbol(value, Span(start - base, end - base)))
                    continue
            if not parts:
                parts_start = start
            parts.append(value)
            parts_end = end
        if parts:
            symbols.append(Terminal("".join(parts), Span(parts_start - base, parts_end - base)))
        return Alternative(tuple(symbols), Span(pieces[0][1] - base, pieces[-1][2] - base))

    def _special(self, rule: str, kind: str, start: int, end: int, *, whole: bool) -> str | RangeSpec:
        """The rarer pieces: ranges, a lone ``<``, unterminated strings. Text if unusable."""
        raw = self.source.text[start:end]
        if kind == "RANGE":
            return self._range(rule, raw, start) or raw
        if kind == "GE_RANGE":
            return self._ge_range(rule, raw, start, whole=whole) or raw
        if kind == "BAD_STRING":
            self.problems.append(unterminated_string(raw, Span(start, end), rule))
            return self._decode(raw[1:], start + 1)
        assert kind == "LT", kind
        return raw

    def _decode(self, raw: str, start: int) -> str:
        value, errors = unescape(raw)
        self.problems.extend(invalid_escape(self.source, start, error) for error in errors)
        return value

    def _counted(self, spec: RangeSpec | None) -> RangeSpec | None:
        if spec is not None:
            self.range_values += spec.size
        return spec

    def _range(self, rule: str, raw: str, start: int) -> RangeSpec | None:
        spec, problems = parse_range(raw, MAX_GRAMMAR_RANGE_VALUES - self.range_values)
        self._counted(spec)
        for problem in problems:
            self.over_budget |= problem.over_budget
            length = len(raw) - problem.offset if problem.length is None else problem.length
            span = Span(start + problem.offset, start + problem.offset + max(length, 1))
            if problem.offset == 0 and problem.length is None:
                span = Span(start, start + len(raw))
            fix = problem.fix
            if problem.code is MALFORMED_RANGE and not self.open_ranges.none_before(start):
                fix = None  # it adds a ]
            self.problems.append(
                problem.code(
                    problem.message,
                    span,
                    rule=rule,
                    hint=problem.hint,
                    fixes=_range_fixes(fix, start),
                    data={"range": raw},
                )
            )
        return spec

    def _look_alikes(self, rule: str, raw: str, start: int) -> None:
        for found in look_alike_ranges(raw):
            span = Span(start + found.offset, start + found.offset + found.length)
            fix = found.fix if found.fix is None or self.open_ranges.none_before(span.start) else None
            self.problems.append(
                RANGE_LOOK_ALIKE(
                    found.message,
                    span,
                    rule=rule,
                    hint=LOOK_ALIKE_HINT,
                    fixes=_range_fixes(fix, span.start),
                    data={"text": self.source.slice(span), "kind": found.meant},
                )
            )

    def _ge_range(self, rule: str, raw: str, start: int, *, whole: bool) -> RangeSpec | None:
        span = Span(start, start + len(raw))
        argument = raw.split(":", 1)[1]
        if not whole:
            self.problems.append(ge_range_not_whole(raw, span, rule))
            return None
        if argument.isdecimal():  # the digits int() reads (any script's, not superscripts)
            size = _size(argument)
        elif argument.isidentifier():
            defined = self.defines
            if argument not in defined:
                self.problems.append(undefined_define(argument, span, rule))
                return None
            size = defined[argument]
        else:
            self.problems.append(ge_range_unreadable(raw, span, rule))
            return None
        if size < 1 or size > MAX_RANGE_VALUES:
            self.problems.append(ge_range_bad_size(raw, size, MAX_RANGE_VALUES, span, rule))
            return None
        if size > MAX_GRAMMAR_RANGE_VALUES - self.range_values:
            problem = over_budget_problem(raw, size)
            self.over_budget = True
            self.problems.append(
                problem.code(problem.message, span, rule=rule, hint=problem.hint, data={"range": raw})
            )
            return None
        return self._counted(RangeSpec(RangeKind.INT, raw, tuple(str(i) for i in range(size))))


# ---- helpers ---------------------------------------------------------------------------


def _range_fixes(fix: RangeFix | None, start: int) -> list[Fix]:
    """A fix inside a range's text (offsets from its start) as edits of the document."""
    if fix is None:
        return []
    edits = tuple(TextEdit(Span(start + e.offset, start + e.offset + e.length), e.text) for e in fix.edits)
    return [Fix(fix.title, edits, SAFE if fix.safe else UNSAFE, preferred=True)]


def _trim(segment: list[Piece], text: str) -> list[Piece]:
    """Drop whitespace at both ends of an alternative, as PonyGE2's ``strip()`` does."""
    first, last = 0, len(segment) - 1
    while first <= last and segment[first][0] in _BLANK:
        first += 1
    while last >= first and segment[last][0] in _BLANK:
        last -= 1
    if first > last:
        return []
    trimmed = segment[first : last + 1]
    kind, start, end = trimmed[-1]
    if kind == "TEXT" and text[end - 1].isspace():
        trimmed[-1] = (kind, start, start + len(text[start:end].rstrip()))
    return trimmed


def _content_end(pieces: list[Piece], default: int) -> int:
    for kind, _, end in reversed(pieces):
        if kind not in _BLANK:
            return end
    return default


def _number(token: Token) -> int | float:
    """A number as written: an int if its value is whole (``30``, ``1e3``, ``2.0``), else a float.

    Never raises: ``1e400`` is ``inf`` and ``1e-400`` is ``0.0`` here, and the annotation
    checks (``annotations._convert``) read the text again to refuse both.
    """
    value = read_number(str(token))
    whole = exact_int(value)
    return whole if whole is not None else float(value)


def _size(digits: str) -> int:
    """The value of decimal digits (any script's), or one more than a range may have if it is
    larger: int() of thousands of digits raises rather than read them."""
    first = next((i for i, digit in enumerate(digits) if unicodedata.decimal(digit)), len(digits))
    significant = digits[first:] or "0"
    return int(significant) if len(significant) <= len(str(MAX_RANGE_VALUES)) else MAX_RANGE_VALUES + 1
