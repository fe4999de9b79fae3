"""Closed loops: a phenotype that reads sensors, split so that a whole population runs at once.

A closed-loop phenotype such as ``7+3*sin(2*PI*t)+0.2*pitch`` is a curve of the phase plus
terms of what the body senses. A backend computes controls from it at every control tick for
every gait, so running each gait's stack machine would cost far more than the physics. This
module splits an expression at its sensors:

* each largest subexpression that reads no sensor but one *phase variable* (``t``, or a
  periodic sensor such as a limb's oscillator ``phase``) is a **slot**: a curve sampled once on
  the phase grid, as an open-loop curve is, and read by interpolation at every physics step;
* each largest subexpression of neither is a **constant**, folded as the compiler folds;
* what is left is the **skeleton**: the operators over slots, constants and sensors.

Gaits whose skeletons are equal (a grammar's feedback terms have a few shapes; the numbers in
them differ) run together: one numpy operation per skeleton step for all of them, their constants
as columns. Equal skeletons with different constants are the common case, since a slot hides the
whole open-loop part of a curve however it was derived.

A phenotype without sensors has no closed loop (:func:`closed_loop` gives None): backends play it
as the open-loop curve it always was, so its score does not change by a bit.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gaitgram.motion.compiler import compile_program
from gaitgram.motion.machine import Motion
from gaitgram.motion.parser import Node, NodeKind, Syntax
from gaitgram.motion.results import MotionError, MotionStatus
from gaitgram.motion.vocabulary import BINARY_UFUNCS, CONSTANTS, FUNCTIONS, VARIABLE, phase_grid

__all__ = ["ClosedLoop", "Program", "Slot", "closed_loop", "run_program", "run_skeleton", "skeleton_program"]

#: A skeleton step: ``("slot", index, phase variable)``, ``("const", index)``,
#: ``("sensor", name)``, ``("unary", ufunc name)`` or ``("binary", operator)``.
Step = tuple[str, ...] | tuple[str, int] | tuple[str, int, str]

_NAME, _NUMBER, _UNARY, _BINARY = NodeKind.NAME, NodeKind.NUMBER, NodeKind.UNARY, NodeKind.BINARY


@dataclass(frozen=True, eq=False)
class Slot:
    """A sensor-free part of a closed loop: a curve of one phase variable (``t`` or a periodic
    sensor), sampled on ``n + 1`` phases from 0 to 1 inclusive (it need not be periodic:
    ``2*PI*t`` inside ``sin(2*PI*t+pitch)`` is a slot), so that interpolation never wraps."""

    motion: Motion
    variable: str
    samples: NDArray[np.float64]  # [n + 1]


@dataclass(frozen=True, eq=False)
class ClosedLoop:
    """A phenotype split at its sensors. ``skeleton`` is hashable: gaits with equal skeletons run
    together (:func:`run_skeleton`), their ``constants`` stacked."""

    text: str
    skeleton: tuple[Step, ...]
    constants: tuple[float, ...]
    slots: tuple[Slot, ...]
    #: The sensors it reads that are not phases (held between control ticks).
    sensors: frozenset[str]
    #: The phase variables its slots are sampled in (``t``, ``phase``).
    variables: frozenset[str]
    n_samples: int

    def run(
        self, slot_values: Sequence[NDArray[np.float64]], sensors: Mapping[str, ArrayLike]
    ) -> NDArray[np.float64]:
        """This loop alone (a group of one): slot values and sensor values broadcast together."""
        constants = np.asarray(self.constants, dtype=np.float64)[None, :]
        return run_skeleton(
            self.skeleton,
            constants,
            [np.asarray(v)[None] for v in slot_values],
            {name: np.asarray(v, dtype=np.float64)[None] for name, v in sensors.items()},
        )[0]

    def nominal(self, readings: Mapping[str, float]) -> NDArray[np.float64]:
        """The curve over one cycle (``n_samples`` phases, the end excluded) with every held sensor
        at ``readings`` and every phase variable at the cycle's phase: what a plot can show of a
        closed loop."""
        values = [slot.samples[:-1] for slot in self.slots]
        result = self.run(values, {name: readings[name] for name in self.sensors})
        return np.array(np.broadcast_to(result, (self.n_samples,)), dtype=np.float64)


def closed_loop(
    motion: Motion, periodic: Collection[str] = (), n_samples: int = 256
) -> ClosedLoop | MotionError | None:
    """Split ``motion`` at its sensors; ``periodic`` sensors are phases in [0, 1) sampled like ``t``.
    None when it reads no sensor (an open-loop curve); a MotionError when a slot or constant of it
    cannot be computed (a division by zero, a non-finite value)."""
    if not motion.sensors:
        return None
    return _split(motion, frozenset(periodic), n_samples)


@lru_cache(maxsize=8192)
def _split(motion: Motion, periodic: frozenset[str], n_samples: int) -> ClosedLoop | MotionError:
    nodes = motion.syntax.nodes
    variables = frozenset({VARIABLE}) | periodic
    # Per node: the names it depends on, and its children (indices), from the postfix order.
    uses: list[frozenset[str]] = []
    children: list[tuple[int, ...]] = []
    first: list[int] = []  # the first node of each node's subtree (a subtree is a run of nodes)
    stack: list[int] = []
    for index, (kind, value, _start, _end, a, _b) in enumerate(nodes):
        arity = 0 if kind in (_NUMBER, _NAME) else 1 if kind is _UNARY else 2 if kind is _BINARY else a
        kids = tuple(stack[len(stack) - arity :]) if arity else ()
        del stack[len(stack) - arity :]
        if kind is _NAME and value not in CONSTANTS:
            used = frozenset({value})  # type: ignore[arg-type]
        elif arity == 1:  # most nodes have one or two operands: share their sets, copy none
            used = uses[kids[0]]
        elif arity == 2:
            left, right = uses[kids[0]], uses[kids[1]]
            used = left | right if left and right and left != right else left or right
        else:
            used = frozenset().union(*(uses[k] for k in kids))
        uses.append(used)
        children.append(kids)
        first.append(first[kids[0]] if kids else index)
        stack.append(index)
    (root,) = stack

    def sampled(index: int) -> bool:
        used = uses[index]
        return len(used) == 1 and next(iter(used)) in variables

    skeleton: list[Step] = []
    constants: list[float] = []
    slots: list[Slot] = []
    # Post-order over the dynamic nodes, each leaf a slot, a constant or a sensor (no recursion:
    # phenotypes nest deeply).
    todo: list[tuple[int, bool]] = [(root, False)]
    while todo:
        index, expanded = todo.pop()
        kind, value = nodes[index][0], nodes[index][1]
        if not uses[index]:
            folded = _fold(motion.text, nodes[first[index] : index + 1])
            if isinstance(folded, MotionError):
                return folded
            skeleton.append(("const", len(constants)))
            constants.append(folded)
        elif sampled(index):
            variable = next(iter(uses[index]))
            slot = _slot(motion.text, nodes[first[index] : index + 1], variable, n_samples)
            if isinstance(slot, MotionError):
                return slot
            skeleton.append(("slot", len(slots), variable))
            slots.append(slot)
        elif kind is _NAME:
            skeleton.append(("sensor", value))  # type: ignore[arg-type]
        elif expanded:
            if kind is _UNARY:
                if value == "-":
                    skeleton.append(("unary", "negative"))
            elif kind is _BINARY:
                skeleton.append(("binary", value))  # type: ignore[arg-type]
            else:
                skeleton.append(("unary", value))  # type: ignore[arg-type]
        else:
            todo.append((index, True))
            todo.extend((kid, False) for kid in reversed(children[index]))
    held = frozenset(name for name in motion.sensors if name not in periodic)
    used_variables = frozenset(step[2] for step in skeleton if step[0] == "slot")  # type: ignore[misc]
    return ClosedLoop(
        motion.text, tuple(skeleton), tuple(constants), tuple(slots), held, used_variables, n_samples
    )


def _subsyntax(text: str, nodes: Sequence[Node], rename: str | None = None) -> Syntax:
    """A subtree's nodes as an expression of its own: spans moved to its text, ``rename`` read as ``t``."""
    start = min(node[2] for node in nodes)
    end = max(node[3] for node in nodes)
    if start == 0:  # a leading subtree (a closed loop's curve before its feedback): nothing moves
        if rename is None:
            return Syntax(text[:end], tuple(nodes))
        return Syntax(
            text[:end],
            tuple(
                (_NAME, VARIABLE, *node[2:]) if node[0] is _NAME and node[1] == rename else node
                for node in nodes
            ),
        )
    moved: list[Node] = []
    for kind, value, a_start, a_end, a, b in nodes:
        if kind is _NAME and value == rename:
            value = VARIABLE
        if kind is _BINARY:
            a, b = a - start, b - start
        moved.append((kind, value, a_start - start, a_end - start, a, b))
    return Syntax(text[start:end], tuple(moved))


def _fold(text: str, nodes: Sequence[Node]) -> float | MotionError:
    syntax = _subsyntax(text, nodes)
    program = compile_program(syntax)
    if program.constant is not None and np.isfinite(program.constant):
        return program.constant
    curve = Motion(syntax.text, syntax, program).evaluate(np.zeros(1))
    if curve.error is not None:
        return curve.error
    return MotionError(MotionStatus.NON_FINITE, f"{syntax.text!r} is not finite", 0, len(syntax.text))


def _slot(text: str, nodes: Sequence[Node], variable: str, n_samples: int) -> Slot | MotionError:
    return _sampled_slot(_subsyntax(text, nodes, rename=variable), variable, n_samples)


@lru_cache(maxsize=8192)
def _sampled_slot(syntax: Syntax, variable: str, n_samples: int) -> Slot | MotionError:
    """A slot by its syntax (text and nodes): gaits of a run that differ only in their feedback gains
    share their curve, which is compiled and sampled once."""
    motion = Motion(syntax.text, syntax, compile_program(syntax))
    curve = motion.evaluate(np.append(phase_grid(n_samples), 1.0))
    if not curve.ok:
        return curve.error  # type: ignore[return-value]
    samples = curve.values.copy()
    samples.flags.writeable = False
    return Slot(motion, variable, samples)


def run_skeleton(
    skeleton: tuple[Step, ...],
    constants: NDArray[np.float64],
    slot_values: Sequence[NDArray[np.float64]],
    sensors: Mapping[str, NDArray[np.float64]],
) -> NDArray[np.float64]:
    """Run one skeleton for a group of gaits: ``constants`` [gaits, k]; ``slot_values[i]`` and each
    sensor's values are arrays whose first axis is the gaits (broadcast together: [gaits, steps,
    actuators] and [gaits, 1, actuators], say). NaN and inf are results, not errors."""
    extra = max((v.ndim for v in (*slot_values, *sensors.values())), default=1) - 1
    column = (len(constants),) + (1,) * extra  # a constant's shape: one value per gait
    columns = [constants[:, k].reshape(column) for k in range(constants.shape[1])]
    return run_program(skeleton_program(skeleton), columns, slot_values, sensors)


#: A skeleton's steps with what each reads or applies looked up once (:func:`skeleton_program`).
Program = tuple[tuple[int, Any], ...]
_SLOT, _CONSTANT, _SENSOR, _BINARY_OP, _UNARY_OP = range(5)


@lru_cache(maxsize=4096)
def skeleton_program(skeleton: tuple[Step, ...]) -> Program:
    """``skeleton`` as :func:`run_program` runs it: per step a code and its slot or constant index,
    its sensor's name, or its ufunc; a control loop runs it at every tick."""
    program: list[tuple[int, Any]] = []
    for step in skeleton:
        what = step[0]
        if what == "slot":
            program.append((_SLOT, step[1]))
        elif what == "const":
            program.append((_CONSTANT, step[1]))
        elif what == "sensor":
            program.append((_SENSOR, step[1]))
        elif what == "binary":
            program.append((_BINARY_OP, BINARY_UFUNCS[step[1]]))  # type: ignore[index]
        else:
            program.append((_UNARY_OP, np.negative if step[1] == "negative" else FUNCTIONS[step[1]].ufunc))  # type: ignore[index]
    return tuple(program)


def run_program(
    program: Program,
    constants: Sequence[NDArray[np.float64]],
    slot_values: Sequence[NDArray[np.float64]],
    sensors: Mapping[str, NDArray[np.float64]],
) -> NDArray[np.float64]:
    """As :func:`run_skeleton`, with each constant already a column that broadcasts against the
    slots and sensors ([gaits, 1, 1], say): what a control loop keeps between ticks."""
    stack: list[NDArray[np.float64]] = []
    with np.errstate(all="ignore"):
        for code, arg in program:
            if code == _BINARY_OP:
                right = stack.pop()
                stack[-1] = arg(stack[-1], right)
            elif code == _SLOT:
                stack.append(slot_values[arg])
            elif code == _CONSTANT:
                stack.append(constants[arg])
            elif code == _SENSOR:
                stack.append(sensors[arg])
            else:
                stack[-1] = arg(stack[-1])
    (result,) = stack
    return result
