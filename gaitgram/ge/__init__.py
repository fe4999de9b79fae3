"""Grammatical Evolution: compile a grammar to a mapper, map genomes to derivations."""

from __future__ import annotations

from gaitgram.ge.derivation import Derivation, InvalidReason, Node
from gaitgram.ge.mapper import CodonMode, Mapped, Mapper, MapperError, MappingOptions, compile_mapper
from gaitgram.ge.ponyge2 import python_filter

__all__ = [
    "CodonMode",
    "Derivation",
    "InvalidReason",
    "Mapped",
    "Mapper",
    "MapperError",
    "MappingOptions",
    "Node",
    "compile_mapper",
    "python_filter",
]
