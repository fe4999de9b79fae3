"""Motion: phenotype expressions compiled to numpy curves, and Fourier tools for sums of sines.

``compile_motion(text)`` turns a joint's phenotype into a :class:`Motion` (or a
:class:`MotionError`) through four stages, each a module: ``parser``, ``checker``,
``compiler`` and ``machine`` (see :mod:`gaitgram.motion.expression`);
``Motion.evaluate(phases)`` gives a :class:`Curve` with a :class:`MotionStatus`.
``fourier_coefficients`` and ``control_matrix`` turn a population's sums of sines into
control arrays with one matrix product, and ``fit_sum_of_sines`` is the paper's Fourier
analysis of sampled seed curves."""

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
