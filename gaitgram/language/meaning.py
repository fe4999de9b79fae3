"""What a grammar's annotations mean: read here, once, and nowhere else.

:mod:`gaitgram.language.annotations` says how each annotation is written and checks its
arguments; this module turns the checked annotations into the grammar's settings. The
builder and the incremental parser call it; the linter, the mapper and the editor features
read what it produced (``Grammar.start``, ``.backend``, ``.units``, ``.defines``,
``.joints``, ``.frequency`` and ``.declared``).

Reading happens at two scopes, so an incremental parse can keep a rule's reading while the
document changes around it:

* **rule scope** (:func:`read_rule`): what a rule's own annotations say, which nothing
  outside the rule changes: its ``@joint`` (one per rule, GG404 for more);
* **document scope** (:func:`read_document`): what depends on the whole text: the one
  ``@start``/``@backend``/``@units`` (the first counts, GG404 for repeats), the ``@define``
  values, the one ``@frequency`` rule (GG404 for a second one or one on a joint's rule),
  and GG207 for a grammar with no rules.

Adding an annotation is an entry in ``annotations.ANNOTATIONS`` and, if it sets anything,
an entry in :data:`FILE_SETTINGS` or a few lines in one of the two readers.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

from gaitgram.language.annotations import ANNOTATIONS, CheckedAnnotation, Target, check_annotation
from gaitgram.language.diagnostics import Applicability, Code, Diagnostic, Severity
from gaitgram.language.edits import deletion_fix
from gaitgram.language.model import (
    Annotation,
    ArgumentValue,
    FrequencyDecl,
    Interval,
    JointDecl,
    Name,
    Rule,
    RuleRef,
)
from gaitgram.language.source import Span

__all__ = [
    "CODES",
    "FILE_SETTINGS",
    "NO_RULES",
    "REPEATED_ANNOTATION",
    "DocumentSettings",
    "FileSetting",
    "read_defines",
    "read_document",
    "read_rule",
]

REPEATED_ANNOTATION = Code(
    "GG404",
    "repeated-annotation",
    Severity.ERROR,
    "an annotation that may appear once, given twice",
    "This annotation may be given once (in a file, or on a rule); the first one counts. Delete "
    "the extra one.",
    fix=Applicability.UNSAFE,
    fix_help="Deletes the extra annotation.",
)
NO_RULES = Code(
    "GG207",
    "no-rules",
    Severity.ERROR,
    "the document defines no rule",
    "A grammar needs at least one rule, <name> ::= alternatives.",
)
CODES = (NO_RULES, REPEATED_ANNOTATION)


@dataclass(frozen=True, slots=True)
class FileSetting:
    """A file annotation that sets one value of the grammar: the first one written counts."""

    read: Callable[[ArgumentValue], str | None]
    default: str | None = None


#: The file annotations that set one value each, by annotation name.
FILE_SETTINGS: dict[str, FileSetting] = {
    "start": FileSetting(lambda value: value.name if isinstance(value, RuleRef) else None),
    "backend": FileSetting(lambda value: value.text if isinstance(value, Name) else None),
    "units": FileSetting(lambda value: value.text if isinstance(value, Name) else None, "deg"),
}


@dataclass(frozen=True, slots=True)
class DocumentSettings:
    """What the whole document's annotations set."""

    #: The value of each :data:`FILE_SETTINGS` entry (its default if none is written).
    values: dict[str, str | None]
    #: The annotation that counts for each file setting that is written.
    declared: dict[str, Annotation]
    frequency: FrequencyDecl | None
    problems: list[Diagnostic]


def read_defines(checked: Iterable[CheckedAnnotation]) -> dict[str, int]:
    """The ``@define`` values, a later one replacing an earlier one of the same name."""
    defines: dict[str, int] = {}
    for c in checked:
        if c.annotation.name == "define":
            defines.update((key, value) for key, value in c.values.items() if isinstance(value, int))
    return defines


def read_rule(
    text: str, rule: Rule, checked: Sequence[CheckedAnnotation]
) -> tuple[JointDecl | None, list[Diagnostic]]:
    """What a rule's annotations (checked, in order) declare about that rule alone."""
    problems: list[Diagnostic] = []
    joints = [c for c in checked if c.annotation.name == "joint"]
    for extra in joints[1:]:
        problems.append(
            REPEATED_ANNOTATION(
                f"<{rule.name}> has more than one @joint",
                extra.annotation.span,
                rule=rule.name,
                hint="a rule derives one joint's curve; give each joint its own rule",
                fixes=[deletion_fix(text, extra.annotation.span, "Delete the extra @joint")],
                data={"annotation": "joint"},
            )
        )
    if not joints or not isinstance(name := joints[0].values.get("joint"), Name):
        return None, problems
    values = joints[0].values
    limits, free = values.get("limits"), values.get("free")
    return JointDecl(
        joint=name.text,
        rule=rule.name,
        limits=(limits.low, limits.high) if isinstance(limits, Interval) else None,  # type: ignore[arg-type]
        free=(int(free.low or 0), None if free.high is None else int(free.high))
        if isinstance(free, Interval)
        else None,
        span=joints[0].annotation.span,
    ), problems


def read_document(
    text: str,
    rules: Sequence[Rule],
    annotations: Iterable[Annotation],
    joints: Sequence[JointDecl],
    *,
    has_problems: bool,
) -> DocumentSettings:
    """What the document's annotations set together. Arguments were checked (and reported)
    when each annotation was read; they are checked again here silently."""
    problems: list[Diagnostic] = []
    values: dict[str, str | None] = {name: setting.default for name, setting in FILE_SETTINGS.items()}
    declared: dict[str, Annotation] = {}
    for annotation in annotations:
        setting = FILE_SETTINGS.get(annotation.name)
        kind = ANNOTATIONS.get(annotation.name)
        if setting is None or kind is None or kind.target is not Target.FILE:
            continue
        name = annotation.name
        if name in declared:
            problems.append(
                REPEATED_ANNOTATION(
                    f"@{name} is given more than once; the first one counts",
                    annotation.span,
                    hint="delete the extra one",
                    fixes=[deletion_fix(text, annotation.span, f"Delete the extra @{name}")],
                    data={"annotation": name},
                )
            )
            continue
        declared[name] = annotation
        value = next(iter(check_annotation(annotation, []).values.values()), None)
        values[name] = setting.read(value) if value is not None else None
        if values[name] is None:
            values[name] = setting.default
    frequency = _frequency(text, rules, joints, problems)
    if not rules and not has_problems and not problems:
        problems.append(
            NO_RULES(
                "no rules: a grammar needs at least one <name> ::= ... rule",
                Span(0, 0),
                hint="for example: <prog> ::= x | y",
            )
        )
    return DocumentSettings(values, declared, frequency, problems)


def _frequency(
    text: str, rules: Sequence[Rule], joints: Sequence[JointDecl], problems: list[Diagnostic]
) -> FrequencyDecl | None:
    """The grammar's one ``@frequency`` rule, if any: a second one, or one on a joint's rule, is
    GG404. Document scope, because which rules drive joints is known only for the whole text."""
    found: FrequencyDecl | None = None
    joint_rules = {j.rule for j in joints}
    for rule in rules:
        for annotation in (a for a in rule.annotations if a.name == "frequency"):
            hint = "one rule derives the cycle's frequency; delete the extra @frequency"
            if rule.name in joint_rules:
                message = f"<{rule.name}> derives a joint's curve, so it cannot derive the frequency too"
                hint = (
                    "give the frequency a rule of its own, such as <frequency> ::= float[0.6..1.9 step 0.1]"
                )
            elif found is not None:
                message = f"@frequency is given more than once; <{found.rule}> derives the frequency"
            else:
                limits = check_annotation(annotation, []).values.get("limits")
                found = FrequencyDecl(
                    rule=rule.name,
                    limits=(float(limits.low), float(limits.high))  # type: ignore[arg-type]
                    if isinstance(limits, Interval)
                    else None,
                    span=annotation.span,
                )
                continue
            problems.append(
                REPEATED_ANNOTATION(
                    message,
                    annotation.span,
                    rule=rule.name,
                    hint=hint,
                    fixes=[deletion_fix(text, annotation.span, "Delete this @frequency")],
                    data={"annotation": "frequency"},
                )
            )
    return found
