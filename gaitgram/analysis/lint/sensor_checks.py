"""Lint checks of the names a grammar's curves read (GG508 to GG512): every name in a joint's (or
the frequency's) motion text must be ``t``, a constant, a function or a sensor of the backend, and
a sensor must be one the joint may read.

The names are found statically (:mod:`gaitgram.analysis.motion_text`), so a misspelt sensor is
reported where it is written, before any genome maps to it; without the linter it would show only
as an unusable gait in a run. Sensors come from the backends' catalogues, read without the
simulator: the declared backend's, or every installed backend's when none is declared.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from difflib import get_close_matches

from gaitgram.analysis.facts import GrammarFacts
from gaitgram.analysis.motion_text import NameUse, SensorScope, name_uses
from gaitgram.backends.sensors import Sensor
from gaitgram.language.diagnostics import Applicability, Code, Diagnostic, Fix, Severity, TextEdit
from gaitgram.language.model import FREQUENCY, Grammar
from gaitgram.motion.names import CONSTANTS, FUNCTION_DOCS, UNSUPPORTED, VARIABLE

__all__ = [
    "CODES",
    "SENSOR_IN_FREQUENCY",
    "SENSOR_NOT_IN_BACKEND",
    "SENSOR_NOT_READABLE",
    "SENSOR_WITHOUT_BACKEND",
    "UNKNOWN_MOTION_NAME",
    "motion_names",
]

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO  # noqa: E741 (short names keep the table readable)
UNSAFE = Applicability.UNSAFE

UNKNOWN_MOTION_NAME = Code(
    "GG508",
    "unknown-motion-name",
    E,
    "a name in a curve that is not t, a constant, a function or a sensor",
    "A joint's (or the frequency's) motion text may read `t`, `PI` (or `pi`), call `sin` and `cos`, "
    "and read the sensors of an installed backend; any other name makes every gait that derives it "
    "unusable. Correct the name; the hint gives the nearest known one.",
    fix=UNSAFE,
    fix_help="Replaces the name with the one it evidently misspells (offered only when one name is "
    "nearest: a case slip such as `Sin`, `time` for `t`, or a single close sensor).",
)
SENSOR_NOT_IN_BACKEND = Code(
    "GG509",
    "sensor-not-in-backend",
    E,
    "a curve reads a sensor the grammar's @backend lacks",
    "The name is a sensor of another installed backend, but the grammar's @backend does not offer it "
    "(a backend without sensors plays open-loop curves only). Use one of the backend's sensors, or "
    "the backend that has it.",
)
SENSOR_NOT_READABLE = Code(
    "GG510",
    "sensor-not-readable-by-joint",
    E,
    "a joint's curve reads a sensor its joint group cannot read",
    "A per-limb sensor (such as the horse's `load`, `contact` or `phase`) reads the limb of "
    "the joint whose curve uses it, so a joint that drives no limb (a neck joint) cannot read it. "
    "Read it only from rules that limb joints reach, or use a sensor of the whole body.",
)
SENSOR_IN_FREQUENCY = Code(
    "GG511",
    "sensor-in-frequency",
    E,
    "the @frequency rule reads a sensor",
    "A gait's cycle frequency is one constant, fixed before it walks, so the @frequency rule "
    "cannot read a sensor. Move the feedback into the joints' curves.",
)
SENSOR_WITHOUT_BACKEND = Code(
    "GG512",
    "sensor-without-backend",
    I,
    "a curve reads sensors with no @backend to check them against",
    "Without @backend, a sensor name is checked only against every installed backend's sensors, and "
    "which joint may read it is not checked. Declare the backend.",
)
CODES = (
    UNKNOWN_MOTION_NAME,
    SENSOR_NOT_IN_BACKEND,
    SENSOR_NOT_READABLE,
    SENSOR_IN_FREQUENCY,
    SENSOR_WITHOUT_BACKEND,
)

#: What a name that is not called may be beside sensors.
_READABLE = (VARIABLE, *CONSTANTS, *FUNCTION_DOCS)


def motion_names(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    if not grammar.joints and grammar.frequency is None:
        return
    uses = [use for use in name_uses(grammar, facts) if not (use.builtin and not use.called)]
    if not uses:
        return
    declared = grammar.declared.get("backend") is not None and grammar.backend is not None
    scope = SensorScope(grammar.backend if declared else None)
    sensing: list[NameUse] = []
    for use in uses:
        if use.called:
            if use.name not in FUNCTION_DOCS and not use.builtin and scope.sensor(use.name) is None:
                yield _unknown(use, sorted(FUNCTION_DOCS), called=True)
            continue
        sensor = scope.sensor(use.name)
        if sensor is None:
            others = scope.offered_by(use.name)
            if scope.backend is not None and others:
                yield _not_in_backend(use, scope, others)
            else:
                known = [
                    *_READABLE,
                    *([s.name for s in scope.sensors] if scope.backend else scope.every_sensor()),
                ]
                yield _unknown(use, sorted(set(known), key=known.index), called=False)
            continue
        sensing.append(use)
        if FREQUENCY in use.readers:
            yield SENSOR_IN_FREQUENCY(
                f"the @frequency rule reads the sensor {use.name!r} (through <{use.rule}>), but a gait's "
                "cycle frequency is a constant",
                use.span,
                rule=use.rule,
                hint="read sensors in the joints' curves; the frequency is fixed before the gait walks",
                data={"name": use.name},
            )
        barred = _not_readable(use, sensor, scope)
        if barred is not None:
            yield barred
    if sensing and not declared:
        names = list(dict.fromkeys(use.name for use in sensing))
        having = [b for b, c in scope.installed.items() if all(c.get(n) for n in names)]
        yield SENSOR_WITHOUT_BACKEND(
            f"no @backend: the sensors read ({', '.join(names)}) are not checked against one",
            sensing[0].span,
            rule=sensing[0].rule,
            hint=f"declare the backend, e.g. @backend {having[0] if having else 'NAME'}",
        )


def _not_readable(use: NameUse, sensor: Sensor, scope: SensorScope) -> Diagnostic | None:
    """GG510 if a joint that reaches ``use`` is of a group the sensor does not serve."""
    if scope.joints is None:
        return None
    barred = {}
    for reader in use.readers:
        joint = scope.joints.get(reader)
        if joint is not None and not sensor.readable_by(joint.group):
            barred[reader] = joint.group
    if not barred:
        return None
    kind = "a per-limb sensor" if sensor.per_limb else "a sensor"
    allowed = " and ".join(sorted(sensor.groups))
    body = [s.name for s in scope.sensors if not s.groups]
    return SENSOR_NOT_READABLE(
        f"{use.name!r} is {kind} that only {allowed} joints read, but {_whose(list(barred))} "
        f"({', '.join(sorted(set(barred.values())))}) reaches it through <{use.rule}>",
        use.span,
        rule=use.rule,
        hint=f"read {use.name} only in rules that {allowed} joints reach"
        + (f", or use a sensor of the whole body: {', '.join(body)}" if body else ""),
        data={"name": use.name, "joint": next(iter(barred))},
    )


def _whose(readers: Sequence[str]) -> str:
    joints = [r for r in readers if r != FREQUENCY]
    if not joints:
        return "the @frequency rule"
    shown = ", ".join(joints[:3]) + (f" and {len(joints) - 3} more" if len(joints) > 3 else "")
    return f"the curve{'s' if len(joints) > 1 else ''} of {shown}"


def _nearest(name: str, known: Sequence[str]) -> tuple[list[str], bool]:
    """Names close to ``name``, closest first, and whether the first is certainly what was meant:
    the same but for case (``PI`` and ``pi`` mean the same), ``time`` for ``t``, or the only one
    near enough."""
    same = [k for k in known if k.lower() == name.lower()]
    if same:
        return same, all(s in CONSTANTS for s in same) or len(same) == 1
    if name.lower() == "time" and VARIABLE in known:
        return [VARIABLE], True
    near = get_close_matches(name, list(known), n=3, cutoff=0.75)
    return near, len(near) == 1


def _unknown(use: NameUse, known: Sequence[str], *, called: bool) -> Diagnostic:
    close, certain = _nearest(use.name, known)
    kind = "function" if called else "name"
    if close:
        hint = f"did you mean {close[0]!r}?" + (
            "" if certain else f" (or {', '.join(map(repr, close[1:]))}?)"
        )
    elif use.name.lower() in UNSUPPORTED:
        hint = f"the language leaves {use.name} out on purpose; its functions are {', '.join(FUNCTION_DOCS)}"
    else:
        hint = f"known: {', '.join(known)}"
    return UNKNOWN_MOTION_NAME(
        f"unknown {kind} {use.name!r} in {_whose(use.readers)} (in <{use.rule}>)",
        use.span,
        rule=use.rule,
        hint=hint,
        fixes=_replacement(use, close[0]) if certain else (),
        data={"name": use.name},
    )


def _not_in_backend(use: NameUse, scope: SensorScope, others: list[str]) -> Diagnostic:
    own = sorted(scope.sensors.names)
    close, _ = _nearest(use.name, own)
    if close:
        hint = f"did you mean {close[0]!r}?"
    elif own:
        hint = f"its sensors: {', '.join(own)}"
    else:
        hint = f"{scope.backend} senses nothing (open-loop curves only); closed loops: @backend {others[0]}"
    return SENSOR_NOT_IN_BACKEND(
        f"backend {scope.backend} has no sensor {use.name!r} (read by {_whose(use.readers)}); "
        f"{', '.join(others)} has one",
        use.span,
        rule=use.rule,
        hint=hint,
        data={"name": use.name, "backend": scope.backend or ""},
    )


def _replacement(use: NameUse, name: str) -> tuple[Fix, ...]:
    if use.span.end - use.span.start != len(use.name):  # spelt through an escape: not the name's span
        return ()
    return (Fix(f"Replace with {name}", (TextEdit(use.span, name),), UNSAFE, preferred=True),)
