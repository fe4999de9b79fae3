"""Where a TOML file writes a key: ``file:line:column`` for messages about what a user wrote.

``tomllib`` reads values, not places; these functions scan the text as TOML lays it out (headers,
arrays of tables, dotted and quoted keys, inline tables, strings and arrays over several lines) to
find the line that writes a key, so that an error in a study file or a run.toml names its line.
"""

from __future__ import annotations

import tomllib
from collections.abc import Iterator
from pathlib import Path


def key_location(path: Path, table: str, key: str, item: int | None = None) -> str:
    """``path:line:column`` where the TOML file ``path`` writes ``key`` (dotted: ``weights.velocty``)
    of ``[table]`` (``""``: the top level): the first line that writes it, a table or key beneath it
    (``[table.weights]``, ``weights.velocty = 1``) or an inline table holding it (``weights = {
    velocty = 1 }``); just ``path`` where it is not written. ``item`` (from 0) picks one table of
    an array of tables: ``key_location(path, "arm.settings", "elite", item=2)`` is in the third
    ``[[arm]]``. Lines inside multi-line strings and arrays are values, not keys."""
    named = tuple(part for part in f"{table}.{key}".split(".") if part)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return str(path)
    header: tuple[str, ...] = ()
    seen = 0  # the [[array]] headers so far
    for number, column, kind, parts in _toml_keys(text):
        if kind == "key":
            written = (*header, *parts)
            holds = named[: len(written)] == written and len(named) > len(written)  # an inline value
        else:
            header = written = parts
            seen += kind == "array" and parts == named[:1]
            holds = False  # a header holds only the lines below it
        found = written[: len(named)] == named or holds
        if found and (item is None or seen == item + 1):
            return f"{path}:{number}:{column}"
    return str(path)


def _toml_keys(text: str) -> Iterator[tuple[int, int, str, tuple[str, ...]]]:
    """Each line that starts a table (``table``, ``array``: ``[[...]]``) or writes a key (``key``),
    with its number, column and the key's parts (quotes removed, so ``"a.b"`` is one part); lines
    that continue a multi-line string or array are skipped."""
    quote = ""  # the string the scan is inside (its opening quotes: one or three)
    depth = 0  # arrays and inline tables open in a value
    for number, line in enumerate(text.splitlines(), 1):
        start = len(line) - len(line.lstrip())
        if not quote and not depth and line[start : start + 1] not in ("", "#"):
            kind, parts = _head(line[start:])
            if parts:
                yield number, start + 1, kind, parts
            if kind != "key":
                continue  # a header line holds no value
        i = start if quote or depth else start + _unquoted(line[start:], "=") + 1  # the value
        while i < len(line):
            c = line[i]
            if quote:
                if c == "\\" and quote[0] == '"':
                    i += 1  # a basic string's escape: the next character is not its end
                elif line.startswith(quote, i):
                    i += len(quote) - 1
                    quote = ""
            elif line.startswith(('"""', "'''"), i):
                quote = line[i : i + 3]
                i += 2
            elif c in "\"'":
                quote = c
            elif c == "#":
                break
            elif c in "[{":
                depth += 1
            elif c in "]}":
                depth = max(depth - 1, 0)
            i += 1
        if quote in ('"', "'"):
            quote = ""  # a single-line string cannot go on to the next line


def _head(line: str) -> tuple[str, tuple[str, ...]]:
    """What a line at the top level starts: a header's kind and key, or a key = value's key."""
    if line.startswith("["):
        array = line.startswith("[[")
        inner = line[2 if array else 1 :]
        close = _unquoted(inner, "]")
        return ("array" if array else "table"), _parts(inner[:close] if close >= 0 else "")
    equals = _unquoted(line, "=")
    return "key", _parts(line[:equals] if equals >= 0 else "")


def _unquoted(text: str, char: str) -> int:
    """The index of the first ``char`` outside quotes in ``text``; -1 if none."""
    quote, escaped = "", False
    for i, c in enumerate(text):
        if quote:
            if escaped:
                escaped = False
            elif c == "\\" and quote == '"':
                escaped = True
            elif c == quote:
                quote = ""
        elif c in "\"'":
            quote = c
        elif c == char:
            return i
    return -1


def _parts(key: str) -> tuple[str, ...]:
    """A TOML key as written (``a . "b.c"``) as its parts (``a``, ``b.c``), escapes read."""
    parts: list[str] = []
    rest = key.strip()
    while rest:
        if rest[0] in "\"'":
            end = _closing(rest)
            if end < 0:
                return ()
            quoted = rest[: end + 1]
            try:
                parts.append(tomllib.loads(f"k = {quoted}")["k"])
            except tomllib.TOMLDecodeError:
                return ()
            rest = rest[end + 1 :].strip()
        else:
            bare, _, _ = rest.partition(".")
            parts.append(bare.strip())
            rest = rest[len(bare) :].strip()
        if rest.startswith("."):
            rest = rest[1:].strip()
            if not rest:
                return ()
        elif rest:
            return ()  # not a key
    return tuple(parts) if parts and all(parts) else ()


def _closing(text: str) -> int:
    """The index of the quote that closes the one ``text`` starts with; -1 if none."""
    quote, i = text[0], 1
    while i < len(text):
        if text[i] == "\\" and quote == '"':
            i += 2
            continue
        if text[i] == quote:
            return i
        i += 1
    return -1
