"""Every PonyGE2 grammar reads as PonyGE2 reads it.

The reference is an independent, straightforward reading built on PonyGE2's own
three regular expressions (``src/representation/grammar.py``): rules, their
productions, and the parts of a production. gaitgram's lark-based reader must
give the same rules, in the same order, with the same productions.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

from conftest import VECTOR_DEFINES
from gaitgram.analysis import build_cfg
from gaitgram.analysis.cfg import RuleKind
from gaitgram.language import load, parse

RULE = re.compile(
    r"(?P<rulename><\S+>)\s*::=\s*(?P<production>(?:(?=\#)\#[^\r\n]*|(?!<\S+>\s*::=).+?)+)", re.DOTALL
)
PRODUCTION = re.compile(
    r"(?=\#)(?:\#.*$)|(?!\#)\s*(?P<production>(?:[^'\"\|\#]+|'.*?'|\".*?\")+)", re.MULTILINE
)
PARTS = re.compile(r"\ *([\r\n]+)\ *|([^'\"<\r\n]+)|'(.*?)'|\"(.*?)\"|(?P<subrule><[^>|\s]+>)|([<]+)")

Symbol = tuple[str, str]  # ("T", text) or ("NT", name)


def ponyge2_reading(text: str, defines: dict[str, int]) -> list[tuple[str, list[list[Symbol]]]]:
    with warnings.catch_warnings():  # unicode-escape warns about PCRE's \d; PonyGE2 ignores it
        warnings.simplefilter("ignore", DeprecationWarning)
        return _ponyge2_reading(text, defines)


def _ponyge2_reading(text: str, defines: dict[str, int]) -> list[tuple[str, list[list[Symbol]]]]:
    rules = []
    for rule in RULE.finditer(text):
        productions: list[list[Symbol]] = []
        for p in PRODUCTION.finditer(rule.group("production")):
            production = p.group("production")
            if production is None or production.isspace():
                continue
            ge_range = re.match(r"GE_RANGE:(.*)", production)
            if ge_range:
                size = ge_range.group(1).strip()
                n = int(size) if size.isdigit() else defines[size]
                productions += [[("T", str(i))] for i in range(n)]
                continue
            symbols: list[Symbol] = []
            terminal: str | None = None
            for part in PARTS.finditer(production.strip()):
                if part.group("subrule"):
                    if terminal is not None:
                        symbols.append(("T", terminal))
                        terminal = None
                    symbols.append(("NT", part.group("subrule")[1:-1]))
                else:
                    decoded = "".join(g.encode().decode("unicode-escape") for g in part.groups() if g)
                    terminal = decoded if terminal is None else terminal + decoded
            if terminal is not None:
                symbols.append(("T", terminal))
            productions.append(symbols)
        rules.append((rule.group("rulename")[1:-1], productions))
    return rules


def gaitgram_reading(path: Path) -> list[tuple[str, list[list[Symbol]]]]:
    grammar = load(path, defines=VECTOR_DEFINES)
    assert not grammar.has_errors, grammar.diagnostics
    cfg = build_cfg(grammar)
    rules = []
    for name, kind, choices in zip(cfg.names, cfg.kinds, cfg.choices, strict=True):
        if kind is RuleKind.DEFINED:
            rules.append(
                (
                    name,
                    [[("NT", cfg.names[i]) if isinstance(i, int) else ("T", i) for i in c] for c in choices],
                )
            )
    return rules


def test_vector_grammar_reads_as_in_ponyge2(vector_grammar: Path) -> None:
    expected = ponyge2_reading(vector_grammar.read_text(), VECTOR_DEFINES)
    assert expected, "the reference found no rules"
    assert gaitgram_reading(vector_grammar) == expected


def test_vector_grammar_start_rule_is_first_rule(vector_grammar: Path) -> None:
    grammar = load(vector_grammar, defines=VECTOR_DEFINES)
    assert grammar.start == grammar.rules[0].name


@pytest.mark.parametrize(
    "text",
    [
        "<e> ::= <e> + <e> | x",
        "<e> ::= a|b |  c  \n   | d",
        "<s> ::= 'a|b' | \"<x>\" | '#'",
        "<s> ::= x # comment\n  | y",
        "<s> ::= line one\n    line two | z",
        "<s> ::= \\t tab\\n | '\\u00e9'",
        "<s> ::= '' | a",
        "<a> ::= <b>\n<b> ::= x y  z",
        "<s> ::= a < b | c<<d",
        "<s> ::= GE_RANGE:3 | x",
    ],
)
def test_reading_rules(text: str) -> None:
    grammar = parse(text)
    cfg = build_cfg(grammar)
    ours = [
        (name, [[("NT", cfg.names[i]) if isinstance(i, int) else ("T", i) for i in c] for c in choices])
        for name, kind, choices in zip(cfg.names, cfg.kinds, cfg.choices, strict=True)
        if kind is not RuleKind.UNDEFINED
    ]
    assert ours == ponyge2_reading(text, {})
