"""Running, the last stage: a compiled phenotype evaluated over whole arrays of phases.

The machine is a small stack machine: one pass over a flat program per evaluation,
however many phases, and no recursion, so deeply nested phenotypes cannot overflow the
Python stack. An evaluation never raises and never warns: its :class:`Curve` says
whether the values are usable (a division by zero, or a non-finite value, at some
phase) and, if not, which subexpression failed first.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gaitgram.motion.compiler import Division, Op, Program
from gaitgram.motion.parser import NodeKind, Syntax
from gaitgram.motion.results import Curve, MotionError, MotionStatus
from gaitgram.motion.tree import Expr
from gaitgram.motion.vocabulary import BINARY_UFUNCS, CONSTANTS, FUNCTIONS, VARIABLE, phase_grid


@dataclass(frozen=True, slots=True, eq=False)
class Motion:
    """A compiled phenotype: a vectorised function of the phase ``t`` (and, for a closed loop,
    of the sensors it reads).

    Build one with :func:`gaitgram.motion.expression.compile_motion`. Calling it gives raw
    values (NaN and inf included, never a warning); :meth:`evaluate` adds the status a
    fitness needs. A motion that reads sensors is evaluated with their values given as arrays
    that broadcast with the phases.
    """

    text: str
    syntax: Syntax = field(repr=False)
    program: Program = field(repr=False)
    _tree: Expr | None = field(default=None, init=False, repr=False)

    @property
    def constant(self) -> float | None:
        """The value of an expression without ``t`` (folded at compile time), else None."""
        return self.program.constant

    @property
    def expr(self) -> Expr:
        """The syntax tree, built the first time it is asked for (running never needs it)."""
        if self._tree is None:
            object.__setattr__(self, "_tree", self.syntax.tree())  # frozen: a cache, not a change
        return self._tree  # type: ignore[return-value]

    @property
    def uses_phase(self) -> bool:
        """Whether the curve moves with the cycle: a phenotype without ``t`` is a fixed angle (or,
        for a closed loop, moves only as its sensors do)."""
        return any(kind is NodeKind.NAME and value == VARIABLE for kind, value, *_ in self.syntax.nodes)

    @property
    def sensors(self) -> frozenset[str]:
        """The sensors the phenotype reads: none for an open-loop curve."""
        return frozenset(
            value
            for kind, value, *_ in self.syntax.nodes
            if kind is NodeKind.NAME and value != VARIABLE and value not in CONSTANTS
        )

    def __call__(
        self, phases: ArrayLike, sensors: Mapping[str, ArrayLike] | None = None
    ) -> NDArray[np.float64]:
        t = np.asarray(phases, dtype=np.float64)
        with np.errstate(all="ignore"):
            return self._run(t, self._readings(sensors))[0]

    def evaluate(self, phases: ArrayLike, sensors: Mapping[str, ArrayLike] | None = None) -> Curve:
        """The curve at ``phases`` (any shape; with ``sensors``, each sensor's values broadcast with
        them), with DIVISION_BY_ZERO or NON_FINITE if it fails."""
        readings = self._readings(sensors)
        t = np.asarray(phases, dtype=np.float64)
        if readings:
            t = np.broadcast_to(t, np.broadcast_shapes(t.shape, *(v.shape for v in readings.values())))
        with np.errstate(all="ignore"):
            values, zero = self._run(t, readings)
        if zero is not None:
            (start, end, divisor_start, divisor_end), index = zero
            phase = float(t.flat[index]) if t.size else 0.0
            snippet = self.text[divisor_start:divisor_end]
            error = MotionError(
                MotionStatus.DIVISION_BY_ZERO,
                f"division by zero at t={phase:.6g}: the divisor {snippet!r} is 0",
                start,
                end - start,
                phase=phase,
            )
            return Curve(MotionStatus.DIVISION_BY_ZERO, values, error)
        finite = np.isfinite(values)
        if not finite.all():
            index = int(np.argmin(finite.reshape(-1)))
            at = {name: float(np.broadcast_to(v, t.shape).flat[index]) for name, v in readings.items()}
            return Curve(MotionStatus.NON_FINITE, values, self._non_finite(float(t.flat[index]), at))
        return Curve(MotionStatus.OK, values)

    def _readings(self, sensors: Mapping[str, ArrayLike] | None) -> dict[str, NDArray[np.float64]]:
        """The values of the sensors this motion reads, as arrays; a missing one is the caller's bug."""
        wanted = self.sensors
        if not wanted:
            return {}
        missing = sorted(wanted - set(sensors or ()))
        if missing:
            raise ValueError(f"{self.text!r} reads the sensors {', '.join(missing)}: pass their values")
        return {name: np.asarray(sensors[name], dtype=np.float64) for name in wanted}  # type: ignore[index]

    def sample(self, n_samples: int) -> Curve:
        """The curve on :func:`phase_grid` of ``n_samples``: one cycle, the end excluded."""
        return self.evaluate(phase_grid(n_samples))

    def _run(
        self, t: NDArray[np.float64], readings: Mapping[str, NDArray[np.float64]] | None = None
    ) -> tuple[NDArray[np.float64], tuple[Division, int] | None]:
        constant = self.program.constant
        if constant is not None:
            return np.full(t.shape, constant), None
        stack: list = []
        zero: tuple[Division, int] | None = None
        T, PUSH, UNARY, BINARY, BINARY_CONST = Op.T, Op.PUSH, Op.UNARY, Op.BINARY, Op.BINARY_CONST  # noqa: N806
        for op, func, const, division in self.program.instructions:
            if op == Op.SENSOR:
                stack.append(readings[func])  # type: ignore[index]
                continue
            if op == BINARY_CONST:
                left, right = stack[-1], const
            elif op == UNARY:
                stack[-1] = func(stack[-1])  # type: ignore[misc]
                continue
            elif op == T:
                stack.append(t)
                continue
            elif op == BINARY:
                right = stack.pop()
                left = stack[-1]
            elif op == PUSH:
                stack.append(np.float64(const))
                continue
            else:  # CONST_BINARY
                left, right = const, stack[-1]
            if division is not None and zero is None:
                hits = np.equal(right, 0)
                if hits.any():
                    index = int(np.argmax(np.broadcast_to(hits, t.shape).reshape(-1))) if t.size else 0
                    zero = (division, index)
            stack[-1] = func(left, right)  # type: ignore[misc]
        (result,) = stack
        if isinstance(result, np.ndarray) and result is not t and result.shape == t.shape:
            return result, zero
        return np.array(np.broadcast_to(result, t.shape), dtype=np.float64), zero

    def _non_finite(self, phase: float, readings: Mapping[str, float] | None = None) -> MotionError:
        """Find the smallest subexpression that turns finite values into a non-finite one."""
        values: list[np.float64] = []
        with np.errstate(all="ignore"):
            for kind, name, start, end, _, _ in self.syntax.nodes:
                inputs = _scalar_inputs(kind, values)
                value = _scalar_node(kind, name, inputs, phase, readings or {})
                values.append(value)
                if not np.isfinite(value) and all(np.isfinite(v) for v in inputs):
                    snippet = self.text[start:end]
                    return MotionError(
                        MotionStatus.NON_FINITE,
                        f"{snippet!r} is {float(value)} at t={phase:.6g}",
                        start,
                        end - start,
                        phase=phase,
                    )
        return MotionError(  # pragma: no cover - the scalar replay disagrees with the array run
            MotionStatus.NON_FINITE,
            f"the curve is not finite at t={phase:.6g}",
            0,
            len(self.text),
            phase=phase,
        )


_ARITY = {NodeKind.NUMBER: 0, NodeKind.NAME: 0, NodeKind.UNARY: 1, NodeKind.BINARY: 2, NodeKind.CALL: 1}


def _scalar_inputs(kind: NodeKind, values: list[np.float64]) -> list[np.float64]:
    arity = _ARITY[kind]
    inputs = values[len(values) - arity :]
    del values[len(values) - arity :]
    return inputs


def _scalar_node(
    kind: NodeKind,
    value: float | str,
    inputs: list[np.float64],
    phase: float,
    readings: Mapping[str, float],
) -> np.float64:
    """One node at one phase, in numpy scalars: the machine's arithmetic, replayed."""
    if kind is NodeKind.NUMBER:
        return np.float64(value)
    if kind is NodeKind.NAME:
        if value == VARIABLE:
            return np.float64(phase)
        return np.float64(CONSTANTS[value] if value in CONSTANTS else readings[value])  # type: ignore[index]
    if kind is NodeKind.UNARY:
        return -inputs[0] if value == "-" else inputs[0]
    if kind is NodeKind.BINARY:
        return BINARY_UFUNCS[value](inputs[0], inputs[1])  # type: ignore[index]
    return FUNCTIONS[value].ufunc(inputs[0])  # type: ignore[index]
