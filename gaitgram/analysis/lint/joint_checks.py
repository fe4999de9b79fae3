"""Lint checks of a grammar's joints against its backend (GG5xx).

Each code is declared here with what it means, what to do about it and what its fixes do, beside
the check that finds it. The backend is read through its catalogue only (the joints it has and
their limits), which loads without the simulator.
"""

from __future__ import annotations

from collections.abc import Iterator
from difflib import get_close_matches
from types import ModuleType

from gaitgram.analysis.facts import INFINITE, GrammarFacts, Occurrences, derived_exactly_once
from gaitgram.language.diagnostics import Applicability, Code, Diagnostic, Fix, Severity, TextEdit
from gaitgram.language.model import Grammar

__all__ = [
    "CODES",
    "DUPLICATE_JOINT",
    "JOINT_NOT_DERIVED_ONCE",
    "JOINT_WITHOUT_BACKEND",
    "JOINT_WITHOUT_CURVE",
    "LIMITS_EXCEED_BACKEND",
    "UNKNOWN_BACKEND",
    "UNKNOWN_JOINT",
    "joints",
    "joints_derived_once",
]

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO  # noqa: E741 (short names keep the table readable)
UNSAFE = Applicability.UNSAFE

UNKNOWN_BACKEND = Code(
    "GG501",
    "unknown-backend",
    E,
    "@backend names a backend that is not installed",
    "@backend names a backend that is not installed (or fails to load). Correct the name, or "
    "install the plug-in that provides it.",
    fix=UNSAFE,
    fix_help="The nearest installed backend.",
)
UNKNOWN_JOINT = Code(
    "GG502",
    "unknown-joint",
    E,
    "@joint names a joint the backend lacks",
    "@joint names a joint the backend does not have. Correct the name; the message lists the nearest one.",
    fix=UNSAFE,
    fix_help="The nearest joint of the backend.",
)
JOINT_WITHOUT_CURVE = Code(
    "GG503",
    "joint-without-curve",
    W,
    "a backend joint that no @joint rule drives",
    "A joint of the backend is driven by no @joint rule, so it holds its neutral angle. Add a "
    "rule for it if it should move.",
)
DUPLICATE_JOINT = Code(
    "GG504",
    "duplicate-joint",
    E,
    "two rules drive the same joint",
    "Two rules drive the same joint; each joint is driven by exactly one rule.",
)
JOINT_NOT_DERIVED_ONCE = Code(
    "GG505",
    "joint-not-derived-once",
    W,
    "a joint rule that a derivation may skip or repeat",
    "A joint's curve should be derived exactly once per individual; some derivation skips or "
    "repeats this rule.",
)
LIMITS_EXCEED_BACKEND = Code(
    "GG506",
    "joint-limits-exceed-backend",
    W,
    "@joint limits wider than the backend allows",
    "The @joint limits are wider than the backend allows; the backend clips the curve to its own limits.",
)
JOINT_WITHOUT_BACKEND = Code(
    "GG507",
    "joint-without-backend",
    I,
    "@joint used with no @backend to check it against",
    "Without @backend, joint names and limits cannot be checked. Declare the backend.",
)
CODES = (
    UNKNOWN_BACKEND,
    UNKNOWN_JOINT,
    JOINT_WITHOUT_CURVE,
    DUPLICATE_JOINT,
    JOINT_NOT_DERIVED_ONCE,
    LIMITS_EXCEED_BACKEND,
    JOINT_WITHOUT_BACKEND,
)


def _registry() -> ModuleType:
    """The backend registry, imported only for a grammar with joints or a backend: it imports the
    backend API and so numpy, which checking any other grammar (``gaitgram check``) does without."""
    from gaitgram.backends import registry

    return registry


def joints(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    seen: dict[str, str] = {}
    for joint in grammar.joints:
        if joint.joint in seen:
            yield DUPLICATE_JOINT(
                f"joint {joint.joint} already has a curve, <{seen[joint.joint]}>",
                joint.span,
                rule=joint.rule,
                hint="each joint is driven by exactly one rule",
            )
        seen.setdefault(joint.joint, joint.rule)

    backend_annotation = grammar.declared.get("backend")
    if grammar.backend is None or backend_annotation is None:
        if grammar.joints:
            yield JOINT_WITHOUT_BACKEND(
                "no @backend: joint names and limits are not checked",
                grammar.joints[0].span,
                hint=f"declare the backend, e.g. @backend {next(iter(_registry().backend_names()), 'NAME')}",
            )
        return
    where = (
        backend_annotation.positional()[0].span
        if backend_annotation.positional()
        else backend_annotation.span
    )
    registry = _registry()
    try:
        backend = registry.get_backend(grammar.backend)
    except registry.BackendLoadError as error:
        yield UNKNOWN_BACKEND(
            f"backend {grammar.backend!r} is installed but fails to load: {error}",
            where,
            hint="reinstall it, or report the problem to its authors",
        )
        return
    except registry.BackendNotFound:
        installed = list(registry.backend_names())
        close = get_close_matches(grammar.backend, installed, n=1, cutoff=0.6)
        yield UNKNOWN_BACKEND(
            f"no backend named {grammar.backend!r} is installed",
            where,
            hint=f"did you mean {close[0]}?"
            if close
            else f"installed backends: {', '.join(installed) or 'none'}",
            fixes=[
                Fix(f"Replace with {n}", (TextEdit(where, n),), Applicability.UNSAFE, preferred=True)
                for n in close
                if backend_annotation.positional()
            ],
            data={"backend": grammar.backend},
        )
        return
    catalogue = backend.catalogue
    if catalogue is None:  # the backend takes any joint names
        return
    scale = 1.0 if grammar.units == "deg" else 3.141592653589793 / 180.0
    annotations = {(a.span.start, a.span.end): a for a in grammar.annotations}
    for joint in grammar.joints:
        known = catalogue.get(joint.joint)
        if known is None:
            suggestion = get_close_matches(joint.joint, catalogue.names, n=1, cutoff=0.5)
            annotation = annotations.get((joint.span.start, joint.span.end))
            argument = annotation.positional()[0] if annotation and annotation.positional() else None
            yield UNKNOWN_JOINT(
                f"backend {backend.name} has no joint {joint.joint!r}",
                joint.span,
                rule=joint.rule,
                hint=f"did you mean {suggestion[0]}?"
                if suggestion
                else f"its joints: {', '.join(catalogue.names)}",
                fixes=[
                    Fix(f"Replace with {n}", (TextEdit(argument.span, n),), Applicability.UNSAFE, True)
                    for n in suggestion
                    if argument is not None
                ],
                data={"joint": joint.joint, "backend": backend.name},
            )
            continue
        if joint.limits is not None:
            low, high = known.limits[0] * scale, known.limits[1] * scale
            if joint.limits[0] < low - 1e-9 or joint.limits[1] > high + 1e-9:
                yield LIMITS_EXCEED_BACKEND(
                    f"limits {joint.limits[0]:g}..{joint.limits[1]:g} of {joint.joint} go beyond the "
                    f"backend's {low:g}..{high:g} ({grammar.units})",
                    joint.span,
                    rule=joint.rule,
                    hint="the backend clips the curve to its own limits",
                )
    driven = {j.joint for j in grammar.joints}
    missing = [name for name in catalogue.names if name not in driven]
    if missing:
        which = f"joint {missing[0]} has" if len(missing) == 1 else f"{len(missing)} joints have"
        yield JOINT_WITHOUT_CURVE(
            f"{which} no curve, and will hold the neutral angle: {', '.join(missing)}",
            where,
            hint=f"add a rule annotated @joint {missing[0]}" + (" (and so on)" if len(missing) > 1 else ""),
        )


def joints_derived_once(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    cfg = facts.cfg
    if not grammar.joints or not facts.start_productive:
        return
    occurrences = Occurrences(cfg, facts.productive)
    once = derived_exactly_once(cfg, facts.productive, occurrences.usable)
    for joint in grammar.joints:
        target = cfg.index.get(joint.rule)
        if target is None or target in once:
            continue
        fewest, most = occurrences.bounds(target)
        if fewest == 1 and most == 1:
            continue
        if most == 0:
            problem = "no derivation uses it"
        elif fewest == 0:
            problem = "a derivation can skip it"
        else:
            problem = "a derivation can use it " + (
                "any number of times" if most == INFINITE else f"{most:g} times"
            )
        yield JOINT_NOT_DERIVED_ONCE(
            f"<{joint.rule}> drives joint {joint.joint}, but {problem}",
            joint.span,
            rule=joint.rule,
            hint="a joint's curve should be derived exactly once per individual",
        )
