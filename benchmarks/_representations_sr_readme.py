"""docs/results/representations-sr/README.md, written from the benchmark's records and statistics
(``bench_representations_sr``): the method, the figures, and each claim's verdict by the rules it
states, whatever the data say. Nothing in it is typed in by hand, so rerunning the benchmark on a
grown record rewrites it consistently."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
PONYGE2_RECORD = ROOT / "docs" / "results" / "ponyge2" / "runs.jsonl"

NAMES = {"ge": "GE", "pige": "πGE", "sge": "SGE", "dsge": "DSGE", "cfg-gp": "CFG-GP"}
TITLES = {"pagie-1": "Pagie-1", "keijzer-6": "Keijzer-6", "vladislavleva-4": "Vladislavleva-4"}

#: Where each representation's settings come from, and why (the values are the benchmark's).
SOURCES = {
    "ge": "the PonyGE2 comparison's, i.e. PonyGE2's GE with `parameters/regression.txt` "
    "([../ponyge2/README.md](../ponyge2/README.md) maps each): eager codons, no wraps, ramped "
    "half-and-half to depth 9 (PonyGE2's 10), variable one-point crossover 0.75 and int-flip "
    "mutation 0.01 within the used codons, depth limit 16 (PonyGE2's 17)",
    "pige": "no reference code to run (alogos is the reference for the stack modes): `inplace`, the "
    "Handbook of GE's example and alogos' default; everything else GE's (its variation, limits and "
    "initial depth), so that πGE and GE differ in the mapping alone",
    "sge": "Lourenço's original SGE (`nunolourenco/sge`, the 2016 paper's code): its regression "
    'example unrolls the grammar to recursion level 5 (`Grammar("grammars/regression.txt", 5)`; '
    "the reader's default is 3), `configs/standard.py` PROB_CROSSOVER 0.9 (a uniform mask over "
    "whole genes) and PROB_MUTATION 0.05 (per gene); no depth limit but the unrolled grammar's, as "
    "in that code",
    "dsge": "sge3 (`nunolourenco/sge3`, DSGE's code), `parameters/standard.yml`: MAX_TREE_DEPTH 17 "
    "and MIN_TREE_DEPTH 5 (18 and 6 here: sge3 counts the root 0), PROB_CROSSOVER 0.9, "
    "PROB_MUTATION 0.1 (per used value)",
    "cfg-gp": "Whigham 1995 as alogos implements it: MAX-TREE-DEPTH 17 (alogos' default); crossover "
    "0.9 and mutation 0.1, gaitgram's defaults; initial trees ramped to GE's depth 9 (alogos' "
    "default initialisation is PTC2; ramped to 17, one Pagie-1 run took 190 s of CPU, its first "
    "trees up to 344,000 characters long)",
}


def _g(value: float | None, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    return f"{value:.{digits}g}"


def _p(value: float | None) -> str:
    if value is None or not math.isfinite(value):
        return "n/a"
    return f"{value:.2g}" if value >= 0.001 else f"{value:.1e}"


def _share(value: float | None) -> str:
    return "n/a" if value is None or not math.isfinite(value) else f"{value:.2f}"


def _generations(window: Sequence[int]) -> str:
    first, last = window
    return f"generation {first}" if first == last else f"generations {first}-{last}"


def _settings(settings: Mapping[str, Any]) -> str:
    return ", ".join(f"`{k} = {json.dumps(v)}`" for k, v in settings.items())


def _pair_text(test: Mapping[str, Any], alpha: float, what: str = "ends lower") -> str:
    first, second = NAMES[test["first"]], NAMES[test["second"]]
    numbers = (
        f"U = {test['u']:.1f}, p = {_p(test['p'])}, Holm {_p(test['p_holm'])}, "
        f"A12 = {test['a12_first_lower']:.2f}"
    )
    if test["p_holm"] < alpha:
        lower = first if test["a12_first_lower"] > 0.5 else second
        return f"{lower} {what} ({numbers}, {test['magnitude']})"
    return f"no difference found ({numbers}, {test['magnitude']})"


def _ge_matches_record(found: Sequence[Mapping[str, Any]]) -> tuple[int, int] | None:
    """How many GE runs end exactly where the PonyGE2 comparison's gaitgram runs of the same
    problem and index ended (None: no such record, or another budget)."""
    if not PONYGE2_RECORD.exists():
        return None
    recorded = {
        (r["problem"], r["run"]): r["fitness"]
        for r in map(json.loads, PONYGE2_RECORD.read_text().splitlines())
        if r.get("tool") == "gaitgram"
    }
    ours = [
        r
        for r in found
        if r.get("representation") == "ge" and "refused" not in r and (r["problem"], r["run"]) in recorded
    ]
    if not ours or any((r["generations"], r["population"]) != (50, 500) for r in ours):
        return None
    return sum(r["fitness"] == recorded[r["problem"], r["run"]] for r in ours), len(ours)


def readme(comparison: Mapping[str, Any], found: Sequence[Mapping[str, Any]], alpha: float = 0.05) -> str:
    """The README of a record: ``comparison`` is :func:`summary`'s, ``found`` every record."""
    budget, problems, claims = comparison["budget"], comparison["problems"], comparison["claims"]
    reps = list(comparison["settings"])
    runs = [r for r in found if "refused" not in r]
    counts = sorted({n for e in problems.values() for n in e["runs"].values()})
    per = "/".join(str(n) for n in counts) or "0"
    early, late = budget["early_generations"], budget["late_generations"]
    out: list[str] = []
    add = out.append
    add("# Five representations on PonyGE2's regression problems: the published claims tested\n")
    add(
        "Issue 41 item 5(b): the published claims about grammar-guided representations, tested on "
        "Pagie-1, Keijzer-6 and Vladislavleva-4 with gaitgram's GE, πGE, SGE, DSGE and CFG-GP, "
        f"{per} runs per representation and problem, with rank tests. The claims:\n"
    )
    add(
        "1. *SGE outperforms GE on every problem* of its first paper (Lourenço, Pereira and Costa, "
        '"SGE: a structured representation for grammatical evolution", EA 2015, LNCS 9554, 2016: '
        '"able to outperform standard grammatical evolution on all selected optimization problems").\n'
        "2. *DSGE is never worse than SGE* (Lourenço et al. 2018, Handbook of Grammatical "
        "Evolution, ch. 6).\n"
        "3. *SGE's redundancy is low early in a run and high later* (Medvet 2017, EuroGP: \"less "
        "redundant at the beginning of the evolution, but with very high redundancy after some "
        'generations").\n'
    )
    add("**In short.** " + " ".join(_short(claims, problems, alpha)) + "\n")

    add("## What ran\n")
    add(
        "The problems, grammars (PonyGE2's files, unchanged), data and fitness (RMSE on the training "
        "split) are those of the PonyGE2 comparison ([../ponyge2/README.md](../ponyge2/README.md)), "
        "set up by the same code (`benchmarks/bench_ponyge2.py`, imported by "
        "`benchmarks/bench_representations_sr.py`). Every representation runs under the same loop: "
        f"{budget['population']} individuals, {budget['generations']} generations, tournaments of "
        f"{budget['tournament']} with replacement, {budget['elite']} elites, generational replacement"
        + (
            " (PonyGE2's `regression.txt` budget)"
            if (budget["population"], budget["generations"]) == (500, 50)
            else " (scaled down from PonyGE2's `regression.txt` budget, 500 x 50)"
        )
        + f". Run *i* of every representation takes the *i*-th seed spawned from seed {budget['seed']}, "
        "as the PonyGE2 comparison's gaitgram runs do; each representation draws differently from "
        "it, so runs are paired by index only."
        + (
            ""
            if (matches := _ge_matches_record(found)) is None
            else f" GE's runs are those runs again: {matches[0]} of {matches[1]} end on exactly the "
            "final best the PonyGE2 comparison recorded for the same problem and index."
        )
        + "\n"
    )
    add(
        "Each representation has the settings of its reference code where there is one. The papers' "
        "texts were not at hand to check their tables against; the values below are the reference "
        "codes' own. What is *not* taken from them is the loop: Lourenço's codes run 1,000 individuals, "
        "tournaments of 3 and 10 % elitism; here every representation has the same selection and "
        "budget, so that what differs is the representation (genome, mapping, initialisation and "
        "variation), not the selection pressure.\n"
    )
    add("| representation | settings (`[representation_settings]`) | from |")
    add("|---|---|---|")
    for rep in reps:
        add(f"| {NAMES[rep]} (`{rep}`) | {_settings(comparison['settings'][rep])} | {SOURCES[rep]} |")
    add("")
    refused = comparison["refused"]
    if refused:
        add("**Refused.** These representations could not run these grammars with these settings:\n")
        for key, why in refused.items():
            problem, rep = key.split("/")
            add(f"- {NAMES[rep]} on {TITLES.get(problem, problem)}: {why}")
        add("")
    else:
        add(
            "**Refused: none.** Every representation compiled every grammar with these settings (SGE's "
            "unrolled genomes stay well under its million-value limit at level 5).\n"
        )

    add("### Redundancy, as measured here\n")
    add(
        "In each generation (the population after it: the elites and the offspring; generation 0 the "
        "first population), of the *distinct* genotypes that map to a phenotype, the share whose "
        "phenotype at least one other distinct genotype of that generation also maps to. Copies of "
        "one genotype (elites, clones) count once; an invalid genotype maps to nothing and is left out "
        "of the "
        "share (it is neither redundant nor not). A genotype is the whole genome (GE's unused tail "
        "included: two GE genomes that differ only there are two genotypes of one phenotype); a "
        "phenotype is the derived text. This is the issue's definition, not Medvet's own measure "
        "(which is not reproduced here), so it tests the claim's direction, not his numbers. "
        "CFG-GP's genotype is the derivation tree itself: where each phenotype has one derivation "
        "(Pagie-1's grammar parenthesises every operation) its redundancy is 0 by construction; "
        "Keijzer-6's and Vladislavleva-4's grammars write `<e>+<e>` without parentheses (and "
        "Keijzer-6's lists `x[:, 0]` and the constants four times each), so there several trees can "
        "give one phenotype. "
        "`runs.jsonl` keeps per "
        "generation the counts it is made of (`genotypes`, `mapped`, `redundant`, `phenotypes`), so "
        "other readings can be computed from the record.\n"
    )
    add(
        f"*Early* is a run's mean over {_generations(early)}, *late* over {_generations(late)} (the "
        "first and the last tenth of the run's generations).\n"
    )
    add("### Statistics and the rules for a verdict\n")
    add(
        "scipy.stats, through `gaitgram.report.stats`: Kruskal-Wallis across the five representations "
        "per problem; two-sided Mann-Whitney U for the claim pairs (SGE vs GE, DSGE vs SGE) on each "
        "problem, Holm's correction over those six tests; Vargha-Delaney A12, the probability that a "
        "run of the first ends lower (better) than a run of the second, ties half; Wilcoxon's "
        "signed-rank test (two-sided) of early against late redundancy run by run, Holm over every "
        "representation and problem. A run whose best is unscored counts as the worst. Quartiles are "
        f"numpy's (linear interpolation). The verdicts, at α = {alpha}:\n"
    )
    add(
        "- claim 1 holds on a problem where SGE's final RMSE is lower than GE's (A12 > 0.5) at Holm "
        "p < 0.05; it is supported if it holds on every problem;\n"
        "- claim 2 fails on a problem where DSGE's final RMSE is higher than SGE's (A12 < 0.5) at Holm "
        "p < 0.05; it is supported if it fails on none (which is the absence of evidence against it, "
        "not proof that DSGE is never worse);\n"
        "- claim 3 holds on a problem where SGE's late redundancy is higher than its early one "
        "(medians) at Holm p < 0.05; it is supported if it holds on every problem. Its comparative "
        "reading, as Medvet compared GE variants, is reported beside it: SGE's early redundancy "
        "lower than both GE's and πGE's (Mann-Whitney U, Holm over those six tests, p < 0.05 and "
        "A12 > 0.5, A12 the probability that an SGE run's early mean is the lower).\n"
    )

    add("## Command\n")
    cpu = sum(r["cpu_seconds"] for r in runs)
    wall = sum(r["seconds"] for r in runs)
    add("```sh")
    add("git clone https://github.com/PonyGE/PonyGE2 /work/ponyge2   # grammars, Vladislavleva-4's data")
    add(
        "nice -n 5 .venv/bin/python -m benchmarks representations_sr --ponyge2 /work/ponyge2 "
        "--out docs/results/representations-sr"
    )
    add("```\n")
    add(
        f"{len(runs)} runs, one after another in one process: {cpu / 60:.0f} minutes of CPU in all, "
        f"{wall / 60:.0f} minutes of wall time on 2 cores shared with other jobs. Per run (CPU seconds, "
        "mean over the problem's runs):\n"
    )
    add("| problem | " + " | ".join(NAMES[r] for r in reps) + " |")
    add("|---|" + "---:|" * len(reps))
    for problem, entry in problems.items():
        cells = [_g(entry["final"][r]["cpu_seconds_mean"], 3) if r in entry["final"] else "n/a" for r in reps]
        add(f"| {TITLES.get(problem, problem)} | " + " | ".join(cells) + " |")
    add("")
    add(
        "`--out` appends each finished run to `runs.jsonl` and skips the runs already there, so an "
        "interrupted record resumes; `comparison.json` and this README are written from every run "
        "in it. PonyGE2 commit f337171708a07e028587ac5ec3537e051691daf7 (its data files are checked "
        "against the digests in `tests/data/ponyge2_regression/datasets.json` first). Files: "
        "`runs.jsonl`, one line per run (problem, representation, run, the budget, final best "
        "training and test RMSE, its phenotype, wall and CPU seconds, and per generation the best "
        "fitness and the census above); `comparison.json`, every figure below.\n"
    )

    add("## Figures\n")
    add(
        "Final best training RMSE (lower is better): median (lower-upper quartile), the best run, "
        "the median test RMSE of the final bests, and Kruskal-Wallis across the five.\n"
    )
    add("| problem | representation | median (quartiles) | best | test median | unscored |")
    add("|---|---|---|---:|---:|---:|")
    for problem, entry in problems.items():
        for rep, final in entry["final"].items():
            add(
                f"| {TITLES.get(problem, problem)} | {NAMES[rep]} | {_g(final['median'])} "
                f"({_g(final['q1'])}-{_g(final['q3'])}) | {_g(final['best'])} | "
                f"{_g(final['test_median'])} | {final['unscored']} |"
            )
    add("")
    add(
        "The final best most runs end on, and how many do (ties by RMSE: two runs count together "
        "only when their RMSE is equal to the last bit):\n"
    )
    add("| problem | representation | RMSE | runs | phenotype |")
    add("|---|---|---:|---:|---|")
    for problem, entry in problems.items():
        for rep, final in entry["final"].items():
            common = final["most_common"]
            text = common["phenotype"] or ""
            shown = f"`{text}`" if len(text) <= 60 else f"`{text[:57]}...` ({len(text):,} characters)"
            add(
                f"| {TITLES.get(problem, problem)} | {NAMES[rep]} | {_g(common['fitness'])} | "
                f"{common['runs']} | {shown} |"
            )
    add("")
    for problem, entry in problems.items():
        kw = entry["kruskal_wallis"]
        add(f"- {TITLES.get(problem, problem)}: Kruskal-Wallis H = {_g(kw['h'], 3)}, p = {_p(kw['p'])}")
    add("")
    add("The claim pairs (A12: the probability that a run of the first ends lower):\n")
    add("| problem | pair | U | p | p (Holm, 6 tests) | A12 | effect |")
    add("|---|---|---:|---:|---:|---:|---|")
    for problem, entry in problems.items():
        for test in entry["claim_pairs"]:
            add(
                f"| {TITLES.get(problem, problem)} | {NAMES[test['first']]} vs {NAMES[test['second']]} | "
                f"{test['u']:.1f} | {_p(test['p'])} | {_p(test['p_holm'])} | "
                f"{test['a12_first_lower']:.2f} | {test['magnitude']} |"
            )
    add("")
    add(
        "Every pair of representations, with Holm's correction over the ten pairs of a problem, is "
        "in `comparison.json` (`pairs`).\n"
    )
    add("### Redundancy\n")
    add(
        "Median over runs of each run's early and late mean; runs whose late mean is higher; Wilcoxon's "
        "signed-rank test, early against late.\n"
    )
    add("| problem | representation | early | late | late higher | W | p | p (Holm) |")
    add("|---|---|---:|---:|---:|---:|---:|---:|")
    for problem, entry in problems.items():
        for rep, red in entry["redundancy"].items():
            add(
                f"| {TITLES.get(problem, problem)} | {NAMES[rep]} | {_share(red['early_median'])} | "
                f"{_share(red['late_median'])} | {red['late_higher']}/{red['runs']} | "
                f"{_g(red['wilcoxon_w'], 4)} | {_p(red['p'])} | {_p(red['p_holm'])} |"
            )
    add("")
    shown = sorted({0, *range(0, budget["generations"] + 1, max(1, budget["generations"] // 10))})
    add("SGE's early redundancy against GE's and πGE's (Medvet's comparison):\n")
    add("| problem | pair | U | p | p (Holm, 6 tests) | A12 (SGE lower) | effect |")
    add("|---|---|---:|---:|---:|---:|---|")
    for problem, entry in problems.items():
        for test in entry.get("early_redundancy_pairs", []):
            add(
                f"| {TITLES.get(problem, problem)} | {NAMES[test['first']]} vs {NAMES[test['second']]} | "
                f"{test['u']:.1f} | {_p(test['p'])} | {_p(test['p_holm'])} | "
                f"{test['a12_first_lower']:.2f} | {test['magnitude']} |"
            )
    add("")
    add("Median redundancy over runs, by generation:\n")
    for problem, entry in problems.items():
        add(f"{TITLES.get(problem, problem)}:\n")
        add("| representation | " + " | ".join(str(g) for g in shown) + " |")
        add("|---|" + "---:|" * len(shown))
        for rep, curve in entry["redundancy_by_generation"].items():
            add(f"| {NAMES[rep]} | " + " | ".join(_share(curve[g]) for g in shown) + " |")
        add("")

    add("## What it shows, and what it does not\n")
    out.extend(_reading(claims, problems, alpha))
    add("")
    return "\n".join(out)


def _verdict(supported: bool) -> str:
    return "**supported**" if supported else "**not supported**"


def _short(claims: Mapping[str, Any], problems: Mapping[str, Any], alpha: float) -> list[str]:
    one, two, three = (
        claims["sge_outperforms_ge"],
        claims["dsge_never_worse_than_sge"],
        claims["sge_redundancy_low_early_high_late"],
    )
    held = [TITLES.get(p, p) for p, ok in one["per_problem"].items() if ok]
    failed = [TITLES.get(p, p) for p, ok in two["per_problem"].items() if not ok]
    rose = [TITLES.get(p, p) for p, ok in three["per_problem"].items() if ok]
    lower = [TITLES.get(p, p) for p, ok in three.get("lower_early_than_ge_and_pige", {}).items() if ok]
    reverse = [
        TITLES.get(problem, problem)
        for problem, entry in problems.items()
        for t in entry["claim_pairs"]
        if (t["first"], t["second"]) == ("sge", "ge") and t["p_holm"] < alpha and t["a12_first_lower"] < 0.5
    ]
    n = len(problems)

    def listed(names: list[str]) -> str:
        return f" ({', '.join(names)})" if names else ""

    return [
        f"Claim 1 (SGE beats GE) is {_verdict(one['supported'])} by these data: SGE ends lower on "
        f"{len(held)} of {n} problems{listed(held)}"
        + (f", GE on {len(reverse)}{listed(reverse)}." if reverse else "."),
        f"Claim 2 (DSGE never worse than SGE) is {_verdict(two['supported'])}: DSGE ends higher on "
        f"{len(failed)} of {n}{listed(failed)}.",
        f"Claim 3 (SGE's redundancy low early, high later) is {_verdict(three['supported'])} as a rise "
        f"within SGE's runs, on {len(rose)} of {n}{listed(rose)}; read as Medvet compared, SGE is less "
        f"redundant early than GE and πGE on {len(lower)} of {n}{listed(lower)}.",
        f"(Holm-corrected tests at α = {alpha}; the rules are below.)",
    ]


def _gathered(problems: Mapping[str, Any]) -> list[str]:
    """Where a third of a representation's runs or more end on one final best (a trap), and which
    representation ends lowest on each problem: what the figures show beside the claims."""
    lines = ["- **Beside the claims.**"]
    for problem, entry in problems.items():
        final = entry["final"]
        runs = entry["runs"]
        traps = [
            f"{final[rep]['most_common']['runs']} of {NAMES[rep]}'s {runs[rep]}"
            for rep in final
            if final[rep]["most_common"]["runs"] * 3 >= runs[rep] and final[rep]["most_common"]["runs"] > 1
        ]
        by_phenotype: dict[str, list[str]] = {}
        for rep in final:
            if final[rep]["most_common"]["runs"] * 3 >= runs[rep] and final[rep]["most_common"]["runs"] > 1:
                by_phenotype.setdefault(final[rep]["most_common"]["phenotype"] or "", []).append(rep)
        lowest = min(final, key=lambda rep: final[rep]["median"])
        text = (
            f"  {TITLES.get(problem, problem)}: {NAMES[lowest]} has the lowest median final RMSE "
            f"({_g(final[lowest]['median'])}; Kruskal-Wallis p = {_p(entry['kruskal_wallis']['p'])})."
        )
        if traps:
            where = "; ".join(
                f"`{phenotype}` ({', '.join(NAMES[r] for r in reps)})"
                if len(phenotype) <= 60
                else f"a phenotype of {len(phenotype):,} characters ({', '.join(NAMES[r] for r in reps)})"
                for phenotype, reps in by_phenotype.items()
            )
            text += f" A third of the runs or more end on one final best: {', '.join(traps)}, on {where}."
        lines.append(text)
    return lines


def _reading(claims: Mapping[str, Any], problems: Mapping[str, Any], alpha: float) -> list[str]:
    lines: list[str] = []
    one = claims["sge_outperforms_ge"]
    lines.append(f"- **Claim 1, SGE outperforms GE: {_verdict(one['supported'])[2:-2]}.**")
    for problem, entry in problems.items():
        test = next((t for t in entry["claim_pairs"] if (t["first"], t["second"]) == ("sge", "ge")), None)
        if test is not None:
            lines.append(f"  {TITLES.get(problem, problem)}: {_pair_text(test, alpha)}.")
    two = claims["dsge_never_worse_than_sge"]
    lines.append(f"- **Claim 2, DSGE never worse than SGE: {_verdict(two['supported'])[2:-2]}.**")
    for problem, entry in problems.items():
        test = next((t for t in entry["claim_pairs"] if (t["first"], t["second"]) == ("dsge", "sge")), None)
        if test is not None:
            lines.append(f"  {TITLES.get(problem, problem)}: {_pair_text(test, alpha)}.")
    lines.append(
        '  A test that finds DSGE no worse is not evidence that it is never worse: "never" is not a '
        "claim 30 runs on three problems can confirm, only one they could have refuted."
    )
    three = claims["sge_redundancy_low_early_high_late"]
    lines.append(
        f"- **Claim 3, SGE's redundancy low early and high later: {_verdict(three['supported'])[2:-2]}.**"
    )
    for problem, entry in problems.items():
        red = entry["redundancy"].get("sge")
        if red is None:
            continue
        early_rank = (
            sorted(entry["redundancy"], key=lambda r: entry["redundancy"][r]["early_median"]).index("sge") + 1
        )
        late_rank = (
            sorted(entry["redundancy"], key=lambda r: -entry["redundancy"][r]["late_median"]).index("sge") + 1
        )
        change = (
            "rises"
            if red["p_holm"] < alpha and red["late_median"] > red["early_median"]
            else ("falls" if red["p_holm"] < alpha else "does not change detectably")
        )
        lines.append(
            f"  {TITLES.get(problem, problem)}: SGE's redundancy {change}, from "
            f"{_share(red['early_median'])} early to {_share(red['late_median'])} late "
            f"(higher late in {red['late_higher']} of "
            f"{red['runs']} runs, Holm p = {_p(red['p_holm'])}); early it ranks {early_rank} of "
            f"{len(entry['redundancy'])} from the lowest, late {late_rank} from the highest. Early, "
            + "; ".join(
                f"against {NAMES[t['second']]}: {_pair_text(t, alpha, 'is lower')}"
                for t in entry.get("early_redundancy_pairs", [])
            )
            + "."
        )
    lines.extend(_gathered(problems))
    lines.append(
        "- **Not tested here.** The claims were made on other problems (the SGE papers' own "
        "benchmarks), other budgets (1,000 individuals) and selection (tournaments of 3, 10 % "
        "elitism), and, for claim 3, with Medvet's own measure of redundancy: these data say whether "
        "the claims carry over to PonyGE2's three regression problems under one shared loop, not "
        "whether the papers' own results reproduce. Only the training RMSE of the final best is "
        "compared; generalisation (the test RMSE, in the table) and run time are reported, not tested. "
        "Thirty runs find large and medium effects reliably; a small one may go undetected."
    )
    return lines
