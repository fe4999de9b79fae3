"""Each phenotype's error on the training data, as PonyGE2's ``supervised_learning.regression``
scores it.

PonyGE2 ``eval``-s the phenotype with ``x`` the training inputs under ``np.seterr(all="raise")``
and scores it with its error metric (RMSE unless a parameter file names another); a phenotype
whose evaluation meets a floating-point error (overflow, underflow, an invalid operation, a
division by zero) scores NaN, worse than any other. Here the phenotype is compiled
(:mod:`.expression`) and run on the same views of the same array (``x[:, i]`` of the inputs as
a 2-D array: numpy's vectorised loops for contiguous arrays may round differently), under the
same error state; such a phenotype is unviable, with a status and what went wrong, never an
exception.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gaitgram.backends.api import Evaluation, GaitStatus, unusable_evaluations
from gaitgram.backends.symbolic_regression.datasets import Dataset, Table
from gaitgram.backends.symbolic_regression.expression import ExpressionError, compile_expression
from gaitgram.motion.gait import MotionBatch

#: PonyGE2's error metrics for regression (``utilities/fitness/error_metric.py``), true values first.
METRICS: dict[str, Callable[[Any, Any], Any]] = {
    "rmse": lambda y, yhat: np.sqrt(np.mean(np.square(y - yhat))),
    "mse": lambda y, yhat: np.mean(np.square(y - yhat)),
    "mae": lambda y, yhat: np.mean(np.abs(y - yhat)),
}

#: The errors PonyGE2's fitness function turns into a NaN score (``base_ff.__call__``).
RUNTIME_ERRORS = (FloatingPointError, ZeroDivisionError, OverflowError, MemoryError)

#: Phenotypes whose evaluation is remembered: a population hands most of them on unchanged.
MEMO_SIZE = 200_000


class _Split:
    """One split's inputs (as the views PonyGE2's ``x[:, i]`` takes) and response."""

    def __init__(self, table: Table) -> None:
        data = np.array(table.rows, dtype=np.float64)
        self.x: NDArray[np.float64] = data[:, :-1]
        self.y: NDArray[np.float64] = data[:, -1]
        self.columns = tuple(self.x[:, i] for i in range(self.x.shape[1]))


class SymbolicRegression:
    """The loaded backend: scores each phenotype of a batch on the training split."""

    def __init__(self, dataset: Dataset, metric: str = "rmse") -> None:
        if metric not in METRICS:
            raise ValueError(f"metric: {metric!r} is not one of {', '.join(METRICS)}")
        self.dataset = dataset
        self.metric = metric
        self._train = _Split(dataset.train)
        self._test = None if dataset.test is None else _Split(dataset.test)
        self._memo: dict[str, Evaluation] = {}

    @property
    def n_inputs(self) -> int:
        return self._train.x.shape[1]

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        if batch.phenotypes is None:
            raise ValueError(
                "symbolic-regression scores phenotype texts, and this batch carries none: build it "
                "through a Pipeline (which passes them to backends with scores_phenotype)"
            )
        done = unusable_evaluations(batch)
        return [done.get(g) or self.score(text or "") for g, text in enumerate(batch.phenotypes)]

    def score(self, phenotype: str) -> Evaluation:
        """``phenotype``'s evaluation on the training split (remembered: it cannot change)."""
        found = self._memo.get(phenotype)
        if found is None:
            found = self._evaluation(phenotype, self._train)
            if len(self._memo) >= MEMO_SIZE:
                self._memo.clear()
            self._memo[phenotype] = found
        return found

    def test_error(self, phenotype: str) -> float | None:
        """``phenotype``'s error on the test split (None: it has no score there, or there is no test
        split), as PonyGE2 reports its best individual's test fitness."""
        if self._test is None:
            return None
        evaluation = self._evaluation(phenotype, self._test)
        return evaluation.fitness if evaluation.status.viable else None

    def _evaluation(self, phenotype: str, split: _Split) -> Evaluation:
        try:
            expression = compile_expression(phenotype)
        except ExpressionError as error:
            return Evaluation.unviable(GaitStatus.INVALID_MOTION, str(error))
        beyond = [i for i in expression.inputs if i >= len(split.columns)]
        if beyond:
            return Evaluation.unviable(
                GaitStatus.INVALID_MOTION,
                f"x[:, {beyond[0]}]: the dataset has {len(split.columns)} inputs, "
                f"x[:, 0] to x[:, {len(split.columns) - 1}]",
            )
        try:
            with np.errstate(all="raise"):
                predicted = expression(split.columns)
                if np.ndim(predicted) != 0 and np.shape(predicted) != split.y.shape:
                    return Evaluation.unviable(
                        GaitStatus.INVALID_MOTION,
                        f"predicts shape {np.shape(predicted)}, not {split.y.shape}",
                    )
                error = float(METRICS[self.metric](split.y, predicted))
        except RUNTIME_ERRORS as problem:
            return Evaluation.unviable(
                GaitStatus.NON_FINITE,
                f"a floating-point error on the data ({problem}), which PonyGE2 scores NaN",
            )
        return Evaluation(error, components={self.metric: error})

    def close(self) -> None:
        self._memo.clear()
