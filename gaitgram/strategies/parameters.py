"""A grammar's parameter vector: for grammars whose derivations differ only in typed-range values.

Such a grammar (``grammars/numerical.gg``: the seed's Fourier curves with every
number a range around it) derives one fixed expression; a genome only picks a
value for each range it reads, in the order the mapper reads them. So the
search space is a box: one coordinate in [0, 1] per range read, mapped onto
the range's values (``k`` values split [0, 1] into ``k`` equal parts), and a
vector becomes a genome that the pipeline maps and scores like any other.

A grammar with a structural choice (alternatives of different shape, such as
``hybrid.gg``'s optional terms) has no such vector: which ranges are read, and
how many, depends on the choices. :func:`parameter_space` refuses it, naming
the rule.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from gaitgram.analysis.cfg import RuleKind
from gaitgram.ge.mapper import CodonMode
from gaitgram.strategies.api import StrategyError

if TYPE_CHECKING:
    from gaitgram.pipeline import Pipeline

#: Expansions of the fixed derivation before it is taken for an endless one.
MAX_EXPANSIONS = 1_000_000


@dataclass(frozen=True)
class ParameterSpace:
    """The codons of a fixed derivation: ``reads[i]`` is the coordinate codon ``i`` comes from,
    or -1 for a codon read by a single-choice rule (eager codons), which is always 0."""

    sizes: tuple[int, ...]  # values of each coordinate's range
    labels: tuple[str, ...]  # the range each coordinate sets, as written
    reads: tuple[int, ...]

    @property
    def dimension(self) -> int:
        return len(self.sizes)

    def choices(self, vector: Sequence[float]) -> np.ndarray:
        """Each coordinate's value index: [0, 1] cut into equal parts, one per value (clipped)."""
        x = np.clip(np.asarray(vector, dtype=float), 0.0, 1.0)
        sizes = np.array(self.sizes)
        return np.minimum((x * sizes).astype(int), sizes - 1)

    def genome(self, vector: Sequence[float]) -> tuple[int, ...]:
        """The genome that picks the values ``vector`` stands for (codon ``c`` picks ``c % k``)."""
        chosen = self.choices(vector)
        return tuple(int(chosen[r]) if r >= 0 else 0 for r in self.reads)

    def vector(self, genome: Sequence[int]) -> np.ndarray:
        """The centre of the cell of each value a genome picks (the inverse of :meth:`genome`)."""
        x = np.full(self.dimension, 0.5)
        for codon, r in zip(genome, self.reads, strict=False):
            if r >= 0:
                x[r] = ((codon % self.sizes[r]) + 0.5) / self.sizes[r]
        return x


def parameter_space(pipeline: Pipeline, strategy: str = "cma-es") -> ParameterSpace:
    """The parameter vector of ``pipeline``'s grammar; :class:`StrategyError` if it has none."""
    grammar = pipeline.grammar
    cfg = pipeline.facts.cfg
    eager = pipeline.config.representation_settings["codons"] == CodonMode.EAGER
    if cfg.start is None:
        raise StrategyError("the grammar has no start rule")
    sizes: list[int] = []
    labels: list[str] = []
    reads: list[int] = []
    stack = [cfg.start]
    expansions = 0
    while stack:
        rule = stack.pop()
        expansions += 1
        if expansions > MAX_EXPANSIONS:
            raise StrategyError(f"strategy {strategy}: the grammar's one derivation does not end")
        choices = cfg.choices[rule]
        if len(choices) == 1:
            if eager:
                reads.append(-1)
            stack.extend(item for item in reversed(choices[0]) if isinstance(item, int))
            continue
        if not _is_range(pipeline, rule):
            raise StrategyError(_structural(pipeline, rule, strategy))
        reads.append(len(sizes))
        sizes.append(len(choices))
        labels.append(cfg.names[rule] if cfg.kinds[rule] is RuleKind.RANGE else f"<{cfg.names[rule]}>")
    if not sizes:
        raise StrategyError(
            f"strategy {strategy}: {grammar.source.name} derives one gait only (it has no typed range to "
            "tune); give it ranges such as float[0..1 step 0.1]"
        )
    return ParameterSpace(tuple(sizes), tuple(labels), tuple(reads))


def _is_range(pipeline: Pipeline, rule: int) -> bool:
    """A choice among a typed range's values: a range inside an alternative, or a rule whose
    alternatives are all ranges on their own."""
    cfg = pipeline.facts.cfg
    if cfg.kinds[rule] is RuleKind.RANGE:
        return True
    written = pipeline.grammar.rule(cfg.names[rule])
    return written is not None and all(a.range_values is not None for a in written.alternatives)


def _structural(pipeline: Pipeline, rule: int, strategy: str) -> str:
    grammar = pipeline.grammar
    name = pipeline.facts.cfg.names[rule]
    written = grammar.rule(name)
    where = grammar.source.name
    if written is not None:
        location = grammar.source.location(written.span.start)
        where = f"{where}:{location.line}:{location.column}"
    return (
        f"strategy {strategy} searches a grammar's parameter vector, one coordinate per typed range, so "
        "every derivation must have the same structure and differ only in range values (a fixed "
        "expression with numbers to tune, such as grammars/numerical.gg, made by `gaitgram seed grammar "
        f"--style numerical`); {where}: <{name}> chooses between alternatives of different structure, "
        "so its genomes have no fixed parameter vector. Search this grammar with ge, random, nsga2 or "
        f"map-elites, or use {strategy} on a numerical grammar"
    )
