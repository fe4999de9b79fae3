"""The language server over its protocol: a real server process driven by pytest-lsp."""

from __future__ import annotations

import sys

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

from gaitgram.analysis import check
from gaitgram.language import parse

URI = "file:///tmp/walk.gg"
TEXT = """\
@backend mujoco-horse
<gait> ::= <hip>;<neck>
@joint hip_hind limits=-30..30
<hip> ::= <amp>*sin(2*PI*t)
<amp> ::= int[0..20]
<unused> ::= <amp> | <missing>
"""


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[sys.executable, "-m", "gaitgram_lsp"]))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(capabilities=types.ClientCapabilities()))
    yield
    await lsp_client.shutdown_session()


def open_document(client: LanguageClient, text: str = TEXT, version: int = 1) -> None:
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=URI, language_id="gaitgram", version=version, text=text)
        )
    )


@pytest.mark.asyncio
async def test_diagnostics_equal_gaitgram_check(client: LanguageClient) -> None:
    open_document(client)
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    published = client.diagnostics[URI]
    expected = check(parse(TEXT)).diagnostics
    assert [d.code for d in published] == [d.code.code for d in expected]
    undefined = next(d for d in published if d.code == "GG201")
    assert undefined.range.start == types.Position(line=1, character=17)
    assert undefined.severity == types.DiagnosticSeverity.Error


@pytest.mark.asyncio
async def test_diagnostics_follow_edits(client: LanguageClient) -> None:
    open_document(client)
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    fixed = TEXT.replace("<hip>;<neck>", "<hip>").replace(" | <missing>", "")
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=fixed)],
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert [d.code for d in client.diagnostics[URI]] == [d.code.code for d in check(parse(fixed)).diagnostics]
    assert "GG201" not in {d.code for d in client.diagnostics[URI]}


@pytest.mark.asyncio
async def test_completion_depends_on_context(client: LanguageClient) -> None:
    text = TEXT + "<more> ::= <\n@jo\n@joint \n"
    open_document(client, text)
    lines = text.split("\n")

    async def labels(line: int) -> set[str]:
        result = await client.text_document_completion_async(
            types.CompletionParams(
                text_document=types.TextDocumentIdentifier(uri=URI),
                position=types.Position(line=line, character=len(lines[line])),
            )
        )
        return {item.label for item in result.items}

    assert {"gait", "hip", "amp"} <= await labels(6)
    assert "joint" in await labels(7)
    joints = await labels(8)
    assert {"hip_hind", "elbow_fore"} <= joints
    assert "gait" not in joints


@pytest.mark.asyncio
async def test_hover_definition_and_references(client: LanguageClient) -> None:
    open_document(client)
    where = {
        "text_document": types.TextDocumentIdentifier(uri=URI),
        "position": types.Position(line=3, character=12),  # on <amp> in the <hip> rule
    }
    hover = await client.text_document_hover_async(types.HoverParams(**where))
    assert "**<amp>**: 21 choices" in hover.contents.value
    definition = await client.text_document_definition_async(types.DefinitionParams(**where))
    assert definition.range.start.line == 4
    references = await client.text_document_references_async(
        types.ReferenceParams(**where, context=types.ReferenceContext(include_declaration=True))
    )
    assert sorted(r.range.start.line for r in references) == [3, 4, 5]


def doc() -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(uri=URI)


def at(line: int, character: int) -> types.Position:
    return types.Position(line=line, character=character)


@pytest.mark.asyncio
async def test_symbols_folding_highlight(client: LanguageClient) -> None:
    open_document(client, TEXT + "<long> ::= a\n  | b\n")
    symbols = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=doc())
    )
    assert [s.name for s in symbols] == ["<gait>", "<hip>", "<amp>", "<unused>", "<long>"]
    assert symbols[1].detail == "joint hip_hind"
    folds = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=doc()))
    assert [(f.start_line, f.end_line) for f in folds] == [(6, 7)]
    highlights = await client.text_document_document_highlight_async(
        types.DocumentHighlightParams(text_document=doc(), position=at(4, 2))
    )
    assert sorted(h.range.start.line for h in highlights) == [3, 4, 5]


@pytest.mark.asyncio
async def test_rename_and_prepare_rename(client: LanguageClient) -> None:
    open_document(client)
    prepared = await client.text_document_prepare_rename_async(
        types.PrepareRenameParams(text_document=doc(), position=at(4, 2))
    )
    assert prepared.start == at(4, 1)
    assert prepared.end == at(4, 4)
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=doc(), position=at(4, 2), new_name="amplitude")
    )
    assert len(edit.changes[URI]) == 3
    assert {e.new_text for e in edit.changes[URI]} == {"amplitude"}
    with pytest.raises(Exception, match="not a rule name"):
        await client.text_document_rename_async(
            types.RenameParams(text_document=doc(), position=at(4, 2), new_name="two words")
        )


@pytest.mark.asyncio
async def test_formatting_and_code_actions(client: LanguageClient) -> None:
    open_document(client, "<a>::=<b>|<aa>\n<b> ::= x\n<zz> ::= y\n")
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=doc(), options=types.FormattingOptions(tab_size=4, insert_spaces=True)
        )
    )
    assert edits[0].new_text == "<a> ::= <b> | <aa>\n<b> ::= x\n<zz> ::= y\n"
    actions = await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=doc(),
            range=types.Range(start=at(0, 11), end=at(0, 12)),
            context=types.CodeActionContext(diagnostics=[]),
        )
    )
    titles = [a.title for a in actions]
    assert "Define <aa>" in titles
    assert "Replace with <a>" in titles
    removal = await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=doc(),
            range=types.Range(start=at(2, 1), end=at(2, 2)),
            context=types.CodeActionContext(diagnostics=[]),
        )
    )
    assert [a.title for a in removal] == ["Remove unreachable <zz>"]


@pytest.mark.asyncio
async def test_inlay_hints(client: LanguageClient) -> None:
    open_document(client)
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(text_document=doc(), range=types.Range(start=at(0, 0), end=at(10, 0)))
    )
    labels = [h.label for h in hints]
    assert " 21 choices, reads a codon" in labels
    assert " 1 choices, no codon (lazy)" in labels


EDITS = ["<", ">", " ::= ", "|", "\n", "@joint ", "int[0..", "]", "'", "é", "😀", "<x>", "#"]


@pytest.mark.asyncio
async def test_random_edits_never_break_the_server(client: LanguageClient) -> None:
    """Insertions, deletions, half-typed rules and garbage: after each, the server answers and
    its diagnostics equal `gaitgram check` on the same text."""
    import random

    rng = random.Random(7)
    text = TEXT
    open_document(client, text)
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    for version in range(2, 42):
        position = rng.randrange(len(text) + 1)
        if rng.random() < 0.3 and text:
            text = text[:position] + text[position + rng.randint(1, 8) :]
        else:
            text = text[:position] + rng.choice(EDITS) + text[position:]
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=version),
                content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
            )
        )
        await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        assert [d.code for d in client.diagnostics[URI]] == [
            d.code.code for d in check(parse(text)).diagnostics
        ]
        lines = text.split("\n")
        result = await client.text_document_completion_async(
            types.CompletionParams(text_document=doc(), position=at(len(lines) - 1, len(lines[-1])))
        )
        assert result is not None


@pytest.mark.asyncio
async def test_range_hover_semantic_tokens_pull_and_workspace_symbols(client: LanguageClient) -> None:
    open_document(client)
    hover = await client.text_document_hover_async(types.HoverParams(text_document=doc(), position=at(4, 12)))
    assert "**int[0..20]**: 21 values" in hover.contents.value
    assert "first `0`, last `20`" in hover.contents.value
    tokens = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=doc())
    )
    assert len(tokens.data) % 5 == 0
    assert len(tokens.data) >= 5 * 10
    first = tokens.data[:5]  # "@backend" on line 0
    assert list(first[:3]) == [0, 0, len("@backend")]
    report = await client.text_document_diagnostic_async(types.DocumentDiagnosticParams(text_document=doc()))
    assert [d.code for d in report.items] == [d.code.code for d in check(parse(TEXT)).diagnostics]
    symbols = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="hi"))
    assert [s.name for s in symbols] == ["<hip>"]


@pytest.mark.asyncio
async def test_snippets_offered_on_right_hand_sides(client: LanguageClient) -> None:
    text = TEXT + "<more> ::= \n"
    open_document(client, text)
    result = await client.text_document_completion_async(
        types.CompletionParams(text_document=doc(), position=at(6, len("<more> ::= ")))
    )
    snippets = [i for i in result.items if i.kind == types.CompletionItemKind.Snippet]
    assert {"int range", "relative range", "new rule"} <= {s.label for s in snippets}
    assert all(s.insert_text_format == types.InsertTextFormat.Snippet for s in snippets)
