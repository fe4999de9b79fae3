"""The annotations gaitgram knows, and how their arguments are checked.

Annotations share one syntax (``@name positional key=value ...``), so adding one means
adding an :class:`AnnotationKind` to :data:`ANNOTATIONS` and, if it sets anything, its
reader in :mod:`gaitgram.language.meaning`; the parser does not change. What a parameter
names (a rule, a backend, a joint) is its :attr:`Parameter.refers`: the linter, navigation,
rename, completion and hover read that, never an annotation's name.
"""

from __future__ import annotations

from dataclasses import dataclass
from difflib import get_close_matches
from enum import StrEnum

from gaitgram.language.diagnostics import Applicability, Code, Diagnostic, Fix, Severity, TextEdit
from gaitgram.language.model import Annotation, Argument, ArgumentValue, Interval, Name, RuleRef
from gaitgram.language.numbers import NUMBER_LIMITS, number_problem, read_number
from gaitgram.language.source import Span

__all__ = [
    "ANNOTATIONS",
    "BAD_ARGUMENTS",
    "CODES",
    "UNKNOWN_ANNOTATION",
    "AnnotationKind",
    "CheckedAnnotation",
    "Parameter",
    "Refers",
    "Target",
    "ValueType",
    "check_annotation",
    "parameter_of",
    "rule_references",
    "unreadable_argument",
]

UNKNOWN_ANNOTATION = Code(
    "GG401",
    "unknown-annotation",
    Severity.WARNING,
    "an annotation gaitgram does not know",
    "gaitgram does not know this annotation and ignores it. Correct the name: @start, @backend, "
    "@units, @define, @joint or @frequency.",
    fix=Applicability.UNSAFE,
    fix_help="The nearest known annotation.",
)
BAD_ARGUMENTS = Code(
    "GG402",
    "bad-annotation-arguments",
    Severity.ERROR,
    "an annotation with missing, extra or ill-typed arguments",
    "An annotation has a missing, extra or ill-typed argument. The message says which; hover "
    "over the annotation for its usage.",
)
CODES = (UNKNOWN_ANNOTATION, BAD_ARGUMENTS)


class Target(StrEnum):
    FILE = "file"  # applies to the whole grammar, wherever it is written
    RULE = "rule"  # applies to the rule written after it


class ValueType(StrEnum):
    NAME = "name"
    RULE = "rule"
    INT = "int"
    NUMBER = "number"
    INTERVAL = "interval"  # lo..hi, both ends given
    GENERATIONS = "generations"  # N (from N on), N..M, or N..


class Refers(StrEnum):
    """What a parameter's value names, so tools can check it, offer it, explain it and rename it."""

    RULE = "rule"  # a rule of this grammar: checked defined, found by references, renamed with it
    BACKEND = "backend"  # an installed fitness backend
    JOINT = "joint"  # a joint of the grammar's backend
    JOINT_LIMITS = "joint-limits"  # a joint's angle range (the backend's is offered)
    JOINT_FREEDOM = "joint-freedom"  # a joint's freedom schedule (the paper's Table 3 is offered)


@dataclass(frozen=True, slots=True)
class Parameter:
    name: str
    type: ValueType
    help: str
    positional: bool = False
    required: bool = False
    choices: tuple[str, ...] = ()
    refers: Refers | None = None


@dataclass(frozen=True, slots=True)
class AnnotationKind:
    name: str
    target: Target
    summary: str
    example: str
    parameters: tuple[Parameter, ...] = ()
    repeatable: bool = False
    any_keywords: ValueType | None = None  # accepts key=value pairs of this type

    @property
    def positional(self) -> tuple[Parameter, ...]:
        return tuple(p for p in self.parameters if p.positional)

    @property
    def keywords(self) -> dict[str, Parameter]:
        return {p.name: p for p in self.parameters if not p.positional}


ANNOTATIONS: dict[str, AnnotationKind] = {
    kind.name: kind
    for kind in (
        AnnotationKind(
            "start",
            Target.FILE,
            "The rule derivations start from (default: the first rule).",
            "@start <prog>",
            (
                Parameter(
                    "rule",
                    ValueType.RULE,
                    "the start rule",
                    positional=True,
                    required=True,
                    refers=Refers.RULE,
                ),
            ),
        ),
        AnnotationKind(
            "backend",
            Target.FILE,
            "The fitness backend whose joints this grammar drives; @joint names are checked against it.",
            "@backend mujoco-horse",
            (
                Parameter(
                    "backend",
                    ValueType.NAME,
                    "an installed backend",
                    positional=True,
                    required=True,
                    refers=Refers.BACKEND,
                ),
            ),
        ),
        AnnotationKind(
            "units",
            Target.FILE,
            "The unit of joint angles in phenotypes (default: deg).",
            "@units deg",
            (
                Parameter(
                    "units",
                    ValueType.NAME,
                    "deg or rad",
                    positional=True,
                    required=True,
                    choices=("deg", "rad"),
                ),
            ),
        ),
        AnnotationKind(
            "define",
            Target.FILE,
            "Named sizes for GE_RANGE:name, as PonyGE2 takes them from its parameters.",
            "@define dataset_n_vars=5",
            repeatable=True,
            any_keywords=ValueType.INT,
        ),
        AnnotationKind(
            "joint",
            Target.RULE,
            "The next rule derives the angle curve of this backend joint.",
            "@joint elbow_fore limits=-35..60 free=11",
            (
                Parameter(
                    "joint",
                    ValueType.NAME,
                    "a joint of the backend",
                    positional=True,
                    required=True,
                    refers=Refers.JOINT,
                ),
                Parameter(
                    "limits",
                    ValueType.INTERVAL,
                    "the angle range the curve should stay in, lo..hi",
                    refers=Refers.JOINT_LIMITS,
                ),
                Parameter(
                    "free",
                    ValueType.GENERATIONS,
                    "generations in which the joint may move: N (from N on), N..M or N..; "
                    "before that it holds its neutral angle",
                    refers=Refers.JOINT_FREEDOM,
                ),
            ),
        ),
        AnnotationKind(
            "frequency",
            Target.RULE,
            "The next rule derives the gait cycle's frequency in Hz (a constant expression), "
            "which then evolves instead of being imposed by the backend.",
            "@frequency limits=0.6..1.9",
            (Parameter("limits", ValueType.INTERVAL, "the frequencies (Hz) a gait may have, lo..hi"),),
        ),
    )
}


@dataclass(frozen=True, slots=True)
class CheckedAnnotation:
    """An annotation whose arguments were checked: ``values`` maps parameter names to values."""

    annotation: Annotation
    kind: AnnotationKind | None
    values: dict[str, ArgumentValue]


def parameter_of(annotation: Annotation, argument: Argument) -> Parameter | None:
    """The parameter an argument of ``annotation`` gives, or None (unknown annotation or key,
    one positional too many)."""
    kind = ANNOTATIONS.get(annotation.name)
    if kind is None:
        return None
    if argument.key is not None:
        return kind.keywords.get(argument.key)
    index = [a for a in annotation.arguments if a.key is None].index(argument)
    return kind.positional[index] if index < len(kind.positional) else None


def rule_references(annotation: Annotation) -> list[tuple[str, Span]]:
    """The rules an annotation names (such as ``@start <prog>``), each with the span of its
    ``<name>``: what the linter checks, and navigation finds and renames."""
    found = []
    for argument in annotation.arguments:
        value = argument.value
        if isinstance(value, RuleRef) and argument.raw.split("=", 1)[-1] == f"<{value.name}>":
            parameter = parameter_of(annotation, argument)
            if parameter is not None and parameter.refers is Refers.RULE:
                found.append((value.name, Span(argument.span.end - len(value.name) - 2, argument.span.end)))
    return found


def check_annotation(annotation: Annotation, problems: list[Diagnostic]) -> CheckedAnnotation:
    """Check arguments against the kind's parameters, appending problems."""
    kind = ANNOTATIONS.get(annotation.name)
    if kind is None:
        known = ", ".join(f"@{n}" for n in ANNOTATIONS)
        nearest = get_close_matches(annotation.name, list(ANNOTATIONS), n=1, cutoff=0.6)
        problems.append(
            UNKNOWN_ANNOTATION(
                f"unknown annotation @{annotation.name}",
                annotation.name_span,
                hint=f"did you mean @{nearest[0]}?" if nearest else f"known annotations: {known}",
                fixes=[
                    Fix(f"Replace with @{n}", (TextEdit(annotation.name_span, f"@{n}"),), preferred=True)
                    for n in nearest
                ],
                data={"name": annotation.name},
            )
        )
        return CheckedAnnotation(annotation, None, {})

    values: dict[str, ArgumentValue] = {}
    positional = list(kind.positional)
    usage = f"usage: {kind.example}"
    for argument in annotation.arguments:
        if argument.key is None:
            if not positional:
                problems.append(_bad(argument, f"@{kind.name} takes no more positional arguments", usage))
                continue
            parameter = positional.pop(0)
        else:
            parameter = kind.keywords.get(argument.key)
            if parameter is None and kind.any_keywords is not None:
                parameter = Parameter(argument.key, kind.any_keywords, "")
            if parameter is None:
                names = ", ".join(kind.keywords) or "none"
                problems.append(
                    _bad(
                        argument, f"@{kind.name} has no argument {argument.key!r} (it takes: {names})", usage
                    )
                )
                continue
            if parameter.name in values:
                problems.append(_bad(argument, f"{parameter.name!r} is given twice", usage))
                continue
        value = _convert(argument, parameter, problems, usage)
        if value is not None:
            values[parameter.name] = value

    for parameter in positional:
        if parameter.required:
            problems.append(
                BAD_ARGUMENTS(
                    f"@{kind.name} needs {parameter.help}",
                    annotation.span,
                    hint=usage,
                )
            )
    return CheckedAnnotation(annotation, kind, values)


def _convert(
    argument: Argument, parameter: Parameter, problems: list[Diagnostic], usage: str
) -> ArgumentValue | None:
    value = argument.value
    wanted = parameter.type
    label = f"{parameter.name!r}" if argument.key else parameter.help

    def fail(expected: str) -> None:
        shown = "nothing" if value is None else repr(argument.raw.split("=", 1)[-1])
        problems.append(_bad(argument, f"{label} must be {expected}, not {shown}", usage))

    numeric = (ValueType.INT, ValueType.NUMBER, ValueType.INTERVAL, ValueType.GENERATIONS)
    if wanted in numeric and isinstance(value, int | float | Interval):
        # Numbers are checked as written, exactly: as ints or doubles, 1e400 would be inf,
        # 1e-400 would be 0 and 0.10000000000000001 would be 0.1.
        written = argument.raw.split("=", 1)[1] if argument.key is not None else argument.raw
        for text in (t for t in written.split("..") if t):
            reason = number_problem(read_number(text))
            if reason is not None:
                shown = text if len(text) <= 30 else f"{text[:24]}…{text[-5:]}"
                problems.append(_bad(argument, f"{label}: {shown} {reason}", NUMBER_LIMITS))
                return None

    if wanted is ValueType.NAME:
        if not isinstance(value, Name):
            fail("a name")
            return None
        if parameter.choices and value.text not in parameter.choices:
            fail(" or ".join(parameter.choices))
            return None
        return value
    if wanted is ValueType.RULE:
        if isinstance(value, RuleRef):
            return value
        fail("a rule such as <prog>")
        return None
    if wanted is ValueType.INT:
        if isinstance(value, int) and not isinstance(value, bool) and value >= 0:
            return value
        fail("a whole number ≥ 0")
        return None
    if wanted is ValueType.NUMBER:
        if isinstance(value, int | float):
            return value
        fail("a number")
        return None
    if wanted is ValueType.INTERVAL:
        if isinstance(value, Interval) and value.low is not None and value.high is not None:
            if value.low > value.high:
                problems.append(
                    _bad(
                        argument,
                        f"{label} is empty: {value.low:g} is above {value.high:g}",
                        "write the lower limit first",
                    )
                )
                return None
            return value
        fail("an interval lo..hi")
        return None
    if wanted is ValueType.GENERATIONS:
        # Whole numbers are ints (``1e3`` and ``10.0`` too); a float is never a whole number.
        if isinstance(value, int) and value >= 0:
            return Interval(value, None)
        if isinstance(value, Interval):
            low = 0 if value.low is None else value.low
            whole = all(x is None or (isinstance(x, int) and x >= 0) for x in (value.low, value.high))
            if whole and (value.high is None or low <= value.high):
                return Interval(int(low), None if value.high is None else int(value.high))
        fail("a generation N, or generations N..M or N..")
        return None
    raise AssertionError(wanted)  # pragma: no cover


def _bad(argument: Argument, message: str, hint: str | None) -> Diagnostic:
    return BAD_ARGUMENTS(message, argument.span, hint=hint)


def unreadable_argument(raw: str, span: Span) -> Diagnostic:
    """An argument that is no value at all (the grammar's ``bad_argument``)."""
    return BAD_ARGUMENTS(
        f"cannot read annotation argument {raw!r}",
        span,
        hint="arguments are names, numbers, <rules>, 'strings', lo..hi intervals, or key=value",
    )
