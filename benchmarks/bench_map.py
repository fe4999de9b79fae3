"""Mapping speed: genomes/s on the 200 vector genomes of ``concat.bnf`` (200 codons, 3 wraps).

Baseline: a plain dict-and-stack mapper of the kind anyone would write first
(measured at about 28,000 genomes/s when the mapper was designed; PonyGE2's own mapper does
about 12,000/s). Target for gaitgram's fast path: 60,000 genomes/s, eager.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from gaitgram.analysis import build_cfg
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.language import load

ROOT = Path(__file__).resolve().parents[1]
VECTORS = ROOT / "tests" / "data" / "ponyge2"


def plain_mapper(rules: dict[int, list[list[int | str]]], start: int, genome: list[int], wraps: int = 3):
    """The baseline: a dict of rules, a stack, ``codon % n``; eager consumption."""
    out, stack, used, limit, n = [], [start], 0, len(genome) * (wraps + 1), len(genome)
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            out.append(item)
            continue
        if used >= limit:
            return None, used
        choices = rules[item]
        stack.extend(reversed(choices[genome[used % n] % len(choices)]))
        used += 1
    return "".join(out), used


def rate(work, genomes: list[list[int]], seconds: float = 1.0) -> float:
    """Genomes per second, best of three runs of at least ``seconds / 3`` each."""
    best = 0.0
    for _ in range(3):
        count, start = 0, time.perf_counter()
        while (elapsed := time.perf_counter() - start) < seconds / 3:
            work(genomes)
            count += len(genomes)
        best = max(best, count / elapsed)
    return best


def main() -> None:
    grammar = load(VECTORS / "concat.bnf")
    with (VECTORS / "concat.jsonl").open() as handle:
        genomes = [json.loads(line)["genome"] for line in handle]
    cfg = build_cfg(grammar)
    rules = {i: [list(c) for c in choices] for i, choices in enumerate(cfg.choices)}
    assert cfg.start is not None
    start = cfg.start

    def baseline(batch: list[list[int]]) -> None:
        for genome in batch:
            plain_mapper(rules, start, genome)

    base = rate(baseline, genomes)
    print(f"{len(genomes)} genomes of concat.bnf; baseline = plain dict-and-stack mapper (eager)")
    print(f"{'baseline, eager':<34} {base:>10,.0f} genomes/s")
    for mode in (CodonMode.EAGER, CodonMode.LAZY):
        mapper = compile_mapper(grammar, codons=mode, max_wraps=3)
        fast = rate(mapper.map_many, genomes)
        full = rate(lambda batch, mapper=mapper: [mapper.map(g) for g in batch], genomes)
        print(
            f"{'map_many (phenotype), ' + mode.value:<34} {fast:>10,.0f} genomes/s"
            f"   ratio {fast / base:5.2f}x"
        )
        print(
            f"{'map (full derivation), ' + mode.value:<34} {full:>10,.0f} genomes/s"
            f"   ratio {full / base:5.2f}x"
        )
