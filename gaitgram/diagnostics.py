"""Diagnostics: what is wrong, where, and how to fix it.

Every problem gaitgram reports, from the parser or the linter, is a
:class:`Diagnostic` with a stable code from :data:`CODES`. Codes never change
meaning once released; new problems get new codes.

A diagnostic carries its fixes as data (:class:`Fix`: a title and :class:`TextEdit` s),
and the names it is about in ``data``, so that ``gaitgram check --fix``, the language
server's quick fixes and SARIF all apply or show the same edits, and no caller has to
read a name back out of a message.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from enum import StrEnum

from gaitgram.spans import Span

__all__ = [
    "CODES",
    "CODES_BY_NAME",
    "Applicability",
    "Code",
    "Diagnostic",
    "Fix",
    "Severity",
    "TextEdit",
    "diagnostic",
]


class Severity(StrEnum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


class Applicability(StrEnum):
    """Whether a fix may be applied without a person looking at it."""

    #: ``gaitgram check --fix`` applies it: it keeps what the grammar means (or, for GG104 and
    #: GG309, does the one thing the text evidently meant) and deletes nothing the user wrote.
    SAFE = "safe"
    #: Offered in the editor, applied by ``--fix`` only with ``--unsafe-fixes``: it changes
    #: what the grammar derives, deletes text, or guesses between names.
    UNSAFE = "unsafe"


@dataclass(frozen=True, slots=True)
class Code:
    code: str
    name: str
    severity: Severity
    summary: str
    syntax: bool = False  # a syntax problem: the document does not say what it means
    #: How safe the fixes its diagnostics carry are; None: it has none (documented and tested
    #: per code: a code with fixes has a sample in the fix tests).
    fix: Applicability | None = None
    #: What to do about it, for ``--format sarif`` and the docs (set from ``_HELP`` below).
    help: str = ""
    #: What its fixes do, in Markdown, for the docs (set from ``_FIX_HELP`` below; empty without fixes).
    fix_help: str = ""

    def __str__(self) -> str:
        return self.code

    @property
    def anchor(self) -> str:
        """The heading anchor of this code in ``docs/diagnostics.md`` (``gg201-undefined-rule``)."""
        return f"{self.code.lower()}-{self.name}"


E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO  # noqa: E741 (short names keep the table readable)
SAFE, UNSAFE = Applicability.SAFE, Applicability.UNSAFE

_CODES = (
    # Syntax: GG1xx. `gaitgram fmt` refuses to rewrite a file that has any of these.
    Code("GG101", "stray-text", E, "text outside any rule", syntax=True),
    Code("GG102", "unterminated-string", E, "a quoted terminal has no closing quote", syntax=True, fix=SAFE),
    Code("GG103", "invalid-escape", E, "a backslash escape that cannot be decoded", syntax=True, fix=UNSAFE),
    Code("GG104", "malformed-range", E, "a typed range that does not parse", syntax=True, fix=SAFE),
    Code(
        "GG105", "bad-ge-range", E, "a GE_RANGE that is not a whole alternative or has no size", syntax=True
    ),
    Code("GG106", "empty-alternative", W, "an empty alternative, which PonyGE2 drops", fix=SAFE),
    Code("GG107", "comment-splits-alternative", W, "text after a comment starts a new alternative", fix=SAFE),
    Code("GG108", "empty-rule", E, "a rule with no alternatives", fix=UNSAFE),
    Code(
        "GG109",
        "unencodable-text",
        E,
        "text that UTF-8 cannot encode (a lone surrogate)",
        syntax=True,
        fix=UNSAFE,
    ),
    # Rules: GG2xx.
    Code("GG201", "undefined-rule", E, "a non-terminal that no rule defines", fix=UNSAFE),
    Code("GG202", "duplicate-rule", E, "a rule defined more than once", fix=UNSAFE),
    Code("GG203", "unproductive-rule", E, "a rule that can never derive a terminal string"),
    Code("GG204", "unreachable-rule", W, "a rule the start rule never reaches", fix=UNSAFE),
    Code("GG205", "start-derives-nothing", E, "the start rule can never derive a terminal string"),
    Code("GG206", "unit-rule-chain", I, "a rule whose only alternative is another rule"),
    Code("GG207", "no-rules", E, "the document defines no rule"),
    # Ranges: GG3xx.
    Code("GG301", "empty-range", E, "a typed range with no values", fix=UNSAFE),
    Code("GG302", "bad-range-step", E, "a typed range whose step or count is not positive"),
    Code("GG303", "range-off-grid", W, "a range bound that is not on its step grid", fix=SAFE),
    Code("GG304", "range-too-large", E, "a typed range with too many values"),
    Code("GG305", "range-kind-mismatch", E, "an int range with fractional bounds or step", fix=UNSAFE),
    Code("GG306", "range-values-collapse", E, "a typed range whose values would not all be distinct"),
    Code("GG307", "unrepresentable-range-number", E, "a range number or value a double cannot hold exactly"),
    Code("GG308", "range-count-too-small", E, "count 1 over a range whose two ends differ"),
    Code("GG309", "range-look-alike", W, "text that looks like a typed range but is plain text", fix=SAFE),
    # Annotations: GG4xx.
    Code("GG401", "unknown-annotation", W, "an annotation gaitgram does not know", fix=UNSAFE),
    Code("GG402", "bad-annotation-arguments", E, "an annotation with missing, extra or ill-typed arguments"),
    Code("GG403", "dangling-annotation", E, "a rule annotation with no rule after it", fix=UNSAFE),
    Code("GG404", "repeated-annotation", E, "an annotation that may appear once, given twice", fix=UNSAFE),
    Code("GG405", "undefined-define", E, "a GE_RANGE name that no @define or --define gives"),
    # Backends and joints: GG5xx.
    Code("GG501", "unknown-backend", E, "@backend names a backend that is not installed", fix=UNSAFE),
    Code("GG502", "unknown-joint", E, "@joint names a joint the backend lacks", fix=UNSAFE),
    Code("GG503", "joint-without-curve", W, "a backend joint that no @joint rule drives"),
    Code("GG504", "duplicate-joint", E, "two rules drive the same joint"),
    Code("GG505", "joint-not-derived-once", W, "a joint rule that a derivation may skip or repeat"),
    Code("GG506", "joint-limits-exceed-backend", W, "@joint limits wider than the backend allows"),
    Code("GG507", "joint-without-backend", I, "@joint used with no @backend to check it against"),
)

#: What to do about each code: the help text of ``--format sarif`` and of ``docs/diagnostics.md``.
_HELP = {
    "GG101": "Text between rules belongs to no rule. Start a rule with <name> ::=, or make the text a "
    "comment with #.",
    "GG102": "A quoted terminal ends at the end of its line. Add the closing quote; the fix adds it at the "
    "end of the line, which is where the text already ends.",
    "GG103": "A backslash starts an escape (\\n, \\t, \\xHH, \\uHHHH, \\UHHHHHHHH, \\N{NAME}). "
    "Write \\\\ for a backslash itself, and a character outside the Basic Multilingual Plane as "
    "itself or as one \\U escape, never as a UTF-16 surrogate pair.",
    "GG104": "A typed range is int[LO..HI], int[LO..HI step S], float[LO..HI step S], float[LO..HI count N] "
    "or float[X ± P% count N]; a float range needs a step or a count. A range left unclosed before a | "
    "reads as one malformed range up to the next ]; the fix closes it before the |.",
    "GG105": "GE_RANGE:n (or GE_RANGE:name, with @define name=n) must be an alternative on its own, with a "
    "size from 1 to 100,000.",
    "GG106": "An alternative with nothing in it is dropped, by PonyGE2 and by gaitgram. Delete the extra |, "
    "or write '' for the empty string.",
    "GG107": "A comment ends an alternative, so text on the next line starts a new one even without |. "
    "Write the | to say so.",
    "GG108": "Every rule needs at least one alternative; '' derives the empty string.",
    "GG109": "Text given to the library or an editor holds UTF-16 surrogates, which no file can hold and "
    "UTF-8 cannot encode. Write the character itself.",
    "GG201": "A non-terminal names a rule that does not exist: define the rule, or correct the name.",
    "GG202": "Only the first definition of a rule counts. Merge the alternatives into one rule with |, or "
    "rename one of the rules.",
    "GG203": "Every alternative of the rule needs a rule that cannot finish, so no derivation through it "
    "ends. Add an alternative that ends, such as a terminal.",
    "GG204": "No derivation from the start rule uses this rule. Delete it, or use it from a rule the start "
    "rule reaches.",
    "GG205": "No derivation from the start rule ever ends, so no genome maps to a phenotype. Give some "
    "rule on the way an alternative that ends.",
    "GG206": "A rule whose only alternative is another rule adds a derivation step (and, in eager mode, "
    "reads a codon). Use the other rule directly.",
    "GG207": "A grammar needs at least one rule, <name> ::= alternatives.",
    "GG301": "The lower bound of a typed range is above its upper bound. Swap the bounds.",
    "GG302": "A step must be positive, a count a whole number of at least 1, a percentage not negative.",
    "GG303": "The upper bound is not a whole number of steps above the lower one, so the last value is "
    "below it. Make the upper bound the last value (the values stay the same), or change the step.",
    "GG304": "A typed range has more than 100,000 values. Use a coarser step or a smaller count.",
    "GG305": "An int range has whole bounds and steps, and no count. Use float[...] for fractional values "
    "or a count.",
    "GG306": "The values of the range would round to the same text, so some choices would be equal. Use "
    "a smaller count or bounds further apart.",
    "GG307": "Numbers in ranges are within ±1e12 with at most 15 significant digits and 15 decimals, so a "
    "double holds each value exactly. Write fewer digits.",
    "GG308": "A count range includes both ends, so count 1 cannot cover two different ends. Use count 2 "
    "or more, or write the one value itself.",
    "GG309": "Text such as flaot[0..1 step 0.1] or an unclosed int[1..5 looks like a typed range but is "
    "read as plain terminal text (as PonyGE2 reads it). Correct the type name to int or float and "
    "close the bracket, or quote the text to keep it as text.",
    "GG401": "gaitgram does not know this annotation and ignores it. Correct the name: @start, @backend, "
    "@units, @define, @joint or @frequency.",
    "GG402": "An annotation has a missing, extra or ill-typed argument. The message says which; hover "
    "over the annotation for its usage.",
    "GG403": "A rule annotation (@joint, @frequency) applies to the rule written after it, and none "
    "follows. Move it above its rule, or delete it.",
    "GG404": "This annotation may be given once (in a file, or on a rule); the first one counts. Delete "
    "the extra one.",
    "GG405": "GE_RANGE:name needs a value for name: add @define name=N, or pass --define name=N.",
    "GG501": "@backend names a backend that is not installed (or fails to load). Correct the name, or "
    "install the plug-in that provides it.",
    "GG502": "@joint names a joint the backend does not have. Correct the name; the message lists the "
    "nearest one.",
    "GG503": "A joint of the backend is driven by no @joint rule, so it holds its neutral angle. Add a "
    "rule for it if it should move.",
    "GG504": "Two rules drive the same joint; each joint is driven by exactly one rule.",
    "GG505": "A joint's curve should be derived exactly once per individual; some derivation skips or "
    "repeats this rule.",
    "GG506": "The @joint limits are wider than the backend allows; the backend clips the curve to its own "
    "limits.",
    "GG507": "Without @backend, joint names and limits cannot be checked. Declare the backend.",
}

#: What the fixes of each code with fixes do (Markdown): the catalogue in ``docs/diagnostics.md``.
_FIX_HELP = {
    "GG102": "Closes the string at the end of its line, where its text already ends, so it reads the same.",
    "GG103": "Writes the `\\U` escape a UTF-16 surrogate pair meant (preferred); or escapes the backslash, "
    "which keeps the text that was read.",
    "GG104": "Closes a range left open before a `|` (`int[1..5 | int[7..9]`), when both ranges then read "
    "without errors and only plain text follows the `|`.",
    "GG106": "Deletes the extra `|`.",
    "GG107": "Writes the `|` before the new alternative; the grammar reads the same.",
    "GG108": "Makes the rule derive the empty string, `''`.",
    "GG109": "Joins UTF-16 surrogate pairs into the characters they encode.",
    "GG201": "Replaces the name with the nearest defined one (preferred; up to three are offered), or "
    "defines the rule, `<name> ::= ''`, after the rule that uses it.",
    "GG202": "Merges the alternatives into the first definition (preferred, when the duplicate has no "
    "annotations), or deletes the ignored definition.",
    "GG204": "Deletes the rule with its annotations, together with the unreachable rules that use it, so no "
    "reference is left undefined (not offered when a reachable rule's ignored duplicate uses it). The"
    " editor also offers one fix removing every unreachable rule.",
    "GG301": "Swaps the bounds, when the range then reads without errors.",
    "GG303": "Makes the upper bound the last value: the range derives exactly the same values.",
    "GG305": "Makes it a float range, when that reads without errors.",
    "GG309": "Corrects the type name to `int` or `float` and closes the bracket, making the text the range "
    "it looks like (not offered when the range would be an error, or the `]` would close an earlier "
    "bracket or make a following `GE_RANGE:` one).",
    "GG401": "The nearest known annotation.",
    "GG403": "Deletes the annotation.",
    "GG404": "Deletes the extra annotation.",
    "GG501": "The nearest installed backend.",
    "GG502": "The nearest joint of the backend.",
}

CODES: dict[str, Code] = {
    c.code: replace(c, help=_HELP[c.code], fix_help=_FIX_HELP.get(c.code, "")) for c in _CODES
}
CODES_BY_NAME: dict[str, Code] = {c.name: c for c in CODES.values()}


@dataclass(frozen=True, slots=True)
class TextEdit:
    """Replace the text at ``span`` with ``text``: an insertion if the span is empty, a
    deletion if the text is. Offsets are characters of the newline-normalised text."""

    span: Span
    text: str


@dataclass(frozen=True, slots=True)
class Fix:
    """One way to fix a diagnostic: a title for people and the edits that do it.

    Data, so that ``gaitgram check --fix``, the language server's quick fixes and SARIF
    ``fixes`` apply or show exactly the same edits. ``preferred``: the one to apply when
    nobody chooses (the editor's preferred quick fix; ``--unsafe-fixes``).
    """

    title: str
    edits: tuple[TextEdit, ...]
    applicability: Applicability = Applicability.UNSAFE
    preferred: bool = False

    @property
    def safe(self) -> bool:
        return self.applicability is Applicability.SAFE


@dataclass(frozen=True, slots=True)
class Diagnostic:
    code: Code
    message: str
    span: Span
    rule: str | None = None
    hint: str | None = None
    severity: Severity | None = None  # None: the code's default
    fixes: tuple[Fix, ...] = ()
    #: The names the problem is about (``{"name": "bee"}`` for an undefined ``<bee>``), for
    #: programs: the message is for people and may change wording.
    data: Mapping[str, str] = field(default_factory=dict, hash=False)

    @property
    def level(self) -> Severity:
        return self.severity or self.code.severity

    @property
    def is_error(self) -> bool:
        return self.level is Severity.ERROR

    def moved(self, delta: int) -> Diagnostic:
        """The same problem ``delta`` characters further on, its fixes' edits included."""
        fixes = tuple(
            replace(fix, edits=tuple(TextEdit(e.span.shifted(delta), e.text) for e in fix.edits))
            for fix in self.fixes
        )
        return replace(self, span=self.span.shifted(delta), fixes=fixes)


def diagnostic(
    code: str,
    message: str,
    span: Span,
    *,
    rule: str | None = None,
    hint: str | None = None,
    fixes: tuple[Fix, ...] | list[Fix] = (),
    data: Mapping[str, str] | None = None,
) -> Diagnostic:
    """Make a diagnostic from a code string; an unknown code is a bug, caught early."""
    return Diagnostic(CODES[code], message, span, rule, hint, None, tuple(fixes), dict(data or {}))
