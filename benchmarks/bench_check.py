"""``gaitgram check`` speed: parse + all analyses + lint, against PonyGE2's regex reader.

The baseline only *reads* a grammar (PonyGE2's three regular expressions, no
analysis at all), so a ratio near 1 means the full check costs about what
PonyGE2 pays merely to load. Target: a 10,000-rule grammar checked in under 1 s.
"""

from __future__ import annotations

import random
import re
from pathlib import Path

from benchmarks._timing import measure, row
from gaitgram.analysis import check
from gaitgram.language import parse

ROOT = Path(__file__).resolve().parents[1]

_RULE = re.compile(
    r"(?P<rulename><\S+>)\s*::=\s*(?P<production>(?:(?=\#)\#[^\r\n]*|(?!<\S+>\s*::=).+?)+)", re.DOTALL
)
_PRODUCTION = re.compile(
    r"(?=\#)(?:\#.*$)|(?!\#)\s*(?P<production>(?:[^'\"\|\#]+|'.*?'|\".*?\")+)", re.MULTILINE
)
_PARTS = re.compile(r"\ *([\r\n]+)\ *|([^'\"<\r\n]+)|'(.*?)'|\"(.*?)\"|(?P<subrule><[^>|\s]+>)|([<]+)")


def ponyge2_read(text: str) -> dict[str, list[list[str]]]:
    """PonyGE2's reading loop, reduced to its regex work (no escapes, no analysis)."""
    rules: dict[str, list[list[str]]] = {}
    for rule in _RULE.finditer(text):
        productions = []
        for p in _PRODUCTION.finditer(rule.group("production")):
            production = p.group("production")
            if production is None or production.isspace():
                continue
            productions.append([m.group(0) for m in _PARTS.finditer(production.strip())])
        rules[rule.group("rulename")] = productions
    return rules


def generated_grammar(rules: int, seed: int = 1) -> str:
    """A random, acyclic, productive grammar of ``rules`` rules (about 37 bytes per rule)."""
    rng = random.Random(seed)
    lines = ["@start <r0>"]
    for i in range(rules):
        alternatives = []
        for _ in range(rng.randint(1, 4)):
            parts = [
                f"<r{rng.randint(i + 1, rules - 1)}>"
                if i < rules - 1 and rng.random() < 0.5
                else rng.choice(["x", "+", "sin(", "1.5", ")"])
                for _ in range(rng.randint(0, 3))
            ]
            alternatives.append(" ".join(parts) or "t")
        lines.append(f"<r{i}> ::= " + " | ".join(alternatives))
    return "\n".join(lines) + "\n"


def main() -> None:
    inputs = {
        "Dow.bnf (PonyGE2, 2 rules)": (ROOT / "tests/data/ponyge2/Dow.bnf").read_text(),
        "Word_Stats.bnf (42 rules)": (ROOT / "tests/data/ponyge2/Word_Stats.bnf").read_text(),
        "generated, 1,000 rules": generated_grammar(1_000),
        "generated, 10,000 rules": generated_grammar(10_000),
    }
    print("check = parse + analyses + lint; baseline = PonyGE2's regex reader (reading only)")
    for label, text in inputs.items():
        ours = measure(lambda text=text: check(parse(text)), runs=5)
        baseline = measure(lambda text=text: ponyge2_read(text), runs=5)
        print(row(label, ours, baseline, "ponyge2-read"))
