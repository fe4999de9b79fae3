"""gaitgram: grammars for Grammatical Evolution of animal gaits."""

__all__ = ["__version__"]

#: The one place the version is written (pyproject.toml reads it): no importlib.metadata at start-up.
__version__ = "0.1.0"
