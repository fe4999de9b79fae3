"""Lint checks of a grammar's rules (GG2xx): undefined, duplicate, unproductive, unreachable and
renaming rules.

Each code is declared here with what it means, what to do about it and what its fixes do, beside
the check that finds it and the fixes it offers. A check is a function from (grammar, facts) to
diagnostics; :func:`gaitgram.analysis.lint.lint` runs them all. Fixes are made when they are
first asked for (``Diagnostic.fixes``): working out what deleting an unreachable rule takes with
it costs more than finding it.
"""

from __future__ import annotations

from collections.abc import Iterator
from difflib import get_close_matches
from functools import partial

from gaitgram.analysis.cfg import RuleKind
from gaitgram.analysis.facts import GrammarFacts, min_depths
from gaitgram.language.annotations import rule_references
from gaitgram.language.diagnostics import Applicability, Code, Diagnostic, Fix, Severity, TextEdit
from gaitgram.language.edits import blank_end, line_end, removal, union
from gaitgram.language.model import Grammar, NonTerminal, Rule
from gaitgram.language.problems import UNTERMINATED_STRING
from gaitgram.language.source import SourceText, Span

__all__ = [
    "CODES",
    "DUPLICATE_RULE",
    "START_DERIVES_NOTHING",
    "UNDEFINED_RULE",
    "UNIT_RULE_CHAIN",
    "UNPRODUCTIVE_RULE",
    "UNREACHABLE_RULE",
    "duplicate_rules",
    "undefined_rules",
    "unit_rule_chains",
    "unproductive_rules",
    "unreachable_rules",
]

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO  # noqa: E741 (short names keep the table readable)
UNSAFE = Applicability.UNSAFE

UNDEFINED_RULE = Code(
    "GG201",
    "undefined-rule",
    E,
    "a non-terminal that no rule defines",
    "A non-terminal names a rule that does not exist: define the rule, or correct the name.",
    fix=UNSAFE,
    fix_help="Replaces the name with the nearest defined one (preferred; up to three are offered), or "
    "defines the rule, `<name> ::= ''`, after the rule that uses it.",
)
DUPLICATE_RULE = Code(
    "GG202",
    "duplicate-rule",
    E,
    "a rule defined more than once",
    "Only the first definition of a rule counts. Merge the alternatives into one rule with |, or "
    "rename one of the rules.",
    fix=UNSAFE,
    fix_help="Merges the alternatives into the first definition (preferred, when the duplicate has no "
    "annotations), or deletes the ignored definition.",
)
UNPRODUCTIVE_RULE = Code(
    "GG203",
    "unproductive-rule",
    E,
    "a rule that can never derive a terminal string",
    "Every alternative of the rule needs a rule that cannot finish, so no derivation through it "
    "ends. Add an alternative that ends, such as a terminal.",
)
UNREACHABLE_RULE = Code(
    "GG204",
    "unreachable-rule",
    W,
    "a rule the start rule never reaches",
    "No derivation from the start rule uses this rule. Delete it, or use it from a rule the start "
    "rule reaches.",
    fix=UNSAFE,
    fix_help="Deletes the rule with its annotations, together with the unreachable rules that use it, so no "
    "reference is left undefined (not offered when a reachable rule's ignored duplicate uses it). The"
    " editor also offers one fix removing every unreachable rule.",
    fix_all="Remove all {n} unreachable rules",
    unnecessary=True,
)
START_DERIVES_NOTHING = Code(
    "GG205",
    "start-derives-nothing",
    E,
    "the start rule can never derive a terminal string",
    "No derivation from the start rule ever ends, so no genome maps to a phenotype. Give some "
    "rule on the way an alternative that ends.",
)
UNIT_RULE_CHAIN = Code(
    "GG206",
    "unit-rule-chain",
    I,
    "a rule whose only alternative is another rule",
    "A rule whose only alternative is another rule adds a derivation step (and, in eager mode, "
    "reads a codon). Use the other rule directly.",
)
CODES = (
    UNDEFINED_RULE,
    DUPLICATE_RULE,
    UNPRODUCTIVE_RULE,
    UNREACHABLE_RULE,
    START_DERIVES_NOTHING,
    UNIT_RULE_CHAIN,
)


def undefined_rules(grammar: Grammar, facts: GrammarFacts) -> Iterator[Diagnostic]:
    defined = grammar.rules_by_name
    near = _Nearest(list(defined))

    for rule in grammar.rules:
        for ref in rule.references():
            if ref.name not in defined:
                close = near(ref.name)
                span = rule.span_of(ref)
                yield UNDEFINED_RULE(
                    f"<{ref.name}> is not defined",
                    span,
                    rule=rule.name,
                    hint=f"did you mean <{close[0]}>?" if close else f"define it: <{ref.name}> ::= ...",
                    fixes=partial(_undefined_fixes, grammar, ref.name, span, rule, close),
                    data={"name": ref.name},
                )
    for annotation in grammar.annotations:
        for name, span in rule_references(annotation):
            if name not in defined:
                close = near(name)
                yield UNDEFINED_RULE(
                    f"@{annotation.name} names <{name}>, which is not defined",
                    span,
                    hint=f"did you mean <{close[0]}>?" if close else "name a rule this file defines",
                    fixes=partial(_undefined_fixes, grammar, name, span, None, close),
                    data={"name": name},
                )


def _undefined_fixes(
    grammar: Grammar, name: str, where: Span, user: Rule | None, nearest: list[str]
) -> list[Fix]:
    """Define the rule (after the rule that uses it, or at the end), or use a name that exists."""
    text = grammar.source.text
    at = len(text)
    if user is not None:
        after = blank_end(text, user.span.end)
        if after == len(text) or text[after] in "\n#":  # nothing else on its last line
            at = line_end(grammar.source, after)
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
    open_ends = _OpenStrings(grammar)
    for rule in grammar.rules:
        original = first[rule.name]
        if rule is not original:
            line = grammar.source.location(original.name_span.start).line
            yield DUPLICATE_RULE(
                f"<{rule.name}> is already defined on line {line}; this definition is ignored",
                rule.name_span,
                rule=rule.name,
                hint="merge the alternatives into one rule with |, or rename one of them",
                fixes=partial(_duplicate_fixes, grammar, original, rule, open_ends),
                data={"name": rule.name},
            )


class _OpenStrings:
    """Where the grammar's unterminated strings end, found once when a fix first asks (not once
    per duplicate: thousands of duplicates and strings would cost their product)."""

    def __init__(self, grammar: Grammar) -> None:
        self.grammar = grammar
        self._ends: frozenset[int] | None = None

    def __contains__(self, offset: int) -> bool:
        if self._ends is None:
            diagnostics = self.grammar.diagnostics
            self._ends = frozenset(d.span.end for d in diagnostics if d.code is UNTERMINATED_STRING)
        return offset in self._ends


def _duplicate_fixes(grammar: Grammar, original: Rule, duplicate: Rule, open_ends: _OpenStrings) -> list[Fix]:
    """Merge the ignored definition's alternatives into the first one, or delete it."""
    text = grammar.source.text
    gone = _rule_removal(grammar.source, duplicate)
    fixes = []
    # Text added after an unterminated string would be part of it.
    if duplicate.alternatives and not duplicate.annotations and original.span.end not in open_ends:
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


def _rule_removal(text: SourceText, rule: Rule) -> Span:
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
            yield START_DERIVES_NOTHING(
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
        yield UNPRODUCTIVE_RULE(
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
    removals = _Removals(grammar, unreachable, users, definitions)
    for rule in grammar.rules_by_name.values():
        if rule.name in unreachable:
            yield UNREACHABLE_RULE(
                f"<{rule.name}> is unreachable: the start rule <{start}> never uses it",
                rule.name_span,
                rule=rule.name,
                hint=f"delete it, or use it from a rule that <{start}> reaches",
                fixes=partial(removals.fixes, rule.name),
                data={"name": rule.name},
            )


#: A removal that would take more rules with it than this is not offered.
MAX_REMOVED_WITH = 50


class _Removals:
    """The fixes that delete unreachable rules: each rule with every unreachable rule that uses
    it, directly or not (so that no reference is left undefined), or none if a reachable rule
    uses one of them or more than :data:`MAX_REMOVED_WITH` would go.

    Computed when asked for (JSON and editors ask for all of them, text output for none), each
    rule's set once: a rule's set holds the sets of the rules that use it, so a grammar of
    thousands of unreachable rules costs set unions, not a search per rule."""

    def __init__(
        self,
        grammar: Grammar,
        unreachable: set[str],
        users: dict[str, list[Rule]],
        definitions: dict[str, list[Rule]],
    ) -> None:
        self.grammar = grammar
        self.unreachable = unreachable
        self.users = {name: {user.name for user in found} for name, found in users.items()}
        self.definitions = definitions
        self._with: dict[str, frozenset[str] | None] = {}  # None: no fix
        self._spans: dict[str, list[Span]] = {}  # each name's definitions: a chain of n rules is in n fixes
        self._edits: dict[Span, TextEdit] = {}  # one object per edit, however many fixes hold it

    def removed_with(self, name: str) -> frozenset[str] | None:
        """``name`` and the unreachable rules that use it, or None if they cannot all go."""
        if name in self._with:
            return self._with[name]
        removed = {name}
        frontier = [name]
        found: frozenset[str] | None = None
        while frontier:
            for user in self.users.get(frontier.pop(), ()):
                if user in removed:
                    continue
                if user not in self.unreachable:
                    break
                known = self._with.get(user, ())
                if known is None:  # it cannot go, and it would have to
                    break
                if known:
                    removed |= known  # every user of those is in it already
                else:
                    removed.add(user)
                    frontier.append(user)
                if len(removed) > MAX_REMOVED_WITH:
                    break
            else:
                continue
            break
        else:
            found = frozenset(removed)
        self._with[name] = found
        return found

    def fixes(self, name: str) -> list[Fix]:
        removed = self.removed_with(name)
        if removed is None:
            return []
        spans = []
        for n in removed:
            found = self._spans.get(n)
            if found is None:
                source = self.grammar.source
                found = self._spans[n] = [_rule_removal(source, rule) for rule in self.definitions[n]]
            spans += found
        edits = []
        for span in union(spans) if len(spans) > 1 else spans:
            edit = self._edits.get(span)
            if edit is None:
                edit = self._edits[span] = TextEdit(span, "")
            edits.append(edit)
        others = len(removed) - 1
        title = f"Remove unreachable <{name}>"
        if others:
            title += f" and the {'rule' if others == 1 else f'{others} rules'} using it"
        return [Fix(title, tuple(edits), Applicability.UNSAFE, preferred=True)]


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
            yield UNIT_RULE_CHAIN(
                f"<{rule.name}> only renames <{target}>",
                rule.name_span,
                rule=rule.name,
                hint=f"use <{target}> directly; in eager mode the extra step reads a codon",
            )


#: Name comparisons (difflib's) all the did-you-mean hints of one check may make: each missing
#: name is compared with every defined one, so without a budget thousands of each cost their
#: product. A name past the budget is matched only case-insensitively.
NEAREST_BUDGET = 100_000
#: Names longer than this are matched only case-insensitively (difflib is quadratic in length).
NEAREST_LONGEST = 64


class _Nearest:
    """Up to three defined names close to a missing one, closest first, each name looked up once."""

    def __init__(self, names: list[str]) -> None:
        self.names = names
        self.budget = NEAREST_BUDGET
        self._found: dict[str, list[str]] = {}  # a missing name is often used many times
        self._folded: dict[str, list[str]] | None = None

    def __call__(self, name: str) -> list[str]:
        found = self._found.get(name)
        if found is None:
            if len(name) <= NEAREST_LONGEST and len(self.names) <= self.budget:
                self.budget -= len(self.names)
                found = get_close_matches(name, self.names, n=3, cutoff=0.6)
            else:
                found = self._same_but_case(name)
            self._found[name] = found
        return found

    def _same_but_case(self, name: str) -> list[str]:
        if self._folded is None:
            self._folded = {}
            for candidate in self.names:
                self._folded.setdefault(candidate.lower(), []).append(candidate)
        return self._folded.get(name.lower(), [])[:3]
