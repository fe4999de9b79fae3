"""gaitgram's GE against PonyGE2's own GE, on PonyGE2's symbolic-regression problems (issue 41, 5a).

Both tools run the same grammar file (PonyGE2's, unchanged), the same data (PonyGE2's files; the
built Pagie-1 and Keijzer-6 are checked equal to them value for value first), the same fitness
(RMSE on the training split, PonyGE2's default metric) and the same budget, ``--runs`` runs each
(30 for the record), on Pagie-1 (PonyGE2's generic ``supervised_learning.bnf``, two inputs),
Keijzer-6 and Vladislavleva-4. PonyGE2 runs from its own code, in a process of its own with its own
interpreter (``_ponyge2_run.py``); gaitgram's runs use the library as ``gaitgram evolve`` does,
without writing run directories (PonyGE2 runs with ``--debug``, which writes nothing). Reported:
each run's final best training (and test) RMSE for each tool, a two-sided Mann-Whitney U per
problem with the Vargha-Delaney A12 (the probability that a gaitgram run ends lower), whatever they
say, and the wall-time and CPU-time ratios. Runs alternate between the tools, so that the load of a
shared machine falls on both alike.

PonyGE2 is not part of gaitgram (GPL-3.0) and is never committed. To run this benchmark::

    git clone https://github.com/PonyGE/PonyGE2 /work/ponyge2   # or any checkout of it
    python3 -m venv /work/ponyge2-venv
    /work/ponyge2-venv/bin/pip install 'numpy<2' scipy matplotlib pandas scikit-learn
    python -m benchmarks ponyge2 --ponyge2 /work/ponyge2 --python /work/ponyge2-venv/bin/python

(PonyGE2 uses ``np.NaN``, gone in numpy 2, hence its own interpreter; ``GAITGRAM_PONYGE2`` and
``GAITGRAM_PONYGE2_PYTHON`` may name the two instead.) ``--runs N`` scales down; ``--out FILE``
appends each finished run as a JSON line and skips the runs already there, so an interrupted record
resumes; ``--problems`` picks problems; ``--ponyge2-args=--invalid_selection`` adds PonyGE2 parameters
after the shared ones (an ablation). The record: docs/results/ponyge2/.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
DRIVER = Path(__file__).with_name("_ponyge2_run.py")
DIGESTS = ROOT / "tests" / "data" / "ponyge2_regression" / "datasets.json"

# ---- the shared settings: one place, read by both tools' parameter lists -------------------------
POPULATION = 500  # PonyGE2's default and regression.txt's
GENERATIONS = 50
ELITE = 4  # PonyGE2's default is 1 % (5): 4 makes its offspring count even, so it breeds no spare
TOURNAMENT = 2
CROSSOVER = 0.75  # PonyGE2's variable one-point, within the used codons
MUTATION = 0.01  # per used codon, both; PonyGE2's default would be 1 / used codons
CODON_SIZE = 100_000
#: Depths as PonyGE2 counts them: its trees have a level of terminals that gaitgram's depth omits.
PONYGE2_MAX_INIT_DEPTH = 10
PONYGE2_MAX_DEPTH = 17  # regression.txt's MAX_TREE_DEPTH
SEED = 2026  # gaitgram's run i takes the i-th of this seed's spawned seeds; PonyGE2's run i seed i


@dataclass(frozen=True)
class Problem:
    name: str
    grammar: str  # under PonyGE2's grammars/
    data: str  # under PonyGE2's datasets/
    built: str | None  # gaitgram's built dataset equal to PonyGE2's files, if any
    defines: Mapping[str, int]  # GE_RANGE sizes PonyGE2 takes from the data


PROBLEMS = {
    p.name: p
    for p in (
        Problem(
            "pagie-1",
            "supervised_learning/supervised_learning.bnf",
            "Paige1",
            "pagie-1",
            {"dataset_n_vars": 2},
        ),
        Problem("keijzer-6", "supervised_learning/Keijzer6.bnf", "Keijzer6", "keijzer-6", {}),
        Problem("vladislavleva-4", "supervised_learning/Vladislavleva4.bnf", "Vladislavleva4", None, {}),
    )
}


class Refused(Exception):
    """The benchmark cannot run here; the message says what to do."""


def ponyge2_arguments(problem: Problem, run: int) -> list[str]:
    """PonyGE2's command line for run ``run``: its GE with the shared settings."""
    return [
        *("--fitness_function", "supervised_learning.regression"),
        *("--grammar_file", problem.grammar),
        *("--dataset_train", f"{problem.data}/Train.txt", "--dataset_test", f"{problem.data}/Test.txt"),
        *("--population_size", str(POPULATION), "--generations", str(GENERATIONS)),
        *("--initialisation", "rhh", "--max_init_tree_depth", str(PONYGE2_MAX_INIT_DEPTH)),
        *("--max_tree_depth", str(PONYGE2_MAX_DEPTH), "--max_wraps", "0", "--codon_size", str(CODON_SIZE)),
        *("--selection", "tournament", "--tournament_size", str(TOURNAMENT)),
        *("--crossover", "variable_onepoint", "--crossover_probability", str(CROSSOVER)),
        *("--mutation", "int_flip_per_codon", "--mutation_probability", str(MUTATION)),
        *("--replacement", "generational", "--elite_size", str(ELITE)),
        *("--random_seed", str(run), "--debug", "--silent"),
    ]


#: gaitgram's GE settings equal to PonyGE2's (docs/results/ponyge2/README.md maps each).
GE_SETTINGS: Mapping[str, Any] = {
    "max_wraps": 0,
    "codons": "eager",  # PonyGE2's codon consumption (gaitgram.ge.mapper.CodonMode.EAGER)
    "codon_size": CODON_SIZE,
    "init_max_depth": PONYGE2_MAX_INIT_DEPTH - 1,
    "grow_probability": 0.5,
    "tail": 0.5,
    "crossover": CROSSOVER,
    "fixed_point": False,
    "crossover_within_used": True,
    "mutation": MUTATION,
    "mutation_within_used": True,
    "max_depth": PONYGE2_MAX_DEPTH - 1,
}


def gaitgram_config(
    problem: Problem,
    ponyge2: Path,
    runs: int,
    representation: str = "ge",
    settings: Mapping[str, Any] = GE_SETTINGS,
    *,
    generations: int = GENERATIONS,
    population: int = POPULATION,
) -> Any:
    """gaitgram's RunConfig with the shared settings: GE's by default; another representation's
    with its own ``settings`` under the same budget, selection and seeds (the representations'
    benchmark, ``bench_representations_sr``)."""
    from gaitgram.configuration import RunConfig

    data = ponyge2 / "datasets" / problem.data
    backend = (
        {"dataset": problem.built}
        if problem.built
        else {"train": str(data / "Train.txt"), "test": str(data / "Test.txt")}
    )
    return RunConfig(
        generations=generations,
        population=population,
        runs=runs,
        seed=SEED,
        elite=ELITE,
        tournament=TOURNAMENT,
        representation=representation,
        representation_settings=dict(settings),
        backend="symbolic-regression",
        backend_settings=backend,
    )


# ---- the runs -----------------------------------------------------------------------------------


def run_ponyge2(
    problem: Problem, run: int, ponyge2: Path, python: str, extra: tuple[str, ...] = ()
) -> dict[str, Any]:
    """One PonyGE2 run, in a process of its own (PonyGE2 keeps its state in module globals);
    ``extra`` parameters after the shared ones (an ablation: ``--invalid_selection``)."""
    done = subprocess.run(
        [python, str(DRIVER), *ponyge2_arguments(problem, run), *extra],
        cwd=ponyge2 / "src",
        capture_output=True,
        text=True,
        check=False,
    )
    lines = done.stdout.strip().splitlines()
    if done.returncode or not lines or not lines[-1].startswith("{"):
        raise RuntimeError(f"PonyGE2 run {run} of {problem.name} failed:\n{done.stderr[-2000:]}")
    return json.loads(lines[-1])


def run_gaitgram(
    problem: Problem,
    run: int,
    runs: int,
    ponyge2: Path,
    config: Any = None,
    watch: Callable[[Any], None] | None = None,
) -> dict[str, Any]:
    """One gaitgram run through the library, as ``gaitgram evolve`` runs it, without its files:
    under ``config`` (default: GE's, :func:`gaitgram_config`), ``watch`` shown the run's state
    after each generation (its time counted in the run's)."""
    from gaitgram.analysis import check
    from gaitgram.backends.symbolic_regression.expression import compile_expression
    from gaitgram.evolution.engine import advance, begin, run_context
    from gaitgram.language import load
    from gaitgram.strategies.registry import load_strategy, run_pipeline

    compile_expression.cache_clear()  # each run starts cold, as a PonyGE2 process does
    wall, cpu = time.perf_counter(), time.process_time()
    grammar = load(ponyge2 / "grammars" / problem.grammar, defines=dict(problem.defines))
    pipeline = run_pipeline(check(grammar), config or gaitgram_config(problem, ponyge2, runs))
    evaluator = pipeline.load_evaluator()
    strategy = load_strategy(pipeline)
    context = run_context(pipeline, run)
    state = begin(strategy, context, evaluator)
    while True:
        if watch is not None:
            watch(state)
        if state.generation >= pipeline.config.generations:
            break
        state = advance(strategy, context, state, evaluator)
    best = state.best
    test = evaluator.test_error(best.phenotype) if best.evaluation.status.viable else None
    result = {
        "fitness": best.fitness if best.evaluation.status.viable else None,
        "test_fitness": test,
        "phenotype": best.phenotype,
        "seconds": time.perf_counter() - wall,
        "cpu_seconds": time.process_time() - cpu,
    }
    evaluator.close()
    return result


def check_checkout(ponyge2: Path | None, benchmark: str = "ponyge2") -> Path:
    """PonyGE2's checkout (its grammars and data), or :class:`Refused` saying how to get it; its
    data checked equal to the recorded files and to the built datasets."""
    how = f"see `python -m benchmarks {benchmark} --help` (or its module's docstring) for the commands"
    if ponyge2 is None:
        raise Refused(f"PonyGE2 is not given: fetch it and pass --ponyge2 DIR (or GAITGRAM_PONYGE2); {how}")
    if not (ponyge2 / "src" / "ponyge.py").is_file():
        raise Refused(f"{ponyge2} is not a PonyGE2 checkout (no src/ponyge.py); {how}")
    check_datasets(ponyge2)
    return ponyge2


def check_setup(ponyge2: Path | None, python: str | None) -> tuple[Path, str]:
    """PonyGE2's checkout and interpreter, or :class:`Refused` saying how to get them; the built
    datasets checked equal to the checkout's files."""
    how = "see `python -m benchmarks ponyge2 --help` (or this module's docstring) for the three commands"
    ponyge2 = check_checkout(ponyge2)
    if python is None:
        raise Refused(
            "PonyGE2's interpreter is not given (it needs numpy<2 and scikit-learn): pass --python "
            f"PATH (or GAITGRAM_PONYGE2_PYTHON); {how}"
        )
    probe = subprocess.run(
        [python, "-c", "import numpy, sklearn, matplotlib, pandas; print(numpy.__version__)"],
        capture_output=True,
        text=True,
        check=False,
    )
    if probe.returncode or probe.stdout.strip().startswith("2."):
        raise Refused(
            f"{python} cannot run PonyGE2 (it needs numpy<2, scipy, matplotlib, pandas and scikit-learn): "
            f"{(probe.stderr.strip().splitlines() or [probe.stdout.strip()])[-1]}; {how}"
        )
    return ponyge2, python


def check_datasets(ponyge2: Path) -> None:
    """PonyGE2's data files are the ones whose digests tests/data records, and the built datasets
    equal them value for value: both tools score on the same numbers."""
    from gaitgram.backends.symbolic_regression.datasets import BUILT, digest, read_table

    recorded = json.loads(DIGESTS.read_text())["files"]
    for problem in PROBLEMS.values():
        for split in ("Train", "Test"):
            name = f"{problem.data}/{split}.txt"
            table = read_table(ponyge2 / "datasets" / name)
            if digest(table) != recorded[name]["values_sha256"]:
                raise Refused(f"{ponyge2}/datasets/{name} holds other values than the PonyGE2 files recorded")
            if problem.built:
                built = BUILT[problem.built]()
                if digest(built.train if split == "Train" else built.test) != digest(table):  # type: ignore[arg-type]
                    raise Refused(f"gaitgram's {problem.built} differs from PonyGE2's {name}")


def records(path: Path | None) -> list[dict[str, Any]]:
    if path is None or not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def plan(problems: list[str], runs: int) -> Iterator[tuple[str, int, str]]:
    """(problem, run, tool), the tools alternating run by run."""
    for name in problems:
        for run in range(runs):
            for tool in ("ponyge2", "gaitgram") if run % 2 == 0 else ("gaitgram", "ponyge2"):
                yield name, run, tool


def execute(
    problems: list[str], runs: int, ponyge2: Path, python: str, out: Path | None, extra: tuple[str, ...] = ()
) -> list[dict[str, Any]]:
    found = records(out)
    have = {(r["problem"], r["run"], r["tool"]) for r in found}
    for name, run, tool in plan(problems, runs):
        if (name, run, tool) in have:
            continue
        problem = PROBLEMS[name]
        if tool == "ponyge2":
            result = run_ponyge2(problem, run, ponyge2, python, extra)
        else:
            result = run_gaitgram(problem, run, runs, ponyge2)
        record = {"problem": name, "tool": tool, "run": run, **result}
        found.append(record)
        shown = "no score" if result["fitness"] is None else f"{result['fitness']:.6g}"
        print(f"{name:16} run {run:2} {tool:8} RMSE {shown:>10}  {result['seconds']:6.1f} s", flush=True)
        if out is not None:
            with out.open("a") as handle:
                handle.write(json.dumps(record) + "\n")
    return [r for r in found if r["problem"] in problems and r["run"] < runs]


# ---- the report ---------------------------------------------------------------------------------


def summary(found: list[dict[str, Any]], problems: list[str]) -> dict[str, Any]:
    """Per problem: both tools' final bests, the rank test and A12, and the time ratios."""
    from gaitgram.report.stats import compare

    table: dict[str, Any] = {}
    for name in problems:
        rows = {
            tool: sorted(
                (r for r in found if r["problem"] == name and r["tool"] == tool), key=lambda r: r["run"]
            )
            for tool in ("gaitgram", "ponyge2")
        }
        fitness = {tool: [_score(r["fitness"]) for r in rows[tool]] for tool in rows}
        if not all(fitness.values()):
            continue
        pair = compare(fitness).pairs[0]
        entry: dict[str, Any] = {"runs": {tool: len(v) for tool, v in fitness.items()}}
        for tool in rows:
            entry[tool] = {
                "median": _median(fitness[tool]),
                "best": min(fitness[tool]),
                "worst": max(fitness[tool]),
                "test_median": _median([_score(r["test_fitness"]) for r in rows[tool]]),
                "seconds": sum(r["seconds"] for r in rows[tool]),
            }
        entry["mann_whitney_u"] = pair.u
        entry["p"] = pair.p_value
        entry["a12_gaitgram_lower"] = pair.a12
        entry["a12_magnitude"] = pair.magnitude
        entry["wall_ratio"] = entry["ponyge2"]["seconds"] / entry["gaitgram"]["seconds"]
        cpu = [r.get("cpu_seconds") for tool in rows for r in rows[tool]]
        if all(c is not None for c in cpu):
            entry["cpu_ratio"] = sum(r["cpu_seconds"] for r in rows["ponyge2"]) / sum(
                r["cpu_seconds"] for r in rows["gaitgram"]
            )
        table[name] = entry
    return table


def _score(value: float | None) -> float:
    return math.inf if value is None else float(value)


def _median(values: list[float]) -> float:
    ordered = sorted(values)
    middle = len(ordered) // 2
    return ordered[middle] if len(ordered) % 2 else (ordered[middle - 1] + ordered[middle]) / 2


def show(table: Mapping[str, Any]) -> None:
    print(
        f"{'problem':16} {'runs':>4} {'gaitgram median':>16} {'PonyGE2 median':>15} {'U':>7} {'p':>7} "
        f"{'A12':>5} {'effect':>10} {'wall x':>7} {'cpu x':>6}"
    )
    for name, e in table.items():
        print(
            f"{name:16} {e['runs']['gaitgram']:>4} {e['gaitgram']['median']:>16.6g} "
            f"{e['ponyge2']['median']:>15.6g} {e['mann_whitney_u']:>7.1f} {e['p']:>7.3f} "
            f"{e['a12_gaitgram_lower']:>5.2f} {e['a12_magnitude']:>10} "
            f"{e['wall_ratio']:>7.2f} {e.get('cpu_ratio', math.nan):>6.2f}"
        )
    print("(RMSE on the training split, lower is better; A12: P(a gaitgram run ends lower), ties half;")
    print(" wall x / cpu x: PonyGE2's time over gaitgram's, summed over the runs)")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks ponyge2",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--runs", type=int, default=30, help="runs per tool and problem (default 30)")
    parser.add_argument(
        "--problems", default=",".join(PROBLEMS), help=f"comma-separated: {', '.join(PROBLEMS)}"
    )
    parser.add_argument(
        "--ponyge2", type=Path, default=os.environ.get("GAITGRAM_PONYGE2"), help="PonyGE2 checkout"
    )
    parser.add_argument(
        "--python", default=os.environ.get("GAITGRAM_PONYGE2_PYTHON"), help="PonyGE2's interpreter"
    )
    parser.add_argument("--out", type=Path, help="JSON lines of finished runs: appended, and resumed from")
    parser.add_argument("--summary", type=Path, help="write the summary as JSON here")
    parser.add_argument(
        "--ponyge2-args",
        default="",
        help='more PonyGE2 parameters after the shared ones, for an ablation ("--invalid_selection")',
    )
    args = parser.parse_args(argv or [])
    problems = [p.strip() for p in args.problems.split(",") if p.strip()]
    wrong = [p for p in problems if p not in PROBLEMS]
    if wrong or args.runs < 1:
        parser.error(f"--problems: unknown {', '.join(wrong)}" if wrong else "--runs: at least 1")
    try:
        ponyge2, python = check_setup(args.ponyge2 and Path(args.ponyge2), args.python)
    except Refused as refusal:
        print(f"bench_ponyge2: {refusal}", file=sys.stderr)
        raise SystemExit(2) from None
    found = execute(problems, args.runs, ponyge2, python, args.out, tuple(args.ponyge2_args.split()))
    table = summary(found, problems)
    show(table)
    if args.summary is not None:
        args.summary.write_text(json.dumps(table, indent=1) + "\n")
