"""Run a reference implementation's own code on one grammar and print what it makes, as JSON.

Run by ``make_vectors.py`` (read it first), never by the tests. It imports nothing of gaitgram and
runs under the reference's interpreter: Python 3 for sge3 (DSGE), Python 2.7 for Lourenco's
original SGE, so it is written for both (no f-strings, no annotations).

    python reference_runner.py dsge REPO/sge GRAMMAR SEED N MAX_TREE_DEPTH MIN_TREE_DEPTH
    python2.7 reference_runner.py sge REPO/src GRAMMAR SEED N MAX_RECURSION_LEVEL  # N or fewer genomes

Every random draw the reference makes goes through ``Draws``, which records whether a draw had more
than one possible outcome: a fill of short genes that made none is deterministic, whatever the seed.
"""

import copy
import json
import random
import sys


class Draws:
    """Stands in for the ``random`` module in the reference's modules: the same calls, from one
    seeded generator, noting any draw that had a choice to make."""

    def __init__(self, seed):
        self.generator = random.Random(seed)
        self.chosen = False

    def randint(self, low, high):
        if high > low:
            self.chosen = True
        return self.generator.randint(low, high)

    def choice(self, options):
        if len(options) > 1:
            self.chosen = True
        return self.generator.choice(options)

    def random(self):
        return self.generator.random()


def dsge(repo, path, seed, n, max_tree_depth, min_tree_depth):
    sys.path.insert(0, repo)
    import sge.grammar as grammar
    import sge.operators.mutation as mutation

    draws = Draws(seed)
    grammar.random = draws
    mutation.random = draws
    grammar.set_path(path)
    grammar.read_grammar()
    grammar.set_max_tree_depth(max_tree_depth)
    grammar.set_min_init_tree_depth(min_tree_depth)
    names = list(grammar.get_non_terminals())
    rules = grammar.get_grammar()
    shortest = {}
    for (name, _), entry in grammar.get_shortest_path().items():
        shortest[name] = [entry[0], sorted({rules[name].index(option) for option in entry[1:]})]

    def mapped(kind, genome):
        draws.chosen = False
        completed = copy.deepcopy(genome)
        positions = [0] * len(names)
        phenotype, depth = grammar.mapping(completed, positions)
        case = {"kind": kind, "genome": genome, "used": positions, "phenotype": phenotype, "depth": depth}
        if completed != genome:  # the mapping filled genes that ran out
            case["completed"] = completed
            case["fill_deterministic"] = not draws.chosen
        return case

    cases = []
    for _ in range(n):
        genome = [[] for _ in names]
        grammar.recursive_individual_creation(genome, grammar.start_rule()[0], 0)
        initial = mapped("initial", genome)
        cases.append(initial)
        # Genes cut short: the mapping fills them (random unless the reference has one option).
        cut = [gene[: draws.generator.randint(0, len(gene))] for gene in genome]
        cases.append(mapped("truncated", cut))
        # sge3's own mutation, then the mapping that fills what it leaves short.
        individual = {
            "genotype": copy.deepcopy(genome),
            "mapping_values": initial["used"],
            "tree_depth": initial["depth"],
            "fitness": None,
        }
        cases.append(mapped("mutated", mutation.mutate(individual, 0.3)["genotype"]))
    return {"nonterminals": names, "shortest_path": shortest, "cases": cases}


def sge(repo, path, seed, n, level):
    sys.path.insert(0, repo)
    sys.argv = sys.argv[:1]  # configs/standard.py reads a run number from argv[1]
    import core.grammar
    import core.sge

    draws = Draws(seed)
    core.sge.random = draws
    core.grammar.random = draws
    grammar = core.grammar.Grammar(path, level)
    grammar.python_filter = lambda text: text  # the raw phenotype: no PonyGE 0.1.3 filter
    core.sge.GRAMMAR = grammar
    names = list(grammar.get_non_terminals())
    sizes = grammar.count_references_to_non_terminals()
    cases = []
    # Genes grow exponentially with the level: at most about 40,000 values per level and grammar.
    for _ in range(min(n, max(3, 40000 // sum(sizes[name] for name in names)))):
        genome = core.sge.generate_sge_individual()
        positions = [0] * len(names)
        phenotype = grammar.mapping(genome, positions)
        cases.append({"genome": [gene[0] for gene in genome], "used": positions, "phenotype": phenotype})
    return {
        "nonterminals": names,
        "gene_sizes": [sizes[name] for name in names],
        "cases": cases,
    }


def main(argv):
    kind, repo, path, seed, n = argv[0], argv[1], argv[2], int(argv[3]), int(argv[4])
    if kind == "dsge":
        out = dsge(repo, path, seed, n, int(argv[5]), int(argv[6]))
    else:
        out = sge(repo, path, seed, n, int(argv[5]))
    sys.stdout.write(json.dumps(out) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
