"""Applying the fixes diagnostics carry: ``gaitgram check --fix``, and fixes combined for editors.

A :class:`~gaitgram.language.diagnostics.Diagnostic` carries its fixes as data (made by the
builder and the linter, where the names and spans are known); this module only chooses
and applies them. :func:`fix_source` is what ``check --fix`` does to one file:

* it applies the safe fixes (with ``unsafe``, also the preferred fix of a diagnostic
  that has no safe one), all that do not overlap at once, then checks the text again
  and repeats, since one fix can make another possible;
* it keeps an edit only if the grammar has no error it did not have before (errors are
  compared by code, rule and the text they are about, so moving text does not count): a
  batch that would add one is halved until a part does not, and a single fix that adds one
  is not applied to that text. So fixing never makes a file worse, and a file without
  diagnostics is never changed, whatever the fixes are;
* it stops at a fixed point: when no fix is left that applies to the text as it now is. A
  fix refused in one text is tried again once other fixes changed it (closing a string can
  make a merge possible), and a fix left out of a batch for overlapping another is tried in
  a later round. Fixing the result again therefore changes nothing. A text that keeps
  changing for :data:`MAX_PASSES` rounds is given up on, and :attr:`FixOutcome.converged`
  says so.
"""

from __future__ import annotations

from bisect import bisect_left
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from gaitgram.analysis import CheckResult, check
from gaitgram.analysis.lint.sensor_checks import CODES as CURVE_NAME_CODES
from gaitgram.language import parse
from gaitgram.language.diagnostics import Applicability, Code, Diagnostic, Fix, TextEdit
from gaitgram.language.edits import EditConflict, apply_edits, conflicts, normalized, union
from gaitgram.language.source import Location, SourceText

__all__ = [
    "MAX_PASSES",
    "AppliedFix",
    "ErrorKey",
    "FixOutcome",
    "chosen_fix",
    "combine",
    "error_keys",
    "fix_all",
    "fix_source",
    "no_worse",
]

#: ``check --fix`` gives up after this many rounds that changed the text (each applies every
#: fix it can at once, so real grammars settle in two or three).
MAX_PASSES = 20

ErrorKey = tuple[str, str | None, str]


@dataclass(frozen=True, slots=True)
class AppliedFix:
    """A fix that was applied: for which code, what it did, and where (in the text it was
    applied to, which is the file as read unless an earlier round changed it)."""

    code: Code
    title: str
    location: Location


@dataclass(frozen=True, eq=False)
class FixOutcome:
    """What fixing one text did."""

    original: SourceText
    text: str
    applied: tuple[AppliedFix, ...]
    #: The check of the fixed text: the problems that remain.
    result: CheckResult
    #: Remaining diagnostics whose fix ``--unsafe-fixes`` would try.
    unsafe_available: int
    #: Fixes not applied because they would have added an error (each counted once, though
    #: it may have been tried on several versions of the text).
    refused: int
    #: Whether no fix is left to apply (false only if fixing gave up after :data:`MAX_PASSES`
    #: rounds), so that fixing ``text`` again changes nothing.
    converged: bool = True
    #: Rounds of fixes that changed the text.
    passes: int = 0

    @property
    def changed(self) -> bool:
        return self.text != self.original.text


def chosen_fix(found: Diagnostic, *, unsafe: bool = False) -> Fix | None:
    """The fix ``check --fix`` applies to a diagnostic: its safe one; with ``unsafe``, else its
    preferred one (a guess between names, a deletion), never an arbitrary one."""
    for fix in found.fixes:
        if fix.safe:
            return fix
    if unsafe:
        return next((fix for fix in found.fixes if fix.preferred), None)
    return None


def error_keys(result: CheckResult) -> Counter[ErrorKey]:
    """The errors of a check as (code, rule, text they are about), which moving text around
    leaves alone; a fix may only make this multiset smaller. A name in a curve is read across
    terminals (``'x'int[1..5`` reads ``xint``), so a fix of a neighbouring terminal changes the
    name without adding an error: those errors count per rule, whatever the name."""
    text = result.grammar.source.text
    return Counter(
        (d.code.code, d.rule, "" if d.code in _PER_RULE else text[d.span.start : d.span.end])
        for d in result.diagnostics
        if d.is_error
    )


_PER_RULE = frozenset(CURVE_NAME_CODES)


def no_worse(before: CheckResult, after: CheckResult) -> bool:
    """Every error of ``after`` was an error of ``before`` (counted with multiplicity)."""
    old = error_keys(before)
    return all(count <= old[key] for key, count in error_keys(after).items())


def fix_source(
    source: SourceText, *, defines: Mapping[str, int] | None = None, unsafe: bool = False
) -> FixOutcome:
    """Apply the chosen fixes of ``source``'s diagnostics until none is left (see the module doc)."""
    result = check(parse(source, defines=defines))
    applied: list[AppliedFix] = []
    refused: set[tuple[str, str, str]] = set()  # in the text as it is now
    ever_refused: set[tuple[str, str, str]] = set()

    def attempt(batch: Sequence[tuple[Diagnostic, Fix]]) -> CheckResult | None:
        text = result.grammar.source.text
        try:
            new_text = apply_edits(text, (e for _, fix in batch for e in fix.edits))
        except EditConflict:  # pragma: no cover - batches are chosen without conflicts
            return None
        if new_text == text:
            return None
        new = check(parse(SourceText(new_text, source.name), defines=defines))
        return new if no_worse(result, new) else None

    def settle(
        batch: Sequence[tuple[Diagnostic, Fix]],
    ) -> tuple[Sequence[tuple[Diagnostic, Fix]], CheckResult] | None:
        """The batch if it adds no error, else the first half of it (halving) that does not;
        a single fix that adds one is refused for this text. A few checks even for many fixes."""
        new = attempt(batch)
        if new is not None:
            return batch, new
        if len(batch) == 1:
            refused.add(_key(result, *batch[0]))
            ever_refused.add(_key(result, *batch[0]))
            return None
        half = len(batch) // 2
        return settle(batch[:half]) or settle(batch[half:])

    passes = 0
    converged = True
    while candidates := [
        (found, fix)
        for found in result.diagnostics
        if (fix := chosen_fix(found, unsafe=unsafe)) is not None and _key(result, found, fix) not in refused
    ]:
        # Each round either changes the text or refuses at least one more fix of it, so
        # rounds that change nothing end by themselves; rounds that do are counted.
        settled = settle(_compatible(candidates))
        if settled is None:
            continue
        if passes == MAX_PASSES:
            converged = False
            break
        passes += 1
        batch, new = settled
        source_now = result.grammar.source
        applied += [AppliedFix(d.code, f.title, source_now.location(d.span.start)) for d, f in batch]
        result = new
        refused.clear()  # refused for the old text: the new one may take them

    remaining = sum(
        1 for d in result.diagnostics if chosen_fix(d) is None and chosen_fix(d, unsafe=True) is not None
    )
    return FixOutcome(
        original=source,
        text=result.grammar.source.text,
        applied=tuple(applied),
        result=result,
        unsafe_available=0 if unsafe else remaining,
        refused=len(ever_refused),
        converged=converged,
        passes=passes,
    )


def _key(result: CheckResult, found: Diagnostic, fix: Fix) -> tuple[str, str, str]:
    return (found.code.code, fix.title, result.grammar.source.slice(found.span))


def _compatible(candidates: Iterable[tuple[Diagnostic, Fix]]) -> list[tuple[Diagnostic, Fix]]:
    """The candidates in order, each whole, leaving out any whose edits conflict with one taken."""
    taken: list[tuple[Diagnostic, Fix]] = []
    keys: list[tuple[int, int]] = []  # the taken edits' spans, sorted; they never overlap
    edits: list[TextEdit] = []
    for found, fix in candidates:
        if any(_clashes(edit, keys, edits) for edit in fix.edits):
            continue
        taken.append((found, fix))
        for edit in fix.edits:
            at = bisect_left(keys, (edit.span.start, edit.span.end))
            keys.insert(at, (edit.span.start, edit.span.end))
            edits.insert(at, edit)
    return taken


def _clashes(edit: TextEdit, keys: list[tuple[int, int]], edits: list[TextEdit]) -> bool:
    """Whether ``edit`` conflicts with one of ``edits`` (sorted, without overlaps): only its
    neighbours in that order can."""
    at = bisect_left(keys, (edit.span.start, edit.span.end))
    return any(conflicts(edit, edits[i]) for i in range(max(at - 1, 0), min(at + 2, len(edits))))


def combine(title: str, fixes: Iterable[Fix]) -> Fix | None:
    """One fix doing all of ``fixes`` (``Remove all 3 unreachable rules``): deletions that
    overlap are merged, repeated edits kept once; None if two other edits overlap."""
    fixes = list(fixes)
    if not fixes:
        return None
    deletions = union(e.span for fix in fixes for e in fix.edits if not e.text)
    others = {e for fix in fixes for e in fix.edits if e.text}
    try:
        edits = normalized([TextEdit(span, "") for span in deletions] + list(others))
    except EditConflict:
        return None
    safe = all(fix.safe for fix in fixes)
    return Fix(title, tuple(edits), Applicability.SAFE if safe else Applicability.UNSAFE)


def fix_all(diagnostics: Iterable[Diagnostic], code: str) -> Fix | None:
    """One fix applying the chosen fix (safe, else preferred) of every diagnostic with ``code``:
    the editor's "fix all of these". None if fewer than two have one, or two of them overlap."""
    declared: Code | None = None
    fixes = []
    for found in diagnostics:
        if found.code.code == code and (fix := chosen_fix(found, unsafe=True)) is not None:
            declared = found.code
            fixes.append(fix)
    if declared is None or len(fixes) < 2:
        return None
    title = (declared.fix_all or "Fix all {n} {code} problems").format(n=len(fixes), code=code)
    return combine(title, fixes)
