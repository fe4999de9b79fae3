"""Options shared by several commands."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable
from typing import Annotated, Any

import typer

from gaitgram.ge.registry import BUILTIN as REPRESENTATIONS
from gaitgram.ge.registry import DEFAULT_REPRESENTATION


def ge_default(name: str) -> Any:
    """GE's default for its setting ``name``, for a help text: read from GE's declaration
    (:data:`gaitgram.ge.classic.SETTINGS`), never copied, so that help cannot drift from it."""
    from gaitgram.ge.classic import REPRESENTATION as GE  # only where a command's help shows one

    return GE.defaults[name]


def listed(names: Iterable[str], default: str) -> str:
    """``ge (default), pige, sge``: built-in names for a help text, the default marked."""
    return ", ".join(f"{name} (default)" if name == default else name for name in names)


Defines = Annotated[
    list[str] | None,
    typer.Option(
        "--define",
        "-D",
        metavar="NAME=N",
        help="Give a value to GE_RANGE:NAME (as PonyGE2's dataset_n_vars); repeatable.",
    ),
]

#: ``evaluate``/``render --run DIR --walk``: the run's best walk, not its best gait.
Walk = Annotated[
    bool,
    typer.Option(
        "--walk",
        help="With --run: the best-scoring walk the run hands back (its final population, Pareto "
        "front or repertoire) instead of its best gait, which the weighted fitness may rank "
        "above every walk.",
    ),
]


#: ``map``, ``sample``, ``compile``, ``test``: what a genome is (docs/ge.md).
Representation = Annotated[
    str,
    typer.Option(
        "--representation",
        help=f"What a genome is: {listed(REPRESENTATIONS, DEFAULT_REPRESENTATION)}, or a plug-in's "
        "(docs/ge.md).",
    ),
]
#: ``map``, ``sample``, ``compile``, ``test``: a representation setting, as JSON or else text.
RepresentationSettings = Annotated[
    list[str] | None,
    typer.Option(
        "--setting",
        metavar="KEY=JSON",
        help="A setting of the representation, for example recursion=3 for sge (repeatable; docs/ge.md).",
    ),
]


#: ``evaluate``/``render``: a backend setting over the configuration's, as JSON or else text.
Settings = Annotated[
    list[str] | None,
    typer.Option("--set", metavar="KEY=JSON", help="A backend setting, for example froude=0.5."),
]


def parse_settings(items: list[str] | None, flag: str = "--set") -> dict[str, object]:
    """``["froude=0.5", "body=pony"]`` -> ``{"froude": 0.5, "body": "pony"}`` (a value that is not
    JSON is text), with a usage error (exit 2) naming the bad one."""
    settings: dict[str, object] = {}
    for item in items or []:
        key, sep, raw = item.partition("=")
        if not sep or not key.strip():
            raise typer.BadParameter(f"{item!r} is not KEY=VALUE", param_hint=flag)
        try:
            settings[key.strip()] = json.loads(raw)
        except json.JSONDecodeError:
            settings[key.strip()] = raw
    return settings


def parse_defines(raw: list[str] | None) -> dict[str, int]:
    """``["n=5"]`` -> ``{"n": 5}``, with a usage error (exit 2) naming the bad one."""
    defines: dict[str, int] = {}
    for item in raw or []:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key.isidentifier():
            raise typer.BadParameter(f"{item!r} is not NAME=N", param_hint="--define")
        try:
            defines[key] = int(value)
        except ValueError:
            shown = f"{value[:12]}…" if len(value) > 15 else value
            # int() refuses thousands of digits (more than any GE_RANGE size needs) as it does text
            why = (
                "the value is too large"
                if value.strip().lstrip("+-").isdecimal()
                else "the value is not an integer"
            )
            raise typer.BadParameter(f"{key}={shown}: {why}", param_hint="--define") from None
    return defines


def within(flag: str, low: float, high: float, unit: str = "") -> Callable[[float], float]:
    """A callback for a float option: a finite number from ``low`` to ``high``, or a usage error
    (exit 2) naming the flag. typer's ``min``/``max`` let ``inf`` and ``nan`` through."""

    def check(value: float) -> float:
        if not (math.isfinite(value) and low <= value <= high):
            raise typer.BadParameter(
                f"{value:g} is not a number from {low:g} to {high:g}{unit}", param_hint=flag
            )
        return value

    return check
