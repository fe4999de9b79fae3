"""Options shared by several commands."""

from __future__ import annotations

from typing import Annotated

import typer

Defines = Annotated[
    list[str] | None,
    typer.Option(
        "--define",
        "-D",
        metavar="NAME=N",
        help="Give a value to GE_RANGE:NAME (as PonyGE2's dataset_n_vars); repeatable.",
    ),
]


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
            raise typer.BadParameter(
                f"{item!r}: {value!r} is not an integer", param_hint="--define"
            ) from None
    return defines
