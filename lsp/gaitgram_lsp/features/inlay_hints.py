"""Inlay hints: after each rule's name, how many choices it has and whether it reads a codon.

In lazy mode (the default, GEVA's) a rule with one choice reads no codon; in eager mode
(PonyGE2's) every expansion reads one. A typed range inside a longer alternative is an
anonymous choice of its own, so it gets a hint too.
"""

from __future__ import annotations

from lsprotocol import types

from gaitgram.language.model import RangeSymbol
from gaitgram_lsp.documents import Snapshot


def label(choices: int) -> str:
    if choices == 1:
        return "1 choice, no codon (lazy)"
    return f"{choices:,} choices, 1 codon"


def inlay_hints(snapshot: Snapshot, start: int, end: int) -> list[types.InlayHint]:
    """Hints for the rules that overlap ``[start, end]``."""
    result = snapshot.result
    positions = snapshot.positions
    hints = []
    for rule in result.grammar.rules:
        if rule.span.end < start:
            continue
        if rule.span.start > end:
            break
        facts = result.facts.rule(rule.name)
        if facts is not None and result.grammar.rule(rule.name) is rule and rule.alternatives:
            hints.append(
                types.InlayHint(
                    position=positions.position(rule.name_span.end),
                    label=label(facts.choices),
                    padding_left=True,
                    tooltip="each choice is one alternative, or one value of a typed range that is one",
                )
            )
        for alternative in rule.alternatives:
            if alternative.range_values is not None:
                continue
            for symbol in alternative.symbols:
                if isinstance(symbol, RangeSymbol):
                    hints.append(
                        types.InlayHint(
                            position=positions.position(symbol.span.end),
                            label=f"{symbol.spec.size:,} values, 1 codon",
                            padding_left=True,
                        )
                    )
    return hints
