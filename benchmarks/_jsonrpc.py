"""A bare JSON-RPC client over a server's stdio, for timing a language server as an editor
sees it.

pygls's client turns every message into lsprotocol objects before a handler sees it; for a
notification with 5,000 diagnostics that takes longer than the server took to make it, and
no editor pays it (they decode JSON natively). So the benchmark reads the frames itself and
stamps each message when its last byte arrives, before decoding it.
"""

from __future__ import annotations

import asyncio
import itertools
import json
import sys
import time
from collections.abc import Callable
from typing import Any


class RawClient:
    """Requests and notifications as plain JSON values; a callback per notification method,
    called with (arrival time, params)."""

    def __init__(self) -> None:
        self._process: asyncio.subprocess.Process | None = None
        self._ids = itertools.count(1)
        self._pending: dict[int, asyncio.Future[Any]] = {}
        self._handlers: dict[str, Callable[[float, Any], None]] = {}
        self._reader: asyncio.Task[None] | None = None

    @property
    def pid(self) -> int:
        assert self._process is not None
        return self._process.pid

    def on(self, method: str, handler: Callable[[float, Any], None]) -> None:
        self._handlers[method] = handler

    async def start(self, *server: str) -> None:
        self._process = await asyncio.create_subprocess_exec(
            *server,
            stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.DEVNULL,
        )
        self._reader = asyncio.create_task(self._read())

    async def request(self, method: str, params: Any) -> Any:
        msg_id = next(self._ids)
        future: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
        self._pending[msg_id] = future
        self._write({"jsonrpc": "2.0", "id": msg_id, "method": method, "params": params})
        return await future

    def notify(self, method: str, params: Any) -> None:
        self._write({"jsonrpc": "2.0", "method": method, "params": params})

    async def stop(self) -> None:
        await self.request("shutdown", None)
        self.notify("exit", None)
        assert self._process is not None
        await self._process.wait()
        if self._reader is not None:
            self._reader.cancel()

    def _write(self, message: dict[str, Any]) -> None:
        assert self._process is not None
        assert self._process.stdin is not None
        body = json.dumps(message).encode()
        self._process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)

    async def _read(self) -> None:
        assert self._process is not None
        assert self._process.stdout is not None
        stream = self._process.stdout
        while True:
            length = 0
            while (line := await stream.readline()) not in (b"\r\n", b""):
                name, _, value = line.decode("ascii").partition(":")
                if name.lower() == "content-length":
                    length = int(value)
            if not line:
                return
            body = await stream.readexactly(length)
            arrived = time.perf_counter()
            message = json.loads(body)
            if "id" in message and "method" not in message:
                future = self._pending.pop(message["id"], None)
                if future is not None and not future.done():
                    if "error" in message:
                        future.set_exception(RuntimeError(message["error"]))
                    else:
                        future.set_result(message.get("result"))
            elif "id" in message:  # a request from the server: answer it with nothing
                self._write({"jsonrpc": "2.0", "id": message["id"], "result": None})
            elif (handler := self._handlers.get(message.get("method", ""))) is not None:
                handler(arrived, message.get("params"))


def server_command() -> list[str]:
    return [sys.executable, "-m", "gaitgram_lsp"]
