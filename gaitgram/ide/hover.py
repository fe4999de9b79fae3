"""Hover: what gaitgram knows about the thing under the cursor, as Markdown.

A rule name shows the rule's productions and its facts (choices, minimum depth, productive,
reachable, recursive), for a ``@joint`` rule the joint, and what the rule is in the genomes of the
representations that say (SGE's and DSGE's genes); a typed range its values; a sensor
in a curve's text what it reads (its description, unit, whether per limb or periodic, its reading
at rest); an annotation its documentation; an argument what it names (by its parameter's
``refers``: a backend, a joint with its limits and freedom schedule). The hints of the diagnostics
under the cursor come last.
"""

from __future__ import annotations

from dataclasses import dataclass

from gaitgram.analysis import CheckResult
from gaitgram.analysis.motion_text import sensor_uses
from gaitgram.backends.catalogue import Joint
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, get_backend
from gaitgram.backends.sensors import Sensor
from gaitgram.ge.registry import (
    RepresentationLoadError,
    RepresentationNotFound,
    get_representation,
    representation_names,
)
from gaitgram.ide.navigation import name_at
from gaitgram.language.annotations import ANNOTATIONS, AnnotationKind, Refers, parameter_of
from gaitgram.language.model import Annotation, Grammar, JointDecl, Name, RangeSpec, RangeSymbol
from gaitgram.language.source import Span

__all__ = [
    "Hover",
    "annotation_doc",
    "catalogue_joint",
    "describe_backend",
    "describe_genes",
    "describe_joint",
    "describe_range",
    "describe_rule",
    "describe_sensor",
    "hover",
]

#: Productions shown in a rule's hover; the rest are counted.
MAX_PRODUCTIONS = 12
_WIDTH = 100


@dataclass(frozen=True, slots=True)
class Hover:
    markdown: str
    span: Span | None  # what it is about; None when only diagnostics' hints are shown


def hover(result: CheckResult, offset: int) -> Hover | None:
    found = _describe(result, offset)
    hints = "\n\n".join(
        f"{d.code.code} hint: {d.hint}"
        for d in result.diagnostics
        if d.hint and d.span.start <= offset <= d.span.end
    )
    if found is None and not hints:
        return None
    text, span = found if found is not None else ("", None)
    return Hover("\n\n".join(part for part in (text, hints) if part), span)


def _describe(result: CheckResult, offset: int) -> tuple[str, Span] | None:
    grammar = result.grammar
    rule = grammar.rule_at(offset)
    if rule is not None:
        for alternative in rule.alternatives:
            for symbol in alternative.symbols:
                if isinstance(symbol, RangeSymbol) and offset in (span := rule.span_of(symbol)):
                    whole = alternative.range_values is not None
                    return describe_range(symbol.spec, whole=whole), span
        for use, sensor, backend in sensor_uses(grammar, result.facts):
            if use.rule == rule.name and use.span.start <= offset <= use.span.end:
                return describe_sensor(sensor, backend), use.span
    name = name_at(grammar, offset)
    if name is not None:
        return describe_rule(result, name.name), name.span
    annotation = grammar.annotation_at(offset)
    if annotation is not None:
        return _describe_annotation(grammar, annotation, offset)
    return None


def describe_range(spec: RangeSpec, whole: bool = True) -> str:
    values = spec.values
    shown = ", ".join(f"`{v}`" for v in values[:3])
    if len(values) > 4:
        shown += f", …, `{values[-1]}`"
    elif len(values) == 4:
        shown += f", `{values[-1]}`"
    where = (
        "its values are choices of the rule" if whole else "an anonymous choice: one codon picks its value"
    )
    return (
        f"**`{spec.text}`**: {spec.size:,} value{'' if spec.size == 1 else 's'} ({spec.kind.value}), "
        f"first `{values[0]}`, last `{values[-1]}`\n\n{shown}\n\n{where}"
    )


def describe_rule(result: CheckResult, name: str) -> str:
    grammar = result.grammar
    rule = grammar.rule(name)
    facts = result.facts.rule(name)
    if rule is None or facts is None:
        users = sorted({r.name for r in grammar.rules for ref in r.references() if ref.name == name})
        used = ", ".join(f"<{u}>" for u in users[:5]) + (" …" if len(users) > 5 else "")
        return f"**`<{name}>`** is not defined" + (f"; used by {used}" if used else "")
    depth = "never finishes" if facts.min_depth is None else f"min depth {facts.min_depth}"
    flags = [
        "productive" if facts.productive else "**unproductive**",
        "reachable" if facts.reachable else "**unreachable**",
    ]
    if facts.recursive:
        flags.append("recursive")
    codon = "reads a codon" if facts.choices > 1 else "reads no codon in lazy mode"
    header = (
        f"**`<{name}>`**: {facts.choices:,} choice{'' if facts.choices == 1 else 's'} ({codon}), "
        f"{depth}; {', '.join(flags)}"
    )
    lines = [_production(grammar.source.slice(rule.span_of(a))) for a in rule.alternatives[:MAX_PRODUCTIONS]]
    pad = " " * (len(name) + 4)
    body = "\n".join(f"<{name}> ::= {line}" if i == 0 else f"{pad}| {line}" for i, line in enumerate(lines))
    if len(rule.alternatives) > MAX_PRODUCTIONS:
        body += f"\n{pad}… {len(rule.alternatives) - MAX_PRODUCTIONS} more"
    parts = [header, f"```\n{body}\n```"]
    joint = grammar.joints_by_rule.get(name)
    if joint is not None:
        parts.append(describe_joint(joint.joint, grammar.backend, joint, grammar.units))
    parts += describe_genes(result, name)
    return "\n\n".join(parts)


def describe_genes(result: CheckResult, name: str) -> list[str]:
    """What a rule is in the genome of each installed representation that declares it
    (``describe_rule``: SGE's genes and their sizes, DSGE's gene), from the grammar alone: a
    document has no run configuration, so at each representation's default settings."""
    cfg = result.facts.cfg
    rule = cfg.index.get(name)
    if rule is None:
        return []
    lines = []
    for representation in representation_names():
        try:
            spec = get_representation(representation)
        except (RepresentationNotFound, RepresentationLoadError):  # a broken plug-in says nothing
            continue
        line = spec.describe_rule(cfg, rule) if spec.describe_rule is not None else None
        if line:
            lines.append(line)
    return lines


def _production(text: str) -> str:
    text = " ".join(text.split("\n"))
    return text if len(text) <= _WIDTH else text[: _WIDTH - 1] + "…"


def catalogue_joint(backend: str | None, joint: str) -> Joint | None:
    """The backend's entry for a joint, if the backend is installed and lists it."""
    if backend is None:
        return None
    try:
        catalogue = get_backend(backend).catalogue
    except (BackendNotFound, BackendLoadError):
        return None
    return catalogue.get(joint) if catalogue is not None else None


def describe_joint(name: str, backend: str | None, declared: JointDecl | None, units: str = "deg") -> str:
    """A joint's limits and freedom schedule: the backend's, and the grammar's narrowing."""
    known = catalogue_joint(backend, name)
    lines = [f"joint **{name}**" + (f" ({known.group})" if known is not None else "")]
    if known is not None:
        if known.description:
            lines.append(known.description)
        lines.append(f"- backend {backend}: limits {known.limits[0]:g}..{known.limits[1]:g} deg")
        lines.append(f"- free from generation {known.free_from} (Table 3 of the paper)")
    elif backend is not None:
        lines.append(f"- backend {backend} does not list it")
    else:
        lines.append("- no @backend: its limits are not checked")
    if declared is not None:
        if declared.limits is not None:
            lines.append(f"- this grammar: limits {declared.limits[0]:g}..{declared.limits[1]:g} {units}")
        if declared.free is not None:
            first, last = declared.free
            until = f" to {last}" if last is not None else " on"
            lines.append(
                f"- this grammar: free from generation {first}{until}; before, it holds its neutral angle"
            )
    return "\n".join(lines)


def describe_sensor(sensor: Sensor, backend: str) -> str:
    """What a sensor reads, as its backend declares it (``sensors.toml``)."""
    head = f"**`{sensor.name}`**: a sensor of {backend}, in {sensor.unit}\n\n{sensor.description}\n"
    lines = [head]
    if sensor.per_limb:
        lines.append(
            "- per limb: each limb's curve reads its own limb"
            + (f" (only {', '.join(sorted(sensor.groups))} joints may read it)" if sensor.groups else "")
        )
    else:
        lines.append("- of the whole body: every curve reads the same value")
    if sensor.periodic:
        lines.append(
            "- periodic: a phase in [0, 1) that advances with the cycle like `t`, read at every step"
        )
    else:
        lines.append("- read at the control rate and held between ticks")
    lines.append(f"- nominal reading (at rest) {sensor.nominal:g}: what plots of a closed loop assume")
    return "\n".join(lines)


def describe_backend(name: str) -> str:
    try:
        spec = get_backend(name)
    except (BackendNotFound, BackendLoadError) as error:
        return f"backend **{name}**: {error}"
    joints = f"; {len(spec.catalogue)} joints" if spec.catalogue is not None else "; any joint names"
    return f"backend **{spec.name}**: {spec.summary}{joints}"


def annotation_doc(kind: AnnotationKind) -> str:
    """An annotation's documentation, from its table entry."""
    parameters = "\n".join(f"- `{p.name}`: {p.help}" for p in kind.parameters)
    text = f"**`@{kind.name}`** ({kind.target.value}): {kind.summary}\n\n```\n{kind.example}\n```"
    return text + (f"\n\n{parameters}" if parameters else "")


def _describe_annotation(grammar: Grammar, annotation: Annotation, offset: int) -> tuple[str, Span] | None:
    if offset in annotation.name_span:
        kind = ANNOTATIONS.get(annotation.name)
        if kind is None:
            return f"`@{annotation.name}` is not an annotation gaitgram knows", annotation.name_span
        return annotation_doc(kind), annotation.name_span
    for argument in annotation.arguments:
        if offset not in argument.span or not isinstance(argument.value, Name):
            continue
        parameter = parameter_of(annotation, argument)
        refers = parameter.refers if parameter is not None else None
        if refers is Refers.JOINT:
            declared = next((j for j in grammar.joints if j.span == annotation.span), None)
            text = describe_joint(argument.value.text, grammar.backend, declared, grammar.units)
            return text, argument.span
        if refers is Refers.BACKEND:
            return describe_backend(argument.value.text), argument.span
    return None
