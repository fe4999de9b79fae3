"""Semantic tokens, folding ranges, formatting and inlay hints over the protocol."""

from __future__ import annotations

import pytest
from lsprotocol import types

from conftest import WALK, Client, at, doc, new_uri, open_document, span

pytestmark = pytest.mark.asyncio(loop_scope="module")


def decode(
    data: list[int], legend: types.SemanticTokensLegend, lines: list[str]
) -> list[tuple[str, str, str]]:
    """(text, type, modifiers) of each token, from LSP's relative encoding (ASCII text here)."""
    found = []
    line = character = 0
    for i in range(0, len(data), 5):
        delta_line, delta_start, length, kind, modifiers = data[i : i + 5]
        line += delta_line
        character = character + delta_start if delta_line == 0 else delta_start
        names = [m for bit, m in enumerate(legend.token_modifiers) if modifiers & (1 << bit)]
        found.append((lines[line][character : character + length], legend.token_types[kind], ",".join(names)))
    return found


async def test_semantic_tokens_follow_the_parser(client: Client) -> None:
    text = WALK + "# a comment\n<q> ::= 'a|#' | x # trailing\n"
    uri = new_uri()
    open_document(client, uri, text)
    legend = client.server_capabilities.semantic_tokens_provider.legend  # type: ignore[attr-defined]
    tokens = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=doc(uri))
    )
    assert tokens is not None
    found = decode(list(tokens.data), legend, text.split("\n"))
    assert found[:4] == [
        ("@start", "decorator", ""),
        ("<gait>", "function", ""),
        ("@backend", "decorator", ""),
        ("mujoco-horse", "enumMember", ""),
    ]
    assert ("<gait>", "function", "declaration") in found
    assert ("::=", "operator", "") in found
    assert ("limits", "parameter", "") in found
    assert ("-20..30", "number", "") in found
    assert ("int[0..20]", "number", "") in found
    assert ("*sin(2*PI*t)", "string", "") in found
    assert ("|", "operator", "") in found
    assert found[-7:] == [
        ("# a comment", "comment", ""),
        ("<q>", "function", "declaration"),
        ("::=", "operator", ""),
        ("'a|#'", "string", ""),  # quoted: neither a | nor a comment
        ("|", "operator", ""),
        ("x", "string", ""),
        ("# trailing", "comment", ""),
    ]
    in_range = await client.text_document_semantic_tokens_range_async(
        types.SemanticTokensRangeParams(text_document=doc(uri), range=span(at(5, 0), at(5, 30)))
    )
    assert in_range is not None
    assert decode(list(in_range.data), legend, text.split("\n")) == [
        ("<amp>", "function", "declaration"),
        ("::=", "operator", ""),
        ("int[0..20]", "number", ""),
    ]


async def test_folding_ranges(client: Client) -> None:
    text = "# one\n# two\n<a> ::= x\n  | y\n  | z\n<b> ::= w\n"
    uri = new_uri()
    open_document(client, uri, text)
    folds = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=doc(uri)))
    assert folds is not None
    assert [(f.start_line, f.end_line, f.kind) for f in folds] == [
        (0, 1, types.FoldingRangeKind.Comment),
        (2, 4, types.FoldingRangeKind.Region),
    ]


async def test_formatting_is_gaitgram_fmt_and_refuses_syntax_errors(client: Client) -> None:
    from gaitgram.language.formatter import format_text

    text = "@start <a>\n<a>::=<b>|<c>\n<b> ::= x\n<c>   ::=   y\n"
    uri = new_uri()
    open_document(client, uri, text)
    options = types.FormattingOptions(tab_size=4, insert_spaces=True)
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(text_document=doc(uri), options=options)
    )
    assert edits is not None
    lines = text.split("\n")
    (change,) = edits
    start = sum(len(line) + 1 for line in lines[: change.range.start.line]) + change.range.start.character
    end = sum(len(line) + 1 for line in lines[: change.range.end.line]) + change.range.end.character
    assert text[:start] + change.new_text + text[end:] == format_text(text)
    assert change.range.start == at(1, 0)  # the untouched first line is left alone
    broken = new_uri()
    open_document(client, broken, "<a> ::= 'open\n")
    refused = await client.text_document_formatting_async(
        types.DocumentFormattingParams(text_document=doc(broken), options=options)
    )
    assert list(refused or []) == []


async def test_inlay_hints_show_choices_and_codons(client: Client) -> None:
    text = WALK + "<k> ::= 2*float[0..1 step 0.5]\n"
    uri = new_uri()
    open_document(client, uri, text)
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(text_document=doc(uri), range=span(at(0, 0), at(20, 0)))
    )
    assert hints is not None
    assert [(h.position, h.label) for h in hints] == [
        (at(2, 6), "1 choice, no codon (lazy)"),
        (at(4, 5), "1 choice, no codon (lazy)"),
        (at(5, 5), "21 choices, 1 codon"),
        (at(6, 8), "2 choices, 1 codon"),
        (at(7, 3), "1 choice, no codon (lazy)"),
        (at(7, 30), "3 values, 1 codon"),
    ]
    some = await client.text_document_inlay_hint_async(
        types.InlayHintParams(text_document=doc(uri), range=span(at(5, 0), at(5, 10)))
    )
    assert [h.label for h in some or []] == ["21 choices, 1 codon"]
