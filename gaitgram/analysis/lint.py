"""The linter: problems with a grammar's meaning, from its model and facts.

Each check is a small function from (grammar, facts) to diagnostics; ``lint``
runs them all. Syntax problems were already found by the parser and live in
``grammar.diagnostics``. Diagnostics carry their fixes (``Diagnostic.fixes``), made
here where the names and spans are at hand.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from difflib import get_close_matches

from gaitgram.analysis.cfg import RuleKind
from gaitgram.analysis.facts import INFINITE, GrammarFacts, min_depths, occurrence_bounds
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, backend_names, get_backend
from gaitgram.diagnostics import Applicability, Diagnostic, Fix, TextEdit, diagnostic
from gaitgram.language.annotations import rule_references
from gaitgram.language.edits import line_end, removal, union
from gaitgram.language.model import Grammar, NonTerminal, Rule
from gaitgram.language.source import Span

Check = Callable[[Grammar, GrammarFacts], Iterator[Diagnostic]]


def undefined_rules(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    defined = grammar.rules_by_name
    nearest: dict[str, list[str]] = {}  # a missing name is often used many times

    def near(name: str) -> list[str]:
        if name not in nearest:
            nearest[name] = _nearest(name, defined)
        return nearest[name]

    for rule in grammar.rules:
        for ref in rule.references():
            if ref.name not in defined:
                close = near(ref.name)
                span = rule.span_of(ref)
                yield diagnostic(
                    "GG201",
                    f"<{ref.name}> is not defined",
                    span,
                    rule=rule.name,
                    hint=f"did you mean <{close[0]}>?" if close else f"define it: <{ref.name}> ::= ...",
                    fixes=_undefined_fixes(grammar, ref.name, span, rule, close),
                    data={"name": ref.name},
                )
    for annotation in grammar.annotations:
        for name, span in rule_references(annotation):
            if name not in defined:
                close = near(name)
                yield diagnostic(
                    "GG201",
                    f"@{annotation.name} names <{name}>, which is not defined",
                    span,
                    hint=f"did you mean <{close[0]}>?" if close else "name a rule this file defines",
                    fixes=_undefined_fixes(grammar, name, span, None, close),
                    data={"name": name},
                )


def _undefined_fixes(
    grammar: Grammar, name: str, where: Span, user: Rule | None, nearest: list[str]
) -> list[Fix]:
    """Define the rule (after the rule that uses it, or at the end), or use a name that exists."""
    text = grammar.source.text
    at = len(text)
    if user is not None:
        end = line_end(text, user.span.end)
        rest = text[user.span.end : end]
        if not rest.strip() or rest.lstrip().startswith("#"):  # nothing else on its last line
            at = end
    if at == len(text):
        insert = ("\n" if text and not text.endswith("\n") else "") + f"<{name}> ::= ''\n"
    else:
        insert = f"\n<{name}> ::= ''"
    fixes = [Fix(f"Define <{name}>", (TextEdit(Span(at, at), insert),), Applicability.UNSAFE)]
    fixes += [
        Fix(f"Replace with <{n}>", (TextEdit(where, f"<{n}>"),), Applicability.UNSAFE, preferred=i == 0)
        for i, n in enumerate(nearest)
    ]
    return fixes


def duplicate_rules(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    first = grammar.rules_by_name
    for rule in grammar.rules:
        original = first[rule.name]
        if rule is not original:
            line = grammar.source.location(original.name_span.start).line
            yield diagnostic(
                "GG202",
                f"<{rule.name}> is already defined on line {line}; this definition is ignored",
                rule.name_span,
                rule=rule.name,
                hint="merge the alternatives into one rule with |, or rename one of them",
                fixes=_duplicate_fixes(grammar, original, rule),
                data={"name": rule.name},
            )


def _duplicate_fixes(grammar: Grammar, original: Rule, duplicate: Rule) -> list[Fix]:
    """Merge the ignored definition's alternatives into the first one, or delete it."""
    text = grammar.source.text
    gone = _rule_removal(text, duplicate)
    fixes = []
    # Text added after an unterminated string would be part of it.
    open_string = any(d.code.code == "GG102" and d.span.end == original.span.end for d in grammar.diagnostics)
    if duplicate.alternatives and not duplicate.annotations and not open_string:
        alternatives = text[duplicate.span_of(duplicate.alternatives[0]).start : duplicate.span.end]
        joined = f" | {alternatives}" if original.alternatives else f" {alternatives}"
        end = original.span.end
        while end > original.span.start and text[end - 1] in " \t":  # a rule's text keeps its trailing spaces
            end -= 1
        at = Span(end, end)
        fixes.append(
            Fix(
                f"Merge its alternatives into the first <{duplicate.name}>",
                (TextEdit(at, joined), TextEdit(gone, "")),
                Applicability.UNSAFE,
                preferred=True,
            )
        )
    fixes.append(Fix("Delete this definition", (TextEdit(gone, ""),), Applicability.UNSAFE, not fixes))
    return fixes


def _rule_removal(text: str, rule: Rule) -> Span:
    """A rule with its annotations, and its lines if nothing else is on them."""
    start = min([rule.span.start, *(a.span.start for a in rule.annotations)])
    return removal(text, start, rule.span.end)


def unproductive_rules(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    cfg = facts.cfg
    # Count undefined names as finishing, so one missing rule is one diagnostic.
    undefined = [i for i, kind in enumerate(cfg.kinds) if kind is RuleKind.UNDEFINED]
    depth, _ = min_depths(cfg, undefined) if undefined else (facts.min_depth, None)
    for rule in grammar.rules_by_name.values():
        i = cfg.index[rule.name]
        if depth[i] is not None or not rule.alternatives:
            continue
        if i == cfg.start:
            yield diagnostic(
                "GG205",
                f"the start rule <{rule.name}> can never derive a terminal string, so no genome maps",
                rule.name_span,
                rule=rule.name,
                hint="every alternative uses a rule that cannot finish; add one that can, e.g. a terminal",
            )
            continue
        stuck = sorted(
            {cfg.names[c] for c in cfg.children(i) if depth[c] is None and cfg.kinds[c] is RuleKind.DEFINED}
        )
        why = ", ".join(f"<{s}>" for s in stuck[:4]) + (" ..." if len(stuck) > 4 else "")
        yield diagnostic(
            "GG203",
            f"<{rule.name}> can never derive a terminal string: every alternative needs {why}, "
            "which cannot finish",
            rule.name_span,
            rule=rule.name,
            hint="add an alternative that ends, such as a terminal or a rule that finishes",
        )


def unreachable_rules(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    cfg = facts.cfg
    if cfg.start is None:
        return
    start = cfg.names[cfg.start]
    unreachable = {
        rule.name for rule in grammar.rules_by_name.values() if not facts.reachable[cfg.index[rule.name]]
    }
    if not unreachable:
        return
    # Every definition that uses each unreachable name: deleting a rule must not leave a
    # reference to it behind (an ignored duplicate of a reachable rule may hold one).
    users: dict[str, list[Rule]] = {}
    definitions: dict[str, list[Rule]] = {}
    for rule in grammar.rules:
        if rule.name in unreachable:
            definitions.setdefault(rule.name, []).append(rule)
        for ref in rule.references():
            if ref.name in unreachable and ref.name != rule.name:
                users.setdefault(ref.name, []).append(rule)
    removals: dict[int, Span] = {}  # by id(rule): a chain of n rules is in n fixes
    for rule in grammar.rules_by_name.values():
        if rule.name in unreachable:
            yield diagnostic(
                "GG204",
                f"<{rule.name}> is unreachable: the start rule <{start}> never uses it",
                rule.name_span,
                rule=rule.name,
                hint=f"delete it, or use it from a rule that <{start}> reaches",
                fixes=_unreachable_fixes(grammar, rule.name, unreachable, users, definitions, removals),
                data={"name": rule.name},
            )


#: A removal that would take more rules with it than this is not offered.
MAX_REMOVED_WITH = 50


def _unreachable_fixes(
    grammar: Grammar,
    name: str,
    unreachable: set[str],
    users: dict[str, list[Rule]],
    definitions: dict[str, list[Rule]],
    removals: dict[int, Span],
) -> list[Fix]:
    """Delete every definition of the rule, and of the unreachable rules that use it (so no
    reference is left undefined); none if a reachable rule's text uses it."""
    removed = [name]
    seen = {name}
    for current in removed:
        for user in users.get(current, ()):
            if user.name in seen:
                continue
            if user.name not in unreachable or len(removed) >= MAX_REMOVED_WITH:
                return []
            seen.add(user.name)
            removed.append(user.name)
    text = grammar.source.text
    spans = []
    for rule in (rule for n in removed for rule in definitions[n]):
        span = removals.get(id(rule))
        if span is None:
            span = removals[id(rule)] = _rule_removal(text, rule)
        spans.append(span)
    if len(spans) > 1:
        spans = union(spans)
    others = len(removed) - 1
    title = f"Remove unreachable <{name}>"
    if others:
        title += f" and the {'rule' if others == 1 else f'{others} rules'} using it"
    return [Fix(title, tuple(TextEdit(s, "") for s in spans), Applicability.UNSAFE, preferred=True)]


def unit_rule_chains(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    defined = grammar.rules_by_name
    for rule in defined.values():
        if rule.annotations or len(rule.alternatives) != 1:
            continue
        symbols = rule.alternatives[0].symbols
        if (
            len(symbols) == 1
            and isinstance(symbols[0], NonTerminal)
            and symbols[0].name in defined
            and symbols[0].name != rule.name  # <a> ::= <a> is unproductive, reported as such
        ):
            target = symbols[0].name
            yield diagnostic(
                "GG206",
                f"<{rule.name}> only renames <{target}>",
                rule.name_span,
                rule=rule.name,
                hint=f"use <{target}> directly; in eager mode the extra step reads a codon",
            )


def joints(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    seen: dict[str, str] = {}
    for joint in grammar.joints:
        if joint.joint in seen:
            yield diagnostic(
                "GG504",
                f"joint {joint.joint} already has a curve, <{seen[joint.joint]}>",
                joint.span,
                rule=joint.rule,
                hint="each joint is driven by exactly one rule",
            )
        seen.setdefault(joint.joint, joint.rule)

    backend_annotation = grammar.declared.get("backend")
    if grammar.backend is None or backend_annotation is None:
        if grammar.joints:
            yield diagnostic(
                "GG507",
                "no @backend: joint names and limits are not checked",
                grammar.joints[0].span,
                hint=f"declare the backend, e.g. @backend {next(iter(backend_names()), 'NAME')}",
            )
        return
    where = (
        backend_annotation.positional()[0].span
        if backend_annotation.positional()
        else backend_annotation.span
    )
    try:
        backend = get_backend(grammar.backend)
    except BackendLoadError as error:
        yield diagnostic(
            "GG501",
            f"backend {grammar.backend!r} is installed but fails to load: {error}",
            where,
            hint="reinstall it, or report the problem to its authors",
        )
        return
    except BackendNotFound:
        installed = list(backend_names())
        close = get_close_matches(grammar.backend, installed, n=1, cutoff=0.6)
        yield diagnostic(
            "GG501",
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
            yield diagnostic(
                "GG502",
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
                yield diagnostic(
                    "GG506",
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
        yield diagnostic(
            "GG503",
            f"{which} no curve, and will hold the neutral angle: {', '.join(missing)}",
            where,
            hint=f"add a rule annotated @joint {missing[0]}" + (" (and so on)" if len(missing) > 1 else ""),
        )


def joints_derived_once(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    cfg = facts.cfg
    if not facts.start_productive:
        return
    for joint in grammar.joints:
        target = cfg.index.get(joint.rule)
        if target is None:
            continue
        fewest, most = occurrence_bounds(cfg, target, facts.productive)
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
        yield diagnostic(
            "GG505",
            f"<{joint.rule}> drives joint {joint.joint}, but {problem}",
            joint.span,
            rule=joint.rule,
            hint="a joint's curve should be derived exactly once per individual",
        )


CHECKS: tuple[Check, ...] = (
    undefined_rules,
    duplicate_rules,
    unproductive_rules,
    unreachable_rules,
    unit_rule_chains,
    joints,
    joints_derived_once,
)


def lint(grammar: Grammar, facts: GrammarFacts) -> list[Diagnostic]:
    found = [d for check in CHECKS for d in check(grammar, facts)]
    return sorted(found, key=lambda d: (d.span.start, d.code.code))


def _nearest(name: str, candidates: dict[str, object]) -> list[str]:
    """Up to three defined names close to ``name``, closest first."""
    if len(candidates) > 5000:  # difflib is quadratic-ish; keep it cheap on huge grammars
        return [c for c in candidates if c.lower() == name.lower()][:3]
    return get_close_matches(name, list(candidates), n=3, cutoff=0.6)
