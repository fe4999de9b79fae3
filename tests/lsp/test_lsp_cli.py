"""Starting the server: ``gaitgram lsp`` answers over stdio, ``gaitgram lsp --tcp HOST:PORT``
over TCP; ``gaitgram-lsp`` exists."""

from __future__ import annotations

import asyncio
import shutil
import socket
import subprocess
import sys
from pathlib import Path

import pytest
from lsprotocol import types
from pygls.lsp.client import LanguageClient


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


async def talk(port: int | None) -> list[types.Diagnostic]:
    """Open a document with an undefined name and return its diagnostics: over TCP to
    ``port``, or over stdio to a ``gaitgram lsp`` this starts."""
    client = LanguageClient("gaitgram-test", "1")
    published: asyncio.Future[list[types.Diagnostic]] = asyncio.get_running_loop().create_future()

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: types.PublishDiagnosticsParams) -> None:
        if not published.done():
            published.set_result(list(params.diagnostics))

    if port is None:
        await client.start_io(sys.executable, "-m", "gaitgram", "lsp")
    else:
        for _ in range(100):  # the server takes a moment to import and listen
            try:
                await client.start_tcp("127.0.0.1", port)
                break
            except OSError:
                await asyncio.sleep(0.1)
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(
                uri="file:///tcp.gg", language_id="gaitgram", version=1, text="<a> ::= <b>\n"
            )
        )
    )
    found = await asyncio.wait_for(published, 20)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return found


def test_gaitgram_lsp_over_stdio() -> None:
    found = asyncio.run(talk(None))
    assert [(d.code, d.message) for d in found] == [("GG201", "<b> is not defined")]


def test_gaitgram_lsp_over_tcp() -> None:
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "gaitgram", "lsp", "--tcp", f"127.0.0.1:{port}"],
        stderr=subprocess.PIPE,
    )
    try:
        found = asyncio.run(talk(port))
    finally:
        server.terminate()
        server.wait(10)
    assert [(d.code, d.message) for d in found] == [("GG201", "<b> is not defined")]


def test_the_gaitgram_lsp_script_is_installed() -> None:
    script = shutil.which("gaitgram-lsp", path=str(Path(sys.executable).parent))
    if script is None:
        pytest.skip("gaitgram is not installed with its scripts here")
    shown = subprocess.run([script, "--help"], capture_output=True, text=True, timeout=60, check=True)
    assert "--tcp HOST:PORT" in shown.stdout
