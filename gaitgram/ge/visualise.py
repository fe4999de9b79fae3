"""Derivation trees for people: ASCII for the terminal, Graphviz DOT and SVG, Mermaid.

Each rule node shows the codon that chose it (``#index=value``, the genome
position is ``index % len(genome)``); a lazy single-choice rule read none.
Nothing recurses, so a tree as deep as a long genome renders fine; but a long
genome with wraps can derive millions of nodes, so :func:`check_derivation_size`
refuses one before it is built, and :func:`render_tree` before any of it is drawn.
"""

from __future__ import annotations

import shutil
import subprocess

from gaitgram.ge.derivation import Derivation, Node

#: The most nodes (rules and terminals) a drawn tree may have. Trees are drawn for people to
#: read: 100,000 nodes is already megabytes of text, and ``<e> ::= <e><e> | x`` with a
#: long genome and wraps reaches millions (ASCII at ~60 bytes a node, plus indentation).
MAX_TREE_NODES = 100_000
#: An ASCII tree indents each node by its depth, so a deep, thin tree (a left-recursive
#: chain) grows as nodes times depth: refused past this many characters of indentation.
MAX_ASCII_INDENT = 50_000_000
#: The most codons a derivation built in full (by ``gaitgram map``) may read: a rule node
#: each, about 0.5 GB of tree at this limit. GE genomes are hundreds to thousands of codons.
MAX_DERIVATION_CODONS = 1_000_000


class TreeTooLarge(ValueError):
    """A tree too large to draw or to build; refused before any of it is."""


class GraphvizMissing(RuntimeError):
    """SVG needs Graphviz's ``dot``."""

    def __init__(self) -> None:
        super().__init__(
            "SVG output needs Graphviz's `dot` program, which is not installed "
            "(Debian/Ubuntu: sudo apt-get install graphviz); --tree dot writes the DOT source instead"
        )


def _node_label(derivation: Derivation, node: Node) -> str:
    if node.is_terminal:
        return repr(node.symbol)
    label = derivation.label(node)
    if node.choice is None:
        return f"{label} (unexpanded)"
    if node.codon_index is None:
        return label
    return f"{label} #{node.codon_index}={node.codon} -> {node.choice}"


def ascii_tree(derivation: Derivation) -> str:
    """An indented tree with box-drawing branches, one node per line."""
    lines: list[str] = []
    stack: list[tuple[Node, str, bool, bool]] = [(derivation.tree, "", True, True)]
    while stack:
        node, prefix, last, root = stack.pop()
        branch = "" if root else ("└── " if last else "├── ")
        lines.append(prefix + branch + _node_label(derivation, node))
        child_prefix = prefix if root else prefix + ("    " if last else "│   ")
        count = len(node.children)
        for i in range(count - 1, -1, -1):
            stack.append((node.children[i], child_prefix, i == count - 1, False))
    return "\n".join(lines) + "\n"


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def dot_tree(derivation: Derivation) -> str:
    """Graphviz DOT: rule nodes as ellipses, terminals as boxes, in left-to-right order."""
    lines = [
        "digraph derivation {",
        '  graph [ordering=out, fontname="Helvetica"];',
        '  node [fontname="Helvetica", fontsize=11];',
    ]
    ids: dict[int, str] = {}
    for number, (node, _) in enumerate(derivation.tree.walk()):
        ids[id(node)] = f"n{number}"
        shape = 'box, style=filled, fillcolor="#eef6ee"' if node.is_terminal else "ellipse"
        lines.append(f"  n{number} [label={_quote(_node_label(derivation, node))}, shape={shape}];")
    for node, _ in derivation.tree.walk():
        for child in node.children:
            lines.append(f"  {ids[id(node)]} -> {ids[id(child)]};")
    lines.append("}")
    return "\n".join(lines) + "\n"


def mermaid_tree(derivation: Derivation) -> str:
    """A Mermaid flowchart (renders on GitHub and in many Markdown viewers)."""
    lines = ["flowchart TD"]
    ids: dict[int, str] = {}
    for number, (node, _) in enumerate(derivation.tree.walk()):
        ids[id(node)] = f"n{number}"
        text = _node_label(derivation, node).replace('"', "#quot;").replace("\n", "\\n")
        lines.append(f'  n{number}["{text}"]' if not node.is_terminal else f'  n{number}(["{text}"])')
    for node, _ in derivation.tree.walk():
        for child in node.children:
            lines.append(f"  {ids[id(node)]} --> {ids[id(child)]}")
    return "\n".join(lines) + "\n"


def svg_tree(derivation: Derivation, *, timeout: float = 60.0) -> str:
    """SVG drawn by Graphviz's ``dot``; raises :class:`GraphvizMissing` when it is absent."""
    dot = shutil.which("dot")
    if dot is None:
        raise GraphvizMissing
    result = subprocess.run(
        [dot, "-Tsvg"],
        input=dot_tree(derivation),
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    if result.returncode != 0:
        raise RuntimeError(f"dot failed: {result.stderr.strip()}")
    return result.stdout


RENDERERS = {"ascii": ascii_tree, "dot": dot_tree, "mermaid": mermaid_tree, "svg": svg_tree}


def check_derivation_size(used_codons: int, *, drawn: bool) -> None:
    """Raise :class:`TreeTooLarge` before a derivation tree is built that is too large to draw
    (``drawn``) or to hold at all: each codon read (as
    :meth:`~gaitgram.ge.mapper.Mapper.map_fast` counts them, in a fraction of the time and no
    memory) makes a rule node, of about 0.5 kB with its children."""
    if drawn and used_codons > MAX_TREE_NODES:
        raise TreeTooLarge(
            f"the derivation tree has more than {MAX_TREE_NODES:,} nodes, the most a tree is drawn with"
        )
    if used_codons > MAX_DERIVATION_CODONS:
        raise TreeTooLarge(
            f"the derivation reads {used_codons:,} codons; its tree would need about "
            f"{used_codons * 500 / 1e9:.1f} GB, and derivations over {MAX_DERIVATION_CODONS:,} codons "
            "are refused"
        )


def render_tree(
    derivation: Derivation,
    style: str,
    *,
    max_nodes: int = MAX_TREE_NODES,
    max_indent: int = MAX_ASCII_INDENT,
) -> str:
    """``RENDERERS[style](derivation)``, or :class:`TreeTooLarge` after one cheap walk
    that stops at the first node over the limit."""
    indent = deepest = 0
    for nodes, (_, level) in enumerate(derivation.tree.walk(), start=1):
        if nodes > max_nodes:
            raise TreeTooLarge(
                f"the derivation tree has more than {max_nodes:,} nodes, the most a tree is drawn with"
            )
        indent += 4 * (level - 1)
        deepest = max(deepest, level)
    if style == "ascii" and indent > max_indent:
        raise TreeTooLarge(
            f"the derivation tree is {deepest:,} levels deep: its ASCII drawing would be over "
            f"{indent / 1e6:,.0f} MB of indentation alone (dot and mermaid do not indent)"
        )
    return RENDERERS[style](derivation)
