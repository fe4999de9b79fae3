"""Statistics for comparing stochastic optimisers, the way the field recommends.

The paper reports mean and standard deviation over 30 runs and tests nothing.
Fitness distributions of evolutionary runs are skewed and bounded, so a study
report uses rank statistics (scipy.stats): Kruskal-Wallis across all arms,
two-sided Mann-Whitney U for each pair with Holm's step-down correction for the
number of pairs, the Vargha-Delaney A12 effect size, and bootstrap confidence
intervals of each arm's median. Fitness is minimised throughout. Two more
questions get their own tests: whether arms' walk rates differ (Fisher's exact
test per pair, Holm-adjusted) and whether their final bests spread differently
(Levene's test centred on the median, the Brown-Forsythe test, robust to skew).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

#: Vargha & Delaney's thresholds for |A12 - 0.5|: negligible below 0.06, small, medium from 0.14,
#: large from 0.21 (A12 of 0.56, 0.64, 0.71).
A12_THRESHOLDS = ((0.21, "large"), (0.14, "medium"), (0.06, "small"))
#: Resamples for bootstrap intervals; the generator is seeded, so reports are reproducible.
BOOTSTRAP_RESAMPLES = 10_000
BOOTSTRAP_SEED = 20_260_401


def a12(x: Sequence[float], y: Sequence[float]) -> float:
    """Vargha-Delaney A12 for minimisation: the probability that a run of ``x`` ends lower (better)
    than a run of ``y``, ties counting half. 0.5: no difference; 1: ``x`` always better."""
    a, b = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if not len(a) or not len(b):
        return math.nan
    less = (a[:, None] < b[None, :]).sum()
    equal = (a[:, None] == b[None, :]).sum()
    return float((less + 0.5 * equal) / (len(a) * len(b)))


def a12_magnitude(value: float) -> str:
    distance = abs(value - 0.5)
    for threshold, name in A12_THRESHOLDS:
        if distance >= threshold:
            return name
    return "negligible"


def holm(p_values: Sequence[float]) -> list[float]:
    """Holm's step-down adjusted p-values (each capped at 1, monotone in the sorted order); a
    p-value that is nan (no test was possible) stays nan and is not counted."""
    tested = [i for i, p in enumerate(p_values) if not math.isnan(p)]
    m = len(tested)
    order = sorted(tested, key=lambda i: p_values[i])
    adjusted = [math.nan] * len(p_values)
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p_values[i]))
        adjusted[i] = running
    return adjusted


def bootstrap_median_ci(values: Sequence[float], confidence: float = 0.95) -> tuple[float, float]:
    """A percentile bootstrap interval of the median (seeded: the same data give the same interval)."""
    from scipy import stats

    data = np.asarray(values, dtype=float)
    if len(data) < 2 or np.ptp(data) == 0:
        median = float(np.median(data)) if len(data) else math.nan
        return median, median
    result = stats.bootstrap(
        (data,),
        np.median,
        confidence_level=confidence,
        n_resamples=BOOTSTRAP_RESAMPLES,
        method="percentile",
        random_state=np.random.default_rng(BOOTSTRAP_SEED),
    )
    return float(result.confidence_interval.low), float(result.confidence_interval.high)


def wilson_interval(successes: int, trials: int, confidence: float = 0.95) -> tuple[float, float]:
    """Wilson's score interval of a share (Wilson 1927): unlike the normal approximation it stays
    within [0, 1] and is not empty at 0 or n successes, which small studies often report."""
    from scipy import stats

    interval = stats.binomtest(successes, trials).proportion_ci(confidence_level=confidence, method="wilson")
    return float(interval.low), float(interval.high)


@dataclass(frozen=True)
class PairedTest:
    """Two treatments of the same units (each run's best gait played two ways), compared pair by
    pair: Wilcoxon's signed-rank test, two-sided, on the differences."""

    first: str
    second: str
    pairs: int
    first_lower: int  # pairs where the first's value is lower (better, for a fitness)
    statistic: float
    p_value: float


def paired_wilcoxon(first: str, second: str, a: Sequence[float], b: Sequence[float]) -> PairedTest:
    from scipy import stats

    x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    lower = int(np.sum(x < y))
    if len(x) == 0 or np.all(x == y):  # no difference to rank
        return PairedTest(first, second, len(x), lower, 0.0, 1.0)
    result = stats.wilcoxon(x, y, alternative="two-sided")
    return PairedTest(first, second, len(x), lower, float(result.statistic), float(result.pvalue))


def mcnemar_exact(first_only: int, second_only: int) -> float:
    """McNemar's exact test of paired yes/no outcomes (a gait that walks one way and not the
    other): two-sided binomial p of the discordant pairs; 1 when there are none."""
    from scipy import stats

    discordant = first_only + second_only
    return float(stats.binomtest(first_only, discordant, 0.5).pvalue) if discordant else 1.0


def paired_summary(
    values: Mapping[str, Sequence[float]], walks: Mapping[str, Sequence[bool]] | None = None
) -> dict[str, Any]:
    """The same units (runs) under several treatments (playings): per treatment the median value
    and, with ``walks``, how many units walk with Wilson's interval; per pair of treatments,
    which is lower unit by unit (Wilcoxon's signed-rank test) and, with ``walks``, which walks
    where the other does not (McNemar's exact test)."""
    names = list(values)
    summary: dict[str, Any] = {"runs": len(values[names[0]]) if names else 0, "playings": {}, "paired": []}
    for name in names:
        entry: dict[str, Any] = {"median_fitness": float(np.median(values[name]))}
        if walks is not None:
            count = sum(walks[name])
            entry |= {"walks": count, "wilson95": list(wilson_interval(count, len(walks[name])))}
        summary["playings"][name] = entry
    for first, second in itertools.combinations(names, 2):
        test: dict[str, Any] = asdict(paired_wilcoxon(first, second, values[first], values[second]))
        if walks is not None:
            only = [
                sum(a and not b for a, b in zip(walks[x], walks[y], strict=True))
                for x, y in ((first, second), (second, first))
            ]
            test |= {
                "walks_first_only": only[0],
                "walks_second_only": only[1],
                "mcnemar_p": mcnemar_exact(*only),
            }
        summary["paired"].append(test)
    return summary


@dataclass(frozen=True)
class PairTest:
    first: str
    second: str
    u: float
    p_value: float
    p_holm: float
    a12: float

    @property
    def magnitude(self) -> str:
        return a12_magnitude(self.a12)


@dataclass(frozen=True)
class Comparison:
    """Every test a study report shows, on one value per run (e.g. the final best fitness)."""

    kruskal_h: float
    kruskal_p: float
    pairs: tuple[PairTest, ...]


def compare(groups: Mapping[str, Sequence[float]]) -> Comparison:
    """Kruskal-Wallis over all groups, and Mann-Whitney U, Holm and A12 for each pair in order."""
    from scipy import stats

    names = list(groups)
    samples = [np.asarray(groups[n], dtype=float) for n in names]
    if len(names) >= 2 and all(len(s) for s in samples) and _varied(samples):
        h, p = stats.kruskal(*samples)
    else:
        h, p = math.nan, math.nan
    raw = []
    for a, b in itertools.combinations(range(len(names)), 2):
        x, y = samples[a], samples[b]
        if len(x) and len(y) and _varied([x, y]):
            u, pu = stats.mannwhitneyu(x, y, alternative="two-sided")
        else:  # identical constants: no evidence of a difference
            u, pu = len(x) * len(y) / 2, 1.0
        raw.append((names[a], names[b], float(u), float(pu), a12(x, y)))
    adjusted = holm([r[3] for r in raw])
    pairs = tuple(PairTest(f, s, u, p_, adj, e) for (f, s, u, p_, e), adj in zip(raw, adjusted, strict=True))
    return Comparison(float(h), float(p), pairs)


def _varied(samples: Sequence[np.ndarray]) -> bool:
    """scipy's rank tests are undefined when every value of every sample is the same."""
    joined = np.concatenate(samples)
    return bool(len(joined) and np.ptp(joined) > 0)


@dataclass(frozen=True)
class RatePair:
    """Two arms' rates of successes (walks) in their runs, compared by Fisher's exact test."""

    first: str
    second: str
    p_value: float
    p_holm: float


def compare_rates(counts: Mapping[str, tuple[int, int]]) -> tuple[RatePair, ...]:
    """Fisher's exact test (two-sided) for each pair of ``name: (successes, trials)``, in order,
    Holm-adjusted over the pairs."""
    from scipy import stats

    raw = []
    for (a, (k, n)), (b, (j, m)) in itertools.combinations(counts.items(), 2):
        p = float(stats.fisher_exact([[k, n - k], [j, m - j]]).pvalue) if n and m else math.nan
        raw.append((a, b, p))
    adjusted = holm([p for *_, p in raw])
    return tuple(RatePair(a, b, p, q) for (a, b, p), q in zip(raw, adjusted, strict=True))


@dataclass(frozen=True)
class SpreadPair:
    first: str
    second: str
    statistic: float
    p_value: float
    p_holm: float


@dataclass(frozen=True)
class SpreadComparison:
    """Levene's test centred on the median (Brown-Forsythe) over all groups and for each pair."""

    statistic: float
    p_value: float
    pairs: tuple[SpreadPair, ...]


def compare_spreads(groups: Mapping[str, Sequence[float]]) -> SpreadComparison:
    """Whether the groups spread differently: Brown-Forsythe over all of them, and for each pair
    in order, Holm-adjusted. A test is nan (and left out of Holm) where some group has fewer than
    two values, or where within every group the deviations from the median are equal (two runs
    an arm always are; so are runs ending on two plateaus): the statistic divides by their spread,
    and rounding alone would make it huge."""
    from scipy import stats

    def equal_deviations(x: np.ndarray) -> bool:
        deviations = np.abs(x - np.median(x))
        scale = max(float(np.max(np.abs(x))), 1e-300)
        return bool(np.ptp(deviations) <= 1e-9 * scale)

    def test(samples: list[np.ndarray]) -> tuple[float, float]:
        if len(samples) < 2 or any(len(x) < 2 for x in samples):
            return math.nan, math.nan
        if all(equal_deviations(x) for x in samples):
            return math.nan, math.nan
        result = stats.levene(*samples, center="median")
        return float(result.statistic), float(result.pvalue)

    names = list(groups)
    samples = {n: np.asarray(groups[n], dtype=float) for n in names}
    overall = test(list(samples.values()))
    raw = [(a, b, *test([samples[a], samples[b]])) for a, b in itertools.combinations(names, 2)]
    adjusted = holm([p for *_, p in raw])
    pairs = tuple(SpreadPair(a, b, w, p, q) for (a, b, w, p), q in zip(raw, adjusted, strict=True))
    return SpreadComparison(*overall, pairs)
