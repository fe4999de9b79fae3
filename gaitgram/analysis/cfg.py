"""A grammar as integer tables: the form analyses and mappers work on.

Each rule is an index; each choice is a tuple of items, an ``int`` for a rule
and a ``str`` for terminal text. Typed ranges are expanded here:

* an alternative that is a range on its own becomes one choice per value of
  its rule (PonyGE2's ``GE_RANGE`` does the same);
* a range inside a longer alternative becomes a *range rule*, an anonymous rule
  whose choices are the values, shared by every use of the same range.

References to undefined names become *undefined rules* with no choices, so
tables are always well-formed; the linter reports them.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

from gaitgram.language.model import Grammar, NonTerminal, RangeSpec, RangeSymbol, Terminal

__all__ = ["Cfg", "Item", "RuleKind", "build_cfg"]

Item = int | str


class RuleKind(IntEnum):
    DEFINED = 0
    RANGE = 1
    UNDEFINED = 2


@dataclass(frozen=True, eq=False)
class Cfg:
    names: tuple[str, ...]
    kinds: tuple[RuleKind, ...]
    choices: tuple[tuple[tuple[Item, ...], ...], ...]
    #: For each rule and choice, the index of the alternative it comes from.
    alternative_of: tuple[tuple[int, ...], ...]
    start: int | None
    index: dict[str, int]

    def __len__(self) -> int:
        return len(self.names)

    def children(self, rule: int) -> set[int]:
        return {item for choice in self.choices[rule] for item in choice if isinstance(item, int)}


def build_cfg(grammar: Grammar) -> Cfg:
    rules = list(grammar.rules_by_name.values())
    index: dict[str, int] = {rule.name: i for i, rule in enumerate(rules)}
    names = [rule.name for rule in rules]
    kinds = [RuleKind.DEFINED] * len(rules)
    choices: list[tuple[tuple[Item, ...], ...]] = []
    origins: list[tuple[int, ...]] = []
    extra_choices: dict[int, tuple[tuple[Item, ...], ...]] = {}
    range_rules: dict[str, int] = {}

    def added(name: str, kind: RuleKind, rule_choices: tuple[tuple[Item, ...], ...]) -> int:
        """A rule the grammar does not define (an undefined name, a range), numbered after the rest."""
        names.append(name)
        kinds.append(kind)
        extra_choices[len(names) - 1] = rule_choices
        return len(names) - 1

    def rule_for(symbol: NonTerminal) -> int:
        found = index.get(symbol.name)
        if found is None:
            found = index[symbol.name] = added(symbol.name, RuleKind.UNDEFINED, ())
        return found

    def range_rule(spec: RangeSpec) -> int:
        found = range_rules.get(spec.text)
        if found is None:
            found = range_rules[spec.text] = added(
                spec.text, RuleKind.RANGE, tuple((value,) for value in spec.values)
            )
        return found

    for rule in rules:
        rule_choices: list[tuple[Item, ...]] = []
        rule_origins: list[int] = []
        for a, alternative in enumerate(rule.alternatives):
            spec = alternative.range_values
            if spec is not None:
                rule_choices.extend((value,) for value in spec.values)
                rule_origins.extend([a] * spec.size)
                continue
            items: list[Item] = []
            for symbol in alternative.symbols:
                if isinstance(symbol, Terminal):
                    items.append(symbol.text)
                elif isinstance(symbol, NonTerminal):
                    items.append(rule_for(symbol))
                else:
                    assert isinstance(symbol, RangeSymbol)
                    items.append(range_rule(symbol.spec))
            rule_choices.append(tuple(items))
            rule_origins.append(a)
        choices.append(tuple(rule_choices))
        origins.append(tuple(rule_origins))

    for i in range(len(rules), len(names)):
        choices.append(extra_choices[i])
        origins.append(tuple(range(len(extra_choices[i]))))

    start = index.get(grammar.start) if grammar.start is not None else None
    if start is not None and kinds[start] is not RuleKind.DEFINED:
        start = None
    return Cfg(tuple(names), tuple(kinds), tuple(choices), tuple(origins), start, index)
