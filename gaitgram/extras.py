"""Optional dependencies: import one, or say exactly how to install it.

A plain ``pip install gaitgram`` must start every command; the heavy parts
(plots, statistics, distribution, optimisers, video) are extras imported only by the
code that needs them, through :func:`require`, so that a missing one is a
one-line message with the install command and never a traceback.
"""

from __future__ import annotations

import importlib
from types import ModuleType

#: Extra that provides each optional top-level module.
EXTRA_OF_MODULE: dict[str, str] = {
    "matplotlib": "plot",
    "PIL": "plot",
    "scipy": "stats",
    "dask": "dask",
    "distributed": "dask",
    "cma": "cma-es",
    "pymoo": "nsga2",
    "ribs": "map-elites",
    "imageio": "video",
    "imageio_ffmpeg": "video",
    "h5py": "dlc",
}


class MissingExtra(ImportError):
    """An optional dependency is not installed; the message says how to install it."""

    def __init__(self, module: str, purpose: str) -> None:
        self.module = module
        self.extra = EXTRA_OF_MODULE.get(module.split(".")[0], "")
        self.install = f"pip install 'gaitgram[{self.extra}]'" if self.extra else f"pip install {module}"
        super().__init__(f"{purpose} need {module}, which is not installed: {self.install}")


def require(module: str, purpose: str) -> ModuleType:
    """Import ``module`` for ``purpose`` (e.g. "study reports"), or raise :class:`MissingExtra`."""
    try:
        return importlib.import_module(module)
    except ImportError as error:
        if error.name is not None and module.startswith(error.name.split(".")[0]):
            raise MissingExtra(module, purpose) from None
        raise
