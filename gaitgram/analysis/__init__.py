"""Analyses of a grammar: rule facts and the linter."""

from __future__ import annotations

from dataclasses import dataclass

from gaitgram.analysis.cfg import Cfg, build_cfg
from gaitgram.analysis.facts import GrammarFacts, RuleFacts, analyse
from gaitgram.analysis.lint import lint
from gaitgram.collector import without_gc
from gaitgram.language.diagnostics import Diagnostic
from gaitgram.language.model import Grammar

__all__ = ["Cfg", "CheckResult", "GrammarFacts", "RuleFacts", "analyse", "build_cfg", "check", "lint"]


@dataclass(frozen=True, eq=False)
class CheckResult:
    grammar: Grammar
    facts: GrammarFacts
    diagnostics: tuple[Diagnostic, ...]

    @property
    def errors(self) -> int:
        return sum(d.is_error for d in self.diagnostics)


@without_gc
def check(grammar: Grammar) -> CheckResult:
    """Everything ``gaitgram check`` reports: syntax problems, then the linter's."""
    facts = analyse(grammar)
    found = list(grammar.diagnostics) + lint(grammar, facts)
    found.sort(key=lambda d: (d.span.start, d.code.code))
    return CheckResult(grammar, facts, tuple(found))
