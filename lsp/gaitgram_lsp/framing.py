"""The LSP base protocol: messages framed by headers, read as the specification says.

A message is a header part, fields ``Name: value`` each ended by ``\\r\\n`` and the part by an
empty line, then a body of ``Content-Length`` bytes of JSON. Header names are case-insensitive
(``content-length`` is ``Content-Length``), ``Content-Type`` is optional, and other fields are
allowed. pygls reads only the exact spelling ``Content-Length: N`` and, given anything else,
goes on reading lines: one message written ``content-length:`` left every later request
unanswered while the process stayed alive.

A malformed message never stops the stream. Its request gets a JSON-RPC error where its id can
be read (a body that is not JSON, a Content-Length missing, unreadable, too large or not the
body's length); else it is skipped with a log message. Then reading starts again at the next
``Content-Length`` header: a length too short leaves the rest of its body before the next
message, a length too long would swallow the start of the next (and wait for bytes that never
come), and both are recognised by the JSON value ending where a header begins.
"""

from __future__ import annotations

import asyncio
import json
import logging
import re
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

from pygls.exceptions import JsonRpcException

__all__ = ["MAX_MESSAGE_BYTES", "Body", "Framing", "Malformed", "request_id", "serve"]

log = logging.getLogger(__name__)

#: A message body larger than this is skipped, not read into memory (an 8 MB grammar, the
#: largest ``gaitgram check`` reads, is at most 48 MB as JSON, every byte escaped).
MAX_MESSAGE_BYTES = 64 * 1024 * 1024
#: Seconds to wait for the rest of a body whose bytes so far are a whole JSON object already.
_IDLE = 0.5
#: A header part longer than this is not one.
MAX_HEADER_BYTES = 64 * 1024
_CHUNK = 1 << 16

#: Where a message starts again after a malformed one.
_RESTART = re.compile(rb"content-length[ \t]*:", re.IGNORECASE)
#: A header field: a token (RFC 9110's characters), a colon, and its value.
_FIELD = re.compile(rb"([!#$%&'*+.^_`|~0-9A-Za-z-]+)[ \t]*:[ \t]*(.*?)[ \t]*")
#: A JSON value's end, then the start of ``Content-Length`` cut short.
_CUT_HEADER = re.compile(
    rb"[}\]][ \t\r\n]*(?:" + b"|".join(b"content-length"[:n] for n in range(14, 0, -1)) + rb")\Z",
    re.IGNORECASE,
)
_BLANKS = re.compile(rb"[ \t\r\n]*")
_HEADER_END = re.compile(rb"\r?\n\r?\n")
_LINE_BREAK = re.compile(rb"\r?\n")
_DIGITS = re.compile(rb"[0-9]+")
_BLANK = b" \t\r\n"


@dataclass(frozen=True)
class Body:
    """A well-framed message's body (it may still not be JSON)."""

    data: bytes


@dataclass(frozen=True)
class Malformed:
    """A message that could not be framed: why, and the id of its request where it was read."""

    reason: str
    id: int | str | None = None


class Framing:
    """Messages from a byte stream: ``await framing.next()`` gives a :class:`Body`, a
    :class:`Malformed` message, or None at the end of the stream."""

    def __init__(self, read: Callable[[int], Awaitable[bytes]]) -> None:
        #: Reads up to that many bytes; ``b""`` at the end of the stream.
        self._read = read
        self._buffer = bytearray()
        self._ended = False
        self._reading: asyncio.Future[bytes] | None = None

    async def _fill(self, wait: float | None = None) -> bool | None:
        """Read more into the buffer; False at the end of the stream, None if nothing came in
        ``wait`` seconds (the read goes on, for the next call: no byte is lost)."""
        if self._ended:
            return False
        if self._reading is None:
            self._reading = asyncio.ensure_future(self._read(_CHUNK))
        done, _ = await asyncio.wait({self._reading}, timeout=wait)
        if not done:
            return None
        chunk = self._reading.result()
        self._reading = None
        if not chunk:
            self._ended = True
            return False
        self._buffer += chunk
        return True

    async def next(self) -> Body | Malformed | None:
        buffer = self._buffer
        while True:  # blank lines between messages are no message
            del buffer[: _BLANKS.match(buffer).end()]  # type: ignore[union-attr]  # the empty run matches
            if buffer or not await self._fill():
                break
        if not buffer:
            return None
        searched = 0
        while (end := _HEADER_END.search(buffer, searched)) is None:
            if len(buffer) > MAX_HEADER_BYTES:
                return self._restart(1, f"no end of the header part in {MAX_HEADER_BYTES:,} bytes")
            searched = max(0, len(buffer) - 3)
            if not await self._fill():
                return None if not buffer.strip(_BLANK) else self._drop_all("the stream ended in a header")
        fields: dict[str, bytes] = {}
        header = bytes(buffer[: end.start()])
        line_start = 0
        for line_end in [*(m.start() for m in _LINE_BREAK.finditer(header)), len(header)]:
            line = header[line_start:line_end]
            field = _FIELD.fullmatch(line)
            if field is None:
                shown = line[:60].decode("utf-8", "replace")
                return self._restart(line_start + 1, f"the header line {shown!r} is not 'Name: value'")
            fields.setdefault(field.group(1).decode("ascii").lower(), field.group(2))
            line_start = line_end + (2 if header.startswith(b"\r\n", line_end) else 1)
        del buffer[: end.end()]
        length = fields.get("content-length")
        if length is None or _DIGITS.fullmatch(length) is None:
            reason = (
                "no Content-Length header"
                if length is None
                else f"Content-Length {length[:40].decode('utf-8', 'replace')!r} is not a number of bytes"
            )
            return await self._unframed(reason)
        self._check_type(fields.get("content-type"))
        return await self._body(int(length))

    def _check_type(self, content_type: bytes | None) -> None:
        if content_type is None:
            return
        charset = re.search(rb"charset\s*=\s*\"?([^;\"\s]+)", content_type, re.IGNORECASE)
        if charset is not None and charset.group(1).lower() not in (b"utf-8", b"utf8"):
            log.warning("Content-Type %r: reading the body as UTF-8, the only charset LSP has", content_type)

    async def _body(self, size: int) -> Body | Malformed | None:
        """``size`` bytes, unless a JSON value ends before them where a message's header begins
        (a Content-Length too long: waiting for the rest would wait for the next message's
        bytes, which may never come). A body too large to keep is skipped."""
        buffer = self._buffer
        searched = 0
        wanted = size if size <= MAX_MESSAGE_BYTES else MAX_HEADER_BYTES
        while len(buffer) < wanted:
            for found in [m.start() for m in _RESTART.finditer(buffer, searched)]:  # none kept: it resizes
                if (too_long := self._ends_before(size, found)) is not None:
                    return too_long
            searched = max(0, len(buffer) - 20)
            # A whole JSON object already, and then nothing: the length may be too long, and
            # the client waiting for the answer (it sends nothing more before it).
            whole = bytes(buffer[-64:]).rstrip(_BLANK)[-1:] == b"}" and _json_end(bytes(buffer)) is not None
            filled = await self._fill(_IDLE if whole else None)
            if filled is None and (too_long := self._ends_before(size, len(buffer))) is not None:
                return too_long
            if filled is False:
                log.error("the stream ended inside a message (%d of %d bytes)", len(buffer), size)
                return None
        if size > MAX_MESSAGE_BYTES:
            return await self._skip(size)
        if buffer[:size].rstrip(_BLANK)[-1:] != b"}":  # no object ends there: one may end before
            # A value, then the start of a header cut at ``size``: the rest of it decides.
            while len(buffer) < size + 20 and _CUT_HEADER.search(buffer, max(0, size - 20), size):
                if not await self._fill():
                    break
            for found in [m.start() for m in _RESTART.finditer(buffer, 0, size + 20)]:
                if (too_long := self._ends_before(size, found)) is not None:
                    return too_long
        data = bytes(buffer[:size])
        del buffer[:size]
        return Body(data)

    def _ends_before(self, size: int, header: int) -> Malformed | None:
        """If a JSON value ends where a header starts (at ``header``, before ``size``): the
        message, its length wrong, and the buffer from the header on."""
        ended = _json_end(bytes(self._buffer[:header]))
        if ended is None:
            return None
        value, at = ended
        del self._buffer[:at]
        return Malformed(
            f"Content-Length {size} is more than the body, which ends after {at} bytes", _id_of(value)
        )

    async def _skip(self, size: int) -> Malformed | None:
        """Read past a body too large to keep, keeping only its start to find the request's id."""
        buffer = self._buffer
        while len(buffer) < min(size, MAX_HEADER_BYTES) and await self._fill():
            pass
        head = bytes(buffer[:MAX_HEADER_BYTES])
        left = size
        while left:
            taken = min(left, len(buffer))
            del buffer[:taken]
            left -= taken
            if left and not await self._fill():
                break
        return Malformed(
            f"the message is {size:,} bytes; messages over {MAX_MESSAGE_BYTES:,} are not read",
            request_id(head),
        )

    async def _unframed(self, reason: str) -> Malformed | None:
        """A body of no known length: a JSON value read as it arrives (its request is answered),
        or else whatever comes before the next message's header."""
        buffer = self._buffer
        while True:
            tail = bytes(buffer[-64:]).rstrip(_BLANK)[-1:]
            ended = _json_end(bytes(buffer)) if tail in (b"}", b"]") else None
            if ended is not None:
                value, at = ended
                del buffer[:at]
                return Malformed(reason, _id_of(value))
            restart = _RESTART.search(buffer)
            if restart is not None:
                head = bytes(buffer[: restart.start()])
                del buffer[: restart.start()]
                return Malformed(reason, request_id(head))
            if len(buffer) > MAX_MESSAGE_BYTES:
                return self._drop_all(reason)
            if not await self._fill():
                return self._drop_all(reason) if buffer.strip(_BLANK) else Malformed(reason)

    def _restart(self, after: int, reason: str) -> Malformed:
        """Drop what cannot be read, up to the next ``Content-Length`` header from ``after`` on."""
        restart = _RESTART.search(self._buffer, after)
        if restart is None:
            return self._drop_all(reason)
        del self._buffer[: restart.start()]
        return Malformed(reason)

    def _drop_all(self, reason: str) -> Malformed:
        head = bytes(self._buffer[:MAX_HEADER_BYTES])
        self._buffer.clear()
        return Malformed(reason, request_id(head))


#: JSON-RPC's codes for a body that is not JSON and a message that is not a request.
PARSE_ERROR, INVALID_REQUEST = -32700, -32600


async def serve(
    read: Callable[[int], Awaitable[bytes]],
    protocol: Any,
    refuse: Callable[[int | str, int, str], None],
    stopped: Callable[[], bool],
    error_handler: Callable[[Exception, type[JsonRpcException]], Any] | None = None,
) -> None:
    """Read messages until the stream ends (or ``stopped``), and hand each to ``protocol`` as
    pygls's own loop does; a malformed one is answered by ``refuse(id, code, message)`` where its
    id is known, else logged, and the next is read."""
    framing = Framing(read)
    while not stopped():
        found = await framing.next()
        if found is None:
            return
        if isinstance(found, Malformed):
            _malformed(found.id, INVALID_REQUEST, f"malformed message: {found.reason}", refuse)
            continue
        try:
            message = json.loads(found.data)
        except ValueError as error:  # not UTF-8, or not JSON
            reason = f"the body is not JSON (is its Content-Length right?): {error}"
            _malformed(request_id(found.data), PARSE_ERROR, reason, refuse)
            continue
        if not isinstance(message, dict):
            log.warning("skipped a message that is no JSON object: %.80r", found.data)
            continue
        try:
            # Only the message itself is structured: pygls's loop asks for every object in it,
            # and leaves all but the outermost as they are (they have no "jsonrpc").
            message = protocol.structure_message(message)
        except Exception as error:  # as pygls's loop: invalid parameters, say
            log.exception("Unable to handle message")
            if error_handler is not None:
                error_handler(error, JsonRpcException)
            continue
        try:
            protocol.handle_message(message)
        except Exception as error:
            log.exception("Unable to handle message")
            if error_handler is not None:
                error_handler(error, JsonRpcException)


def _malformed(
    msg_id: int | str | None, code: int, reason: str, refuse: Callable[[int | str, int, str], None]
) -> None:
    if msg_id is None:
        log.warning("skipped a message: %s", reason)
    else:
        refuse(msg_id, code, reason)


def _json_end(data: bytes) -> tuple[object, int] | None:
    """The JSON value at the start of ``data`` and the bytes it and the blanks after it take, if
    it is whole and nothing but blanks or a header follow it."""
    text = data.decode("utf-8", "surrogateescape")
    stripped = text.lstrip()
    if not stripped.startswith(("{", "[")):
        return None
    try:
        value, end = json.JSONDecoder().raw_decode(stripped)
    except ValueError:
        return None
    end += len(text) - len(stripped)
    rest = text[end:]
    if rest.strip() and _RESTART.match(rest.lstrip().encode("utf-8", "surrogateescape")) is None:
        return None
    end += len(rest) - len(rest.lstrip())
    return value, len(text[:end].encode("utf-8", "surrogateescape"))


def _id_of(value: object) -> int | str | None:
    found = value.get("id") if isinstance(value, dict) else None
    return found if isinstance(found, int | str) and not isinstance(found, bool) else None


def request_id(data: bytes) -> int | str | None:
    """The ``id`` of the JSON object that ``data`` starts with, read key by key up to it: found
    even when the object is cut short or broken after it (its request can then be answered)."""
    text = data.decode("utf-8", "surrogateescape")
    decode = json.JSONDecoder().raw_decode
    at = len(text) - len(text.lstrip())
    if not text.startswith("{", at):
        return None
    at += 1
    try:
        while True:
            at = _skip_blank(text, at)
            key, at = decode(text, at)
            at = _skip_blank(text, at)
            if not isinstance(key, str) or not text.startswith(":", at):
                return None
            value, at = decode(text, _skip_blank(text, at + 1))
            if key == "id":
                return _id_of({"id": value})
            at = _skip_blank(text, at)
            if not text.startswith(",", at):
                return None
            at += 1
    except ValueError:
        return None


def _skip_blank(text: str, at: int) -> int:
    while at < len(text) and text[at] in " \t\r\n":
        at += 1
    return at
