"""PonyGE2's own ``map_ind_from_genome`` timed on genomes given: run by ``bench_map`` with PonyGE2's
interpreter in PonyGE2's ``src`` directory (its modules import each other from there).

``python _ponyge2_map.py`` reads one JSON object from stdin, ``{"grammars": [{"path": ..., "genomes":
[[...], ...]}, ...], "max_wraps": 3, "n_vars": 5}``, loads each grammar with PonyGE2's ``Grammar``
(``GE_RANGE:dataset_n_vars`` and its kin expand to ``n_vars``), maps its genomes with
``map_ind_from_genome`` (no depth limit) and prints one JSON line per grammar: genomes/s (CPU time,
the best of five rounds of at least 50 ms) and each genome's phenotype (null if PonyGE2 calls it
invalid). Nothing of gaitgram is imported: this file runs under PonyGE2's own numpy.
"""

import json
import os
import sys
import time
from types import SimpleNamespace


def rate(work, count):
    best = 0.0
    for _ in range(5):
        start, loops = time.process_time(), 0
        while (elapsed := time.process_time() - start) < 0.05 or not loops:
            work()
            loops += 1
        best = max(best, count * loops / elapsed)
    return best


def main():
    sys.path.insert(0, os.getcwd())  # PonyGE2's src
    from algorithm.mapper import map_ind_from_genome
    from algorithm.parameters import params
    from representation.grammar import Grammar

    job = json.load(sys.stdin)
    n = job["n_vars"]
    params["FITNESS_FUNCTION"] = SimpleNamespace(n_vars=n, n_is=n, n_os=n)
    params["MAX_WRAPS"] = job["max_wraps"]
    params["MAX_TREE_DEPTH"] = None
    for entry in job["grammars"]:
        params["BNF_GRAMMAR"] = Grammar(entry["path"])
        genomes = entry["genomes"]
        phenotypes = [map_ind_from_genome(g)[0] for g in genomes]
        per_second = rate(lambda genomes=genomes: [map_ind_from_genome(g) for g in genomes], len(genomes))
        print(json.dumps({"path": entry["path"], "rate": per_second, "phenotypes": phenotypes}), flush=True)


if __name__ == "__main__":
    main()
