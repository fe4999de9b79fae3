"""Sensors over the protocol, on the real server: a curve that reads a misspelt sensor gets the
linter's GG508 with its quick fix, hover shows what a sensor reads, completion in a curve's text
offers the backend's sensors as variables with their units, and semantic tokens mark them as
readonly variables."""

from __future__ import annotations

import pytest
from lsprotocol import types

from conftest import Client, at, doc, new_uri, open_document, published

pytestmark = pytest.mark.asyncio(loop_scope="module")

GRAMMAR = """\
@backend mujoco-horse
<gait> ::= <hip>;<neck>
@joint hip_hind limits=-20..30
<hip> ::= <amp>*sin(2*PI*t)+<gain>*pitch+<gain>*(load-1)
@joint neck_mid
<neck> ::= <amp>*sin(2*PI*t)+<gain>*pich
<amp> ::= int[0..20]
<gain> ::= float[-1..1 step 0.5]
"""
LINES = GRAMMAR.split("\n")


async def test_a_closed_loop_grammar_in_the_editor(client: Client) -> None:
    uri = new_uri("sensors")
    open_document(client, uri, GRAMMAR)

    diagnostics = await published(client, uri, 1)
    (unknown,) = [d for d in diagnostics if d.code == "GG508"]
    column = LINES[5].index("pich")
    assert unknown.range == types.Range(start=at(5, column), end=at(5, column + 4))
    assert unknown.severity == types.DiagnosticSeverity.Error
    actions = await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=doc(uri),
            range=unknown.range,
            context=types.CodeActionContext(diagnostics=[unknown]),
        )
    )
    assert actions is not None
    titles = {a.title for a in actions if isinstance(a, types.CodeAction)}
    assert "Replace with pitch" in titles

    hover = await client.text_document_hover_async(
        types.HoverParams(text_document=doc(uri), position=at(3, LINES[3].index("load") + 1))
    )
    assert hover is not None
    assert isinstance(hover.contents, types.MarkupContent)
    assert "**`load`**: a sensor of mujoco-horse, in share" in hover.contents.value
    assert hover.range == types.Range(
        start=at(3, LINES[3].index("load")), end=at(3, LINES[3].index("load") + 4)
    )

    typed = LINES[3] + "+0.1*sp"
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=at(3, 0), end=at(3, len(LINES[3]))), text=typed
                )
            ],
        )
    )
    await published(client, uri, 2)
    result = await client.text_document_completion_async(
        types.CompletionParams(text_document=doc(uri), position=at(3, len(typed)))
    )
    assert isinstance(result, types.CompletionList)
    sensors = {i.label: i for i in result.items if i.kind == types.CompletionItemKind.Variable}
    assert set(sensors) == {
        "pitch",
        "pitch_rate",
        "height",
        "speed",
        "pace",
        "cycle_pace",
        "load",
        "contact",
        "phase",
    }
    assert sensors["speed"].detail == "m/s"
    assert sensors["speed"].text_edit is not None
    assert sensors["speed"].text_edit.range == types.Range(start=at(3, len(typed) - 2), end=at(3, len(typed)))

    legend = client.server_capabilities.semantic_tokens_provider.legend  # type: ignore[attr-defined]
    assert "variable" in legend.token_types
    assert "readonly" in legend.token_modifiers
    tokens = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=doc(uri))
    )
    assert tokens is not None
    lines = GRAMMAR.split("\n")
    lines[3] = typed
    marked = []
    line = character = 0
    data = list(tokens.data)
    for i in range(0, len(data), 5):
        delta_line, delta_start, length, kind, modifiers = data[i : i + 5]
        line += delta_line
        character = character + delta_start if delta_line == 0 else delta_start
        if legend.token_types[kind] == "variable":
            readonly = bool(modifiers & (1 << legend.token_modifiers.index("readonly")))
            marked.append((line, lines[line][character : character + length], readonly))
    # ``sp`` is no sensor and ``pich`` a misspelt one: only real sensors are marked.
    assert marked == [(3, "pitch", True), (3, "load", True)]
