"""Derivation trees rendered as ASCII, DOT, SVG and Mermaid."""

from __future__ import annotations

import shutil

import pytest

from gaitgram.ge import compile_mapper
from gaitgram.ge.visualise import GraphvizMissing, ascii_tree, dot_tree, mermaid_tree, svg_tree
from gaitgram.language import parse

GRAMMAR = parse('<e> ::= <e>+<v> | <v>\n<v> ::= x | "y"')


def derivation():
    return compile_mapper(GRAMMAR).map([0, 1, 1, 0])


def test_ascii_tree_shows_rules_codons_and_terminals() -> None:
    assert ascii_tree(derivation()) == (
        "<e> #0=0 -> 0\n"
        "├── <e> #1=1 -> 1\n"
        "│   └── <v> #2=1 -> 1\n"
        "│       └── 'y'\n"
        "├── '+'\n"
        "└── <v> #3=0 -> 0\n"
        "    └── 'x'\n"
    )


def test_dot_and_mermaid_have_every_node_and_edge() -> None:
    d = derivation()
    dot = dot_tree(d)
    assert dot.startswith("digraph derivation {")
    assert sum(line.startswith("  n") and " -> n" in line for line in dot.splitlines()) == 6
    assert dot.count(" [label=") == 7
    mermaid = mermaid_tree(d)
    assert mermaid.startswith("flowchart TD")
    assert mermaid.count("-->") == 6


def test_deep_trees_render_without_recursion() -> None:
    deep = compile_mapper(parse("<e> ::= (<e>) | x"), max_wraps=0).map([0] * 5000 + [1])
    assert deep.valid
    lines = ascii_tree(deep).splitlines()
    assert len(lines) == 5001 + 2 * 5000 + 1  # rule nodes, "(" and ")" leaves, the final "x"


@pytest.mark.skipif(shutil.which("dot") is None, reason="needs Graphviz's dot; .ci/run installs it")
def test_svg_through_graphviz() -> None:
    svg = svg_tree(derivation())
    assert "<svg" in svg
    assert "&lt;e&gt; #0=0" in svg


def test_svg_without_graphviz_says_how_to_get_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(GraphvizMissing, match="apt-get install graphviz"):
        svg_tree(derivation())
