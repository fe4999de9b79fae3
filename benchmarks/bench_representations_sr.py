"""The published representation claims, tested on PonyGE2's regression problems (issue 41, 5b).

GE, πGE, SGE, DSGE and CFG-GP each run ``--runs`` times (30 for the record) on Pagie-1, Keijzer-6
and Vladislavleva-4 with the grammars, data, fitness (training RMSE), budget (500 x 50), selection
(tournaments of 2, 4 elites) and seeds of ``bench_ponyge2`` (its problem setup, imported, not
repeated), each representation with the settings of its reference code (:data:`REPRESENTATIONS`,
and why, in docs/results/representations-sr/README.md); GE's runs are those of the PonyGE2
comparison, seed for seed. Tested, whatever they say:

* "SGE outperforms GE on every problem" (Lourenço, Pereira and Costa 2016) and "DSGE is never
  worse than SGE" (Lourenço et al. 2018): the final best training RMSE, Kruskal-Wallis across the
  five, two-sided Mann-Whitney U for SGE vs GE and DSGE vs SGE with Holm's correction over those
  six tests, and the Vargha-Delaney A12;
* "SGE's redundancy is low early and high later" (Medvet 2017): in each generation, of the
  population's distinct genotypes that map to a phenotype, the share whose phenotype at least one
  other distinct genotype of that generation also maps to (:func:`census`); its mean over the first
  and over the last tenth of the generations, compared run by run (Wilcoxon's signed-rank test,
  Holm over every representation and problem).

The statistics are scipy.stats' through :mod:`gaitgram.report.stats`. Runs go one after another in
this process (one worker), the representations alternating run by run. The PonyGE2 checkout gives
the grammars and Vladislavleva-4's data (no PonyGE2 run, no interpreter of its own)::

    git clone https://github.com/PonyGE/PonyGE2 /work/ponyge2
    python -m benchmarks representations_sr --ponyge2 /work/ponyge2 --out docs/results/representations-sr

``--out DIR`` appends each finished run to ``DIR/runs.jsonl`` and skips the runs already there (an
interrupted record resumes), then writes ``comparison.json`` and ``README.md`` from every run in it;
``--runs``, ``--generations`` and ``--population`` scale down (a record holds one budget only).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from benchmarks.bench_ponyge2 import (
    CODON_SIZE,
    CROSSOVER,
    ELITE,
    GE_SETTINGS,
    GENERATIONS,
    MUTATION,
    PONYGE2_MAX_DEPTH,
    PONYGE2_MAX_INIT_DEPTH,
    POPULATION,
    PROBLEMS,
    SEED,
    TOURNAMENT,
    Refused,
    check_checkout,
    gaitgram_config,
    records,
    run_gaitgram,
)

#: Each representation's settings (``[representation_settings]``); README.md says where each
#: value comes from. GE's are the PonyGE2 comparison's; πGE has GE's variation and limits. πGE
#: and CFG-GP ramp their initial trees to GE's depth: ramped to their limits (16, 17), a full tree
#: of Pagie-1's grammar runs to 300,000 characters, and a CFG-GP run took 190 s.
REPRESENTATIONS: dict[str, Mapping[str, Any]] = {
    "ge": GE_SETTINGS,
    "pige": {
        "stack": "inplace",
        "max_wraps": 0,
        "max_depth": PONYGE2_MAX_DEPTH - 1,
        "init_max_depth": PONYGE2_MAX_INIT_DEPTH - 1,
        "codon_size": CODON_SIZE,
        "crossover": CROSSOVER,
        "fixed_point": False,
        "crossover_within_used": True,
        "mutation": MUTATION,
        "grow_probability": 0.5,
        "tail": 0.5,
    },
    # Lourenço's SGE (nunolourenco/sge): its regression example unrolls to level 5
    # (``Grammar("grammars/regression.txt", 5)``), configs/standard.py PROB_CROSSOVER 0.9,
    # PROB_MUTATION 0.05 per gene; no depth limit but the unrolled grammar's.
    "sge": {"recursion": 5, "crossover": 0.9, "mutation": 0.05},
    # sge3 (DSGE), parameters/standard.yml: MAX_TREE_DEPTH 17, MIN_TREE_DEPTH 5 (root at 0, so 18
    # and 6 here), PROB_CROSSOVER 0.9, PROB_MUTATION 0.1.
    "dsge": {"max_depth": 18, "init_depth": 6, "crossover": 0.9, "mutation": 0.1},
    # Whigham's CFG-GP as alogos implements it: max_depth 17 (alogos' default).
    "cfg-gp": {
        "max_depth": 17,
        "init_max_depth": PONYGE2_MAX_INIT_DEPTH - 1,
        "crossover": 0.9,
        "mutation": 0.1,
        "grow_probability": 0.5,
    },
}

#: The claim pairs, (first, second): A12 is the probability that a run of the first ends lower.
CLAIM_PAIRS = (("sge", "ge"), ("dsge", "sge"))
#: Claim 3 read as Medvet compared: SGE's early redundancy against that of the GE variants he ran.
EARLY_PAIRS = (("sge", "ge"), ("sge", "pige"))
ALPHA = 0.05


# ---- the runs -----------------------------------------------------------------------------------


def census(population: Iterable[Any]) -> tuple[int, int, int, int]:
    """One generation's genotypes: (distinct genotypes; those of them that map to a phenotype; those
    of these whose phenotype at least one other distinct genotype of the generation also maps to;
    distinct phenotypes). Redundancy is the third over the second: an invalid genotype maps to
    nothing, so it is neither redundant nor not."""
    phenotype_of = {individual.genome: individual.phenotype for individual in population}
    mapped = Counter(p for p in phenotype_of.values() if p is not None)
    redundant = sum(count for count in mapped.values() if count > 1)
    return len(phenotype_of), sum(mapped.values()), redundant, len(mapped)


def redundancy(record: Mapping[str, Any]) -> list[float]:
    """A run's redundancy per generation, from its record (nan where no genotype maps)."""
    return [r / m if m else math.nan for r, m in zip(record["redundant"], record["mapped"], strict=True)]


def run_one(
    problem: str, representation: str, run: int, runs: int, ponyge2: Path, generations: int, population: int
) -> dict[str, Any]:
    """One run and its record: the final best, its time, and per generation the best fitness and
    the census of the population."""
    config = gaitgram_config(
        PROBLEMS[problem],
        ponyge2,
        runs,
        representation,
        REPRESENTATIONS[representation],
        generations=generations,
        population=population,
    )
    best: list[float | None] = []
    counts: list[tuple[int, int, int, int]] = []

    def watch(state: Any) -> None:
        fitness = state.best.fitness
        best.append(fitness if math.isfinite(fitness) else None)
        counts.append(census(state.population))

    result = run_gaitgram(PROBLEMS[problem], run, runs, ponyge2, config, watch)
    names = ("genotypes", "mapped", "redundant", "phenotypes")
    columns = {name: [c[i] for c in counts] for i, name in enumerate(names)}
    return {
        "problem": problem,
        "representation": representation,
        "run": run,
        "generations": generations,
        "population": population,
        **result,
        "best": best,
        **columns,
    }


def refusal(problem: str, representation: str, ponyge2: Path) -> str | None:
    """Why ``representation`` cannot run ``problem``'s grammar with its settings (None: it can)."""
    from gaitgram.analysis import check
    from gaitgram.language import load
    from gaitgram.pipeline import PipelineError
    from gaitgram.strategies.registry import run_pipeline

    spec = PROBLEMS[problem]
    config = gaitgram_config(spec, ponyge2, 1, representation, REPRESENTATIONS[representation])
    try:
        run_pipeline(check(load(ponyge2 / "grammars" / spec.grammar, defines=dict(spec.defines))), config)
    except PipelineError as error:  # what the representation says of the grammar and its settings
        return str(error)
    return None


def plan(
    problems: Sequence[str], representations: Sequence[str], runs: int
) -> Iterator[tuple[str, int, str]]:
    """(problem, run, representation), the representations alternating run by run, so that the
    load of a shared machine falls on all alike."""
    for problem in problems:
        for run in range(runs):
            shift = run % len(representations)
            for representation in (*representations[shift:], *representations[:shift]):
                yield problem, run, representation


def execute(
    problems: Sequence[str],
    representations: Sequence[str],
    runs: int,
    ponyge2: Path,
    out: Path | None,
    generations: int = GENERATIONS,
    population: int = POPULATION,
) -> list[dict[str, Any]]:
    """Every run of the plan not yet in ``out`` (appended there as it ends), and every record."""
    found = records(out)
    other = {(r.get("generations"), r.get("population")) for r in found if "refused" not in r}
    if other - {(generations, population)}:
        raise Refused(
            f"{out} holds runs of another budget ({', '.join(f'{g} x {p}' for g, p in sorted(other))}); "
            "pick another --out or the same --generations and --population"
        )
    done = {(r["problem"], r["representation"], r.get("run")) for r in found}
    refused = {(r["problem"], r["representation"]) for r in found if "refused" in r}

    def keep(record: dict[str, Any]) -> None:
        found.append(record)
        if out is not None:
            out.parent.mkdir(parents=True, exist_ok=True)
            with out.open("a") as handle:
                handle.write(json.dumps(record) + "\n")

    for problem in problems:
        for representation in representations:
            if (problem, representation) not in refused and not any(
                (problem, representation, run) in done for run in range(runs)
            ):
                why = refusal(problem, representation, ponyge2)
                if why is not None:
                    keep({"problem": problem, "representation": representation, "run": None, "refused": why})
                    refused.add((problem, representation))
    for problem, run, representation in plan(problems, representations, runs):
        if (problem, representation, run) in done or (problem, representation) in refused:
            continue
        record = run_one(problem, representation, run, runs, ponyge2, generations, population)
        keep(record)
        shown = "no score" if record["fitness"] is None else f"{record['fitness']:.6g}"
        print(
            f"{problem:16} run {run:2} {representation:7} RMSE {shown:>10}  "
            f"{record['cpu_seconds']:6.1f} s CPU",
            flush=True,
        )
    return [r for r in found if r["problem"] in problems and r["representation"] in representations]


# ---- the statistics -----------------------------------------------------------------------------


def _score(value: float | None) -> float:
    return math.inf if value is None else float(value)


def quartiles(values: Sequence[float]) -> tuple[float, float, float]:
    """Lower quartile, median and upper quartile (numpy's linear interpolation)."""
    import numpy as np

    q1, median, q3 = np.percentile(np.asarray(values, dtype=float), [25, 50, 75])
    return float(q1), float(median), float(q3)


def most_common(runs: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """The final best most runs end on (a trap such as Pagie-1's constant shows here): its RMSE,
    how many runs end on it, and the phenotype of the first of them."""
    ends = Counter(r["fitness"] for r in runs)
    fitness, count = max(ends.items(), key=lambda item: (item[1], -_score(item[0])))
    return {
        "fitness": fitness,
        "runs": count,
        "phenotype": next(r["phenotype"] for r in runs if r["fitness"] == fitness),
    }


def windows(generations: int) -> tuple[range, range]:
    """The early and the late generations: the first and the last tenth of the run's states
    (generations 0-4 and 46-50 of 0-50), at least one each."""
    width = max(1, (generations + 1) // 10)
    return range(width), range(generations + 1 - width, generations + 1)


def _window_mean(values: Sequence[float], window: range) -> float:
    chosen = [values[g] for g in window if not math.isnan(values[g])]
    return sum(chosen) / len(chosen) if chosen else math.nan


def summary(
    found: Sequence[Mapping[str, Any]], problems: Sequence[str], representations: Sequence[str]
) -> dict[str, Any]:
    """Everything comparison.json holds, computed from the records alone."""
    import numpy as np

    from gaitgram.report.stats import a12_magnitude, compare, holm, paired_wilcoxon

    refused = {f"{r['problem']}/{r['representation']}": r["refused"] for r in found if "refused" in r}
    budget = {(r["generations"], r["population"]) for r in found if "refused" not in r}
    generations, population = budget.pop() if len(budget) == 1 else (GENERATIONS, POPULATION)
    early, late = windows(generations)
    table: dict[str, Any] = {}
    claim_tests: list[dict[str, Any]] = []
    redundancy_tests: list[dict[str, Any]] = []
    early_tests: list[dict[str, Any]] = []
    for problem in problems:
        rows = {
            rep: sorted(
                (
                    r
                    for r in found
                    if r["problem"] == problem and r["representation"] == rep and "refused" not in r
                ),
                key=lambda r: r["run"],
            )
            for rep in representations
        }
        rows = {rep: runs for rep, runs in rows.items() if runs}
        if not rows:
            continue
        fitness = {rep: [_score(r["fitness"]) for r in runs] for rep, runs in rows.items()}
        entry: dict[str, Any] = {"runs": {rep: len(runs) for rep, runs in rows.items()}, "final": {}}
        for rep, values in fitness.items():
            q1, median, q3 = quartiles(values)
            entry["final"][rep] = {
                "median": median,
                "q1": q1,
                "q3": q3,
                "best": min(values),
                "worst": max(values),
                "unscored": sum(not math.isfinite(v) for v in values),
                "test_median": quartiles([_score(r["test_fitness"]) for r in rows[rep]])[1],
                "cpu_seconds_mean": sum(r["cpu_seconds"] for r in rows[rep]) / len(rows[rep]),
                "most_common": most_common(rows[rep]),
            }
        everything = compare(fitness)
        entry["kruskal_wallis"] = {"h": everything.kruskal_h, "p": everything.kruskal_p}
        entry["pairs"] = [
            {
                "first": pair.first,
                "second": pair.second,
                "u": pair.u,
                "p": pair.p_value,
                "p_holm_within_problem": pair.p_holm,
                "a12_first_lower": pair.a12,
            }
            for pair in everything.pairs
        ]
        entry["claim_pairs"] = []
        for first, second in CLAIM_PAIRS:
            if first in fitness and second in fitness:
                pair = compare({first: fitness[first], second: fitness[second]}).pairs[0]
                test = {
                    "first": first,
                    "second": second,
                    "u": pair.u,
                    "p": pair.p_value,
                    "a12_first_lower": pair.a12,
                }
                entry["claim_pairs"].append(test)
                claim_tests.append(test)
        entry["redundancy"] = {}
        entry["redundancy_by_generation"] = {}
        early_means: dict[str, list[float]] = {}
        for rep, runs in rows.items():
            curves = [redundancy(r) for r in runs]
            before = [_window_mean(c, early) for c in curves]
            after = [_window_mean(c, late) for c in curves]
            paired = [
                (a, b) for a, b in zip(before, after, strict=True) if not (math.isnan(a) or math.isnan(b))
            ]
            test = paired_wilcoxon("early", "late", [a for a, _ in paired], [b for _, b in paired])
            early_means[rep] = [a for a in before if not math.isnan(a)]
            entry["redundancy"][rep] = {
                "early_median": float(np.median([a for a, _ in paired])) if paired else math.nan,
                "late_median": float(np.median([b for _, b in paired])) if paired else math.nan,
                "runs": test.pairs,
                "late_higher": sum(b > a for a, b in paired),
                "wilcoxon_w": test.statistic,
                "p": test.p_value,
            }
            redundancy_tests.append(entry["redundancy"][rep])
            entry["redundancy_by_generation"][rep] = [
                float(np.nanmedian(column)) if not all(math.isnan(v) for v in column) else math.nan
                for column in zip(*curves, strict=True)
            ]
        entry["early_redundancy_pairs"] = []
        for first, second in EARLY_PAIRS:
            if early_means.get(first) and early_means.get(second):
                pair = compare({first: early_means[first], second: early_means[second]}).pairs[0]
                test = {
                    "first": first,
                    "second": second,
                    "u": pair.u,
                    "p": pair.p_value,
                    "a12_first_lower": pair.a12,
                }
                entry["early_redundancy_pairs"].append(test)
                early_tests.append(test)
        table[problem] = entry
    for tests in (claim_tests, redundancy_tests, early_tests):  # Holm within each family of tests
        for test, adjusted in zip(tests, holm([t["p"] for t in tests]), strict=True):
            test["p_holm"] = adjusted
            if "a12_first_lower" in test:
                test["magnitude"] = a12_magnitude(test["a12_first_lower"])
    return {
        "budget": {
            "generations": generations,
            "population": population,
            "elite": ELITE,
            "tournament": TOURNAMENT,
            "seed": SEED,
            "early_generations": [early.start, early.stop - 1],
            "late_generations": [late.start, late.stop - 1],
        },
        "settings": {rep: dict(REPRESENTATIONS[rep]) for rep in representations},
        "refused": refused,
        "problems": table,
        "claims": verdicts(table),
    }


def verdicts(table: Mapping[str, Any]) -> dict[str, Any]:
    """Each claim per problem, by the rules README.md states: SGE outperforms GE where its final
    RMSE is lower at Holm-adjusted p < 0.05; DSGE is worse than SGE where its RMSE is higher at
    Holm-adjusted p < 0.05 (the claim holds where that is not found); SGE's redundancy rises where
    its late mean is higher than its early one at Holm-adjusted p < 0.05. Beside claim 3, its
    comparative reading: SGE is less redundant early than GE and πGE (each at Holm p < 0.05)."""

    def pair(entry: Mapping[str, Any], first: str, second: str) -> Mapping[str, Any] | None:
        return next((p for p in entry["claim_pairs"] if (p["first"], p["second"]) == (first, second)), None)

    sge_ge, dsge_sge, rises, lower_early = {}, {}, {}, {}
    for problem, entry in table.items():
        if (test := pair(entry, "sge", "ge")) is not None:
            sge_ge[problem] = test["p_holm"] < ALPHA and test["a12_first_lower"] > 0.5
        if (test := pair(entry, "dsge", "sge")) is not None:
            dsge_sge[problem] = not (test["p_holm"] < ALPHA and test["a12_first_lower"] < 0.5)
        if (red := entry["redundancy"].get("sge")) is not None:
            rises[problem] = red["p_holm"] < ALPHA and red["late_median"] > red["early_median"]
        if tests := entry.get("early_redundancy_pairs"):
            lower_early[problem] = all(t["p_holm"] < ALPHA and t["a12_first_lower"] > 0.5 for t in tests)
    return {
        "sge_outperforms_ge": {"per_problem": sge_ge, "supported": bool(sge_ge) and all(sge_ge.values())},
        "dsge_never_worse_than_sge": {
            "per_problem": dsge_sge,
            "supported": bool(dsge_sge) and all(dsge_sge.values()),
        },
        "sge_redundancy_low_early_high_late": {
            "per_problem": rises,
            "supported": bool(rises) and all(rises.values()),
            "lower_early_than_ge_and_pige": lower_early,
        },
    }


# ---- the report ---------------------------------------------------------------------------------


def show(comparison: Mapping[str, Any]) -> None:
    for problem, entry in comparison["problems"].items():
        kw = entry["kruskal_wallis"]
        print(f"{problem}: Kruskal-Wallis H = {kw['h']:.2f}, p = {kw['p']:.3g}")
        for rep, final in entry["final"].items():
            red = entry["redundancy"][rep]
            print(
                f"  {rep:7} RMSE median {final['median']:.5g} ({final['q1']:.5g}-{final['q3']:.5g})"
                f"  redundancy early {red['early_median']:.3f} late {red['late_median']:.3f}"
                f" (Wilcoxon p {red['p']:.3g})"
            )
        for test in entry["claim_pairs"]:
            print(
                f"  {test['first']} vs {test['second']}: U = {test['u']:.1f}, p = {test['p']:.3g}, "
                f"Holm {test['p_holm']:.3g}, A12 = {test['a12_first_lower']:.2f} {test['magnitude']}"
            )
    for claim, verdict in comparison["claims"].items():
        print(f"{claim}: {'supported' if verdict['supported'] else 'not supported'} {verdict['per_problem']}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks representations_sr",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--runs", type=int, default=30, help="runs per representation and problem (default 30)"
    )
    parser.add_argument("--generations", type=int, default=GENERATIONS, help=f"default {GENERATIONS}")
    parser.add_argument("--population", type=int, default=POPULATION, help=f"default {POPULATION}")
    parser.add_argument(
        "--problems", default=",".join(PROBLEMS), help=f"comma-separated: {', '.join(PROBLEMS)}"
    )
    parser.add_argument(
        "--representations",
        default=",".join(REPRESENTATIONS),
        help=f"comma-separated: {', '.join(REPRESENTATIONS)}",
    )
    parser.add_argument(
        "--ponyge2", type=Path, default=os.environ.get("GAITGRAM_PONYGE2"), help="PonyGE2 checkout"
    )
    parser.add_argument(
        "--out", type=Path, help="a folder: runs.jsonl (appended, resumed), comparison.json, README.md"
    )
    args = parser.parse_args(argv or [])
    problems = [p.strip() for p in args.problems.split(",") if p.strip()]
    representations = [r.strip() for r in args.representations.split(",") if r.strip()]
    for flag, given, known in (
        ("--problems", problems, PROBLEMS),
        ("--representations", representations, REPRESENTATIONS),
    ):
        wrong = [name for name in given if name not in known]
        if wrong:
            parser.error(f"{flag}: unknown {', '.join(wrong)}; known: {', '.join(known)}")
    for flag, value, least in (
        ("--runs", args.runs, 2),
        ("--generations", args.generations, 1),
        ("--population", args.population, 2 * ELITE),
    ):
        if value < least:
            parser.error(f"{flag}: at least {least}, not {value}")
    try:
        ponyge2 = check_checkout(args.ponyge2 and Path(args.ponyge2), "representations_sr")
        found = execute(
            problems,
            representations,
            args.runs,
            ponyge2,
            args.out and args.out / "runs.jsonl",
            args.generations,
            args.population,
        )
    except Refused as refusal:
        print(f"bench_representations_sr: {refusal}", file=sys.stderr)
        raise SystemExit(2) from None
    found = [r for r in found if r.get("run") is None or r["run"] < args.runs]
    comparison = summary(found, problems, representations)
    show(comparison)
    if args.out is not None:
        write(args.out, comparison, found)


def write(out: Path, comparison: Mapping[str, Any], found: Sequence[Mapping[str, Any]]) -> None:
    """comparison.json (a figure that is not a number, such as no test possible, as null) and README.md."""
    from benchmarks._representations_sr_readme import readme
    from gaitgram.jsonio import dumps

    (out / "comparison.json").write_text(dumps(comparison, indent=1) + "\n")
    (out / "README.md").write_text(readme(comparison, found))
