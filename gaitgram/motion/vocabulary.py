"""What the names and operators of a motion expression mean: the one place to extend the language.

The checker accepts these names, the compiler folds and emits these functions, and the
machine runs them; nothing else names a function or constant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True, slots=True)
class Function:
    """A function a phenotype may call: its numpy ufunc, and why it is in the language."""

    name: str
    ufunc: np.ufunc
    doc: str


#: Functions, each of one argument in radians. Only what the paper's grammars derive: a wider
#: vocabulary (tan, exp, log, sqrt, powers) would add singularities and domain errors that no
#: gait needs. Add an entry here to extend the language; nothing else needs to change.
FUNCTIONS: dict[str, Function] = {
    "sin": Function("sin", np.sin, "the sum-of-sines representation (Eq. 1, Fig. 2)"),
    "cos": Function("cos", np.cos, "cosine terms of the concatenating grammar (Fig. 2) and Fig. 5"),
}

#: Named constants. The paper writes ``PI``; ``pi`` is accepted as well.
CONSTANTS: dict[str, float] = {"PI": math.pi, "pi": math.pi}

#: The phase of the gait cycle, in [0, 1).
VARIABLE = "t"

#: The binary operators as numpy ufuncs: compile-time folding and the machine compute alike.
BINARY_UFUNCS: dict[str, np.ufunc] = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.true_divide}

#: Functions people try that the language leaves out on purpose (a hint says so).
UNSUPPORTED = frozenset(
    {"tan", "exp", "log", "ln", "sqrt", "abs", "pow", "min", "max", "asin", "acos", "atan"}
)


def phase_grid(n_samples: int) -> NDArray[np.float64]:
    """``n_samples`` equally spaced phases ``k / n`` over one cycle, the end excluded."""
    if n_samples < 1:
        raise ValueError(f"a phase grid needs at least one sample, not {n_samples}")
    return np.arange(n_samples, dtype=np.float64) / n_samples
