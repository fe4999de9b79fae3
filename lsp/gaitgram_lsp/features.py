"""What the server knows, as pure functions of a document's text: no server, no protocol types.

Positions here are (0-based line, 0-based column in code points); ``server.py`` converts
to and from LSP's UTF-16 columns.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache
from itertools import pairwise

from gaitgram.analysis import CheckResult, check
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, backend_names, get_backend
from gaitgram.language import parse
from gaitgram.language.annotations import ANNOTATIONS
from gaitgram.language.model import NonTerminal
from gaitgram.language.source import Span


@lru_cache(maxsize=32)
def analysed(text: str) -> CheckResult:
    """Parse and check once per text: every feature on the same version shares the work."""
    return check(parse(text))


@dataclass(frozen=True)
class Completion:
    label: str
    kind: str  # "rule" | "annotation" | "joint" | "backend"
    detail: str = ""


def offset_of(result: CheckResult, line: int, column: int) -> int:
    return result.grammar.source.offset(line + 1, column + 1)


def completions(text: str, line: int, column: int, model: CheckResult | None = None) -> list[Completion]:
    """Context-aware: annotation names after ``@``, joints after ``@joint``, backends after
    ``@backend``, rule names inside a right-hand side (never where a rule's name is typed).

    ``model`` may be the last analysis of an earlier version of the text: completion must
    not wait for a large document to be re-checked after every keystroke.
    """
    result = model or analysed(text)
    lines = text.split("\n")
    before = lines[line][:column] if line < len(lines) else ""
    if re.fullmatch(r"\s*@[\w-]*", before):
        return [
            Completion(name, "annotation", f"{kind.summary} e.g. {kind.example}")
            for name, kind in ANNOTATIONS.items()
        ]
    if re.fullmatch(r"\s*@joint\s+[\w-]*", before):
        return [
            Completion(j.name, "joint", f"{j.group}, limits {j.limits[0]:g}..{j.limits[1]:g}")
            for j in _catalogue_joints(result)
        ]
    if re.fullmatch(r"\s*@backend\s+[\w-]*", before):
        return [Completion(name, "backend") for name in backend_names()]
    if "::=" not in before and not re.search(r"[|]", before) and before.lstrip().startswith("<"):
        return []  # a new rule's name is being typed
    typed = re.search(r"<([^<>|\s]*)$", before)
    prefix = typed.group(1) if typed else ""
    return [
        Completion(rule.name, "rule", _first_production(result, rule.name))
        for rule in result.grammar.rules
        if rule.name.startswith(prefix)
    ]


def _first_production(result: CheckResult, name: str) -> str:
    rule = result.grammar.rule(name)
    if rule is None or not rule.alternatives:
        return ""
    return result.grammar.source.slice(rule.alternatives[0].span)[:60]


def _catalogue_joints(result: CheckResult):
    name = result.grammar.backend or "mujoco-horse"
    try:
        catalogue = get_backend(name).catalogue
    except (BackendNotFound, BackendLoadError):
        return []
    return list(catalogue.joints) if catalogue else []


def reference_at(result: CheckResult, offset: int) -> str | None:
    """The rule name under the cursor: a reference or a rule's own name."""
    for rule in result.grammar.rules:
        if rule.name_span.start <= offset <= rule.name_span.end:
            return rule.name
        if rule.span.start <= offset <= rule.span.end:
            for ref in rule.references():
                if ref.span.start <= offset <= ref.span.end:
                    return ref.name
    return None


def definition(text: str, line: int, column: int) -> Span | None:
    result = analysed(text)
    name = reference_at(result, offset_of(result, line, column))
    rule = result.grammar.rule(name) if name else None
    return rule.name_span if rule else None


def references(text: str, line: int, column: int) -> list[Span]:
    result = analysed(text)
    name = reference_at(result, offset_of(result, line, column))
    if name is None:
        return []
    spans = [r.name_span for r in result.grammar.rules if r.name == name]
    spans += [ref.span for r in result.grammar.rules for ref in r.references() if ref.name == name]
    return sorted(spans)


def hover(text: str, line: int, column: int) -> str | None:
    """Markdown: a rule's productions and facts."""
    result = analysed(text)
    name = reference_at(result, offset_of(result, line, column))
    if name is None:
        return None
    facts = result.facts.rule(name)
    rule = result.grammar.rule(name)
    if rule is None or facts is None:
        return f"`<{name}>` is not defined"
    productions = "\n".join(f"| {result.grammar.source.slice(a.span)}" for a in rule.alternatives[:8])
    depth = "never finishes" if facts.min_depth is None else str(facts.min_depth)
    joint = result.grammar.joints_by_rule.get(name)
    joint_line = ""
    if joint is not None:
        limits = f"{joint.limits[0]:g}..{joint.limits[1]:g}" if joint.limits else "the backend's"
        free = "always" if joint.free is None else f"from generation {joint.free[0]}"
        joint_line = f"\n\njoint **{joint.joint}**: limits {limits}, free {free}"
    return (
        f"**<{name}>**: {facts.choices} choices, min depth {depth}, "
        f"{'productive' if facts.productive else 'unproductive'}, "
        f"{'reachable' if facts.reachable else 'unreachable'}"
        f"{', recursive' if facts.recursive else ''}{joint_line}\n\n```\n{productions}\n```"
    )


__all__ = [
    "CheckResult",
    "Completion",
    "NonTerminal",
    "analysed",
    "completions",
    "definition",
    "hover",
    "references",
]


# ---- symbols, highlights, folding ------------------------------------------------------


@dataclass(frozen=True)
class Symbol:
    name: str
    span: Span  # the whole rule
    name_span: Span
    detail: str


def document_symbols(text: str) -> list[Symbol]:
    result = analysed(text)
    joints = result.grammar.joints_by_rule
    return [
        Symbol(
            rule.name,
            rule.span,
            rule.name_span,
            f"joint {joints[rule.name].joint}"
            if rule.name in joints
            else f"{len(rule.alternatives)} alternatives",
        )
        for rule in result.grammar.rules
    ]


def folding_ranges(text: str) -> list[tuple[int, int]]:
    """Multi-line rules, as (first line, last line), 0-based."""
    result = analysed(text)
    source = result.grammar.source
    ranges = []
    for rule in result.grammar.rules:
        first, last = source.location(rule.span.start).line - 1, source.location(rule.span.end).line - 1
        if last > first:
            ranges.append((first, last))
    return ranges


# ---- rename --------------------------------------------------------------------------------

_RULE_NAME = re.compile(r"[^<>|\s]+")


def prepare_rename(text: str, line: int, column: int) -> Span | None:
    """The span of the name (without brackets) under the cursor, if it can be renamed."""
    result = analysed(text)
    offset = offset_of(result, line, column)
    name = reference_at(result, offset)
    if name is None or result.grammar.rule(name) is None:
        return None
    for span in references(text, line, column):
        if span.start <= offset <= span.end:
            return Span(span.start + 1, span.end - 1)
    return None


class RenameError(ValueError):
    pass


def rename(text: str, line: int, column: int, new_name: str) -> list[tuple[Span, str]]:
    """Edits (span, replacement) renaming the rule under the cursor everywhere; refuses bad names."""
    new_name = new_name.strip("<>")
    if not _RULE_NAME.fullmatch(new_name):
        raise RenameError(f"{new_name!r} is not a rule name: no spaces, <, > or |")
    result = analysed(text)
    name = reference_at(result, offset_of(result, line, column))
    if name is None:
        raise RenameError("no rule under the cursor")
    if new_name != name and result.grammar.rule(new_name) is not None:
        raise RenameError(f"<{new_name}> already exists")
    edits = [(Span(s.start + 1, s.end - 1), new_name) for s in references(text, line, column)]
    for annotation in result.grammar.annotations:  # @start <name>
        for argument in annotation.arguments:
            if getattr(argument.value, "name", None) == name and argument.raw == f"<{name}>":
                edits.append((Span(argument.span.start + 1, argument.span.end - 1), new_name))
    return sorted(edits, key=lambda e: e[0])


# ---- code actions ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Fix:
    title: str
    edits: tuple[tuple[Span, str], ...]
    code: str


def code_actions(text: str, start: int, end: int) -> list[Fix]:
    """Quick fixes for diagnostics overlapping ``[start, end]`` (offsets)."""
    result = analysed(text)
    fixes: list[Fix] = []
    for d in result.diagnostics:
        if d.span.end < start or d.span.start > end:
            continue
        if d.code.code == "GG201":
            missing = result.grammar.source.slice(d.span).strip("<>")
            end_of_text = len(result.grammar.source.text)
            newline = "" if result.grammar.source.text.endswith("\n") else "\n"
            fixes.append(
                Fix(
                    f"Define <{missing}>",
                    ((Span(end_of_text, end_of_text), f"{newline}<{missing}> ::= \n"),),
                    d.code.code,
                )
            )
            if d.hint and d.hint.startswith("did you mean <"):
                nearest = d.hint.removeprefix("did you mean <").split(">")[0]
                fixes.append(Fix(f"Replace with <{nearest}>", ((d.span, f"<{nearest}>"),), d.code.code))
        elif d.code.code == "GG204" and d.rule:
            rule = result.grammar.rule(d.rule)
            if rule is not None:
                line_end = result.grammar.source.text.find("\n", rule.span.end)
                stop = len(result.grammar.source.text) if line_end == -1 else line_end + 1
                fixes.append(
                    Fix(f"Remove unreachable <{d.rule}>", ((Span(rule.span.start, stop), ""),), d.code.code)
                )
    return fixes


# ---- inlay hints ----------------------------------------------------------------------------


def inlay_hints(text: str) -> list[tuple[int, str]]:
    """(offset, label) after each rule's name: its number of choices and whether it reads a codon."""
    result = analysed(text)
    hints = []
    for rule in result.grammar.rules:
        facts = result.facts.rule(rule.name)
        if facts is None:
            continue
        reads = "reads a codon" if facts.choices > 1 else "no codon (lazy)"
        hints.append((rule.name_span.end, f" {facts.choices} choices, {reads}"))
    return hints


# ---- typed ranges, semantic tokens, snippets -------------------------------------------------


def range_at(result: CheckResult, offset: int):
    """The typed range (a ``RangeSpec``) under the cursor, with its span."""
    for rule in result.grammar.rules:
        if not rule.span.start <= offset <= rule.span.end:
            continue
        for alternative in rule.alternatives:
            whole = alternative.range_values
            if whole is not None and alternative.span.start <= offset <= alternative.span.end:
                return whole, alternative.span
            for symbol in alternative.symbols:
                spec = getattr(symbol, "spec", None)
                if spec is not None and symbol.span.start <= offset <= symbol.span.end:
                    return spec, symbol.span
    return None


def range_hover(text: str, line: int, column: int) -> str | None:
    result = analysed(text)
    found = range_at(result, offset_of(result, line, column))
    if found is None:
        return None
    spec, _ = found
    values = spec.values
    return (
        f"**{spec.text}**: {len(values)} values, one codon picks one\n\n"
        f"first `{values[0]}`, last `{values[-1]}`" + (f", then `{values[1]}`" if len(values) > 2 else "")
    )


#: Semantic token types, in the legend's order.
TOKEN_TYPES = ("function", "variable", "string", "number", "decorator", "comment", "operator")


def semantic_tokens(text: str) -> list[tuple[int, int, str]]:
    """(start offset, length, token type) for rule heads, references, terminals, ranges,
    annotations and comments, in document order."""
    from gaitgram.language.parser import parse_tree, scanner

    tree = parse_tree(text)
    kinds = {
        "NONTERMINAL": "variable",
        "STRING": "string",
        "RANGE": "number",
        "GE_RANGE": "number",
        "COMMENT": "comment",
        "PIPE": "operator",
        "TEXT": "string",
    }
    tokens: list[tuple[int, int, str]] = []
    for token in tree.scan_values(lambda v: hasattr(v, "type")):
        if token.type == "RULE_HEAD":
            close = token.index(">") + 1
            tokens.append((token.start_pos, close, "function"))
        elif token.type == "ANNOTATION":
            at = token.index("@")
            tokens.append((token.start_pos + at, len(token) - at, "decorator"))
        elif token.type == "COMMENT":
            tokens.append((token.start_pos, len(token), "comment"))
        elif token.type == "PIECES":
            for kind, start, end in scanner().pieces(text, token.start_pos, token.end_pos):
                if kind in kinds and (kind != "TEXT" or text[start:end].strip()):
                    tokens.append((start, end - start, kinds[kind]))
    return sorted(tokens)


SNIPPETS = {
    "new rule": ("<${1:name}> ::= ${2:a} | ${3:b}", "a rule with two alternatives"),
    "int range": ("int[${1:0}..${2:10}]", "integers, one codon per value"),
    "float range by step": ("float[${1:0}..${2:20} step ${3:0.25}]", "floats on a grid"),
    "float range by count": ("float[${1:-3.14}..${2:3.14} count ${3:64}]", "evenly spaced floats"),
    "relative range": ("float[${1:7.7} ± ${2:25}% count ${3:21}]", "within a percentage of a value"),
}


# ---- value lists <-> typed ranges -----------------------------------------------------------

_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d+)?|\.\d+)")
MAX_EXPANDED = 200


def range_refactors(text: str, offset: int) -> list[Fix]:
    """For the rule under the cursor: collapse a written-out arithmetic value list
    (``0 | 0.25 | 0.5 | ... | 20``) to a typed range, or expand a typed range into its values."""
    from decimal import Decimal

    result = analysed(text)
    rule = next((r for r in result.grammar.rules if r.span.start <= offset <= r.span.end), None)
    if rule is None or not rule.alternatives:
        return []
    source = result.grammar.source
    body = Span(rule.alternatives[0].span.start, rule.alternatives[-1].span.end)
    written = [source.slice(a.span) for a in rule.alternatives]
    if len(written) == 1 and rule.alternatives[0].range_values is not None:
        values = rule.alternatives[0].range_values.values
        if len(values) <= MAX_EXPANDED:
            return [Fix(f"Expand into {len(values)} alternatives", ((body, " | ".join(values)),), "refactor")]
        return []
    if len(written) >= 3 and all(_NUMBER.fullmatch(w) for w in written):
        numbers = [Decimal(w) for w in written]
        step = numbers[1] - numbers[0]
        if step > 0 and all(b - a == step for a, b in pairwise(numbers)):
            is_int = all(n == n.to_integral_value() for n in numbers)
            kind = "int" if is_int else "float"
            suffix = "" if is_int and step == 1 else f" step {step.normalize()}"
            spec = f"{kind}[{numbers[0].normalize()}..{numbers[-1].normalize()}{suffix}]"
            return [Fix(f"Collapse into {spec}", ((body, spec),), "refactor")]
    return []
