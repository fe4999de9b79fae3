"""Motion: phenotype expressions compiled to numpy curves, and Fourier tools for sums of sines.

``compile_motion(text)`` turns a joint's phenotype into a :class:`Motion` (or a
:class:`MotionError`) through four stages, each a module: ``parser``, ``checker``,
``compiler`` and ``machine`` (see :mod:`gaitgram.motion.expression`);
``Motion.evaluate(phases)`` gives a :class:`Curve` with a :class:`MotionStatus`.
``fourier_coefficients`` and ``control_matrix`` turn a population's sums of sines into
control arrays with one matrix product, and ``fit_sum_of_sines`` is the paper's Fourier
analysis of sampled seed curves.

The names below are loaded on first use (PEP 562): importing a numpy-free submodule such as
:mod:`gaitgram.motion.problems` does not import numpy, so ``gaitgram check`` starts quickly."""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from gaitgram.motion.expression import (
        CONSTANTS,
        FUNCTIONS,
        VARIABLE,
        Curve,
        Expr,
        Motion,
        MotionError,
        MotionStatus,
        compile_motion,
        evaluate_motion,
        parse_expression,
        phase_grid,
        to_text,
    )
    from gaitgram.motion.fourier import (
        FourierSeries,
        SineFit,
        SineTerm,
        control_matrix,
        fit_sum_of_sines,
        fourier_basis,
        fourier_coefficients,
        render_sum_of_sines,
        shift_phase,
    )

_SUBMODULE_OF = {
    "CONSTANTS": "expression",
    "FUNCTIONS": "expression",
    "VARIABLE": "expression",
    "Curve": "expression",
    "Expr": "expression",
    "Motion": "expression",
    "MotionError": "expression",
    "MotionStatus": "expression",
    "compile_motion": "expression",
    "evaluate_motion": "expression",
    "parse_expression": "expression",
    "phase_grid": "expression",
    "to_text": "expression",
    "FourierSeries": "fourier",
    "SineFit": "fourier",
    "SineTerm": "fourier",
    "control_matrix": "fourier",
    "fit_sum_of_sines": "fourier",
    "fourier_basis": "fourier",
    "fourier_coefficients": "fourier",
    "render_sum_of_sines": "fourier",
    "shift_phase": "fourier",
}

__all__ = [
    "CONSTANTS",
    "FUNCTIONS",
    "VARIABLE",
    "Curve",
    "Expr",
    "FourierSeries",
    "Motion",
    "MotionError",
    "MotionStatus",
    "SineFit",
    "SineTerm",
    "compile_motion",
    "control_matrix",
    "evaluate_motion",
    "fit_sum_of_sines",
    "fourier_basis",
    "fourier_coefficients",
    "parse_expression",
    "phase_grid",
    "render_sum_of_sines",
    "shift_phase",
    "to_text",
]


def __getattr__(name: str) -> Any:
    submodule = _SUBMODULE_OF.get(name)
    if submodule is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f"{__name__}.{submodule}"), name)
    globals()[name] = value
    return value
