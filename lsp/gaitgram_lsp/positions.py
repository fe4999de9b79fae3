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
from itertools import accumulate

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
    character. Found by encoding the line's head once (no loop over its characters: a line may
    be megabytes long, and every change and request on it asks)."""
    if encoding == UTF32 or (line.isascii() and encoding in (UTF8, UTF16)):
        return max(0, min(character, len(line)))
    character = max(0, character)
    head = line[:character]  # no code point is less than one code unit
    codec, width = ("utf-8", 1) if encoding == UTF8 else ("utf-16-le", 2)
    data = head.encode(codec, "surrogatepass")
    cut = min(len(data), character * width)
    if cut < len(data):  # inside the head: back to the start of the character the cut falls in
        if width == 1:
            while cut > 0 and data[cut] & 0xC0 == 0x80:  # a UTF-8 continuation byte
                cut -= 1
        elif 0xDC <= data[cut + 1] <= 0xDF and cut >= 2 and 0xD8 <= data[cut - 1] <= 0xDB:
            cut -= 2  # between the two halves of a surrogate pair
    found = len(data[:cut].decode(codec, "surrogatepass"))
    if units(line[:found], encoding) <= character and (
        found == len(line) or units(line[: found + 1], encoding) > character
    ):
        return found
    # Lone surrogates that the codec joined into a pair: count character by character.
    used = 0
    for index, ch in enumerate(line):
        used += units(ch, encoding)
        if used > character:
            return index
    return len(line)


#: On a line longer than this, the code units before every multiple of it are kept (a line's
#: marks are made once, when first needed), so an offset's character is counted from the mark
#: before it rather than from the line's start.
_STRIDE = 256


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

        #: For long lines of a text whose offsets and columns differ: the code units before
        #: each multiple of ``_STRIDE`` characters.
        self._marks: dict[int, list[int]] = {}

    def _units_before(self, line: int, offset: int) -> int:
        """Code units from the start of ``line`` to ``offset`` (on that line)."""
        text = self.source.text
        start = self.source.line_starts[line]
        character = offset - start
        if character <= _STRIDE:
            return units(text[start:offset], self.encoding)
        marks = self._marks.get(line)
        if marks is None:  # the whole line's, at once: an index may be read from two threads
            end = self.source.line_end(line + 1)
            marks = list(
                accumulate(
                    (units(text[at : at + _STRIDE], self.encoding) for at in range(start, end, _STRIDE)),
                    initial=0,
                )
            )
            self._marks[line] = marks
        mark = character // _STRIDE
        return marks[mark] + units(text[start + mark * _STRIDE : offset], self.encoding)

    def position(self, offset: int) -> types.Position:
        line, character = self.line_character(offset)
        return types.Position(line=line, character=character)

    def line_character(self, offset: int) -> tuple[int, int]:
        """An offset's 0-based line and character, as plain ints."""
        return self.line_characters([offset])[0]

    def line_characters(self, offsets: Iterable[int]) -> list[tuple[int, int]]:
        """Many offsets' lines and characters at once (thousands of diagnostics per change)."""
        source = self.source
        starts = source.line_starts
        size = len(source.text)
        found = []
        for offset in offsets:
            offset = min(max(offset, 0), size)
            line = bisect_right(starts, offset) - 1
            character = offset - starts[line]
            if not self.simple and character:
                character = self._units_before(line, offset)
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
        starts = source.line_starts
        line = 0
        last = len(starts) - 1
        for offset in offsets:
            if line < last and offset >= starts[line + 1]:
                line = bisect_right(starts, offset, line) - 1
            character = offset - starts[line]
            if not self.simple and character:
                character = self._units_before(line, offset)
            yield line, character


def raw_line_starts(text: str) -> list[int]:
    """Line starts of text as the client has it (``\\r\\n`` and ``\\r`` not yet normalised)."""
    return [0, *(m.end() for m in _LINE_BREAK.finditer(text))]


def apply_change(text: str, range_: types.Range, new_text: str, encoding: str) -> str:
    """Apply one incremental change to the client's text (positions clamped as LSP says)."""
    client = ClientText.of(text)
    client.apply(range_, new_text, encoding)
    return client.text


class ClientText:
    """The client's copy of a document, line breaks as sent, kept as its lines. A change
    re-reads only the lines it touches and splices them in; the whole text is joined once, when
    an analysis asks for it. On a 20,000-rule document, changes arriving by the hundred must not
    hold up the completion request queued behind them, as a scan of the text per change would.

    Line ``i`` holds its break (``\\n``, ``\\r\\n`` or ``\\r``, as in LSP); the last has none."""

    def __init__(self, lines: list[str]) -> None:
        self.lines = lines
        self._text: str | None = None

    @classmethod
    def of(cls, text: str) -> ClientText:
        starts = raw_line_starts(text)
        return cls([text[a:b] for a, b in zip(starts, [*starts[1:], len(text)], strict=True)])

    @property
    def text(self) -> str:
        if self._text is None:
            self._text = "".join(self.lines)
        return self._text

    @property
    def starts(self) -> list[int]:
        """Every line's start offset (built on demand: the edits do not need it)."""
        return list(accumulate((len(line) for line in self.lines[:-1]), initial=0))

    def line(self, number: int) -> str:
        """Line ``number`` (0-based) without its break; ``""`` past the end."""
        return self.lines[number].rstrip("\r\n") if number < len(self.lines) else ""

    def _locate(self, position: types.Position, encoding: str) -> tuple[int, int]:
        """(line, offset in the line), clamped as LSP says: a line past the end is the end."""
        if position.line >= len(self.lines):
            return len(self.lines) - 1, len(self.lines[-1])
        return position.line, column(self.line(position.line), position.character, encoding)

    def apply(self, range_: types.Range, new_text: str, encoding: str) -> None:
        start, end = sorted((self._locate(range_.start, encoding), self._locate(range_.end, encoding)))
        lines = self.lines
        # From the line before the edit's first (a \\r\\n may join or split at the edit) to the
        # line after its last, whose break lies wholly after the edit: re-read.
        first, last = max(start[0] - 1, 0), min(end[0] + 1, len(lines) - 1)
        region = "".join(lines[first : last + 1])
        cut = sum(len(line) for line in lines[first : start[0]]) + start[1]
        resume = sum(len(line) for line in lines[first : end[0]]) + end[1]
        edited = region[:cut] + new_text + region[resume:]
        starts = raw_line_starts(edited)
        spliced = [edited[a:b] for a, b in zip(starts, [*starts[1:], len(edited)], strict=True)]
        if last < len(lines) - 1:  # the region ends with a break: no empty line after it
            spliced.pop()
        lines[first : last + 1] = spliced
        self._text = None


#: LSP's ``uinteger`` ends at 2^31 - 1.
MAX_UINTEGER = 2**31 - 1


def position_problems(value: object) -> list[str]:
    """Why ``value`` is not an LSP position (empty: it is one). A client that sends a negative,
    huge or fractional line or character gets an InvalidParams answer naming it, not silence or
    a guess (lsprotocol's own converter turns 1.5 into 1)."""
    if not isinstance(value, dict):
        return [f"a position must be an object with line and character, not {value!r}"]
    found = []
    for name in ("line", "character"):
        number = value.get(name)
        if type(number) is not int or not 0 <= number <= MAX_UINTEGER:
            found.append(f"position.{name} must be an integer in [0, {MAX_UINTEGER}], not {number!r}")
    return found
