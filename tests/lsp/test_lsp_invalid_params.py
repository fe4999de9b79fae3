"""Requests with positions that are not LSP positions get InvalidParams, over the real protocol:
raw JSON-RPC on the server's stdio, since a typed client cannot even send them."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
import time
from pathlib import Path

import pytest

INVALID_PARAMS = -32602
DOCUMENT = {"uri": "file:///x.gg", "languageId": "gaitgram", "version": 1, "text": "<a> ::= <b>\n<b> ::= x\n"}


class RawServer:
    def __init__(self) -> None:
        self.process = subprocess.Popen(
            [sys.executable, "-m", "gaitgram_lsp"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
        )
        self.buffer = b""

    def send(self, message: dict) -> None:
        body = json.dumps({"jsonrpc": "2.0", **message}).encode()
        assert self.process.stdin is not None
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.process.stdin.flush()

    def answers(self, ids: set[int], timeout: float = 30.0) -> dict[int, dict]:
        found: dict[int, dict] = {}
        deadline = time.monotonic() + timeout
        assert self.process.stdout is not None
        descriptor = self.process.stdout.fileno()
        while not ids <= set(found) and time.monotonic() < deadline:
            if select.select([descriptor], [], [], 0.1)[0]:
                self.buffer += os.read(descriptor, 65536)
            while b"\r\n\r\n" in self.buffer:
                head, rest = self.buffer.split(b"\r\n\r\n", 1)
                length = next(int(line.split(b":")[1]) for line in head.split(b"\r\n") if b"Length" in line)
                if len(rest) < length:
                    break
                message, self.buffer = json.loads(rest[:length]), rest[length:]
                if message.get("id") in ids:
                    found[message["id"]] = message
        return found

    def close(self) -> None:
        self.process.kill()
        self.process.wait()


@pytest.fixture
def server():
    raw = RawServer()
    raw.send(
        {"id": 0, "method": "initialize", "params": {"processId": None, "rootUri": None, "capabilities": {}}}
    )
    assert raw.answers({0})
    raw.send({"method": "initialized", "params": {}})
    raw.send({"method": "textDocument/didOpen", "params": {"textDocument": DOCUMENT}})
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
