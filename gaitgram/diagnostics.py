"""Diagnostics: what is wrong, where, and how to fix it.

Every problem gaitgram reports, from the parser or the linter, is a
:class:`Diagnostic` with a stable code from :data:`CODES`. Codes never change
meaning once released; new problems get new codes.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # a runtime import would be circular: the language package reports diagnostics
    from gaitgram.language.source import Span


class Severity(StrEnum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True, slots=True)
class Code:
    code: str
    name: str
    severity: Severity
    summary: str
    syntax: bool = False  # a syntax problem: the document does not say what it means

    def __str__(self) -> str:
        return self.code


E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO  # noqa: E741 (short names keep the table readable)

_CODES = (
    # Syntax: GG1xx. `gaitgram fmt` refuses to rewrite a file that has any of these.
    Code("GG101", "stray-text", E, "text outside any rule", syntax=True),
    Code("GG102", "unterminated-string", E, "a quoted terminal has no closing quote", syntax=True),
    Code("GG103", "invalid-escape", E, "a backslash escape that cannot be decoded", syntax=True),
    Code("GG104", "malformed-range", E, "a typed range that does not parse", syntax=True),
    Code(
        "GG105", "bad-ge-range", E, "a GE_RANGE that is not a whole alternative or has no size", syntax=True
    ),
    Code("GG106", "empty-alternative", W, "an empty alternative, which PonyGE2 drops"),
    Code("GG107", "comment-splits-alternative", W, "text after a comment starts a new alternative"),
    Code("GG108", "empty-rule", E, "a rule with no alternatives"),
    Code("GG109", "unencodable-text", E, "text that UTF-8 cannot encode (a lone surrogate)", syntax=True),
    # Rules: GG2xx.
    Code("GG201", "undefined-rule", E, "a non-terminal that no rule defines"),
    Code("GG202", "duplicate-rule", E, "a rule defined more than once"),
    Code("GG203", "unproductive-rule", E, "a rule that can never derive a terminal string"),
    Code("GG204", "unreachable-rule", W, "a rule the start rule never reaches"),
    Code("GG205", "start-derives-nothing", E, "the start rule can never derive a terminal string"),
    Code("GG206", "unit-rule-chain", I, "a rule whose only alternative is another rule"),
    Code("GG207", "no-rules", E, "the document defines no rule"),
    # Ranges: GG3xx.
    Code("GG301", "empty-range", E, "a typed range with no values"),
    Code("GG302", "bad-range-step", E, "a typed range whose step or count is not positive"),
    Code("GG303", "range-off-grid", W, "a range bound that is not on its step grid"),
    Code("GG304", "range-too-large", E, "a typed range with too many values"),
    Code("GG305", "range-kind-mismatch", E, "an int range with fractional bounds or step"),
    Code("GG306", "range-values-collapse", E, "a typed range whose values would not all be distinct"),
    Code("GG307", "unrepresentable-range-number", E, "a range number or value a double cannot hold exactly"),
    Code("GG308", "range-count-too-small", E, "count 1 over a range whose two ends differ"),
    # Annotations: GG4xx.
    Code("GG401", "unknown-annotation", W, "an annotation gaitgram does not know"),
    Code("GG402", "bad-annotation-arguments", E, "an annotation with missing, extra or ill-typed arguments"),
    Code("GG403", "dangling-annotation", E, "a rule annotation with no rule after it"),
    Code("GG404", "repeated-annotation", E, "an annotation that may appear once, given twice"),
    Code("GG405", "undefined-define", E, "a GE_RANGE name that no @define or --define gives"),
    # Backends and joints: GG5xx.
    Code("GG501", "unknown-backend", E, "@backend names a backend that is not installed"),
    Code("GG502", "unknown-joint", E, "@joint names a joint the backend lacks"),
    Code("GG503", "joint-without-curve", W, "a backend joint that no @joint rule drives"),
    Code("GG504", "duplicate-joint", E, "two rules drive the same joint"),
    Code("GG505", "joint-not-derived-once", W, "a joint rule that a derivation may skip or repeat"),
    Code("GG506", "joint-limits-exceed-backend", W, "@joint limits wider than the backend allows"),
    Code("GG507", "joint-without-backend", I, "@joint used with no @backend to check it against"),
)

CODES: dict[str, Code] = {c.code: c for c in _CODES}
CODES_BY_NAME: dict[str, Code] = {c.name: c for c in _CODES}


@dataclass(frozen=True, slots=True)
class Diagnostic:
    code: Code
    message: str
    span: Span
    rule: str | None = None
    hint: str | None = None
    severity: Severity | None = None  # None: the code's default

    @property
    def level(self) -> Severity:
        return self.severity or self.code.severity

    @property
    def is_error(self) -> bool:
        return self.level is Severity.ERROR


def diagnostic(
    code: str,
    message: str,
    span: Span,
    *,
    rule: str | None = None,
    hint: str | None = None,
) -> Diagnostic:
    """Make a diagnostic from a code string; an unknown code is a bug, caught early."""
    return Diagnostic(CODES[code], message, span, rule, hint)
