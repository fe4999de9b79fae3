"""Hover: what gaitgram knows about the thing under the cursor.

A rule name shows the rule's productions and its facts (choices, minimum depth, productive,
reachable, recursive) and, for a ``@joint`` rule, the joint; a typed range its values; an
annotation its documentation; a joint its limits and freedom schedule (the backend's, and
the grammar's if it narrows them). The hints of diagnostics under the cursor come last.
"""

from __future__ import annotations

from lsprotocol import types

from gaitgram.backends.catalogue import Joint
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, get_backend
from gaitgram.language.annotations import ANNOTATIONS
from gaitgram.language.model import Annotation, JointDecl, Name, RangeSpec, RangeSymbol
from gaitgram.language.source import Span
from gaitgram_lsp.documents import Snapshot
from gaitgram_lsp.features.navigation import annotation_at, name_at, rule_at

#: Productions shown in a rule's hover; the rest are counted.
MAX_PRODUCTIONS = 12
_WIDTH = 100


def hover(snapshot: Snapshot, offset: int, markdown: bool = True) -> types.Hover | None:
    found = _describe(snapshot, offset)
    hints = _hints(snapshot, offset)
    if found is None and not hints:
        return None
    text, span = found if found is not None else ("", Span(offset, offset))
    value = "\n\n".join(part for part in (text, hints) if part)
    kind = types.MarkupKind.Markdown if markdown else types.MarkupKind.PlainText
    return types.Hover(
        contents=types.MarkupContent(kind=kind, value=value),
        range=snapshot.positions.range(span) if found is not None else None,
    )


def _describe(snapshot: Snapshot, offset: int) -> tuple[str, Span] | None:
    rule = rule_at(snapshot, offset)
    if rule is not None:
        for alternative in rule.alternatives:
            for symbol in alternative.symbols:
                if isinstance(symbol, RangeSymbol) and offset in symbol.span:
                    return describe_range(
                        symbol.spec, whole=alternative.range_values is not None
                    ), symbol.span
    name = name_at(snapshot, offset)
    if name is not None:
        return describe_rule(snapshot, name.name), name.span
    annotation = annotation_at(snapshot, offset)
    if annotation is not None:
        return _describe_annotation(snapshot, annotation, offset)
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


def describe_rule(snapshot: Snapshot, name: str) -> str:
    result = snapshot.result
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
    lines = [_production(grammar.source.slice(a.span)) for a in rule.alternatives[:MAX_PRODUCTIONS]]
    pad = " " * (len(name) + 4)
    body = "\n".join(f"<{name}> ::= {line}" if i == 0 else f"{pad}| {line}" for i, line in enumerate(lines))
    if len(rule.alternatives) > MAX_PRODUCTIONS:
        body += f"\n{pad}… {len(rule.alternatives) - MAX_PRODUCTIONS} more"
    parts = [header, f"```\n{body}\n```"]
    joint = grammar.joints_by_rule.get(name)
    if joint is not None:
        parts.append(describe_joint(joint.joint, grammar.backend, joint, grammar.units))
    return "\n\n".join(parts)


def _production(text: str) -> str:
    text = " ".join(text.split("\n"))
    return text if len(text) <= _WIDTH else text[: _WIDTH - 1] + "…"


def _catalogue_joint(backend: str | None, joint: str) -> Joint | None:
    if backend is None:
        return None
    try:
        catalogue = get_backend(backend).catalogue
    except (BackendNotFound, BackendLoadError):
        return None
    return catalogue.get(joint) if catalogue is not None else None


def describe_joint(name: str, backend: str | None, declared: JointDecl | None, units: str = "deg") -> str:
    """A joint's limits and freedom schedule: the backend's, and the grammar's narrowing."""
    known = _catalogue_joint(backend, name)
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


def _describe_annotation(snapshot: Snapshot, annotation: Annotation, offset: int) -> tuple[str, Span] | None:
    grammar = snapshot.result.grammar
    if offset in annotation.name_span:
        kind = ANNOTATIONS.get(annotation.name)
        if kind is None:
            return f"`@{annotation.name}` is not an annotation gaitgram knows", annotation.name_span
        parameters = "\n".join(f"- `{p.name}`: {p.help}" for p in kind.parameters)
        text = f"**`@{kind.name}`** ({kind.target.value}): {kind.summary}\n\n```\n{kind.example}\n```"
        return text + (f"\n\n{parameters}" if parameters else ""), annotation.name_span
    for argument in annotation.arguments:
        if offset not in argument.span or not isinstance(argument.value, Name) or argument.key is not None:
            continue
        if annotation.name == "joint":
            declared = next((j for j in grammar.joints if j.span == annotation.span), None)
            return describe_joint(
                argument.value.text, grammar.backend, declared, grammar.units
            ), argument.span
        if annotation.name == "backend":
            try:
                spec = get_backend(argument.value.text)
            except (BackendNotFound, BackendLoadError) as error:
                return f"backend **{argument.value.text}**: {error}", argument.span
            joints = f"; {len(spec.catalogue)} joints" if spec.catalogue is not None else "; any joint names"
            return f"backend **{spec.name}**: {spec.summary}{joints}", argument.span
    return None


def _hints(snapshot: Snapshot, offset: int) -> str:
    return "\n\n".join(
        f"{d.code.code} hint: {d.hint}"
        for d in snapshot.result.diagnostics
        if d.hint and d.span.start <= offset <= d.span.end
    )
