"""The server never crashes or stops answering: random edit sequences (insertions, deletions,
half-typed rules, garbage, emoji, odd line breaks) go through didChange, and after each the
server answers requests and publishes exactly ``gaitgram check``'s diagnostics for that text.

One server serves every example (a fresh document each); the debounce is set to 5 ms through
the initialization options so that waiting for each version stays quick.
"""

from __future__ import annotations

import asyncio
import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lsprotocol import types
from pytest_lsp import client_capabilities

from conftest import SERVER, at, doc, expected, make_client, new_uri, open_document, published, seen

SEEDS = [
    "",
    "@start <gait>\n@backend mujoco-horse\n<gait> ::= <hip>;<neck>\n"
    "@joint hip_hind limits=-20..30 free=11..\n<hip> ::= <amp>*sin(2*PI*t)\n"
    "<amp> ::= int[0..20] | float[0..1 step 0.25]\n<unused> ::= <amp> | <x>\n",
    "<e> ::= <e> + <e>\n  | <v>  # a comment\n<v> ::= x | y | '|' | GE_RANGE:3\n",
]
PIECES = [
    "<",
    ">",
    "<ne",
    "<new> ::= ",
    " ::= ",
    "|",
    " | x",
    "\n",
    "\r\n",
    "\r",
    "@",
    "@joint ",
    "@start <e",
    "@define n=2\n",
    "GE_RANGE:n",
    "int[0..",
    "float[0..1 step 0.",
    "]",
    "'",
    '"',
    "#",
    "\\",
    "é",
    "😀",
    "\u2028",
    "\x0c",
]
insertion = st.one_of(st.sampled_from(PIECES), st.text(max_size=6))
edits = st.lists(
    st.tuples(st.floats(0, 1), st.integers(0, 6), st.lists(insertion, max_size=3).map("".join)),
    min_size=1,
    max_size=10,
)


@pytest.fixture(scope="module")
def server():
    loop = asyncio.new_event_loop()
    client = make_client()

    async def start() -> None:
        await client.start_io(*SERVER)
        await client.initialize_session(
            types.InitializeParams(
                capabilities=client_capabilities("visual-studio-code"), initialization_options={"debounce": 5}
            )
        )

    loop.run_until_complete(start())
    yield loop, client
    loop.run_until_complete(client.shutdown_session())
    loop.run_until_complete(client.stop())
    loop.close()


_BREAK = re.compile(r"\r\n|\r|\n")


def position(text: str, offset: int) -> types.Position:
    """The LSP (UTF-16) position of an offset of the client's text."""
    line, start = 0, 0
    for found in _BREAK.finditer(text, 0, offset):
        if found.end() <= offset:
            line, start = line + 1, found.end()
    return at(line, len(text[start:offset].encode("utf-16-le")) // 2)


def not_inside_crlf(text: str, offset: int) -> int:
    return offset - 1 if 0 < offset < len(text) and text[offset - 1 : offset + 1] == "\r\n" else offset


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(seed=st.sampled_from(SEEDS), steps=edits)
def test_random_edits_keep_the_server_answering_with_checks_diagnostics(server, seed: str, steps) -> None:
    loop, client = server
    loop.run_until_complete(_run(client, seed, steps))


async def _run(client, text: str, steps) -> None:
    uri = new_uri("hypothesis")
    open_document(client, uri, text)
    assert seen(await published(client, uri, 1)) == expected(text)
    for version, (where, length, inserted) in enumerate(steps, start=2):
        start = not_inside_crlf(text, round(where * len(text)))
        end = not_inside_crlf(text, min(len(text), start + length))
        change = types.TextDocumentContentChangePartial(
            range=types.Range(start=position(text, start), end=position(text, end)), text=inserted
        )
        text = text[:start] + inserted + text[end:]
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[change],
            )
        )
        assert seen(await published(client, uri, version)) == expected(text), text
        cursor = position(text, start + len(inserted))
        completion = await client.text_document_completion_async(
            types.CompletionParams(text_document=doc(uri), position=cursor)
        )
        assert completion is not None
        await client.text_document_hover_async(types.HoverParams(text_document=doc(uri), position=cursor))
        await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=doc(uri)))
    client.text_document_did_close(types.DidCloseTextDocumentParams(text_document=doc(uri)))
