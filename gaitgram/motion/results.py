"""What compiling and running a phenotype give: a status, an error that says where, a curve.

Everything that can go wrong with a phenotype is a value, not an exception, so a fitness
backend can score any text without a ``try``; every stage (parse, check, compile, run)
reports its problems as a :class:`MotionError`.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

import numpy as np
from numpy.typing import NDArray


class MotionStatus(StrEnum):
    """Whether a phenotype gives a usable curve, and if not, why."""

    OK = "ok"
    #: The text is not a motion expression (syntax, a function called with the wrong arity, a
    #: constant called as a function). Adversarial text such as ``__import__('os')`` lands here.
    PARSE_ERROR = "parse-error"
    #: A name that is not ``t``, ``PI``, ``pi``, ``sin`` or ``cos``.
    UNKNOWN_NAME = "unknown-name"
    #: Some divisor is exactly zero at some phase of the evaluation grid.
    DIVISION_BY_ZERO = "division-by-zero"
    #: The curve is infinite or NaN at some phase (overflow, ``sin`` of infinity, ...).
    NON_FINITE = "non-finite"
    #: From :func:`gaitgram.motion.fourier.fourier_coefficients`: the curve is not a finite sum of
    #: sines of whole harmonics up to the requested one.
    NOT_A_SUM_OF_SINES = "not-a-sum-of-sines"


@dataclass(frozen=True, slots=True)
class MotionError:
    """What is wrong with a phenotype, and where: ``text[offset:offset + length]``.

    ``phase`` is the first grid phase where an evaluation problem shows, if any.
    """

    status: MotionStatus
    message: str
    offset: int = 0
    length: int = 0
    hint: str | None = None
    phase: float | None = None

    def __str__(self) -> str:
        return self.message if self.hint is None else f"{self.message} ({self.hint})"


@dataclass(frozen=True, slots=True, eq=False)
class Curve:
    """A motion evaluated at some phases: always has values, usable only if ``ok``.

    The values are kept even when the status is not OK (NaN everywhere if the text
    did not compile), so a plot can still show what went wrong.
    """

    status: MotionStatus
    values: NDArray[np.float64]
    error: MotionError | None = None

    @property
    def ok(self) -> bool:
        return self.status is MotionStatus.OK
