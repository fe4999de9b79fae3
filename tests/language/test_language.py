"""The .gg language: annotations, typed ranges, quoting, spans and error recovery."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from gaitgram.analysis import check
from gaitgram.language import parse
from gaitgram.language.model import NonTerminal, RangeSymbol, Terminal
from gaitgram.language.source import SourceText, Span, decode_source, encode_as_read, normalize_newlines


def codes(text: str) -> list[str]:
    return [d.code.code for d in check(parse(text)).diagnostics]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("<a> ::= x | y", []),
        ("<a> ::= int[5..1]", ["GG301"]),
        ("<a> ::= float[0..1]", ["GG104"]),
        ("<a> ::= float[0..1 step 0]", ["GG302"]),
        ("<a> ::= int[0..1 step 0.5]", ["GG305"]),
        ("<a> ::= int[0..10000000]", ["GG304"]),
        ("<a> ::= float[0..1 step 0.3]", ["GG303"]),
        ("<a> ::= <b> | 'oops\n<b> ::= x", ["GG102"]),
        ("<a> ::= '\\x4'", ["GG103"]),
        ("<a> ::= GE_RANGE:3 x", ["GG105"]),
        ("<a> ::= GE_RANGE:0", ["GG105"]),
        ("<a> ::= x | | y", ["GG106"]),
        ("<a> ::= x # note\n  y", ["GG107"]),
        ("<a> ::=\n<b> ::= x", ["GG108", "GG204"]),
        ("hello\n<a> ::= x", ["GG101"]),
        ("<a> ::= <bb>\n<b> ::= x", ["GG201", "GG204"]),
        ("<a> ::= x\n<a> ::= y", ["GG202"]),
        ("<a> ::= <b> | x\n<b> ::= <b> y", ["GG203"]),
        ("<a> ::= <b>\n<b> ::= <b> x", ["GG205", "GG206", "GG203"]),
        ("<a> ::= x\n<b> ::= y", ["GG204"]),
        ("<a> ::= <b>\n<b> ::= x", ["GG206"]),
        ("", ["GG207"]),
        ("# only a comment <a> ::= x\n", ["GG207"]),
        ("@nonsense 1\n<a> ::= x", ["GG401"]),
        ("@joint\n<a> ::= x", ["GG402"]),
        ("@units furlongs\n<a> ::= x", ["GG402"]),
        ("<a> ::= x\n@joint hip_hind", ["GG403"]),
        ("@start <a>\n@start <a>\n<a> ::= x", ["GG404"]),
        ("<a> ::= GE_RANGE:n_vars", ["GG405"]),
        ("@backend nope\n<a> ::= x", ["GG501"]),
        ("@joint hip_hind\n<a> ::= 1", ["GG507"]),
        ("@start <nope>\n<a> ::= x", ["GG201"]),
    ],
)
def test_diagnostic_codes(text: str, expected: list[str]) -> None:
    assert codes(text) == expected


def test_comments_never_define_rules() -> None:
    grammar = parse("<a> ::= x  # <b> ::= y\n# <c> ::= z\n")
    assert [r.name for r in grammar.rules] == ["a"]
    assert [[s.text for s in alt.symbols] for alt in grammar.rules[0].alternatives] == [["x"]]


def test_annotations_attach_to_the_next_rule_and_the_file() -> None:
    grammar = parse(
        "@start <gait>\n@backend mujoco-horse\n@units rad\n"
        "<gait> ::= <hip>\n"
        "@joint hip_hind limits=-0.2..0.2 free=11..\n<hip> ::= 0\n"
    )
    assert (grammar.start, grammar.backend, grammar.units) == ("gait", "mujoco-horse", "rad")
    (joint,) = grammar.joints
    assert (joint.joint, joint.rule, joint.limits, joint.free) == ("hip_hind", "hip", (-0.2, 0.2), (11, None))
    assert not joint.is_free(10)
    assert joint.is_free(11)
    assert [a.name for a in grammar.rule("hip").annotations] == ["joint"]


@pytest.mark.parametrize(
    ("range_text", "values"),
    [
        ("int[5..8]", ["5", "6", "7", "8"]),
        ("int[0..100 step 25]", ["0", "25", "50", "75", "100"]),
        ("float[0..1 step 0.25]", ["0", "0.25", "0.5", "0.75", "1"]),
        ("float[-1..1 count 3]", ["-1", "0", "1"]),
        ("float[10 ± 10% step 0.5]", ["9", "9.5", "10", "10.5", "11"]),
        ("float[10 +- 10% count 3]", ["9", "10", "11"]),
        ("int[10 ± 25%]", ["8", "9", "10", "11", "12"]),
    ],
)
def test_typed_range_values(range_text: str, values: list[str]) -> None:
    grammar = parse(f"<a> ::= {range_text}")
    assert not grammar.diagnostics
    spec = grammar.rules[0].alternatives[0].range_values
    assert spec is not None
    assert list(spec.values) == values
    assert grammar.rules[0].choice_count == len(values)


def test_range_inside_an_alternative_is_one_choice_point() -> None:
    alternative = parse("<a> ::= 2*float[0..1 step 0.5]+1").rules[0].alternatives[0]
    kinds = [type(s) for s in alternative.symbols]
    assert kinds == [Terminal, RangeSymbol, Terminal]
    assert alternative.symbols[1].spec.values == ("0", "0.5", "1")


def test_ponyge2_text_that_looks_like_a_range_keeps_its_meaning() -> None:
    # "int" and "float" without brackets (or without ..) stay terminal text.
    grammar = parse("<a> ::= int(x) | float[i] | print[0]")
    assert [[s.text for s in alt.symbols] for alt in grammar.rules[0].alternatives] == [
        ["int(x)"],
        ["float[i]"],
        ["print[0]"],
    ]


def test_quoted_terminals_and_escapes_are_unicode_correct() -> None:
    grammar = parse("<a> ::= 'é|#' | \"<b>\" | '\\u00e9\\t' | naïve\\n | '\\N{GREEK SMALL LETTER ALPHA}'")
    assert not grammar.diagnostics
    texts = [alt.symbols[0].text for alt in grammar.rules[0].alternatives]
    assert texts == ["é|#", "<b>", "é\t", "naïve\n", "α"]


@given(st.text(alphabet="ab\n\r", max_size=12), st.integers(-3, 15), st.integers(-3, 15))
def test_bounds_are_the_locations_of_both_ends(text: str, start: int, end: int) -> None:
    source = SourceText(text)
    first, last = source.location(start), source.location(end)
    assert source.bounds(start, end) == (first.line, first.column, last.line, last.column)


def test_spans_point_at_the_source() -> None:
    text = "<a> ::= <b> x\n<b> ::= y"
    grammar = parse(text)
    a, b = grammar.rules
    assert grammar.source.slice(a.name_span) == "<a>"
    ref = a.alternatives[0].symbols[0]
    assert isinstance(ref, NonTerminal)
    assert grammar.source.slice(a.span_of(ref)) == "<b>"
    assert grammar.source.location(b.name_span.start).line == 2
    assert grammar.source.slice(a.span_of(a.alternatives[0])) == "<b> x"
    # A rule's pieces count from the rule's start, so that a rule can move without them.
    (y,) = b.alternatives
    assert y.local_span == Span(8, 9)
    assert grammar.source.slice(b.span_of(y)) == "y"
    moved = b.moved(5)
    assert moved.alternatives is b.alternatives
    assert moved.span_of(y) == b.span_of(y).shifted(5)


def test_spans_cannot_change() -> None:
    span = parse("<a> ::= x").rules[0].span
    with pytest.raises(AttributeError):
        span.start = 3  # type: ignore[misc]


def test_a_broken_document_still_yields_the_rules_that_parse() -> None:
    grammar = parse(
        "<a> ::= <b> | 'unterminated\ngarbage here\n<b> ::= float[1..0 step 1]\n<c> ::= fine | <d\n"
    )
    assert [r.name for r in grammar.rules] == ["a", "b", "c"]
    assert grammar.has_errors
    assert [alt.symbols[0].text for alt in grammar.rule("c").alternatives] == ["fine", "<d"]


def test_crlf_and_cr_line_endings_read_like_lf() -> None:
    lf = parse("<a> ::= x\n  | y\n<b> ::= z")
    for newline in ("\r\n", "\r"):
        other = parse(lf.source.text.replace("\n", newline))
        assert [(r.name, [a.symbols[0].text for a in r.alternatives]) for r in other.rules] == [
            (r.name, [a.symbols[0].text for a in r.alternatives]) for r in lf.rules
        ]


@st.composite
def files_and_edits(draw: st.DrawFn) -> tuple[bytes, str]:
    """A file's bytes (lines ending LF, CRLF or CR, each its own, maybe a byte order mark) and
    a new version of its text: lines deleted, inserted (blank ones too) and changed."""
    lines = draw(st.lists(st.sampled_from(["", "<a> ::= x", "# c", "  | y\t"]), max_size=8))
    breaks = draw(st.lists(st.sampled_from(["\n", "\r\n", "\r"]), min_size=len(lines), max_size=len(lines)))
    raw = "".join(line + end for line, end in zip(lines, breaks, strict=True))
    if raw and draw(st.booleans()):
        raw = raw.rstrip("\r\n")  # no line break at the end
    bom = b"\xef\xbb\xbf" if draw(st.booleans()) else b""
    new = [line + "\n" for line in normalize_newlines(raw).split("\n")]
    for _ in range(draw(st.integers(0, 4))):
        at = draw(st.integers(0, len(new)))
        edit = draw(st.sampled_from(["delete", "insert", "change"]))
        if edit == "insert" or at == len(new):
            new.insert(at, draw(st.sampled_from(["\n", "<b> ::= z\n", "\t# new\n"])))
        elif edit == "delete":
            del new[at]
        else:
            new[at] = "<c> ::= w\n"
    return bom + raw.encode(), "".join(new)


@given(files_and_edits())
def test_a_new_text_is_written_with_the_files_line_breaks_and_reads_back_as_that_text(
    case: tuple[bytes, str],
) -> None:
    read, new = case
    written = encode_as_read(read, new)
    assert written.startswith(b"\xef\xbb\xbf") == read.startswith(b"\xef\xbb\xbf")
    assert decode_source(written).text == new  # a lone CR before an LF would merge two breaks
    assert encode_as_read(read, decode_source(read).text) == read  # no change, the same bytes


def test_defines_give_ge_range_its_size() -> None:
    assert parse("<a> ::= GE_RANGE:n", defines={"n": 3}).rules[0].choice_count == 3
    assert parse("@define n=4\n<a> ::= GE_RANGE:n").rules[0].choice_count == 4


def test_non_terminating_grammar_is_a_diagnostic_not_a_hang() -> None:
    # PonyGE2 loops forever loading this.
    result = check(parse("<a> ::= <a> <b>\n<b> ::= <a>"))
    assert {d.code.code for d in result.diagnostics} >= {"GG203", "GG205"}
