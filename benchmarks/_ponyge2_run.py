"""One run of PonyGE2's own GE, from its own code: run by ``bench_ponyge2`` with PonyGE2's
interpreter in PonyGE2's ``src`` directory (its imports and its ``../datasets`` paths need both).

``python _ponyge2_run.py --population_size 500 ... --random_seed 3`` takes PonyGE2's command-line
parameters, runs ``params['SEARCH_LOOP']`` exactly as ``ponyge.py`` does (with ``--debug`` and
``--silent``, so that it writes no files and prints nothing), and prints one JSON line: the best
individual's training and test fitness and phenotype, and the run's wall time. Nothing of gaitgram
is imported: this file runs under PonyGE2's own numpy.
"""

import json
import os
import sys
import time


def main(argv):
    sys.path.insert(0, os.getcwd())  # PonyGE2's src: its modules import each other from there
    import importlib

    from algorithm.parameters import params, set_params
    from stats.stats import get_stats
    from utilities.stats import trackers

    # What set_params imports by name, imported before the clocks start (gaitgram's are too).
    for name in (
        "fitness.supervised_learning.regression",
        "utilities.fitness.error_metric",
        "operators.initialisation",
        "operators.crossover",
        "operators.mutation",
        "operators.selection",
        "operators.replacement",
        "algorithm.search_loop",
        "algorithm.step",
    ):
        importlib.import_module(name)
    start, cpu = time.perf_counter(), time.process_time()
    set_params(argv)  # reads the grammar and the data, as gaitgram's clock counts its own reading
    individuals = params["SEARCH_LOOP"]()
    get_stats(individuals, end=True)  # as ponyge.py: sets the best's training and test fitness
    best = trackers.best_ever
    seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu

    def number(value):
        value = float(value)
        return value if value == value else None  # NaN: no score

    print(
        json.dumps(
            {
                "fitness": number(best.training_fitness),
                "test_fitness": number(best.test_fitness),
                "phenotype": best.phenotype,
                "seconds": seconds,
                "cpu_seconds": cpu_seconds,
            }
        )
    )


if __name__ == "__main__":
    main(sys.argv[1:])
