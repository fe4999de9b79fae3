"""Text that looks like a typed range but is plain text (GG309).

PonyGE2 compatibility keeps ``flaot[0..1 step 0.1]`` and an unclosed ``int[1..5`` as plain
terminal text (only the exact bracketed shape of the grammar's ``RANGE`` token is a range), so a
typo silently turns a choice of values into one fixed string. The builder looks for such text in
every run of unquoted terminal text; what it looks for is built from the grammar's own range
terminals (its numbers, ``..``/``±``, ``step``/``count`` and spaces) around any word and an
optional ``]``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache

from gaitgram.language.diagnostics import Applicability, Code, Severity
from gaitgram.language.model import RangeKind
from gaitgram.language.parser import terminal
from gaitgram.language.ranges import RangeEdit, RangeFix, apply_range_edits, range_reads

__all__ = ["CODES", "HINT", "RANGE_LOOK_ALIKE", "LookAlike", "look_alike_ranges"]

RANGE_LOOK_ALIKE = Code(
    "GG309",
    "range-look-alike",
    Severity.WARNING,
    "text that looks like a typed range but is plain text",
    "Text such as flaot[0..1 step 0.1] or an unclosed int[1..5 looks like a typed range but is "
    "read as plain terminal text (as PonyGE2 reads it). Correct the type name to int or float and "
    "close the bracket, or quote the text to keep it as text.",
    fix=Applicability.SAFE,
    fix_help="Corrects the type name to `int` or `float` and closes the bracket, making the text the range "
    "it looks like (not offered when the range would be an error, or the `]` would close an earlier "
    "bracket or make a following `GE_RANGE:` one).",
)
CODES = (RANGE_LOOK_ALIKE,)


@cache
def _look_alike() -> re.Pattern[str]:
    """Any word, ``[``, ``LO..HI`` or ``X ± P%``, an optional step or count, and maybe ``]``."""

    def part(name: str) -> str:
        return f"(?:{terminal(name).pattern})"

    number, space = part("RANGE_NUMBER"), part("RANGE_WS")
    between = f"(?:{part('RANGE_DOTS')}|{part('RANGE_PLUSMINUS')})"
    option = f"(?:{part('RANGE_STEP')}|{part('RANGE_COUNT')})"
    gap = f"{space}?"
    return re.compile(
        rf"(?<![\w\\])(?P<kind>[A-Za-z_]\w*)\[(?P<body>{gap}{number}{gap}{between}{gap}{number}(?:{gap}%)?"
        rf"(?:{space}{option}{space}{number})?)(?P<close>{gap}\])?"
    )


#: After a number, more of the same word: ``int[1..5x`` is not an unclosed range.
_WORD_GOES_ON = re.compile(r"[\w.]")

#: Other languages' names for the two kinds.
_KIND_ALIASES = {"integer": "int", "double": "float"}


@dataclass(frozen=True, slots=True)
class LookAlike:
    """Terminal text that looks like a typed range: where (in the text given), why, the fix."""

    offset: int
    length: int
    message: str
    fix: RangeFix | None
    meant: str  # the range it looks like: int or float


HINT = "PonyGE2 reads it as plain text too; to keep it as text, quote it ('...')"


def look_alike_ranges(text: str) -> list[LookAlike]:
    """The typed ranges in a run of terminal text that are not ranges: a type name one typo
    (or a letter's case) away from int or float, or no closing ``]``, before ``LO..HI``."""
    if "[" not in text:
        return []
    found = []
    for match in _look_alike().finditer(text):
        word = match["kind"]
        meant = _kind_meant(word)
        closed = match["close"] is not None
        end = match.end() if closed else match.end("body")
        if meant is None or (word == meant and closed) or (not closed and _WORD_GOES_ON.match(text, end)):
            continue
        shown = text[match.start() : end]
        edits = [] if word == meant else [RangeEdit(0, len(word), meant)]
        if not closed:
            edits.append(RangeEdit(end - match.start(), 0, "]"))
        why = [] if word == meant else [f"{word!r} is not int or float"]
        if not closed:
            why.append("it has no closing ]")
        fixed = apply_range_edits(shown, tuple(edits))
        # Once a range ends the text run, a GE_RANGE after it is read as one, not as text.
        usable = range_reads(fixed) and "GE_RANGE:" not in text[end:]
        found.append(
            LookAlike(
                match.start(),
                len(shown),
                f"{shown!r} looks like a typed range but is plain text: {' and '.join(why)}",
                RangeFix(f"Make it the range {fixed}", tuple(edits), safe=True) if usable else None,
                meant,
            )
        )
    return found


def _kind_meant(word: str) -> str | None:
    lower = word.lower()
    if lower in _KIND_ALIASES:
        return _KIND_ALIASES[lower]
    if len(lower) < 3:  # `in[1..5]`, `it[0..1]`: too likely to be meant
        return None
    return next((kind.value for kind in RangeKind if _typos(lower, kind) <= 1), None)


def _typos(a: str, b: str) -> int:
    """Edits from ``a`` to ``b`` (insert, delete, replace, swap two neighbours), up to 2."""
    if abs(len(a) - len(b)) > 1:
        return 2
    previous2: list[int] = []
    previous = list(range(len(b) + 1))
    for i, x in enumerate(a, 1):
        current = [i]
        for j, y in enumerate(b, 1):
            cost = min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (x != y))
            if i > 1 and j > 1 and x == b[j - 2] and a[i - 2] == y:
                cost = min(cost, previous2[j - 2] + 1)
            current.append(cost)
        previous2, previous = previous, current
    return min(previous[-1], 2)
