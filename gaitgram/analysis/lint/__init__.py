"""The linter: problems with a grammar's meaning, from its model and facts.

Each check is a small function from (grammar, facts) to diagnostics, kept with the codes it
reports (:mod:`~gaitgram.analysis.lint.rule_checks` for rules, :mod:`~gaitgram.analysis.lint.joint_checks`
for joints and backends, :mod:`~gaitgram.analysis.lint.sensor_checks` for the names curves read);
``lint`` runs them all. Syntax problems were already found by the parser and live in
``grammar.diagnostics``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from gaitgram.analysis.facts import GrammarFacts
from gaitgram.analysis.lint.joint_checks import joints, joints_derived_once
from gaitgram.analysis.lint.rule_checks import (
    duplicate_rules,
    undefined_rules,
    unit_rule_chains,
    unproductive_rules,
    unreachable_rules,
)
from gaitgram.analysis.lint.sensor_checks import motion_names
from gaitgram.language.diagnostics import Diagnostic
from gaitgram.language.model import Grammar

__all__ = ["CHECKS", "Check", "lint"]

Check = Callable[[Grammar, GrammarFacts], Iterator[Diagnostic]]

CHECKS: tuple[Check, ...] = (
    undefined_rules,
    duplicate_rules,
    unproductive_rules,
    unreachable_rules,
    unit_rule_chains,
    joints,
    joints_derived_once,
    motion_names,
)


def lint(grammar: Grammar, facts: GrammarFacts) -> list[Diagnostic]:
    found = [d for check in CHECKS for d in check(grammar, facts)]
    return sorted(found, key=lambda d: (d.span.start, d.code.code))
