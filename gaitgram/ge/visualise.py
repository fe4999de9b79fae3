"""Derivation trees for people: ASCII for the terminal, Graphviz DOT and SVG, Mermaid.

Each rule node shows the codon that chose it (``#index=value``, the genome
position is ``index % len(genome)``); a lazy single-choice rule read none.
Nothing recurses, so a tree as deep as a long genome renders fine.
"""

from __future__ import annotations

import shutil
import subprocess

from gaitgram.ge.derivation import Derivation, Node


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
