"""Source text, spans and line/column positions.

Spans are character offsets into the text; lines and columns are computed on
demand, so the parser does no position bookkeeping per token.
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass, field
from pathlib import Path


@dataclass(slots=True, order=True, unsafe_hash=True)
class Span:
    """A half-open range ``[start, end)`` of character offsets.

    Not frozen only because frozen dataclasses are four times slower to build,
    and a large grammar has hundreds of thousands of spans; never mutate one.
    """

    start: int
    end: int

    def cover(self, other: Span) -> Span:
        return Span(min(self.start, other.start), max(self.end, other.end))

    def __contains__(self, offset: object) -> bool:
        return isinstance(offset, int) and self.start <= offset <= self.end


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
    _line_starts: tuple[int, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        text = normalize_newlines(self.text)
        object.__setattr__(self, "text", text)
        starts = [0]
        find = text.find
        pos = find("\n")
        while pos != -1:
            starts.append(pos + 1)
            pos = find("\n", pos + 1)
        object.__setattr__(self, "_line_starts", tuple(starts))

    @property
    def line_count(self) -> int:
        return len(self._line_starts)

    def location(self, offset: int) -> Location:
        offset = max(0, min(offset, len(self.text)))
        line = bisect_right(self._line_starts, offset) - 1
        return Location(line + 1, offset - self._line_starts[line] + 1)

    def offset(self, line: int, column: int) -> int:
        """The offset of a 1-based line and column, clamped to the text."""
        if line < 1:
            return 0
        if line > len(self._line_starts):
            return len(self.text)
        start = self._line_starts[line - 1]
        return min(start + max(column, 1) - 1, self.line_end(line))

    def line_end(self, line: int) -> int:
        if line < len(self._line_starts):
            return self._line_starts[line] - 1
        return len(self.text)

    def line_text(self, line: int) -> str:
        start = self._line_starts[line - 1]
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


def read_source(path: str | Path, *, max_bytes: int = MAX_SOURCE_BYTES) -> SourceText:
    """Read a grammar file, turning every way it can fail into a :class:`SourceError`."""
    name = str(path)
    p = Path(path)
    try:
        if p.is_dir():
            raise SourceError(name, "is a directory", "pass the .gg files inside it")
        size = p.stat().st_size
        if size > max_bytes:
            raise SourceError(
                name,
                f"is {size / 1e6:.1f} MB; grammars over {max_bytes / 1e6:.1f} MB are refused",
                "is this really a grammar file?",
            )
        data = p.read_bytes()
    except FileNotFoundError:
        raise SourceError(name, "no such file") from None
    except PermissionError:
        raise SourceError(name, "permission denied") from None
    except OSError as exc:
        raise SourceError(name, exc.strerror or str(exc)) from None
    return decode_source(data, name)


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
