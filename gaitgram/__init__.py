"""gaitgram: grammars for Grammatical Evolution of animal gaits."""

from importlib.metadata import PackageNotFoundError, version

__all__ = ["__version__"]

try:
    __version__ = version("gaitgram")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"
