"""The ``.gg`` grammar language: text in, :class:`~gaitgram.language.model.Grammar` out."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from gaitgram.collector import without_gc
from gaitgram.language.builder import build_grammar
from gaitgram.language.model import Grammar
from gaitgram.language.parser import parse_tree
from gaitgram.language.source import SourceError, SourceText, read_source

__all__ = ["Grammar", "SourceError", "SourceText", "load", "parse"]


@without_gc
def parse(
    text: str | SourceText, *, name: str = "<text>", defines: Mapping[str, int] | None = None
) -> Grammar:
    """Parse grammar text. Never raises on bad input: problems are in ``grammar.diagnostics``."""
    source = text if isinstance(text, SourceText) else SourceText(text, name)
    return build_grammar(parse_tree(source.text), source, defines)


def load(path: str | Path, *, defines: Mapping[str, int] | None = None) -> Grammar:
    """Read and parse a grammar file; raises :class:`SourceError` if it cannot be read."""
    return parse(read_source(path), defines=defines)
