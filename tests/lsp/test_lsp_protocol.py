"""The server keeps the protocol over raw stdio: every request gets an answer (an error where
the LSP specification or JSON-RPC says so), never silence, and ``exit`` ends the process with
the status the specification gives. Every wait has a deadline, so a server that does not answer
fails the test instead of hanging it."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from rawrpc import CLI_SERVER, DOCUMENT, SERVER, RawServer

INVALID_REQUEST = -32600
SERVER_NOT_INITIALIZED = -32002
HOVER = {"textDocument": {"uri": DOCUMENT["uri"]}, "position": {"line": 0, "character": 9}}


@pytest.fixture
def server() -> Iterator[RawServer]:
    raw = RawServer()
    raw.initialize()
    yield raw
    raw.close()


def refused(answer: dict, *words: str) -> bool:
    error = answer.get("error") or {}
    return error.get("code") == INVALID_REQUEST and all(word in error.get("message", "") for word in words)


def test_before_initialize_requests_get_server_not_initialized_and_initialize_is_taken_once() -> None:
    server = RawServer()
    try:
        server.send({"method": "textDocument/didOpen", "params": {"textDocument": DOCUMENT}})  # dropped
        server.send({"id": 1, "method": "textDocument/hover", "params": HOVER})
        server.send({"id": 2, "method": "shutdown"})
        found = server.answers({1, 2}, timeout=10)
        assert set(found) == {1, 2}, found
        for answer in found.values():
            assert answer["error"]["code"] == SERVER_NOT_INITIALIZED
            assert "send initialize before" in answer["error"]["message"]
        server.send({"id": 3, "method": "initialize", "params": {"processId": None, "capabilities": {}}})
        assert "capabilities" in server.answers({3}, timeout=30)[3]["result"]
        server.send({"id": 4, "method": "initialize", "params": {"processId": None, "capabilities": {}}})
        assert refused(server.answers({4}, timeout=10)[4], "only once")
        server.send({"id": 5, "method": "textDocument/hover", "params": HOVER})
        assert server.answers({5}, timeout=10)[5]["result"] is None  # the early didOpen was not taken
    finally:
        server.close()


def test_after_shutdown_requests_get_invalid_request_and_exit_ends_with_0(server: RawServer) -> None:
    server.send({"id": 1, "method": "shutdown"})
    assert server.answers({1}, timeout=10) == {1: {"jsonrpc": "2.0", "id": 1, "result": None}}
    server.send({"id": 2, "method": "textDocument/hover", "params": HOVER})
    server.send({"id": 3, "method": "shutdown"})  # a second shutdown is a request after shutdown too
    server.send({"id": "four", "method": "workspace/symbol", "params": {"query": ""}})
    server.send({"method": "textDocument/didClose", "params": {"textDocument": {"uri": DOCUMENT["uri"]}}})
    found = server.answers({2, 3, "four"}, timeout=10)
    assert set(found) == {2, 3, "four"}, found
    assert refused(found[2], "shut down", "textDocument/hover")
    assert refused(found[3], "shut down", "shutdown")
    assert refused(found["four"], "shut down", "workspace/symbol")
    server.send({"method": "exit"})
    assert server.exit_status(timeout=10) == 0


@pytest.mark.parametrize("command", [SERVER, CLI_SERVER], ids=["gaitgram-lsp", "gaitgram lsp"])
@pytest.mark.parametrize(("shut_down", "status"), [(False, 1), (True, 0)])
def test_exit_ends_with_1_without_shutdown_and_0_after_it(
    command: tuple[str, ...], shut_down: bool, status: int
) -> None:
    server = RawServer(*command)
    try:
        server.initialize()
        server.send({"id": 1, "method": "textDocument/hover", "params": HOVER})
        assert "result" in server.answers({1}, timeout=10)[1]
        if shut_down:
            server.send({"id": 2, "method": "shutdown"})
            assert server.answers({2}, timeout=10)[2]["result"] is None
        server.send({"method": "exit"})
        assert server.exit_status(timeout=10) == status
    finally:
        server.close()


@pytest.mark.parametrize(
    ("message", "answered_id", "words"),
    [
        ({"id": 5}, 5, ["needs a method"]),
        ({"id": "five", "params": {}}, "five", ["needs a method"]),
        ({"id": 6, "method": 7}, 6, ["method must be a string"]),
        ({"id": 7, "method": "textDocument/hover", "params": HOVER, "jsonrpc": "1.0"}, 7, ['"2.0"']),
        ({"id": {"not": "an id"}, "method": "textDocument/hover", "params": HOVER}, None, ["id must be"]),
    ],
)
def test_a_message_with_an_id_that_is_no_request_gets_invalid_request(
    server: RawServer, message: dict, answered_id: object, words: list[str]
) -> None:
    server.send(message)
    found = server.answers({answered_id}, timeout=10)
    assert answered_id in found, server.received
    assert refused(found[answered_id], "invalid request", *words), found
    server.send({"id": 100, "method": "textDocument/hover", "params": HOVER})
    assert "result" in server.answers({100}, timeout=10)[100]  # and the server goes on


def test_a_request_without_jsonrpc_gets_invalid_request(server: RawServer) -> None:
    server.send({"id": 8, "method": "textDocument/hover", "params": HOVER}, jsonrpc=False)
    found = server.answers({8}, timeout=10)
    assert 8 in found, server.received
    assert refused(found[8], '"jsonrpc": "2.0"')


@pytest.mark.parametrize(
    ("method", "params"),
    [
        ("initialized", {}),
        (
            "textDocument/didChange",
            {"textDocument": {"uri": DOCUMENT["uri"], "version": 2}, "contentChanges": []},
        ),
        ("$/cancelRequest", {"id": 1}),
        ("exit", None),
    ],
)
def test_a_notification_sent_with_an_id_gets_invalid_request_and_is_not_acted_on(
    server: RawServer, method: str, params: object
) -> None:
    server.send({"id": 9, "method": method, "params": params})
    found = server.answers({9}, timeout=10)
    assert 9 in found, server.received
    assert refused(found[9], f"{method} is a notification")
    server.send({"id": 10, "method": "textDocument/hover", "params": HOVER})
    assert "result" in server.answers({10}, timeout=10)[10]  # still running: exit with an id did not exit
    assert server.process.poll() is None


def test_a_response_from_the_client_is_not_answered(server: RawServer) -> None:
    """A message with an id and a result is a response (to a request of the server's), which
    JSON-RPC never answers."""
    server.send({"id": 11, "result": None})
    server.send({"id": 12, "method": "textDocument/hover", "params": HOVER})
    assert 12 in server.answers({12}, timeout=10)
    assert not [m for m in server.received if m.get("id") == 11]  # messages are handled in order
