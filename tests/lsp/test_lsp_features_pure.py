"""The server's pure functions, without a server: positions, completion contexts, names,
ranges for value lists, symbols and tokens of a snapshot."""

from __future__ import annotations

import gc
import json
import weakref

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lsprotocol import types
from pygls.protocol import default_converter

from gaitgram.ide import completion as ide_completion
from gaitgram.ide.completion import Where, context
from gaitgram.ide.tokens import tokens
from gaitgram.language.source import SourceText, Span
from gaitgram.language.syntax import is_rule_name
from gaitgram_lsp.documents import Documents, analyse
from gaitgram_lsp.features import (
    code_actions,
    completion,
    formatting,
    inlay_hints,
    navigation,
    semantic_tokens,
)
from gaitgram_lsp.features.diagnostics import SEVERITY
from gaitgram_lsp.positions import (
    UTF8,
    UTF16,
    UTF32,
    ClientText,
    PositionIndex,
    apply_change,
    column,
    raw_line_starts,
    units,
)

EMOJI_LINE = "<a> ::= '😀é' <b>\n<b> ::= x\n"


@pytest.mark.parametrize(("encoding", "character"), [(UTF16, 14), (UTF8, 17), (UTF32, 13)])
def test_positions_count_code_units_of_the_encoding(encoding: str, character: int) -> None:
    positions = PositionIndex(SourceText(EMOJI_LINE), encoding)
    offset = EMOJI_LINE.index("<b>")  # 13 code points in: after an emoji and an é
    assert positions.position(offset) == types.Position(line=0, character=character)
    assert positions.offset(types.Position(line=0, character=character)) == offset
    assert positions.offset(types.Position(line=0, character=999)) == EMOJI_LINE.index("\n")  # clamped
    assert positions.offset(types.Position(line=9, character=0)) == len(EMOJI_LINE)
    assert list(positions.line_column([offset, EMOJI_LINE.index("x")])) == [(0, character), (1, 8)]


def test_a_position_inside_a_surrogate_pair_means_the_character() -> None:
    assert column("'😀'", 2, UTF16) == 1  # the second half of the emoji: the emoji itself
    assert units("😀é", UTF16) == 3
    assert units("😀é", UTF8) == 6


def test_incremental_changes_use_lsp_line_breaks() -> None:
    text = "a\r\nb😀c\rd\u2028e\n"
    change = types.Range(start=types.Position(line=1, character=3), end=types.Position(line=2, character=1))
    assert apply_change(text, change, "X", UTF16) == "a\r\nb😀X\u2028e\n"  # \r ends a line, U+2028 does not


def _full_apply(text: str, range_: types.Range, inserted: str, encoding: str) -> str:
    """The change applied the slow, obvious way: every line start scanned again."""
    starts = raw_line_starts(text)

    def offset(position: types.Position) -> int:
        if position.line >= len(starts):
            return len(text)
        end = starts[position.line + 1] if position.line + 1 < len(starts) else len(text)
        line = text[starts[position.line] : end].rstrip("\r\n")
        return starts[position.line] + column(line, position.character, encoding)

    start, end = sorted((offset(range_.start), offset(range_.end)))
    return text[:start] + inserted + text[end:]


_LINE_PIECES = st.sampled_from(["a", "b c", "\n", "\r", "\r\n", "😀", "\u2028", "<r> ::= x", ""])
_positions = st.builds(types.Position, line=st.integers(0, 12), character=st.integers(0, 12))


@settings(max_examples=300, deadline=None)
@given(
    text=st.lists(_LINE_PIECES, max_size=30).map("".join),
    edits=st.lists(
        st.tuples(_positions, _positions, st.lists(_LINE_PIECES, max_size=4).map("".join)), max_size=8
    ),
    encoding=st.sampled_from([UTF8, UTF16, UTF32]),
)
def test_the_client_text_keeps_its_line_starts_through_any_edits(text, edits, encoding) -> None:
    client = ClientText.of(text)
    for start, end, inserted in edits:
        range_ = types.Range(start=start, end=end)
        text = _full_apply(text, range_, inserted, encoding)
        client.apply(range_, inserted, encoding)
        assert client.text == text
        assert client.starts == raw_line_starts(text)
        assert [client.line(i) for i in range(len(client.lines) + 1)] == [
            *(
                text[a:b].rstrip("\r\n")
                for a, b in zip(client.starts, [*client.starts[1:], len(text)], strict=True)
            ),
            "",
        ]


@pytest.mark.parametrize(
    ("before", "after", "where", "typed"),
    [
        ("@jo", "", Where.ANNOTATION, "jo"),
        ("@joint ", "", Where.ARGUMENT, ""),
        ("@joint hip_hind ", "", Where.KEYWORD, ""),
        ("@joint hip_hind limits=-2", "", Where.ARGUMENT, "-2"),
        ("@backend mu", "", Where.ARGUMENT, "mu"),
        ("<ne", "", Where.HEAD, "ne"),
        ("<ne", "> ::= x", Where.HEAD, "ne"),
        ("<ne", ">", Where.HEAD, "ne"),  # the editor closed the bracket
        ("<ne", "> | <a>", Where.RULE, "ne"),  # a continuation line, not a head
        ("<a> ::= <b", "", Where.RULE, "b"),
        ("  | x", "", Where.RULE, "x"),
        ("<a> ::= x # <b", "", Where.NOTHING, ""),
        ("<a> ::= '<b", "", Where.NOTHING, ""),
        ("<a> ::= '#' <b", "", Where.RULE, "b"),
    ],
)
def test_completion_context(before: str, after: str, where: Where, typed: str) -> None:
    found = context(before, after)
    assert (found.where, found.typed) == (where, typed)


def test_completion_model_and_ranking() -> None:
    snapshot = analyse("<top> ::= <ab> | x\n<ab> ::= 1 | 2 | 3\n<abc> ::= q\n<zab> ::= r\n")
    model = snapshot.completion
    assert [(r.name, r.detail, r.line) for r in model.rules][:2] == [
        ("top", "<ab> | …", 0),
        ("ab", "1 | …", 1),
    ]
    result = completion.complete(model, 4, "<n> ::= <ab", 11, encoding=UTF16)
    assert [i.label for i in result.items] == ["<ab>", "<abc>", "<zab>"]  # exact, prefix, inside


@given(
    names=st.lists(st.text("abAB", min_size=1, max_size=3), max_size=300),
    typed=st.text("abB", max_size=2),
    line=st.integers(-5, 320),
)
def test_ranking_equals_a_full_sort(names: list[str], typed: str, line: int) -> None:
    """The two-pointer ranking equals sorting every match, however many there are."""
    model = ide_completion.CompletionModel(names=tuple(names), lines=tuple(range(len(names))))
    wanted = typed.lower()
    scored = sorted(
        (0 if n.lower() == wanted else 1 if n.lower().startswith(wanted) else 2, abs(i - line), i)
        for i, n in enumerate(names)
        if wanted in n.lower()
    )
    ranked, more = ide_completion._rank(model, typed, line)
    assert [entry.line for entry in ranked] == [i for *_, i in scored[: ide_completion.MAX_ITEMS]]
    assert more == (len(scored) > ide_completion.MAX_ITEMS)


@pytest.mark.parametrize(
    ("name", "valid"),
    [
        ("amp", True),
        ("a-b.c", True),
        ("é😀", True),
        ("", False),
        ("a b", False),
        ("a|b", False),
        ("a>", False),
    ],
)
def test_rule_names_are_what_the_scanner_reads_as_one(name: str, valid: bool) -> None:
    assert is_rule_name(name) is valid


@pytest.mark.parametrize(
    ("values", "spec"),
    [
        (["0", "0.25", "0.5", "0.75", "1"], "float[0..1 step 0.25]"),
        (["1", "2", "3"], "int[1..3]"),
        (["-10", "0", "10"], "int[-10..10 step 10]"),
        (["0.1", "0.2", "0.3"], "float[0.1..0.3 step 0.1]"),
        (["0", "0.50", "1"], None),
        (["1", "2", "4"], None),
        (["3", "2", "1"], None),
        (["1", "2"], None),
    ],
)
def test_value_lists_collapse_only_into_ranges_with_the_same_texts(
    values: list[str], spec: str | None
) -> None:
    assert code_actions.range_for(values) == spec


def test_symbols_tokens_hints_and_formatting_of_a_snapshot() -> None:
    snapshot = analyse("@start <a>\n<a>::=<b> # c\n<b> ::= int[0..3]\n")
    assert [s.name for s in navigation.document_symbols(snapshot, hierarchical=False)] == [
        "@start",
        "<a>",
        "<b>",
    ]
    found = [
        (snapshot.text[t.start : t.start + t.length], semantic_tokens.TOKEN_TYPES[t.type])
        for t in tokens(snapshot.result.grammar)
    ]
    assert found == [
        ("@start", "decorator"),
        ("<a>", "function"),
        ("<a>", "function"),
        ("::=", "operator"),
        ("<b>", "function"),
        ("# c", "comment"),
        ("<b>", "function"),
        ("::=", "operator"),
        ("int[0..3]", "number"),
    ]
    assert [h.label for h in inlay_hints.inlay_hints(snapshot, 0, len(snapshot.text))] == [
        "1 choice, no codon (lazy)",
        "4 choices, 1 codon",
    ]
    (edit,) = formatting.formatting(snapshot)
    assert edit.new_text == "<a> ::= <b>  # c\n"
    assert snapshot.positions.span(edit.range) == Span(11, 25)


def test_rename_refuses_with_a_reason() -> None:
    snapshot = analyse("<a> ::= <b>\n<b> ::= x\n")
    with pytest.raises(navigation.RenameRefused, match="already defined"):
        navigation.rename(snapshot, 1, "b")
    with pytest.raises(navigation.RenameRefused, match="no rule name here"):
        navigation.rename(snapshot, 6, "c")
    edit = navigation.rename(snapshot, 1, "<c>")
    assert edit.changes is not None
    assert [e.new_text for e in edit.changes[snapshot.uri]] == ["c"]


def test_wire_diagnostics_are_what_lsprotocol_would_send() -> None:
    """The fast path (plain JSON values) against lsprotocol's classes, unstructured."""
    text = "@start <a>\n<a> ::= <b> | <missing>\n<b> ::= int[0..2O]\n<unused> ::= 'é😀' <a>\n"
    snapshot = analyse(text, uri="file:///w.gg", version=7)
    result, positions = snapshot.result, snapshot.positions
    assert {d.code.code for d in result.diagnostics} >= {"GG201", "GG204"}
    made = [
        types.Diagnostic(
            range=positions.range(d.span),
            message=d.message,
            severity=SEVERITY[d.level],
            code=d.code.code,
            source="gaitgram",
            tags=[types.DiagnosticTag.Unnecessary] if d.code.code == "GG204" else None,
        )
        for d in result.diagnostics
    ]
    converter = default_converter()
    assert snapshot.wire_diagnostics == converter.unstructure(made)
    assert converter.unstructure(snapshot.diagnostics) == converter.unstructure(made)
    assert json.loads(snapshot.published_params) == {
        "uri": "file:///w.gg",
        "version": 7,
        "diagnostics": converter.unstructure(made),
    }


def test_the_idle_collection_frees_cycles_that_analyses_froze() -> None:
    class Node:
        other: object = None

    cycle = Node()
    cycle.other = cycle
    alive = weakref.ref(cycle)
    gc.freeze()  # as after an analysis
    del cycle
    gc.collect()
    assert alive() is not None  # frozen: the collector does not look at it
    Documents.collect()
    assert alive() is None
