"""The files shipped inside the package: the language's grammar, the horse's model, joints and
bodies, the seed data.

Read by path from the installed tree rather than through :mod:`importlib.resources`: pip installs
gaitgram as files, never as a zip, and the first use of importlib.resources costs about 8 ms, a
twentieth of a whole ``gaitgram check`` (issue 28).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["packaged"]

_ROOT = Path(__file__).resolve().parent


def packaged(package: str, name: str) -> Path:
    """The file ``name`` in the directory of ``package``, a gaitgram package
    (``packaged("gaitgram.motion", "horse_walk.csv")``)."""
    top, *inner = package.split(".")
    if top != "gaitgram":
        raise ValueError(f"{package} is not a gaitgram package")
    return _ROOT.joinpath(*inner, name)
