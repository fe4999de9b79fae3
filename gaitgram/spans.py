"""Spans: where a piece of the model came from in its text, as character offsets."""

from __future__ import annotations

from typing import NamedTuple


class Span(NamedTuple):
    """A half-open range ``[start, end)`` of character offsets.

    A tuple, so that it cannot change: a model keeps its spans for as long as it lives
    (a frozen dataclass would do too, but is twice as slow to build, and a large grammar
    has hundreds of thousands of spans). Ordered by start, then end.
    """

    start: int
    end: int

    def cover(self, other: Span) -> Span:
        return Span(min(self.start, other.start), max(self.end, other.end))

    def shifted(self, delta: int) -> Span:
        return Span(self.start + delta, self.end + delta)

    def __contains__(self, offset: object) -> bool:  # type: ignore[override]  # an offset, not an item
        return isinstance(offset, int) and self.start <= offset <= self.end
