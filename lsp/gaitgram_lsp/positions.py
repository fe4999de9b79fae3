"""LSP positions and the model's offsets.

The model's spans are offsets in code points into the newline-normalised text. LSP
positions are (line, character) where the character counts code units of the encoding
agreed at initialisation: UTF-16 unless the client offers UTF-8 or UTF-32. A character
outside the Basic Multilingual Plane (an emoji) is two UTF-16 units and four UTF-8 ones.
Lines end at ``\\n``, ``\\r\\n`` or ``\\r``, as in LSP and in :class:`SourceText`.
"""

from __future__ import annotations

import re
from bisect import bisect_right
from collections.abc import Iterable, Iterator

from lsprotocol import types

from gaitgram.language.source import SourceText, Span

UTF8, UTF16, UTF32 = (
    types.PositionEncodingKind.Utf8,
    types.PositionEncodingKind.Utf16,
    types.PositionEncodingKind.Utf32,
)

_ASTRAL = re.compile("[\U00010000-\U0010ffff]")
_LINE_BREAK = re.compile(r"\r\n|\r|\n")


def units(text: str, encoding: str) -> int:
    """Length of ``text`` in code units of ``encoding``."""
    if encoding == UTF32:
        return len(text)
    if encoding == UTF8:
        return len(text.encode("utf-8", "surrogatepass"))
    return len(text) + len(_ASTRAL.findall(text))


def column(line: str, character: int, encoding: str) -> int:
    """The code-point column of ``character`` code units into ``line`` (clamped to the line).

    A position inside a character (half of a surrogate pair) means the start of that
    character."""
    if encoding == UTF32 or (line.isascii() and encoding in (UTF8, UTF16)):
        return max(0, min(character, len(line)))
    used = 0
    for index, ch in enumerate(line):
        width = units(ch, encoding)
        if used + width > character:
            return index
        used += width
    return len(line)


class PositionIndex:
    """Converts between offsets in one :class:`SourceText` and LSP positions."""

    def __init__(self, source: SourceText, encoding: str = UTF16) -> None:
        self.source = source
        self.encoding = encoding
        text = source.text
        #: Offsets and columns agree when every character is one code unit.
        self.simple = (
            encoding == UTF32
            or (encoding == UTF16 and _ASTRAL.search(text) is None)
            or (encoding == UTF8 and text.isascii())
        )

    def position(self, offset: int) -> types.Position:
        line, character = self.line_character(offset)
        return types.Position(line=line, character=character)

    def line_character(self, offset: int) -> tuple[int, int]:
        """An offset's 0-based line and character, as plain ints."""
        return self.line_characters([offset])[0]

    def line_characters(self, offsets: Iterable[int]) -> list[tuple[int, int]]:
        """Many offsets' lines and characters at once (thousands of diagnostics per change)."""
        source = self.source
        starts = source._line_starts  # private, but the index is what makes this cheap
        size = len(source.text)
        found = []
        for offset in offsets:
            offset = min(max(offset, 0), size)
            line = bisect_right(starts, offset) - 1
            character = offset - starts[line]
            if not self.simple and character:
                character = units(source.text[starts[line] : offset], self.encoding)
            found.append((line, character))
        return found

    def range(self, span: Span) -> types.Range:
        return types.Range(start=self.position(span.start), end=self.position(span.end))

    def offset(self, position: types.Position) -> int:
        """The offset of a position, clamped to the text (a line past the end is the end)."""
        line = position.line + 1
        if line > self.source.line_count:
            return len(self.source.text)
        character = position.character
        if not self.simple:
            character = column(self.source.line_text(line), character, self.encoding)
        return self.source.offset(line, character + 1)

    def span(self, range_: types.Range) -> Span:
        start, end = self.offset(range_.start), self.offset(range_.end)
        return Span(min(start, end), max(start, end))

    def line_column(self, offsets: Iterable[int]) -> Iterator[tuple[int, int]]:
        """(line, character) of ascending offsets, walking the lines once: for the many
        positions of semantic tokens."""
        source = self.source
        starts = source._line_starts  # private, but the index is what makes this cheap
        line = 0
        last = len(starts) - 1
        for offset in offsets:
            if line < last and offset >= starts[line + 1]:
                line = bisect_right(starts, offset, line) - 1
            character = offset - starts[line]
            if not self.simple and character:
                character = units(source.text[starts[line] : offset], self.encoding)
            yield line, character


def raw_line_starts(text: str) -> list[int]:
    """Line starts of text as the client has it (``\\r\\n`` and ``\\r`` not yet normalised)."""
    return [0, *(m.end() for m in _LINE_BREAK.finditer(text))]


def apply_change(text: str, range_: types.Range, new_text: str, encoding: str) -> str:
    """Apply one incremental change to the client's text (positions clamped as LSP says)."""
    starts = raw_line_starts(text)

    def offset(position: types.Position) -> int:
        if position.line >= len(starts):
            return len(text)
        start = starts[position.line]
        end = starts[position.line + 1] if position.line + 1 < len(starts) else len(text)
        line = text[start:end].rstrip("\r\n")
        return start + column(line, position.character, encoding)

    start, end = offset(range_.start), offset(range_.end)
    if end < start:
        start, end = end, start
    return text[:start] + new_text + text[end:]
