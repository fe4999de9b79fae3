"""A bare client for the server process: JSON-RPC framed by hand on its stdio, for messages a
typed client cannot send (bad positions, ids without a method, requests after shutdown), and
with a deadline on every wait, so that a server that never answers fails a test instead of
hanging it."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
import time
from typing import Any

SERVER = (sys.executable, "-m", "gaitgram_lsp")
#: The same server, started as users start it from the command line.
CLI_SERVER = (sys.executable, "-m", "gaitgram", "lsp")

DOCUMENT = {"uri": "file:///x.gg", "languageId": "gaitgram", "version": 1, "text": "<a> ::= <b>\n<b> ::= x\n"}


class RawServer:
    """``python -m gaitgram_lsp`` on pipes; every message it sent, in order, in ``received``."""

    def __init__(self, *command: str) -> None:
        self.process = subprocess.Popen(
            list(command or SERVER),
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
        )
        self.buffer = b""
        self.received: list[dict[str, Any]] = []

    def send(self, message: dict[str, Any], *, jsonrpc: bool = True) -> None:
        body = json.dumps({"jsonrpc": "2.0", **message} if jsonrpc else message).encode()
        assert self.process.stdin is not None
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.process.stdin.flush()

    def send_bytes(self, data: bytes) -> None:
        """Bytes as they are, framed (or misframed) by the caller."""
        assert self.process.stdin is not None
        self.process.stdin.write(data)
        self.process.stdin.flush()

    def answers(self, ids: set[Any], timeout: float = 30.0) -> dict[Any, dict[str, Any]]:
        """The answers to ``ids`` (requests, or any message with an id), waiting for them at
        most ``timeout`` seconds; those that did not come are missing."""
        found = {m["id"]: m for m in self.received if "method" not in m and m.get("id", ...) in ids}
        deadline = time.monotonic() + timeout
        assert self.process.stdout is not None
        descriptor = self.process.stdout.fileno()
        while not ids <= set(found) and time.monotonic() < deadline:
            if select.select([descriptor], [], [], 0.1)[0]:
                data = os.read(descriptor, 65536)
                if not data:  # the server ended
                    break
                self.buffer += data
            while b"\r\n\r\n" in self.buffer:
                head, rest = self.buffer.split(b"\r\n\r\n", 1)
                length = next(int(line.split(b":")[1]) for line in head.split(b"\r\n") if b"Length" in line)
                if len(rest) < length:
                    break
                message, self.buffer = json.loads(rest[:length]), rest[length:]
                self.received.append(message)
                if "method" not in message and message.get("id", ...) in ids:
                    found[message["id"]] = message
        return found

    def initialize(self) -> None:
        self.send(
            {
                "id": 0,
                "method": "initialize",
                "params": {"processId": None, "rootUri": None, "capabilities": {}},
            }
        )
        assert self.answers({0})
        self.send({"method": "initialized", "params": {}})
        self.send({"method": "textDocument/didOpen", "params": {"textDocument": DOCUMENT}})

    def exit_status(self, timeout: float = 30.0) -> int:
        """The process's exit status, once it ends (``subprocess.TimeoutExpired`` if it does not)."""
        return self.process.wait(timeout)

    def close(self) -> None:
        self.process.kill()
        self.process.wait()
