"""Mapping speed of πGE, SGE, DSGE and CFG-GP: genomes/s against a plain mapper of the same algorithm.

No other tool maps these representations on gaitgram's grammars, so each is measured against a
plain reference mapper written here, on the same genomes: the reference code's mapping algorithm,
in its shape, written plainly, giving what gaitgram's ``map`` gives (the phenotype, the tree's
depth and its number of rule nodes; as PonyGE2's ``map_ind_from_genome``, GE's yardstick, does),
checked to agree before timing. What is slow in a reference by accident is left out (a linear
``list.index`` per node, a ``pop(0)`` queue). Symbols are ``(text, "NT" | "T")`` pairs, as in
Lourenço's readers. The target (issue 41): gaitgram at least 3x the plain mapper.

* πGE: alogos' ``mapping._forward_slow``: a tree of ``Node`` objects (a node per symbol, its
  ``_expand``), a list of open nodes, ``pop(order % len)``, the new rule nodes inserted per the
  stack mode; then the leaves joined (``DerivationTree.string``).
* SGE: the original SGE's ``mapping`` over its unrolled grammar (last-level alternatives spliced in,
  as its reader makes them, and counted as the nodes they stand for): leftmost first, each rule's
  gene read with its own cursor; a stack of (symbol, depth).
* DSGE: sge3's ``_recursive_mapping``: recursive, a cursor per gene (checked against the gene's
  length, where sge3 would fill it), each call returning the largest of its children's depths.
* CFG-GP: the genome (the tree's choices in pre-order) read leftmost first with a stack of (symbol,
  depth), as the GE mapper's plain baseline reads codons (``bench_map``).

gaitgram's side also cuts the joint phenotypes and counts the values read. Genomes are each
representation's own initialisation (``max_depth`` 10; default settings, so SGE at recursion level
5, refused where its genome would hold over a million values: PCRE, Word_Stats); times are CPU
seconds, the best of five alternating rounds, so that load on the machine counts little.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from gaitgram.ge.cfggp import compile_cfggp
from gaitgram.ge.dsge import compile_dsge
from gaitgram.ge.mapper import MapperError
from gaitgram.ge.pige import compile_pige
from gaitgram.ge.sge import compile_sge
from gaitgram.language import load

ROOT = Path(__file__).resolve().parents[1]
DEFINES = {"dataset_n_vars": 5, "dataset_n_is": 5, "dataset_n_os": 5}
GENOMES = 200
MAX_DEPTH = 10
TARGET = 3.0


def grammars() -> list[Path]:
    ponyge2 = ROOT / "tests" / "data" / "ponyge2"
    return [
        *sorted((ROOT / "grammars").glob("*.gg")),
        *sorted(p for p in ponyge2.glob("*.bnf")),
        ROOT / "tests" / "data" / "ponyge2_regression" / "Keijzer6.bnf",
    ]


# ---- the plain reference mappers ------------------------------------------------------------------

Symbol = tuple[str, str]  # (text, "NT" | "T"); a rule's text is its number, as a string
Plain = dict[str, list[list[Symbol]]]
Spliced = dict[str, list[list[tuple[Symbol, int]]]]  # each symbol with its levels below the rule


def plain_grammar(choices: Sequence[Sequence[Sequence[int | str]]]) -> Plain:
    """Rules as Lourenço's readers hold them: by name, each choice a list of typed symbols."""
    return {
        str(r): [[(str(i), "NT") if isinstance(i, int) else (i, "T") for i in choice] for choice in rule]
        for r, rule in enumerate(choices)
    }


class Node:
    """A derivation tree's node as alogos keeps one, with its depth."""

    __slots__ = ("children", "depth", "symbol")

    def __init__(self, symbol: Symbol, depth: int) -> None:
        self.symbol = symbol
        self.depth = depth
        self.children: list[Node] = []


Summary = tuple[str, int, int]  # phenotype, depth, rule nodes


def plain_pige(
    grammar: Plain, start: int, genome: Sequence[int], mode: str, max_wraps: int = 3
) -> Summary | None:
    """alogos' ``_forward_slow`` and ``DerivationTree.string``."""
    root = Node((str(start), "NT"), 1)
    stack = [root]
    n, c, deepest, nodes = len(genome), 0, 1, 0
    while stack:
        if c // n > max_wraps:
            return None
        order = genome[c % n]
        c += 1
        index = order % len(stack)
        node = stack.pop(index)
        content = genome[c % n]
        c += 1
        rules = grammar[node.symbol[0]]
        chosen = rules[content % len(rules)]
        nodes += 1
        new_nodes = []
        for symbol in chosen:  # DerivationTree._expand
            child = Node(symbol, node.depth + 1)
            new_nodes.append(child)
            node.children.append(child)
        new_nt_nodes = [child for child in new_nodes if child.symbol[1] == "NT"]
        if new_nt_nodes:
            deepest = max(deepest, node.depth + 1)
        if mode == "start":
            stack = new_nt_nodes + stack
        elif mode == "end":
            stack = stack + new_nt_nodes
        else:
            stack[index:index] = new_nt_nodes
    leaves = []
    todo = deque([root])
    while todo:
        node = todo.pop()
        if node.children:
            todo.extend(reversed(node.children))
        else:
            leaves.append(node)
    return "".join(leaf.symbol[0] for leaf in leaves), deepest, nodes


def plain_sge(
    grammar: Spliced, order: dict[str, int], start: int, genome: Sequence[Sequence[int]]
) -> Summary:
    """The original SGE's ``mapping`` (a stack where it prepends to a list and pops its front). A
    spliced alternative's symbol carries the rule nodes it stands for and their depth below it."""
    positions = [0] * len(genome)
    output = []
    deepest = nodes = 0
    stack: list[tuple[Symbol, int]] = [((str(start), "NT"), 1)]
    while stack:
        current, depth = stack.pop()
        if current[1] == "T":
            output.append(current[0])
            continue
        if current[1] == "IN":  # where an alternative was spliced in: a rule node above its symbols
            nodes += 1
            deepest = max(deepest, depth)
            continue
        nodes += 1
        deepest = max(deepest, depth)
        position = order[current[0]]
        production = genome[position][positions[position]]
        positions[position] += 1
        stack.extend(
            (symbol, depth + 1 + level) for symbol, level in reversed(grammar[current[0]][production])
        )
    return "".join(output), deepest, nodes


def plain_dsge(grammar: Plain, order: dict[str, int], start: int, genome: Sequence[Sequence[int]]) -> Summary:
    """sge3's ``_recursive_mapping``: the phenotype and the depth (sge3 counts the root 0 and a
    terminal one below its rule: gaitgram's count of rule levels), and the rule nodes."""
    positions = [0] * len(genome)
    output: list[str] = []

    def recursive(symbol: Symbol, depth: int) -> int:
        depths = [depth]
        if symbol[1] == "T":
            output.append(symbol[0])
        else:
            position = order[symbol[0]]
            if positions[position] >= len(genome[position]):
                raise RuntimeError("sge3 would fill the gene here; these genomes are complete")
            production = genome[position][positions[position]]
            positions[position] += 1
            for child in grammar[symbol[0]][production]:
                depths.append(recursive(child, depth + 1))
        return max(depths)

    depth = recursive((str(start), "NT"), 0)
    return "".join(output), depth, sum(positions)


def plain_cfggp(grammar: Plain, start: int, choices: Sequence[int]) -> Summary:
    """The tree's choices read leftmost first with a stack."""
    output = []
    values = iter(choices)
    deepest = nodes = 0
    stack: list[tuple[Symbol, int]] = [((str(start), "NT"), 1)]
    while stack:
        symbol, depth = stack.pop()
        if symbol[1] == "T":
            output.append(symbol[0])
            continue
        nodes += 1
        deepest = max(deepest, depth)
        stack.extend((child, depth + 1) for child in reversed(grammar[symbol[0]][next(values)]))
    return "".join(output), deepest, nodes


def spliced(unrolled: Any) -> Spliced:
    """SGE's unrolled grammar as its reader makes it: inlined alternatives spliced in place, each
    spliced symbol with how many levels below its rule it stands (an ``IN`` symbol marks the rule
    node a spliced alternative stands for)."""

    def splice(items: Sequence[int | str], level: int) -> list[tuple[Symbol, int]]:
        out: list[tuple[Symbol, int]] = []
        for i in items:
            if isinstance(i, int) and i >= unrolled.genes:
                out.append((("", "IN"), level))
                out.extend(splice(unrolled.choices[i][0], level + 1))
            else:
                out.append(((str(i), "NT") if isinstance(i, int) else (i, "T"), level))
        return out

    return {
        str(e): [splice(c, 0) for c in choices]
        for e, choices in enumerate(unrolled.choices[: unrolled.genes])
    }


# ---- timing ---------------------------------------------------------------------------------------


def rate(work: Callable[[], object], count: int) -> float:
    """``work``'s genomes/s (it maps ``count``), CPU time over at least 50 ms."""
    start = time.process_time()
    loops = 0
    while (elapsed := time.process_time() - start) < 0.05 or not loops:
        work()
        loops += 1
    return count * loops / elapsed


def compare(ours: Callable[[], object], plain: Callable[[], object], count: int) -> tuple[float, float]:
    """The best genomes/s of each in five alternating rounds."""
    best_ours = best_plain = 0.0
    for _ in range(5):
        best_ours = max(best_ours, rate(ours, count))
        best_plain = max(best_plain, rate(plain, count))
    return best_ours, best_plain


def cases(
    grammar: Any, rng: np.random.Generator, label: str
) -> list[tuple[str, Callable[[], Any], Callable[[], Any]]]:
    """Per representation: gaitgram's mapping and the plain one of the same genomes (checked to
    agree here, before timing)."""
    pige = compile_pige(grammar)
    cfg = pige.tables.cfg
    start = cfg.start
    assert start is not None
    plain = plain_grammar(cfg.choices)
    order = {str(r): r for r in range(len(cfg))}
    codons = pige.initialise(rng, GENOMES, MAX_DEPTH)
    mode = pige.settings.stack
    dsge = compile_dsge(grammar)
    dsge_genomes = dsge.initialise(rng, GENOMES, MAX_DEPTH)
    cfggp = compile_cfggp(grammar)
    trees = cfggp.initialise(rng, GENOMES, MAX_DEPTH)
    found = [
        ("pige", lambda: pige.map_many(codons), lambda: [plain_pige(plain, start, g, mode) for g in codons]),
        (
            "dsge",
            lambda: dsge.map_many(dsge_genomes),
            lambda: [plain_dsge(plain, order, start, g) for g in dsge_genomes],
        ),
        ("cfg-gp", lambda: cfggp.map_many(trees), lambda: [plain_cfggp(plain, start, t) for t in trees]),
    ]

    def summary(m: Any) -> Any:
        return (m.phenotype, m.depth, m.nodes) if m.valid else None

    try:
        sge = compile_sge(grammar)
    except MapperError as error:
        print(f"{label:<34}sge: refused ({str(error).removeprefix('sge: ')})")
    else:
        unrolled = sge.unrolled
        sge_plain = spliced(unrolled)
        sge_order = {str(e): e for e in range(unrolled.genes)}
        sge_genomes = sge.initialise(rng, GENOMES, MAX_DEPTH)
        found.insert(
            1,
            (
                "sge",
                lambda: sge.map_many(sge_genomes),
                lambda: [plain_sge(sge_plain, sge_order, start, g) for g in sge_genomes],
            ),
        )
    for name, ours, plain_mapper in found:
        assert [summary(m) for m in ours()] == plain_mapper(), f"{name}: the plain mapper disagrees"
    return found


def main() -> None:
    print(f"{GENOMES} genomes per grammar from each representation's initialisation (max depth {MAX_DEPTH})")
    print(f"plain = the reference's algorithm, plainly (this file's docstring); target {TARGET:.0f}x\n")
    print(f"{'grammar':<34}{'representation':<16}{'gaitgram/s':>12}{'plain/s':>12}{'ratio':>8}")
    worst: dict[str, float] = {}
    for path in grammars():
        label = str(path.relative_to(ROOT)).removeprefix("tests/data/")
        for name, ours, plain in cases(load(path, defines=DEFINES), np.random.default_rng(41), label):
            fast, slow = compare(ours, plain, GENOMES)
            ratio = fast / slow
            worst[name] = min(worst.get(name, ratio), ratio)
            print(f"{label:<34}{name:<16}{fast:>12,.0f}{slow:>12,.0f}{ratio:>7.2f}x", flush=True)
    print()
    for name, ratio in worst.items():
        verdict = "meets" if ratio >= TARGET else "MISSES"
        print(f"{name:<8} worst ratio {ratio:5.2f}x  {verdict} the {TARGET:.0f}x target")
