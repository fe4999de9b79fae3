"""Motion expressions: a joint curve's phenotype text, compiled in stages and run over the gait phase.

A phenotype is untrusted text that GE assembled from grammar pieces, so it is read by
our own parser and never reaches ``eval``. The language is the paper's: numbers, the
phase ``t`` in [0, 1), ``PI`` (or ``pi``), ``+ - * /``, unary minus and plus,
parentheses, ``sin`` and ``cos``; that is everything its grammars (Fig. 2 and the free
grammar of Fig. 5) derive. :func:`compile_motion` runs the stages, each a module with a
small API:

1. :mod:`~gaitgram.motion.parser`: text to postfix nodes, or a syntax error
   (``expression.lark`` specifies the syntax);
2. :mod:`~gaitgram.motion.checker`: every name known, every call of one argument;
3. :mod:`~gaitgram.motion.compiler`: a flat program, constant subexpressions folded;
4. :mod:`~gaitgram.motion.machine`: the program run over arrays of phases, as a
   :class:`Curve`.

Everything that can go wrong is a value, not an exception: :func:`compile_motion` returns
a :class:`Motion` or a :class:`MotionError`, and :meth:`Motion.evaluate` a :class:`Curve`
whose :class:`MotionStatus` says whether the values are usable. This module also keeps
the names other modules and plug-ins have always imported from it.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike

from gaitgram.motion.checker import check
from gaitgram.motion.compiler import compile_program
from gaitgram.motion.machine import Motion
from gaitgram.motion.parser import parse, parse_expression
from gaitgram.motion.printer import format_number, to_text
from gaitgram.motion.results import Curve, MotionError, MotionStatus
from gaitgram.motion.tree import Binary, Call, Expr, Name, Number, Unary, children, postorder
from gaitgram.motion.vocabulary import CONSTANTS, FUNCTIONS, VARIABLE, Function, phase_grid

__all__ = [
    "CONSTANTS",
    "FUNCTIONS",
    "VARIABLE",
    "Binary",
    "Call",
    "Curve",
    "Expr",
    "Function",
    "Motion",
    "MotionError",
    "MotionStatus",
    "Name",
    "Number",
    "Unary",
    "children",
    "compile_motion",
    "evaluate_motion",
    "format_number",
    "parse_expression",
    "phase_grid",
    "postorder",
    "to_text",
]


@lru_cache(maxsize=4096)
def compile_motion(text: str, sensors: frozenset[str] = frozenset()) -> Motion | MotionError:
    """Compile phenotype text to a :class:`Motion`, or say why it is not one. ``sensors`` are the
    names (a backend's sensors) a closed-loop phenotype may read beside ``t``.

    Never raises for any string. Results are cached: GE re-evaluates elites and
    duplicate phenotypes, and both results are immutable.
    """
    syntax = parse(text)
    if isinstance(syntax, MotionError):
        return syntax
    problem = check(syntax, sensors)
    if problem is not None:
        return problem
    return Motion(text, syntax, compile_program(syntax))


def evaluate_motion(motion: Motion | str, phases: ArrayLike) -> Curve:
    """Compile (if text) and evaluate: a total function for batches, one :class:`Curve` per call.

    Text that does not compile gives a curve of NaN with the compile error.
    """
    if isinstance(motion, str):
        compiled = compile_motion(motion)
        if isinstance(compiled, MotionError):
            shape = np.shape(phases)
            return Curve(compiled.status, np.full(shape, np.nan), compiled)
        motion = compiled
    return motion.evaluate(phases)
