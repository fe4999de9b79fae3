"""The server reads every message the LSP base protocol allows, and no malformed one stops it.

Over raw stdio, bytes framed by hand: header names in any case, extra headers, a Content-Type;
then messages with a length that is missing, not a number, too short, too long or too large, and
bodies that are not JSON. Each malformed request whose id can be read gets a JSON-RPC error
naming what is wrong, and a well-framed hover sent after it must still be answered."""

from __future__ import annotations

import json
from collections.abc import Iterator

import pytest

from rawrpc import DOCUMENT, RawServer

PARSE_ERROR, INVALID_REQUEST = -32700, -32600
HOVER = {"textDocument": {"uri": DOCUMENT["uri"]}, "position": {"line": 0, "character": 9}}


@pytest.fixture
def server() -> Iterator[RawServer]:
    raw = RawServer()
    raw.initialize()
    yield raw
    raw.close()


def request(msg_id: int, method: str = "textDocument/hover", params: object = HOVER) -> bytes:
    return json.dumps({"jsonrpc": "2.0", "id": msg_id, "method": method, "params": params}).encode()


def framed(body: bytes) -> bytes:
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


def hover_answered(server: RawServer, msg_id: int) -> None:
    """A well-framed hover, sent now, is answered with the hover of ``<b>``."""
    server.send({"id": msg_id, "method": "textDocument/hover", "params": HOVER})
    answer = server.answers({msg_id}, timeout=20).get(msg_id)
    assert answer is not None, "the server stopped answering"
    assert "<b>" in answer["result"]["contents"]["value"], answer


HEADERS = [
    b"content-length: %d\r\n\r\n",
    b"CONTENT-LENGTH:%d\r\n\r\n",
    b"Content-length:   %d  \r\n\r\n",
    b"Content-Type: application/vscode-jsonrpc; charset=utf-8\r\nContent-Length: %d\r\n\r\n",
    b"X-Trace: 1\r\ncontent-type: application/vscode-jsonrpc; charset=utf8\r\nContent-Length: %d\r\n\r\n",
    b"Content-Length: %d\r\nX-Client: test\r\n\r\n",
]


def test_every_well_formed_header_is_read(server: RawServer) -> None:
    """Names in any case, spaces around the value, a Content-Type, headers LSP does not define."""
    for msg_id, header in enumerate(HEADERS, start=10):
        body = request(msg_id)
        server.send_bytes(header % len(body) + body)
        answer = server.answers({msg_id}, timeout=20).get(msg_id)
        assert answer is not None, f"no answer to a message framed {header!r}"
        assert "<b>" in answer["result"]["contents"]["value"], answer
    hover_answered(server, 99)


@pytest.mark.parametrize(
    ("data", "code", "words"),
    [
        (b"Content-Length: abc\r\n\r\n" + request(20), INVALID_REQUEST, ["Content-Length 'abc'"]),
        (b"Content-Length: -5\r\n\r\n" + request(20), INVALID_REQUEST, ["not a number of bytes"]),
        (
            b"Content-Type: application/vscode-jsonrpc\r\n\r\n" + request(20),
            INVALID_REQUEST,
            ["no Content-Length"],
        ),
        (b"Content-Length: 50\r\n\r\n" + request(20), PARSE_ERROR, ["not JSON", "Content-Length"]),
        (
            b"Content-Length: %d\r\n\r\n" % (len(request(20)) + 400) + request(20),
            INVALID_REQUEST,
            ["more than the body"],
        ),
        (
            b"Content-Length: %d\r\n\r\n" % (len(request(20)) + 3) + request(20),
            INVALID_REQUEST,
            ["more than the body"],
        ),
        (b"Content-Length: 99999999999999\r\n\r\n" + request(20), INVALID_REQUEST, ["more than the body"]),
        (framed(b'{"jsonrpc": "2.0", "id": 20, "method": "x", nonsense'), PARSE_ERROR, ["not JSON"]),
    ],
    ids=[
        "not-a-number",
        "negative",
        "missing",
        "too-short",
        "too-long",
        "a-little-too-long",
        "huge",
        "not-json",
    ],
)
def test_a_malformed_request_gets_an_error_and_the_next_is_answered(
    server: RawServer, data: bytes, code: int, words: list[str]
) -> None:
    server.send_bytes(data)  # and right after it, as a client that expects no answer would:
    server.send({"id": 21, "method": "textDocument/hover", "params": HOVER})
    found = server.answers({20, 21}, timeout=20)
    assert 20 in found, "the malformed request was not answered"
    assert found[20]["error"]["code"] == code, found[20]
    assert all(word in found[20]["error"]["message"] for word in words), found[20]
    assert 21 in found, "the hover after it was not answered"
    assert "<b>" in found[21]["result"]["contents"]["value"], found


def test_malformed_messages_with_no_id_are_skipped(server: RawServer) -> None:
    """Skipped with a log message: there is no id to answer. A notification framed in lower case
    is taken (the document it opens is hovered last)."""
    opened = {"uri": "file:///y.gg", "languageId": "gaitgram", "version": 1, "text": "<c> ::= x\n"}
    notification = json.dumps(
        {"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": opened}}
    )
    for data in [
        b"content-length: %d\r\n\r\n" % len(notification) + notification.encode(),
        framed(b"{not json at all"),
        framed(b"\xff\xfe not UTF-8"),
        framed(b"[1, 2, 3]"),
        framed(b""),
        b"this is no header\r\n\r\n",
        b"\r\n\r\n\r\n",
        b"Content-Length: 7\r\n\r\ngarbage",
    ]:
        server.send_bytes(data)
    hover_answered(server, 30)
    server.send(
        {
            "id": 31,
            "method": "textDocument/hover",
            "params": {
                **HOVER,
                "textDocument": {"uri": opened["uri"]},
                "position": {"line": 0, "character": 1},
            },
        }
    )
    answer = server.answers({31}, timeout=20).get(31)
    assert answer is not None, "the hover of the document opened in lower case was not answered"
    assert "<c>" in answer["result"]["contents"]["value"], answer
    assert not any("error" in m for m in server.received), server.received


def test_an_oversize_body_is_skipped_unread_and_its_request_answered(server: RawServer) -> None:
    """A body over the limit (64 MiB) is read past, not kept: its request's id is read from its
    start, and the stream goes on right after it."""
    from gaitgram_lsp.framing import MAX_MESSAGE_BYTES

    head = b'{"jsonrpc": "2.0", "id": 40, "method": "textDocument/hover", "params": {"padding": "'
    size = MAX_MESSAGE_BYTES + 1
    server.send_bytes(b"Content-Length: %d\r\n\r\n" % size + head)
    filler = b"x" * (1 << 20)
    left = size - len(head)
    while left:
        piece = filler[: min(left, len(filler))]
        server.send_bytes(piece)
        left -= len(piece)
    answer = server.answers({40}, timeout=60).get(40)
    assert answer is not None, "the oversize request was not answered"
    assert answer["error"]["code"] == INVALID_REQUEST, answer
    assert "are not read" in answer["error"]["message"]
    hover_answered(server, 41)
