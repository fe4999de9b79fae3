"""Incremental parsing: after an edit, read again only the parts of a document it touched.

Public API for editors (the language server uses it): :class:`IncrementalParser` gives
exactly what :func:`gaitgram.language.parse` gives, for one document that changes a little at
a time.

A full ``parse`` of a 5,000-rule grammar takes a third of a second, most of it in the
scanner and the model builder, so the server cannot afford one per keystroke. But the
scanner has no state at a line that starts with an item: every line start is a token
boundary in body mode (no piece crosses a line break, and a rule head that does cannot
be followed by another head on the line it reaches). So a document splits, without
parsing, into *segments* that read the same alone as in place. A segment starts at a
line that begins with a rule head, provided the item line before it was a rule head too:
then no annotation is pending there, and every annotation stays in the segment of the
rule it annotates.

Each segment is read once and kept, keyed by its text; after an edit only new texts are
read, in place (the lexer reads a window of the document, so spans come out absolute), and
many new segments together in windows of about :data:`WINDOW` characters: between two, the
caller may stop a read whose text is already out of date (:class:`Stale`), and what was read
is kept for the next. A kept segment that moved is rebuilt at its new place by ``Parts.moved``, which is
cheap because a rule's pieces count from the rule's start (``Rule.span_of``): only the
rules, annotations, joints and problems are new objects. Nothing is changed in place, so a
:class:`~gaitgram.language.model.Grammar` from an earlier call stays true to its text.

A segment keeps what the builder read of it (:class:`~gaitgram.language.builder.Parts`:
rule-scope meaning only); what depends on the whole document is decided from all segments
by the same ``assemble_grammar`` a full parse ends with (``meaning.read_document``), and the
``@define`` values that ``GE_RANGE:name`` reads are re-checked here.
``tests/language/test_incremental.py`` checks that the result equals ``parse(text)``, spans
and diagnostics included, over random edits.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable, Iterator, Mapping
from typing import NamedTuple

from gaitgram.collector import gc_paused
from gaitgram.language import parse
from gaitgram.language.annotations import check_annotation
from gaitgram.language.builder import Parts, assemble_grammar, read_parts
from gaitgram.language.meaning import read_defines
from gaitgram.language.model import Grammar, RangeSymbol, Rule
from gaitgram.language.parser import parse_tree
from gaitgram.language.ranges import MAX_GRAMMAR_RANGE_VALUES
from gaitgram.language.source import SourceText
from gaitgram.language.syntax import item_lines

__all__ = ["FULL_PARSE_AT", "WINDOW", "IncrementalMismatch", "IncrementalParser", "Stale", "segment_starts"]

#: With more new segments than this (and than a quarter of them), one full parse is cheaper.
FULL_PARSE_AT = 64


def segment_starts(text: str) -> list[int]:
    """Offsets where independent segments start (always 0 first)."""
    starts = [0]
    previous_was_rule = False
    for found in item_lines().finditer(text):
        is_rule = found.lastgroup == "RULE_HEAD"
        if is_rule and previous_was_rule and found.start() > 0:
            starts.append(found.start())
        previous_was_rule = is_rule
    return starts


class Segment(NamedTuple):
    """What one segment reads as, with spans at ``base`` (its offset in the document)."""

    text: str
    base: int
    parts: Parts
    #: For a segment with ``GE_RANGE:``: the document's defines it was read with.
    read_with: tuple[tuple[str, int], ...] | None = None

    @property
    def needs_defines(self) -> bool:
        return _needs_defines(self.text)

    def at(self, base: int) -> Segment:
        """This segment moved to ``base``: new parts, the old ones untouched."""
        if base == self.base:
            return self
        return Segment(self.text, base, self.parts.moved(base - self.base), self.read_with)


def _needs_defines(text: str) -> bool:
    """Whether a text's meaning may depend on the document's ``@define`` values."""
    return "GE_RANGE:" in text


def _read_window(
    source: SourceText, starts: list[int], ends: list[int], defines: Mapping[str, int]
) -> list[Segment]:
    """Read consecutive segments of ``source`` at once, in place (their spans come out
    absolute), and cut what they read into those segments."""
    window = (starts[0], ends[-1])
    parts = read_parts(parse_tree(source.text, *window), source, defines, window)
    return _split(parts, source.text, starts, ends, dict(defines))


def _split(
    parts: Parts, text: str, starts: list[int], ends: list[int], defines: dict[str, int]
) -> list[Segment]:
    """Cut a whole document's parts into segments (every span lies inside its segment)."""
    buckets: list[tuple[list, list, list, list]] = [([], [], [], []) for _ in starts]

    def where(offset: int) -> int:
        return max(0, bisect_right(starts, offset) - 1)

    for rule in parts.rules:
        buckets[where(rule.name_span.start)][0].append(rule)
    for annotation in parts.annotations:
        buckets[where(annotation.span.start)][1].append(annotation)
    for joint in parts.joints:
        buckets[where(joint.span.start)][2].append(joint)
    for problem in parts.problems:
        buckets[where(problem.span.start)][3].append(problem)
    read_with = tuple(sorted(defines.items()))
    refused = parts.over_budget  # a range refused for the limit: read the whole document in order
    segments = []
    for start, end, (rules, notes, joints, problems) in zip(starts, ends, buckets, strict=True):
        own = read_defines(check_annotation(a, []) for a in notes)
        segment_parts = Parts(
            tuple(rules), tuple(notes), tuple(joints), tuple(problems), own, _range_values(rules), refused
        )
        segment_text = text[start:end]
        segments.append(
            Segment(segment_text, start, segment_parts, read_with if _needs_defines(segment_text) else None)
        )
    return segments


def _range_values(rules: list[Rule]) -> int:
    """The values of the typed ranges of ``rules``, counted as the builder counts them."""
    return sum(
        symbol.spec.size
        for rule in rules
        for alternative in rule.alternatives
        for symbol in alternative.symbols
        if isinstance(symbol, RangeSymbol)
    )


#: A document with many new segments is read in windows of about this many characters.
WINDOW = 1 << 16


def _windows(missing: list[int], starts: list[int], ends: list[int]) -> Iterator[list[int]]:
    """The missing segments (ascending) in groups to read at once: consecutive ones, up to about
    :data:`WINDOW` characters (one read of many segments costs less than one read of each)."""
    group: list[int] = []
    for i in missing:
        if group and (i != group[-1] + 1 or ends[group[-1]] - starts[group[0]] >= WINDOW):
            yield group
            group = []
        group.append(i)
    if group:
        yield group


def _never() -> bool:
    return False


class Stale(Exception):
    """The text was read no further: the caller's ``stop`` said it is out of date."""


class IncrementalMismatch(AssertionError):
    """An incremental parse gave another grammar than a full parse: a bug in this module."""


#: What ``verify`` compares: every part of a grammar.
_COMPARED = (
    "rules",
    "annotations",
    "joints",
    "frequency",
    "diagnostics",
    "start",
    "backend",
    "units",
    "defines",
    "declared",
)


class IncrementalParser:
    """``parse`` for one document that changes a little at a time. Not thread-safe: one
    document's parses run one after another."""

    def __init__(
        self,
        defines: Mapping[str, int] | None = None,
        *,
        full_parse_at: int = FULL_PARSE_AT,
        verify: bool = False,
    ) -> None:
        self.external_defines = dict(defines or {})
        self.full_parse_at = full_parse_at
        #: Compare every result with a full parse and raise ``IncrementalMismatch`` if they
        #: differ (slow: for tests and bug hunts).
        self.verify = verify
        self._kept: dict[str, list[Segment]] = {}
        self._defines: dict[str, int] = dict(self.external_defines)
        #: How the last call went: "full", or how many segments it read.
        self.last_reads: str | int = "full"

    def reset(self) -> None:
        """Forget every kept segment: the next parse reads the whole document."""
        self._kept = {}
        self._defines = dict(self.external_defines)

    def parse(self, text: str | SourceText, stop: Callable[[], bool] | None = None) -> Grammar:
        """The same grammar as ``parse(text)``; earlier results are left as they were.

        ``stop`` is asked between the parts read (about :data:`WINDOW` characters each): once it
        says yes, :class:`Stale` is raised, and what was read so far is kept for the next call
        (the language server stops reading a text the user has already changed)."""
        source = text if isinstance(text, SourceText) else SourceText(text)
        with gc_paused():
            grammar = self._parse(source, stop or _never)
        if self.verify:
            full = parse(source, defines=self.external_defines)
            for part in _COMPARED:
                if getattr(grammar, part) != getattr(full, part):
                    self.reset()
                    raise IncrementalMismatch(f"incremental parse differs from a full parse in {part}")
        return grammar

    def _parse(self, source: SourceText, stop: Callable[[], bool]) -> Grammar:
        text = source.text
        starts = segment_starts(text)
        ends = [*starts[1:], len(text)]
        kept = self._kept
        segments: list[Segment | None] = []
        missing: list[int] = []
        for i, (start, end) in enumerate(zip(starts, ends, strict=True)):
            bucket = kept.get(text[start:end])
            if bucket:
                segments.append(bucket.pop())
            else:
                segments.append(None)
                missing.append(i)
        full = len(missing) > max(self.full_parse_at, len(starts) // 4)
        if full:  # read everything again, as a parse of the whole text would
            segments = [None] * len(starts)
            missing = list(range(len(starts)))
        try:
            for run in _windows(missing, starts, ends):
                if stop():
                    raise Stale
                first, last = run[0], run[-1] + 1
                segments[first:last] = _read_window(
                    source, starts[first:last], ends[first:last], self._defines
                )
            filled: list[Segment] = segments  # type: ignore[assignment]  # every hole is filled
            if sum(s.parts.range_values for s in filled) > MAX_GRAMMAR_RANGE_VALUES or any(
                s.parts.over_budget for s in filled
            ):  # the limit counts in document order, over the whole document
                return self._whole(source)
            ready = [segment.at(start) for segment, start in zip(filled, starts, strict=True)]
            defines: dict[str, int] = {}
            for segment in ready:
                defines.update(segment.parts.defines)
            defines.update(self.external_defines)
            key = tuple(sorted(defines.items()))
            reread = 0
            for i, segment in enumerate(ready):
                if segment.needs_defines and segment.read_with != key:
                    if stop():
                        raise Stale
                    ready[i] = _read_window(source, [starts[i]], [ends[i]], defines)[0]
                    reread += 1
        except Stale:  # keep what was read, and what was found kept, for the next text
            for segment in reversed(segments):
                if segment is not None:
                    kept.setdefault(segment.text, []).append(segment)
            raise
        self._keep(ready, defines)
        self.last_reads = "full" if full else len(missing) + reread
        return assemble_grammar(source, [segment.parts for segment in ready], defines)

    def _whole(self, source: SourceText) -> Grammar:
        """The whole document read at once, in order (its ranges have passed the grammar's limit on
        range values, which counts in document order). Nothing is kept: after an edit a
        segment's ranges may read otherwise."""
        parts = read_parts(parse_tree(source.text), source, self.external_defines)
        defines = {**parts.defines, **self.external_defines}
        self._keep([], defines)
        self.last_reads = "full"
        return assemble_grammar(source, [parts], defines)

    def _keep(self, segments: list[Segment], defines: dict[str, int]) -> None:
        kept: dict[str, list[Segment]] = {}
        for segment in reversed(segments):  # popped from the end: first occurrence first
            kept.setdefault(segment.text, []).append(segment)
        self._kept = kept
        self._defines = defines
