"""Motion compiling speed: expressions/s on the bundled grammars' phenotypes, against the old compiler.

The phenotypes are the joints of random derivations of each grammar in ``grammars/``, made by
the initialisation evolution uses (as ``gaitgram sample`` makes them). Each is compiled
(parse, check, compile: the cache bypassed) and sampled on the 256-phase grid a gait's curves
use, as ``gaitgram.motion.gait.sampled_curve`` does for every new phenotype of a run.

Baseline: the compiler before it was split into stages (one module with a hand-written fast
parser, lark for errors), loaded from git at ``BASELINE_COMMIT`` and timed in the same run on
the same phenotypes; without git history the figures are printed alone. Target: compiling
at least 2x the baseline's rate on every grammar (sampling is mostly numpy's ``sin``, which
no compiler change may alter).
"""

from __future__ import annotations

import gc
import importlib.util
import math
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import numpy as np

from gaitgram.analysis import check
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.ge.initialisation import ramped_population
from gaitgram.language import load
from gaitgram.motion import expression
from gaitgram.motion.gait import DEFAULT_SAMPLES
from gaitgram.motion.vocabulary import phase_grid

ROOT = Path(__file__).resolve().parents[1]
BASELINE_COMMIT = "d99e791"
DERIVATIONS = 30


def phenotypes(grammar: Path) -> list[str]:
    """The distinct joint phenotypes of ``DERIVATIONS`` ramped random derivations."""
    result = check(load(grammar))
    mapper = compile_mapper(result.grammar, codons=CodonMode.LAZY, max_wraps=0)
    trees = ramped_population(result.facts, np.random.default_rng(1), DERIVATIONS, max_depth=10, tail=0)
    found: dict[str, None] = {}
    for mapped in mapper.map_many([tree.genome for tree in trees]):
        found.update(dict.fromkeys(mapped.joints.values()))
    return list(found)


def baseline_module() -> ModuleType | None:
    """``gaitgram/motion/expression.py`` as it was at ``BASELINE_COMMIT``, or None without git."""
    try:
        source = subprocess.run(
            ["git", "show", f"{BASELINE_COMMIT}:gaitgram/motion/expression.py"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    name = f"_motion_expression_{BASELINE_COMMIT}"
    spec = importlib.util.spec_from_loader(name, loader=None)
    assert spec is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up
    exec(compile(source, f"{BASELINE_COMMIT}:gaitgram/motion/expression.py", "exec"), module.__dict__)
    return module


def rates(
    compilers: list[Callable[[str], object]], texts: list[str], passes: int = 15
) -> list[tuple[float, float]]:
    """Expressions per second of each compiler: compiled (uncached), and compiled then sampled on
    the gait grid.

    The compilers take turns, pass after pass, and each keeps its fastest pass in CPU time: on a
    busy machine other processes only ever slow a pass down, and taking turns spreads what they
    do over every compiler alike.
    """
    grid = phase_grid(DEFAULT_SAMPLES)
    best = [[math.inf, math.inf] for _ in compilers]
    for _ in range(passes):
        for fastest, compile_motion in zip(best, compilers, strict=True):
            uncached = getattr(compile_motion, "__wrapped__", compile_motion)
            gc.collect()
            start = time.process_time()
            for text in texts:
                uncached(text)
            middle = time.process_time()
            for text in texts:
                uncached(text).evaluate(grid)  # type: ignore[attr-defined]
            end = time.process_time()
            fastest[0] = min(fastest[0], middle - start)
            fastest[1] = min(fastest[1], end - middle)
    return [(len(texts) / compiling, len(texts) / sampling) for compiling, sampling in best]


def main() -> None:
    old = baseline_module()
    print(f"joint phenotypes of {DERIVATIONS} derivations per grammar; expressions/s (CPU time, best of 15)")
    print(
        f"baseline: the compiler at {BASELINE_COMMIT} (from git), in this run"
        if old is not None
        else "no git history: the baseline compiler could not be loaded; figures alone"
    )
    print(f"{'grammar':<16} {'exprs':>5} {'chars':>5} {'compile':>9} {'baseline':>9} {'ratio':>6}"
          f" {'+sample':>9} {'baseline':>9} {'ratio':>6}")  # fmt: skip
    for grammar in sorted((ROOT / "grammars").glob("*.gg")):
        texts = phenotypes(grammar)
        new, *others = rates([expression.compile_motion, *([old.compile_motion] if old else [])], texts)
        line = f"{grammar.stem:<16} {len(texts):>5} {sum(map(len, texts)) // len(texts):>5} {new[0]:>9,.0f}"
        if not others:
            print(f"{line} {new[1]:>26,.0f}")
            continue
        (base,) = others
        print(
            f"{line} {base[0]:>9,.0f} {new[0] / base[0]:>5.1f}x"
            f" {new[1]:>9,.0f} {base[1]:>9,.0f} {new[1] / base[1]:>5.1f}x"
        )
    for size in (100_000, 200_000):  # linear: twice the text, twice the time
        text = "t" + " " * size
        start = time.process_time()
        expression.compile_motion.__wrapped__(text)
        print(f"'t' and {size:,} spaces: {(time.process_time() - start) * 1e3:.1f} ms")
