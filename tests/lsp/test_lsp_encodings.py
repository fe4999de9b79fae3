"""Positions in the encoding each editor negotiates: UTF-16 (VS Code), UTF-8 (Neovim 0.11),
UTF-32 (Emacs 29), on text with characters outside the Basic Multilingual Plane."""

from __future__ import annotations

import pytest
import pytest_lsp
from lsprotocol import types

from conftest import (
    CONFIG,
    Client,
    at,
    capabilities,
    code_units,
    doc,
    edit,
    expected,
    new_uri,
    open_document,
    published,
    seen,
    span,
)

pytestmark = pytest.mark.asyncio(loop_scope="module")

EDITORS = {"visual-studio-code": "utf-16", "neovim@v0.11.0": "utf-8", "emacs": "utf-32"}
TEXT = "<gait> ::= '😀' <hip> | é<missing>\n<hip> ::= x\n"


@pytest_lsp.fixture(scope="module", config=CONFIG, params=list(EDITORS))
async def editor(lsp_client: Client, request):
    result = await lsp_client.initialize_session(
        types.InitializeParams(capabilities=capabilities(request.param))
    )
    lsp_client.encoding = result.capabilities.position_encoding  # type: ignore[attr-defined]
    lsp_client.pulls = result.capabilities.diagnostic_provider is not None and request.param.startswith(
        "neovim"
    )  # type: ignore[attr-defined]
    assert lsp_client.encoding == EDITORS[request.param]  # type: ignore[attr-defined]
    yield
    await lsp_client.shutdown_session()


async def diagnostics(client: Client, uri: str, version: int) -> list[types.Diagnostic]:
    if client.pulls:  # type: ignore[attr-defined]
        report = await client.text_document_diagnostic_async(
            types.DocumentDiagnosticParams(text_document=doc(uri))
        )
        return list(report.items)  # type: ignore[union-attr]
    return await published(client, uri, version)


def column(line: str, characters: int, encoding: str) -> int:
    return code_units(line[:characters], encoding)


async def test_ranges_and_edits_after_an_emoji(editor: Client) -> None:
    encoding = editor.encoding  # type: ignore[attr-defined]
    uri = new_uri("encodings")
    open_document(editor, uri, TEXT)
    assert seen(await diagnostics(editor, uri, 1)) == expected(TEXT, encoding)
    line = TEXT.split("\n")[0]
    missing = line.index("<missing>")
    # rename the reference by an incremental edit just after the emoji's line position
    edit(
        editor,
        uri,
        2,
        span(at(0, column(line, missing + 1, encoding)), at(0, column(line, missing + 8, encoding))),
        "hip",
    )
    fixed = TEXT.replace("<missing>", "<hip>")
    assert seen(await diagnostics(editor, uri, 2)) == expected(fixed, encoding) == []
    hover = await editor.text_document_hover_async(
        types.HoverParams(
            text_document=doc(uri), position=at(0, column(line, line.index("<hip>") + 2, encoding))
        )
    )
    assert hover is not None
    assert hover.range == span(
        at(0, column(line, line.index("<hip>"), encoding)),
        at(0, column(line, line.index("<hip>") + 5, encoding)),
    )


async def test_completion_edits_are_in_the_negotiated_units(editor: Client) -> None:
    encoding = editor.encoding  # type: ignore[attr-defined]
    uri = new_uri("encodings")
    text = TEXT + "<more> ::= '😀😀' <g"
    open_document(editor, uri, text)
    line = text.split("\n")[2]
    result = await editor.text_document_completion_async(
        types.CompletionParams(text_document=doc(uri), position=at(2, column(line, len(line), encoding)))
    )
    assert result is not None
    gait = next(item for item in result.items if item.label == "<gait>")  # type: ignore[union-attr]
    assert gait.text_edit is not None
    assert gait.text_edit.range == span(
        at(2, column(line, len(line) - 2, encoding)), at(2, column(line, len(line), encoding))
    )
