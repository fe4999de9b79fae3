"""Diagnostics: what is wrong, where, and how to fix it.

Every problem gaitgram reports, from the parser or the linter, is a :class:`Diagnostic` of a
:class:`Code`. A code is declared once, in the module that finds its problem, beside the
function that reports it: its stable number and name, its severity, what it means, what to do
about it and what its fixes do. The catalogue of every code
(:data:`gaitgram.analysis.diagnostic_codes.CODES`) gathers those declarations; ``docs/diagnostics.md``,
SARIF's rule metadata and the language server read them from there. Codes never change meaning
once released; new problems get new codes.

A diagnostic carries its fixes as data (:class:`Fix`: a title and :class:`TextEdit` s),
and the names it is about in ``data``, so that ``gaitgram check --fix``, the language
server's quick fixes and SARIF all apply or show the same edits, and no caller has to
read a name back out of a message. Fixes that cost something to work out are made the first
time they are asked for (:attr:`Diagnostic.fixes`), so a check that only reports pays nothing
for them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
from enum import StrEnum

from gaitgram.spans import Span

__all__ = [
    "Applicability",
    "Code",
    "Diagnostic",
    "Fix",
    "FixMaker",
    "Severity",
    "TextEdit",
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


#: What makes a diagnostic's fixes when they are first asked for.
FixMaker = Callable[[], Iterable[Fix]]


@dataclass(frozen=True, slots=True)
class Code:
    """One kind of problem, declared once with everything said about it.

    ``summary`` is the catalogue's one line, ``help`` what to do about it (SARIF's help and the
    code's section of ``docs/diagnostics.md``), ``fix_help`` what its fixes do (Markdown; given
    exactly when ``fix`` says how safe they are). Calling a code makes a diagnostic of it.
    """

    code: str
    name: str
    severity: Severity
    summary: str
    help: str
    syntax: bool = False  # a syntax problem: the document does not say what it means
    #: How safe the fixes its diagnostics carry are; None: it has none (a code with fixes has a
    #: sample in the fix tests).
    fix: Applicability | None = None
    fix_help: str = ""
    #: The title of the editor's one fix for every diagnostic of this code, with ``{n}`` for
    #: their number; empty: the generic ``Fix all {n} GGxxx problems``.
    fix_all: str = ""
    #: What it marks does nothing (an editor shows it faded: LSP's ``Unnecessary`` tag).
    unnecessary: bool = False

    def __post_init__(self) -> None:
        if (self.fix is None) != (not self.fix_help):
            raise ValueError(f"{self.code}: fix_help is given exactly when the code has fixes")

    def __str__(self) -> str:
        return self.code

    @property
    def anchor(self) -> str:
        """The heading anchor of this code in ``docs/diagnostics.md`` (``gg201-undefined-rule``)."""
        return f"{self.code.lower()}-{self.name}"

    def __call__(
        self,
        message: str,
        span: Span,
        *,
        rule: str | None = None,
        hint: str | None = None,
        fixes: Iterable[Fix] | FixMaker = (),
        data: Mapping[str, str] | None = None,
    ) -> Diagnostic:
        """A diagnostic of this code; ``fixes`` may be a function that makes them when asked."""
        made = fixes if callable(fixes) else tuple(fixes)
        return Diagnostic(self, message, span, rule, hint, None, made, dict(data or {}))


@dataclass(frozen=True, slots=True, eq=False)
class Diagnostic:
    code: Code
    message: str
    span: Span
    rule: str | None = None
    hint: str | None = None
    severity: Severity | None = None  # None: the code's default
    #: The fixes, or what makes them when :attr:`fixes` is first read (then replaced by them).
    made_fixes: tuple[Fix, ...] | FixMaker = field(default=(), repr=False)
    #: The names the problem is about (``{"name": "bee"}`` for an undefined ``<bee>``), for
    #: programs: the message is for people and may change wording.
    data: Mapping[str, str] = field(default_factory=dict)

    @property
    def fixes(self) -> tuple[Fix, ...]:
        made = self.made_fixes
        if callable(made):
            made = tuple(made())
            object.__setattr__(self, "made_fixes", made)  # the same fixes every time: made once
        return made

    @property
    def level(self) -> Severity:
        return self.severity or self.code.severity

    @property
    def is_error(self) -> bool:
        return self.level is Severity.ERROR

    def _key(self) -> tuple[object, ...]:
        return (self.code, self.message, self.span, self.rule, self.hint, self.severity, self.fixes)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Diagnostic):
            return NotImplemented
        return self._key() == other._key() and self.data == other.data

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        return (
            f"Diagnostic(code={self.code.code}, message={self.message!r}, span={self.span!r}, "
            f"rule={self.rule!r}, hint={self.hint!r}, severity={self.severity!r}, fixes={self.fixes!r}, "
            f"data={dict(self.data)!r})"
        )

    def moved(self, delta: int) -> Diagnostic:
        """The same problem ``delta`` characters further on, its fixes' edits included."""
        made = self.made_fixes

        def shifted(fixes: Iterable[Fix]) -> tuple[Fix, ...]:
            return tuple(
                replace(fix, edits=tuple(TextEdit(e.span.shifted(delta), e.text) for e in fix.edits))
                for fix in fixes
            )

        moved_fixes: tuple[Fix, ...] | FixMaker = (
            (lambda: shifted(made())) if callable(made) else shifted(made)
        )
        return replace(self, span=self.span.shifted(delta), made_fixes=moved_fixes)
