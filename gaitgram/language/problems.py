"""The problems the reader finds in a document's text, each in one place.

Every code here is declared (what it means, what to do about it, what its fix does) beside the
function that reports it: its message, hint and fixes. The builder (:mod:`~gaitgram.language.
builder`) calls these where it meets the problem as it reads the text; the catalogue
(:mod:`gaitgram.analysis.diagnostic_codes`) lists the declarations for the docs, SARIF and editors.
Problems of ranges, annotations and the document's settings are declared with their readers
(:mod:`~gaitgram.language.ranges`, :mod:`~gaitgram.language.look_alikes`,
:mod:`~gaitgram.language.annotations`, :mod:`~gaitgram.language.meaning`).
"""

from __future__ import annotations

import re

from gaitgram.language.diagnostics import Applicability, Code, Diagnostic, Fix, Severity, TextEdit
from gaitgram.language.edits import deletion_fix
from gaitgram.language.escapes import EscapeError
from gaitgram.language.model import Annotation
from gaitgram.language.source import SourceText, Span

__all__ = [
    "BAD_GE_RANGE",
    "CODES",
    "COMMENT_SPLITS_ALTERNATIVE",
    "DANGLING_ANNOTATION",
    "EMPTY_ALTERNATIVE",
    "EMPTY_RULE",
    "INVALID_ESCAPE",
    "STRAY_TEXT",
    "UNDEFINED_DEFINE",
    "UNENCODABLE_TEXT",
    "UNTERMINATED_STRING",
]

E, W = Severity.ERROR, Severity.WARNING
SAFE, UNSAFE = Applicability.SAFE, Applicability.UNSAFE

# ---- GG101 stray-text --------------------------------------------------------------------

STRAY_TEXT = Code(
    "GG101",
    "stray-text",
    E,
    "text outside any rule",
    "Text between rules belongs to no rule. Start a rule with <name> ::=, or make the text a comment with #.",
    syntax=True,
)


def stray_text(span: Span, shown: str) -> Diagnostic:
    """A run of text outside any rule (one per line); ``shown`` is its text, stripped."""
    return STRAY_TEXT(
        f"text outside any rule: {shorten(shown)!r}",
        span,
        hint="rules are written <name> ::= alternatives; comments start with #",
    )


# ---- GG102 unterminated-string -------------------------------------------------------------

UNTERMINATED_STRING = Code(
    "GG102",
    "unterminated-string",
    E,
    "a quoted terminal has no closing quote",
    "A quoted terminal ends at the end of its line. Add the closing quote; the fix adds it at the "
    "end of the line, which is where the text already ends.",
    syntax=True,
    fix=SAFE,
    fix_help="Closes the string at the end of its line, where its text already ends, so it reads the same.",
)


def unterminated_string(raw: str, span: Span, rule: str) -> Diagnostic:
    """A string with no closing quote on its line: ``raw`` is its text, which runs to the line's end."""
    # The text already runs to the end of the line, so a quote there keeps its meaning.
    end = Span(span.end, span.end)
    close = Fix(f"Close the string with {raw[0]}", (TextEdit(end, raw[0]),), SAFE, True)
    return UNTERMINATED_STRING(
        "unterminated string: no closing quote on this line",
        span,
        rule=rule,
        hint=f"add the closing {raw[0]} (a string cannot span lines)",
        fixes=[close],
    )


# ---- GG103 invalid-escape ------------------------------------------------------------------

INVALID_ESCAPE = Code(
    "GG103",
    "invalid-escape",
    E,
    "a backslash escape that cannot be decoded",
    "A backslash starts an escape (\\n, \\t, \\xHH, \\uHHHH, \\UHHHHHHHH, \\N{NAME}). "
    "Write \\\\ for a backslash itself, and a character outside the Basic Multilingual Plane as "
    "itself or as one \\U escape, never as a UTF-16 surrogate pair.",
    syntax=True,
    fix=UNSAFE,
    fix_help="Writes the `\\U` escape a UTF-16 surrogate pair meant (preferred); or escapes the backslash, "
    "which keeps the text that was read.",
)


def invalid_escape(source: SourceText, base: int, error: EscapeError) -> Diagnostic:
    """An escape that cannot be decoded, ``error`` found in text that starts at offset ``base``."""
    span = Span(base + error.start, base + error.end)
    escape = source.slice(span)
    # A bad escape is read as its own text, so doubling its backslash keeps the text.
    literal = Fix(
        f"Escape the backslash: \\{escape}",
        (TextEdit(Span(span.start, span.start), "\\"),),
        UNSAFE,
        error.replacement is None,
    )
    fixes = [literal]
    if error.replacement is not None:
        fixes.insert(0, Fix(f"Write {error.replacement}", (TextEdit(span, error.replacement),), UNSAFE, True))
    return INVALID_ESCAPE(
        error.message,
        span,
        hint="write \\\\ for a backslash; escapes are \\n \\t \\xHH \\uHHHH \\N{NAME}",
        fixes=fixes,
        data={"escape": escape},
    )


# ---- GG105 bad-ge-range --------------------------------------------------------------------

BAD_GE_RANGE = Code(
    "GG105",
    "bad-ge-range",
    E,
    "a GE_RANGE that is not a whole alternative or has no size",
    "GE_RANGE:n (or GE_RANGE:name, with @define name=n) must be an alternative on its own, with a "
    "size from 1 to 100,000.",
    syntax=True,
)


def ge_range_not_whole(raw: str, span: Span, rule: str) -> Diagnostic:
    return BAD_GE_RANGE(
        f"{raw} must be a whole alternative",
        span,
        rule=rule,
        hint="put it alone between | separators, or use a typed range such as int[0..9]",
    )


def ge_range_unreadable(raw: str, span: Span, rule: str) -> Diagnostic:
    return BAD_GE_RANGE(
        f"{raw}: the size must be a number or a name", span, rule=rule, hint="for example GE_RANGE:10"
    )


def ge_range_bad_size(raw: str, size: int, most: int, span: Span, rule: str) -> Diagnostic:
    """A size outside 1..``most``; ``size`` may be any int (a ``--define``)."""
    # str() of an int with thousands of digits raises.
    shown = f"has size {size}" if abs(size) < 10**15 else "is too large" if size > 0 else "is negative"
    return BAD_GE_RANGE(f"{shorten(raw)} {shown}; its size must be between 1 and {most:,}", span, rule=rule)


# ---- GG106 empty-alternative ---------------------------------------------------------------

EMPTY_ALTERNATIVE = Code(
    "GG106",
    "empty-alternative",
    W,
    "an empty alternative, which PonyGE2 drops",
    "An alternative with nothing in it is dropped, by PonyGE2 and by gaitgram. Delete the extra |, "
    "or write '' for the empty string.",
    fix=SAFE,
    fix_help="Deletes the extra `|`.",
)


def empty_alternative(text: str, pipe: Span, rule: str) -> Diagnostic:
    """An alternative with nothing in it, next to the ``|`` at ``pipe`` (in ``text``, the document)."""
    gone = _pipe_removal(text, pipe.start, pipe.end)
    fixes = [] if gone is None else [Fix("Delete the extra |", (TextEdit(gone, ""),), SAFE, True)]
    return EMPTY_ALTERNATIVE(
        "empty alternative: PonyGE2 drops it, and so does gaitgram",
        pipe,
        rule=rule,
        hint="delete the extra |, or write '' for an empty string",
        fixes=fixes,
    )


_AT = re.compile(r"[ \t]*@")


def _pipe_removal(text: str, start: int, end: int) -> Span | None:
    """A ``|`` with the spaces before it on its line, or else those after it; None if what
    follows would then start its line with ``@`` and so become an annotation."""
    blank = start  # only the blanks before it are read, never the whole line
    while blank > 0 and text[blank - 1] != "\n" and text[blank - 1].isspace():
        blank -= 1
    if (blank == 0 or text[blank - 1] == "\n") and _AT.match(text, end):
        return None
    before = start
    while before > 0 and text[before - 1] in " \t":
        before -= 1
    if before < start:
        return Span(before, end)
    after = end
    while after < len(text) and text[after] in " \t":
        after += 1
    return Span(start, after)


# ---- GG107 comment-splits-alternative ------------------------------------------------------

COMMENT_SPLITS_ALTERNATIVE = Code(
    "GG107",
    "comment-splits-alternative",
    W,
    "text after a comment starts a new alternative",
    "A comment ends an alternative, so text on the next line starts a new one even without |. "
    "Write the | to say so.",
    fix=SAFE,
    fix_help="Writes the `|` before the new alternative; the grammar reads the same.",
)


def comment_splits_alternative(where: Span, rule: str) -> Diagnostic:
    """The alternative at ``where`` starts after a comment, with no ``|`` before it."""
    at = Span(where.start, where.start)
    return COMMENT_SPLITS_ALTERNATIVE(
        "this line starts a new alternative, because a comment ended the one before it",
        where,
        rule=rule,
        hint="PonyGE2 reads it that way too; put | before it to say so",
        fixes=[Fix("Write the | before it", (TextEdit(at, "| "),), SAFE, True)],
    )


# ---- GG108 empty-rule ----------------------------------------------------------------------

EMPTY_RULE = Code(
    "GG108",
    "empty-rule",
    E,
    "a rule with no alternatives",
    "Every rule needs at least one alternative; '' derives the empty string.",
    fix=UNSAFE,
    fix_help="Makes the rule derive the empty string, `''`.",
)


def empty_rule(name: str, name_span: Span, end: int) -> Diagnostic:
    """Rule ``<name>`` has no alternatives; its text ends at ``end``."""
    empty = Fix("Derive the empty string ''", (TextEdit(Span(end, end), " ''"),), UNSAFE, True)
    return EMPTY_RULE(
        f"<{name}> has no alternatives",
        name_span,
        rule=name,
        hint=f"write <{name}> ::= a | b, or '' for the empty string",
        fixes=[empty],
        data={"name": name},
    )


# ---- GG109 unencodable-text ----------------------------------------------------------------

UNENCODABLE_TEXT = Code(
    "GG109",
    "unencodable-text",
    E,
    "text that UTF-8 cannot encode (a lone surrogate)",
    "Text given to the library or an editor holds UTF-16 surrogates, which no file can hold and "
    "UTF-8 cannot encode. Write the character itself.",
    syntax=True,
    fix=UNSAFE,
    fix_help="Joins UTF-16 surrogate pairs into the characters they encode.",
)

#: UTF-16 surrogates: code points that are not characters and that UTF-8 cannot encode. Decoding
#: a file never yields one; a str from the library API or an editor can hold them.
_SURROGATES = re.compile("[\ud800-\udfff]+")


def unencodable_text(source: SourceText, start: int = 0, end: int | None = None) -> list[Diagnostic]:
    """GG109 for each run of text (from ``start`` to ``end``) that cannot be encoded as UTF-8, which
    every command that writes the grammar, its phenotypes or its tables out would otherwise fail
    on later."""
    text = source.text
    end = len(text) if end is None else end
    if (text if start == 0 and end == len(text) else text[start:end]).isascii():
        return []
    problems = []
    for match in _SURROGATES.finditer(text, start, end):
        run = match.group()
        points = ", ".join(f"U+{ord(c):04X}" for c in run[:4]) + (", ..." if len(run) > 4 else "")
        what = "a lone UTF-16 surrogate, not a character" if len(run) == 1 else "UTF-16 surrogates"
        span = Span(match.start(), match.end())
        fixes = []
        try:  # pairs of a high and a low surrogate: the characters UTF-16 meant
            meant = run.encode("utf-16-le", "surrogatepass").decode("utf-16-le")
        except UnicodeDecodeError:
            meant = None
        if meant is not None:
            shown = ", ".join(f"U+{ord(c):04X}" for c in meant[:4]) + (", ..." if len(meant) > 4 else "")
            title = f"Join the surrogate pairs into {shown}"
            fixes.append(Fix(title, (TextEdit(span, meant),), UNSAFE, preferred=True))
        problems.append(
            UNENCODABLE_TEXT(
                f"text that cannot be encoded as UTF-8: {points} ({what})",
                span,
                hint="the text was decoded wrongly somewhere; write a character outside the Basic "
                "Multilingual Plane as itself, or as an escape such as \\U0001F600",
                fixes=fixes,
            )
        )
    return problems


# ---- GG403 dangling-annotation -------------------------------------------------------------

DANGLING_ANNOTATION = Code(
    "GG403",
    "dangling-annotation",
    E,
    "a rule annotation with no rule after it",
    "A rule annotation (@joint, @frequency) applies to the rule written after it, and none "
    "follows. Move it above its rule, or delete it.",
    fix=UNSAFE,
    fix_help="Deletes the annotation.",
)


def dangling_annotation(text: SourceText, annotation: Annotation) -> Diagnostic:
    return DANGLING_ANNOTATION(
        f"@{annotation.name} annotates the rule after it, but no rule follows",
        annotation.span,
        hint="move it above the rule it is about, or delete it",
        fixes=[deletion_fix(text, annotation.span, "Delete it")],
        data={"annotation": annotation.name},
    )


# ---- GG405 undefined-define ----------------------------------------------------------------

UNDEFINED_DEFINE = Code(
    "GG405",
    "undefined-define",
    E,
    "a GE_RANGE name that no @define or --define gives",
    "GE_RANGE:name needs a value for name: add @define name=N, or pass --define name=N.",
)


def undefined_define(name: str, span: Span, rule: str) -> Diagnostic:
    return UNDEFINED_DEFINE(
        f"GE_RANGE:{name} needs a value for {name!r}",
        span,
        rule=rule,
        hint=f"add @define {name}=N at the top, or pass --define {name}=N",
    )


def shorten(text: str, limit: int = 40) -> str:
    return text if len(text) <= limit else text[: limit - 1] + "…"


CODES = (
    STRAY_TEXT,
    UNTERMINATED_STRING,
    INVALID_ESCAPE,
    BAD_GE_RANGE,
    EMPTY_ALTERNATIVE,
    COMMENT_SPLITS_ALTERNATIVE,
    EMPTY_RULE,
    UNENCODABLE_TEXT,
    DANGLING_ANNOTATION,
    UNDEFINED_DEFINE,
)
