"""Source text, spans and line/column positions.

Spans are character offsets into the text; lines and columns are computed on
demand, so the parser does no position bookkeeping per token.
"""

from __future__ import annotations

import codecs
import difflib
import os
import re
import stat
from bisect import bisect_right
from collections import Counter
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

from gaitgram.spans import Span

__all__ = [
    "MAX_SOURCE_BYTES",
    "Location",
    "SourceError",
    "SourceText",
    "Span",
    "decode_source",
    "describe_os_error",
    "encode_as_read",
    "normalize_newlines",
    "read_bytes",
    "read_limited",
    "read_source",
]


@dataclass(frozen=True, slots=True)
class Location:
    """A 1-based line and column (columns count Unicode code points)."""

    line: int
    column: int


def normalize_newlines(text: str) -> str:
    """Universal newlines, as Python's text mode reads files (and PonyGE2 with it)."""
    if "\r" not in text:
        return text
    return text.replace("\r\n", "\n").replace("\r", "\n")


@dataclass(frozen=True)
class SourceText:
    """The text of one document, with its name and a line index.

    The text is newline-normalised on construction; line and column numbers are
    unaffected by that, so they match the file as the user sees it.
    """

    text: str
    name: str = "<text>"
    line_starts: tuple[int, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        text = normalize_newlines(self.text)
        object.__setattr__(self, "text", text)
        starts = [0]
        find = text.find
        pos = find("\n")
        while pos != -1:
            starts.append(pos + 1)
            pos = find("\n", pos + 1)
        object.__setattr__(self, "line_starts", tuple(starts))

    @property
    def line_count(self) -> int:
        return len(self.line_starts)

    def location(self, offset: int) -> Location:
        offset = max(0, min(offset, len(self.text)))
        line = bisect_right(self.line_starts, offset) - 1
        return Location(line + 1, offset - self.line_starts[line] + 1)

    def bounds(self, start: int, end: int) -> tuple[int, int, int, int]:
        """Line and column of ``start`` and of ``end``, as :meth:`location` gives them, with one
        search when both are on one line (tens of thousands per ``check --format json``)."""
        length = len(self.text)
        start = max(0, min(start, length))
        end = max(0, min(end, length))
        starts = self.line_starts
        line = bisect_right(starts, start) - 1
        first = starts[line]
        if start <= end and (line + 1 == len(starts) or end < starts[line + 1]):
            return line + 1, start - first + 1, line + 1, end - first + 1
        last = bisect_right(starts, end) - 1
        return line + 1, start - first + 1, last + 1, end - starts[last] + 1

    def line_indices(self, offsets: Iterable[int]) -> Iterator[int]:
        """The 0-based line of each of ascending ``offsets``, walking the lines once (for the
        thousands of rule starts of a large grammar)."""
        starts = self.line_starts
        line, last = 0, len(starts) - 1
        for offset in offsets:
            if line < last and offset >= starts[line + 1]:
                line = bisect_right(starts, offset, line) - 1
            yield line

    def offset(self, line: int, column: int) -> int:
        """The offset of a 1-based line and column, clamped to the text."""
        if line < 1:
            return 0
        if line > len(self.line_starts):
            return len(self.text)
        start = self.line_starts[line - 1]
        return min(start + max(column, 1) - 1, self.line_end(line))

    def line_start_of(self, offset: int) -> int:
        """The offset where the line holding ``offset`` starts: a search of the line index, not a
        scan of the text (a line may be megabytes long and hold thousands of diagnostics)."""
        return self.line_starts[bisect_right(self.line_starts, offset) - 1]

    def line_end_of(self, offset: int) -> int:
        """The offset of the newline ending the line holding ``offset`` (or the end of the text)."""
        return self.line_end(bisect_right(self.line_starts, offset))

    def line_end(self, line: int) -> int:
        if line < len(self.line_starts):
            return self.line_starts[line] - 1
        return len(self.text)

    def line_text(self, line: int) -> str:
        start = self.line_starts[line - 1]
        return self.text[start : self.line_end(line)]

    def slice(self, span: Span) -> str:
        return self.text[span.start : span.end]


class SourceError(Exception):
    """A file that cannot be read as a grammar: missing, a directory, not UTF-8, too big."""

    def __init__(self, path: str, message: str, hint: str | None = None) -> None:
        super().__init__(f"{path}: {message}")
        self.path = path
        self.message = message
        self.hint = hint


#: Real grammars are kilobytes; past this we refuse rather than make the user wait.
MAX_SOURCE_BYTES = 8 * 1024 * 1024
_CHUNK = 1024 * 1024

#: What each kind of non-file is called when it is refused: reading one is endless (/dev/zero),
#: has side effects (a tape, a terminal) or is a mistake (a disk).
_NOT_FILES = {
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
}


def read_source(path: str | Path, *, max_bytes: int = MAX_SOURCE_BYTES) -> SourceText:
    """Read a grammar file, turning every way it can fail into a :class:`SourceError`."""
    return decode_source(read_bytes(path, max_bytes=max_bytes), str(path))


def read_bytes(path: str | Path, *, max_bytes: int = MAX_SOURCE_BYTES, what: str = "grammar") -> bytes:
    """The bytes of a regular file or a FIFO, never more than ``max_bytes``; else a :class:`SourceError`.

    The size is checked from ``stat`` first (for the message), but the read itself stops
    at ``max_bytes + 1`` whatever ``stat`` said: a pipe, a ``/proc`` file or a file still
    growing has no honest size. Devices are refused before they are opened.
    """
    name = str(path)
    try:
        kind = stat.S_IFMT(os.stat(path).st_mode)
        _refuse_non_files(name, kind, what)
        with open(path, "rb", buffering=0) as handle:
            info = os.fstat(handle.fileno())  # what was opened, if it changed since the stat
            _refuse_non_files(name, stat.S_IFMT(info.st_mode), what)
            if stat.S_ISREG(info.st_mode) and info.st_size > max_bytes:
                raise SourceError(
                    name,
                    f"is {info.st_size / 1e6:.1f} MB; {what}s over {max_bytes / 1e6:.1f} MB are refused",
                    f"is this really a {what} file?",
                )
            return read_limited(handle, name, max_bytes=max_bytes, what=what)
    except FileNotFoundError:
        raise SourceError(name, "no such file") from None
    except PermissionError:
        raise SourceError(name, "permission denied") from None
    except OSError as exc:
        raise SourceError(name, describe_os_error(exc)) from None
    except ValueError:  # os.stat refuses a name holding a NUL: no file can have it
        raise SourceError(repr(name), "is no file name: it holds a NUL character") from None


def read_limited(
    handle: BinaryIO, name: str, *, max_bytes: int = MAX_SOURCE_BYTES, what: str = "grammar"
) -> bytes:
    """Read an open binary stream (a file, a pipe, standard input) to its end, in chunks,
    refusing it as soon as it passes ``max_bytes``."""
    chunks: list[bytes] = []
    total = 0
    while total <= max_bytes:
        chunk = handle.read(min(_CHUNK, max_bytes + 1 - total))
        if not chunk:
            return b"".join(chunks)
        chunks.append(chunk)
        total += len(chunk)
    raise SourceError(
        name,
        f"is over {max_bytes / 1e6:.1f} MB; {what}s over {max_bytes / 1e6:.1f} MB are refused",
        f"is this really a {what} file?",
    )


def _refuse_non_files(name: str, kind: int, what: str) -> None:
    if kind == stat.S_IFDIR:
        raise SourceError(name, "is a directory", f"pass the {what} files inside it")
    if kind in _NOT_FILES:
        raise SourceError(name, f"is {_NOT_FILES[kind]}, not a file", f"give the path of a {what} file")


def path_problem(path: str | Path, *, directory: bool = False) -> str | None:
    """Why ``path`` is no file (with ``directory``: no directory) to read, as said after its name:
    ``no such file``, ``is a directory``, or what the system says (a symbolic link that loops, no
    permission); None if it is one."""
    want = "directory" if directory else "file"
    try:
        kind = stat.S_IFMT(os.stat(path).st_mode)
    except FileNotFoundError:
        return f"no such {want}"
    except OSError as error:
        return describe_os_error(error)
    except ValueError:  # a NUL in the name
        return f"no {want} has such a name"
    if directory:
        return None if kind == stat.S_IFDIR else "is a file, not a directory"
    if kind == stat.S_IFDIR:
        return "is a directory, not a file"
    return f"is {_NOT_FILES[kind]}, not a file" if kind in _NOT_FILES else None


def describe_os_error(error: OSError) -> str:
    """``No space left on device`` as ``no space left on device``, to read as part of a sentence."""
    reason = error.strerror or str(error) or type(error).__name__
    return reason[:1].lower() + reason[1:]


def decode_source(data: bytes, name: str = "<bytes>") -> SourceText:
    """Decode UTF-8 (a BOM is allowed), reporting where the first bad byte is."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        good = data[: exc.start].decode("utf-8", errors="replace")
        line = good.count("\n") + 1
        column = len(good) - (good.rfind("\n") + 1) + 1
        raise SourceError(
            name,
            f"line {line}, column {column}: not valid UTF-8 (byte 0x{data[exc.start]:02x})",
            "grammars are UTF-8 text; re-save the file as UTF-8",
        ) from None
    if "\x00" in text:
        line = text.count("\n", 0, text.index("\x00")) + 1
        raise SourceError(name, f"line {line}: contains a NUL byte; this looks like a binary file")
    return SourceText(text, name)


_RAW_LINE = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+$")
_LINE = re.compile(r"[^\n]*\n|[^\n]+$")
_NEWLINE = re.compile(r"\r\n|\r|\n")


def encode_as_read(read: bytes, text: str) -> bytes:
    """``text``, a new version of what :func:`decode_source` made of ``read``, as bytes laid out
    like ``read``: its byte order mark, and the line breaks of the lines that did not change
    (a new or changed line gets the file's most common line break). What ``check --fix`` and
    ``fmt`` write, so a CRLF file stays CRLF and its diff shows only what changed."""
    bom = codecs.BOM_UTF8 if read.startswith(codecs.BOM_UTF8) else b""
    raw = read[len(bom) :].decode("utf-8")
    if "\r" not in raw:
        return bom + text.encode("utf-8")
    newline = Counter(_NEWLINE.findall(raw)).most_common(1)[0][0]
    # Normalising newlines maps each line break to one "\n", so the lines correspond one to one.
    raw_lines, old_lines, new_lines = (
        _RAW_LINE.findall(raw),
        _LINE.findall(normalize_newlines(raw)),
        _LINE.findall(text),
    )
    parts: list[str] = []
    matcher = difflib.SequenceMatcher(None, old_lines, new_lines, autojunk=False)
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        for line in (
            raw_lines[i1:i2] if tag == "equal" else (x.replace("\n", newline) for x in new_lines[j1:j2])
        ):
            if line.startswith("\n") and parts and parts[-1].endswith("\r"):
                parts[-1] += "\n"  # a lone CR then an LF would read as one CRLF break, not two
            parts.append(line)
    return bom + "".join(parts).encode("utf-8")
