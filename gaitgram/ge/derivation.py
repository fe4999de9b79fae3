"""What mapping a genome produces: a derivation tree and its summary.

Trees can be as deep as the genome is long (a left-recursive rule nests once
per codon), so nothing here recurses: equality, traversal and text are loops
over explicit stacks.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any


class InvalidReason(StrEnum):
    """Why a genome maps to no phenotype. Invalid individuals are values, not errors."""

    #: More than ``len(genome) * (max_wraps + 1)`` codons would be read.
    CODONS = "codons"
    #: A rule node would lie deeper than ``max_depth``.
    DEPTH = "depth"
    #: The derivation reached a rule with no choices (undefined, or all alternatives empty).
    UNDEFINED = "undefined"
    #: Lazy mode without a depth limit: a chain of single-choice rules that expands forever
    #: without reading a codon (GEVA would hang here).
    NONTERMINATING = "nonterminating"


class Node:
    """One node of a derivation tree.

    ``symbol`` is a rule index (into ``Derivation.rule_names``) or, for a leaf,
    terminal text. ``choice`` is the index of the choice taken; ``codon_index``
    the read position that chose it (counting across wraps, so the genome
    position is ``codon_index % len(genome)``) and ``codon`` its value; both are
    None for terminals and for single-choice rules in lazy mode. A rule node
    with ``choice`` None was never expanded (the derivation stopped there).
    """

    __slots__ = ("children", "choice", "codon", "codon_index", "symbol")

    def __init__(
        self,
        symbol: int | str,
        choice: int | None = None,
        codon_index: int | None = None,
        codon: int | None = None,
        children: list[Node] | None = None,
    ) -> None:
        self.symbol = symbol
        self.choice = choice
        self.codon_index = codon_index
        self.codon = codon
        self.children: list[Node] = [] if children is None else children

    @property
    def is_terminal(self) -> bool:
        return isinstance(self.symbol, str)

    def walk(self) -> Iterator[tuple[Node, int]]:
        """Every node in pre-order (the order the mapper expanded them), with its depth (root 1)."""
        stack: list[tuple[Node, int]] = [(self, 1)]
        while stack:
            node, level = stack.pop()
            yield node, level
            stack.extend((child, level + 1) for child in reversed(node.children))

    def text(self) -> str:
        """The terminals under this node, in order: the phenotype of this subtree."""
        return "".join(n.symbol for n, _ in self.walk() if isinstance(n.symbol, str))

    def __eq__(self, other: object) -> bool:
        """Same derivation: same symbols and choices everywhere (codon values may differ,
        since many codons select the same choice)."""
        if not isinstance(other, Node):
            return NotImplemented
        pairs = [(self, other)]
        while pairs:
            a, b = pairs.pop()
            if a.symbol != b.symbol or a.choice != b.choice or len(a.children) != len(b.children):
                return False
            pairs.extend(zip(a.children, b.children, strict=True))
        return True

    __hash__ = None  # type: ignore[assignment]  # mutable

    def __repr__(self) -> str:
        if isinstance(self.symbol, str):
            return f"Node({self.symbol!r})"
        return f"Node(rule={self.symbol}, choice={self.choice}, children={len(self.children)})"


@dataclass(eq=False)
class Derivation:
    """The result of mapping one genome: phenotype, tree and the statistics GE reports.

    ``wraps`` is ``(used_codons - 1) // len(genome)`` (0 when nothing was read),
    the convention of the PonyGE2 vectors; ``depth`` counts rule nodes only (a
    rule that derives terminals only has depth 1, as in the grammar analyses);
    ``nodes`` is the number of rule nodes. For an invalid genome ``phenotype``
    is None, ``joints`` is empty and ``tree`` is the partial tree built so far.
    """

    phenotype: str | None
    used_codons: int
    wraps: int
    depth: int
    nodes: int
    tree: Node
    joints: dict[str, str] = field(default_factory=dict)
    reason: InvalidReason | None = None
    rule_names: tuple[str, ...] = ()
    genome_length: int = 0

    @property
    def valid(self) -> bool:
        return self.reason is None

    def label(self, node: Node) -> str:
        """A node's display name: ``<rule>`` or the terminal text."""
        if isinstance(node.symbol, str):
            return node.symbol
        return f"<{self.rule_names[node.symbol]}>"

    def summary(self) -> dict[str, Any]:
        """The JSON-ready record ``gaitgram map --json`` prints (everything but the tree)."""
        return {
            "phenotype": self.phenotype,
            "valid": self.valid,
            "reason": None if self.reason is None else str(self.reason),
            "used_codons": self.used_codons,
            "wraps": self.wraps,
            "depth": self.depth,
            "nodes": self.nodes,
            "joints": dict(self.joints),
        }
