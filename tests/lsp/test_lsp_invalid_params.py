"""Requests with positions that are not LSP positions get InvalidParams, over the real protocol:
raw JSON-RPC on the server's stdio, since a typed client cannot even send them."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from rawrpc import DOCUMENT, RawServer

INVALID_PARAMS = -32602


@pytest.fixture
def server():
    raw = RawServer()
    raw.initialize()
    yield raw
    raw.close()


BAD = [
    ({"line": -1, "character": 0}, "position.line"),
    ({"line": 0, "character": -3}, "position.character"),
    ({"line": 2**31, "character": 0}, "position.line"),
    ({"line": 0, "character": 2**40}, "position.character"),
    ({"line": 0.5, "character": 0}, "position.line"),
    ({"line": 0, "character": "3"}, "position.character"),
    ({"line": True, "character": 0}, "position.line"),
]
METHODS = [
    "textDocument/completion",
    "textDocument/hover",
    "textDocument/definition",
    "textDocument/references",
]


def test_invalid_positions_get_invalid_params_and_the_server_goes_on(server: RawServer) -> None:
    ids = {}
    for i, (position, named) in enumerate(BAD):
        for j, method in enumerate(METHODS):
            request = 100 * i + j + 1
            params = {"textDocument": {"uri": DOCUMENT["uri"]}, "position": position}
            if method == "textDocument/references":
                params["context"] = {"includeDeclaration": True}
            server.send({"id": request, "method": method, "params": params})
            ids[request] = (method, named)
    good = 99_999
    server.send(
        {
            "id": good,
            "method": "textDocument/hover",
            "params": {"textDocument": {"uri": DOCUMENT["uri"]}, "position": {"line": 0, "character": 9}},
        }
    )
    found = server.answers({*ids, good})
    assert set(found) == {*ids, good}
    for request, (method, named) in ids.items():
        error = found[request].get("error")
        assert error is not None, (method, found[request])
        assert error["code"] == INVALID_PARAMS
        assert named in error["message"]
        assert method in error["message"]
    assert "error" not in found[good]
    assert found[good]["result"] is not None  # a hover on <b>: valid requests still answer


def test_stdin_from_a_regular_file_is_served_too(tmp_path: Path) -> None:
    """The server reads a pipe on its event loop; stdin that cannot be (a regular file) falls
    back to pygls's reader, and is answered all the same."""
    messages = [
        {
            "jsonrpc": "2.0",
            "id": 0,
            "method": "initialize",
            "params": {"processId": None, "capabilities": {}},
        },
        {"jsonrpc": "2.0", "method": "initialized", "params": {}},
        {"jsonrpc": "2.0", "id": 1, "method": "shutdown"},
        {"jsonrpc": "2.0", "method": "exit"},
    ]
    framed = b"".join(b"Content-Length: %d\r\n\r\n%s" % (len(body), body) for body in map(_encode, messages))
    requests = tmp_path / "requests.bin"
    requests.write_bytes(framed)
    with requests.open("rb") as stdin:
        done = subprocess.run(
            [sys.executable, "-m", "gaitgram_lsp"], stdin=stdin, capture_output=True, timeout=60
        )
    assert b'"id": 0' in done.stdout or b'"id":0' in done.stdout
    assert b'"capabilities"' in done.stdout


def _encode(message: dict) -> bytes:
    return json.dumps(message).encode()
