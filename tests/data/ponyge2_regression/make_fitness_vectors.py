"""Makes fitness_vectors.jsonl: phenotypes of PonyGE2's regression grammars scored by PonyGE2's own
fitness function (``supervised_learning.regression``, RMSE), the oracle for the symbolic-regression
backend. Run from the repository's root with a PonyGE2 checkout and its interpreter:

    .venv/bin/python tests/data/ponyge2_regression/make_fitness_vectors.py PONYGE2_DIR PONYGE2_PYTHON

Phenotypes: gaitgram's eager mapping (no wraps) of random genomes (lengths 1-300, seeded) and of
ramped trees (depths up to 16, where np.exp chains overflow), plus a few written by hand.
"""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

from gaitgram.analysis import analyse
from gaitgram.ge import CodonMode, compile_mapper
from gaitgram.ge.initialisation import ramped_population
from gaitgram.language import load

HERE = Path(__file__).parent
CASES = {  # problem: (grammar, defines, PonyGE2 dataset directory or our own)
    "keijzer-6": (HERE / "Keijzer6.bnf", {}, "Keijzer6"),
    "pagie-1": (HERE.parent / "ponyge2" / "supervised_learning.bnf", {"dataset_n_vars": 2}, "Paige1"),
    "five-inputs": (HERE.parent / "ponyge2" / "Vladislavleva4.bnf", {}, "five_inputs"),
}
BY_HAND = [
    "pdiv(x[:, 0],x[:, 0]-x[:, 0])",
    "pdiv(1.0,0.0)",
    "pdiv(00.00,00.00)",
    "np.exp(np.exp(np.exp(x[:, 0])))",
    "np.exp(00.00-99.99*99.99)",
    "x[:, 0]--1.5*x[:, 0]",
    "aq(x[:, 0],99.99*99.99*99.99*99.99*99.99*99.99)",
    "plog(x[:, 0]*-0.0)",
    "psqrt(x[:, 0]-12.34)",
    "(x[:, 0]*(x[:, 0]+-0.5))",
    "12.34",
]


def phenotypes(grammar_path, defines, seed):
    grammar = load(grammar_path, defines=defines)
    mapper = compile_mapper(grammar, codons=CodonMode.EAGER, max_wraps=0)
    rng = np.random.default_rng(seed)
    found = []
    for length in rng.integers(1, 300, size=400):
        mapped = mapper.map([int(c) for c in rng.integers(0, 100_000, size=int(length))])
        if mapped.valid:
            found.append(mapped.phenotype)
    trees = ramped_population(
        analyse(grammar), rng, 300, max_depth=16, codons=CodonMode.EAGER, codon_size=100_000
    )
    found += [mapper.map(t.genome).phenotype for t in trees]
    return list(dict.fromkeys(found))  # distinct, in order


SCORE = r"""
import json, sys
sys.path.insert(0, ".")
from algorithm.parameters import params, set_params
data = sys.argv[1]
set_params(["--fitness_function", "supervised_learning.regression", "--dataset_train", data + "/Train.txt",
            "--dataset_test", data + "/Test.txt", "--grammar_file", "supervised_learning/Keijzer6.bnf",
            "--debug", "--silent"])
class Ind:
    runtime_error = False
for line in sys.stdin:
    ind = Ind(); ind.phenotype = json.loads(line)
    value = float(params["FITNESS_FUNCTION"](ind))
    print(json.dumps({"phenotype": ind.phenotype, "fitness": value if value == value else None}))
"""


def main(ponyge2, python):
    own = Path(ponyge2) / "datasets" / "five_inputs"
    shutil.copytree(HERE / "five_inputs", own, dirs_exist_ok=True)
    lines = []
    for seed, (problem, (grammar, defines, data)) in enumerate(CASES.items()):
        texts = phenotypes(grammar, defines, seed) + [t for t in BY_HAND if problem == "keijzer-6"]
        done = subprocess.run(
            [python, "-c", SCORE, data],
            cwd=Path(ponyge2) / "src",
            input="".join(json.dumps(t) + "\n" for t in texts),
            capture_output=True,
            text=True,
            check=True,
        )
        for line in done.stdout.splitlines():
            if line.startswith("{"):
                lines.append(json.dumps({"problem": problem, **json.loads(line)}))
    (HERE / "fitness_vectors.jsonl").write_text("\n".join(lines) + "\n")
    shutil.rmtree(own)


if __name__ == "__main__":
    main(*sys.argv[1:3])
