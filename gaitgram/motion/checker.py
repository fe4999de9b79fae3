"""Checking, the second stage: every name is known and every call has its one argument.

Kept apart from parsing so that an unknown name is reported as one, with a hint (a
misspelt ``Sin``, ``time`` for ``t``, a function the language leaves out), rather than
as a syntax error. Of several problems, the first in the text is reported.

A backend that senses its body offers *sensors* (``pitch``, ``load``, ...): names a closed-loop
phenotype may read beside ``t``. They are known only where the caller passes them, so the same
text is a closed loop for a backend that has them and an unknown name for one that has not.
"""

from __future__ import annotations

from collections.abc import Collection
from difflib import get_close_matches

from gaitgram.motion.parser import NodeKind, Syntax
from gaitgram.motion.results import MotionError, MotionStatus
from gaitgram.motion.vocabulary import CONSTANTS, FUNCTIONS, UNSUPPORTED, VARIABLE

_NAME, _CALL = NodeKind.NAME, NodeKind.CALL


def check(syntax: Syntax, sensors: Collection[str] = ()) -> MotionError | None:
    """The first problem with the names of ``syntax``, or None: the compiler may take it.
    ``sensors`` are the sensor names the expression may read."""
    first: MotionError | None = None
    for kind, name, start, end, n_args, _ in syntax.nodes:
        if kind is _NAME:
            if name == VARIABLE or name in CONSTANTS or name in sensors:
                continue
            problem = _name_problem(name, start, called=False, sensors=sensors)  # type: ignore[arg-type]
        elif kind is _CALL:
            if name not in FUNCTIONS:
                problem = _name_problem(name, start, called=True, sensors=sensors)  # type: ignore[arg-type]
            elif n_args != 1:
                problem = MotionError(
                    MotionStatus.PARSE_ERROR,
                    f"{name} takes exactly one argument, not {n_args}, at offset {start}",
                    start,
                    end - start,
                    f"write {name}(x)",
                )
            else:
                continue
        else:
            continue
        if first is None or problem.offset < first.offset:
            first = problem
    return first


def _name_problem(name: str, offset: int, *, called: bool, sensors: Collection[str] = ()) -> MotionError:
    length = len(name)
    if called and (name == VARIABLE or name in CONSTANTS or name in sensors):
        return MotionError(
            MotionStatus.PARSE_ERROR,
            f"{name} is not a function, at offset {offset}",
            offset,
            length,
            f"write '*' for a product: {name}*(...)",
        )
    if not called and name in FUNCTIONS:
        return MotionError(
            MotionStatus.PARSE_ERROR,
            f"{name} is a function, at offset {offset}",
            offset,
            length,
            f"call it: {name}(...)",
        )
    kind = "function" if called else "name"
    known = sorted(FUNCTIONS) if called else [VARIABLE, *CONSTANTS, *sorted(sensors)]
    message = f"unknown {kind} {name!r} at offset {offset}; known: {', '.join(known)}"
    every = (*FUNCTIONS, VARIABLE, *CONSTANTS, *sorted(sensors))
    close = [k for k in every if k.lower() == name.lower()]
    near = [] if called else get_close_matches(name, sorted(sensors), n=1, cutoff=0.75)
    if close:
        hint = f"did you mean {close[0]!r}? names are case-sensitive"
    elif near:
        hint = f"did you mean the sensor {near[0]!r}?"
    elif name.lower() in ("time", "phase"):
        hint = f"the phase variable is {VARIABLE!r}"
    elif name.lower() in UNSUPPORTED:
        hint = f"motion expressions support only {' and '.join(FUNCTIONS)}"
    else:
        hint = None
    return MotionError(MotionStatus.UNKNOWN_NAME, message, offset, length, hint)
