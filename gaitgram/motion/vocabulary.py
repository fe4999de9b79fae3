"""What the names and operators of a motion expression compute.

The checker accepts these names, the compiler folds and emits these functions, and the
machine runs them; nothing else names a function or constant. The names themselves are spelt in
:mod:`gaitgram.motion.names` (without numpy, for the linter and the editor): the one place to
extend the language.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gaitgram.motion.names import CONSTANTS, FUNCTION_DOCS, UNSUPPORTED, VARIABLE

__all__ = [
    "BINARY_UFUNCS",
    "CONSTANTS",
    "FUNCTIONS",
    "UNSUPPORTED",
    "VARIABLE",
    "Function",
    "phase_grid",
]


@dataclass(frozen=True, slots=True)
class Function:
    """A function a phenotype may call: its numpy ufunc, and why it is in the language."""

    name: str
    ufunc: np.ufunc
    doc: str


#: Functions, each of one argument in radians: numpy's ufunc of each name in
#: :data:`~gaitgram.motion.names.FUNCTION_DOCS`, where the language's words are spelt.
FUNCTIONS: dict[str, Function] = {
    name: Function(name, getattr(np, name), doc) for name, doc in FUNCTION_DOCS.items()
}

#: The binary operators as numpy ufuncs: compile-time folding and the machine compute alike.
BINARY_UFUNCS: dict[str, np.ufunc] = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.true_divide}


def phase_grid(n_samples: int) -> NDArray[np.float64]:
    """``n_samples`` equally spaced phases ``k / n`` over one cycle, the end excluded."""
    if n_samples < 1:
        raise ValueError(f"a phase grid needs at least one sample, not {n_samples}")
    return np.arange(n_samples, dtype=np.float64) / n_samples
