"""Representations as plug-ins: how a genome becomes a derivation, declared once and found by name.

A representation is what a run's genomes are and how they map to phenotypes: GE's codons (the
default, ``ge``), position-independent GE (``pige``), structured GE and its dynamic variant
(``sge``, ``dsge``), CFG-GP's derivation trees (``cfg-gp``), or a plug-in's. A package declares
one as a backend or a strategy is declared, in its ``pyproject.toml``::

    [project.entry-points."gaitgram.representations"]
    my-representation = "my_package.representation:REPRESENTATION"

where ``REPRESENTATION`` is a :class:`RepresentationSpec`: its settings (names, defaults and
ranges, checked with a "did you mean"), and ``compile``, which turns a grammar and those settings
into a :class:`Compiled` representation that initialises, varies, maps, encodes and decodes
genomes. Everything above this floor (the pipeline, the strategies, run records, commands) speaks
of a :data:`Genome` through that API and never of codons. Loading a spec must be cheap: a run's
configuration is checked against it.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from gaitgram.analysis.cfg import Cfg
from gaitgram.analysis.facts import GrammarFacts
from gaitgram.backends.api import SettingsError
from gaitgram.ge.derivation import Derivation, InvalidReason
from gaitgram.ge.mapper import MapperError
from gaitgram.language.model import Grammar
from gaitgram.plugins import PluginLoadError, PluginNotFound, Registry

if TYPE_CHECKING:  # loading a spec is cheap: no numpy (``gaitgram map`` starts without it)
    import numpy as np

__all__ = [
    "DEFAULT_REPRESENTATION",
    "ENTRY_POINT_GROUP",
    "Compiled",
    "Genome",
    "GenomeError",
    "Mapped",
    "Parent",
    "RepresentationLoadError",
    "RepresentationNotFound",
    "RepresentationSpec",
    "Setting",
    "check_fields",
    "compile_representation",
    "genome_key",
    "get_representation",
    "mapping_summary",
    "representation_names",
    "representation_version",
]

ENTRY_POINT_GROUP = "gaitgram.representations"

#: The representation of a run that names none: GE, the paper's.
DEFAULT_REPRESENTATION = "ge"

#: A genome of any representation: an immutable tuple (of codons, of genes, of a tree's choices).
Genome = tuple[Any, ...]

#: The representations gaitgram ships (also declared as entry points in its pyproject.toml).
BUILTIN = {
    "ge": "gaitgram.ge.classic:REPRESENTATION",
    "pige": "gaitgram.ge.pige:REPRESENTATION",
    "sge": "gaitgram.ge.sge:REPRESENTATION",
    "dsge": "gaitgram.ge.dsge:REPRESENTATION",
    "cfg-gp": "gaitgram.ge.cfggp:REPRESENTATION",
}


class GenomeError(ValueError):
    """A genome this representation cannot hold: malformed text or JSON, the wrong number of
    genes, a value that names no choice of its rule. The message says where and what to write."""


class Mapped(Protocol):
    """What mapping a genome gives the layers above: its phenotype and joint phenotypes (None and
    empty when invalid, ``reason`` saying why) and ``used``, how much of the genome the mapping read
    (codons, gene values, tree nodes), which variation may confine itself to."""

    @property
    def phenotype(self) -> str | None: ...

    @property
    def joints(self) -> Mapping[str, str]: ...

    @property
    def reason(self) -> InvalidReason | None: ...

    @property
    def valid(self) -> bool: ...

    @property
    def used(self) -> int: ...


class Parent(Protocol):
    """A member of the population varied: its genome and what its mapping used (an ``Individual``)."""

    @property
    def genome(self) -> Genome: ...

    @property
    def used(self) -> int: ...


class Compiled(Protocol):
    """A representation compiled for one grammar and one set of settings. Immutable; every random
    draw comes from the ``rng`` it is given, so that runs are reproducible and resumable."""

    name: str
    #: What a mapping's ``used`` counts, a plural noun (``codons``, ``values``, ``nodes``): a run's
    #: ``best.json`` records it as ``used_<counts>``.
    counts: str

    def initialise(self, rng: np.random.Generator, n: int) -> list[Genome]:
        """``n`` genomes of a first generation (each within the settings' depth limits)."""
        ...

    def vary(self, rng: np.random.Generator, parents: Sequence[Parent], count: int) -> list[Genome]:
        """``count`` children of ``parents`` (tournament winners, paired in order), by the
        representation's crossover and mutation."""
        ...

    def map_many(self, genomes: Sequence[Genome]) -> Sequence[Mapped]: ...

    def derivation(self, genome: Genome) -> Derivation:
        """The full derivation tree of a genome (for ``gaitgram map --tree`` and a run's best)."""
        ...

    def encode(self, genome: Genome) -> str:
        """The genome as text, as ``gaitgram map --genome`` reads it."""
        ...

    def decode(self, text: str) -> Genome:
        """A genome from its text; :class:`GenomeError` says where it is wrong and what to write."""
        ...

    def to_json(self, genome: Genome) -> Any:
        """The genome as a JSON value (checkpoints, ``best.json``)."""
        ...

    def from_json(self, value: Any) -> Genome:
        """A genome from its JSON value, checked; :class:`GenomeError` if it is none of this one's."""
        ...

    def tables(self) -> dict[str, Any]:
        """What ``gaitgram compile`` writes: the mapping's tables as JSON data."""
        ...


@dataclass(frozen=True)
class Setting:
    """One setting a representation declares: its default, its type (the default's, or ``kind``),
    its inclusive range or its ``choices``, and whether it may be None (``optional``: no limit,
    written by leaving the key out of a run.toml)."""

    name: str
    default: Any
    help: str
    low: float | None = None
    high: float | None = None
    choices: tuple[str, ...] = ()
    optional: bool = False
    kind: type | None = None

    @property
    def type(self) -> type:
        if self.kind is not None:
            return self.kind
        if self.choices:
            return str
        return bool if isinstance(self.default, bool) else type(self.default)

    @property
    def shown(self) -> str:
        """What values it takes, for messages and docs."""
        if self.choices:
            return "one of " + ", ".join(self.choices)
        kind = self.type
        if kind is bool:
            return "true or false"
        if kind is float and (self.low, self.high) == (0, 1):
            return "a probability in [0, 1]"
        what = "an integer" if kind is int else "a number"
        if self.high is not None:
            return f"{what} in [{_number(self.low)}, {_number(self.high)}]"
        return what + (f" >= {_number(self.low)}" if self.low is not None else "")

    def problem(self, value: Any) -> str | None:
        """What is wrong with ``value`` for this setting (None: nothing)."""
        if value is None and self.optional:
            return None
        kind = self.type
        if isinstance(value, float) and not math.isfinite(value):
            return f"must be a finite number, not {value}"
        if kind is str:
            if value in self.choices:
                return None
            close = difflib.get_close_matches(str(value), self.choices, n=1)
            return f"must be {self.shown}, not {value!r}" + (f"; did you mean {close[0]!r}?" if close else "")
        fits = (
            isinstance(value, bool)
            if kind is bool
            else not isinstance(value, bool)
            and isinstance(value, int if kind is int else int | float)
            and (self.low is None or value >= self.low)
            and (self.high is None or value <= self.high)
        )
        return None if fits else f"must be {self.shown}, not {value!r}"

    def check(self, value: Any) -> Any:
        """``value`` normalised (a number setting written 1 is 1.0), or :class:`SettingsError`
        naming the setting and what it takes."""
        problem = self.problem(value)
        if problem is not None:
            raise SettingsError(self.name, problem)
        return float(value) if self.type is float and value is not None else value


def check_fields(owner: str, settings: Sequence[Setting], values: Any) -> None:
    """Each declared setting of a settings object (``values``: its attributes) as it declares it,
    else :class:`~gaitgram.ge.mapper.MapperError` ``owner: name must be ...``: the library's
    dataclasses check themselves by the declarations their plug-in's settings are checked by."""
    for setting in settings:
        problem = setting.problem(getattr(values, setting.name))
        if problem is not None:
            raise MapperError(f"{owner}: {setting.name} {problem}")


def _number(value: float | None) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    return f"{value:,}".replace(",", "_")


@dataclass(frozen=True)
class RepresentationSpec:
    """What a representation declares about itself.

    * ``settings``: every setting it takes (:class:`Setting`), with defaults; a run's
      ``[representation_settings]`` is checked against them (unknown keys get a "did you mean")
      and recorded with the defaults spelt out.
    * ``compile(grammar, facts, settings)`` returns the :class:`Compiled` representation of a
      checked grammar (``facts``: its analysis) under checked settings; it raises
      :class:`~gaitgram.ge.mapper.MapperError` for a grammar it cannot compile (naming why). It may
      be slow on a large grammar.
    * ``check_run(compiled)`` raises :class:`~gaitgram.backends.api.SettingsError`, naming the
      setting, for settings a run cannot use with this grammar (an initial depth below its
      shortest derivation); commands that only map genomes (``map``, ``compile``) skip it. A run
      also draws a first genome before it starts, so an initialisation that cannot keep to its
      depths is refused then.
    * ``genome_syntax``: an example of its genome text, for help and messages.
    * ``version`` changes whenever the same genome could map, or the same run vary, differently; a
      run records it (except GE's, whose runs are what they always were) and is not resumed under
      another.
    * ``describe_rule(cfg, rule)``: a line on what a rule is in this representation's genome (SGE:
      its genes), for the editor's hover; None: nothing to say.
    * ``source``: the reference it follows, for the documentation.
    """

    name: str
    summary: str
    settings: tuple[Setting, ...]
    compile: Callable[[Grammar, GrammarFacts, Mapping[str, Any]], Compiled]
    genome_syntax: str
    version: str = ""
    check_run: Callable[[Compiled], None] | None = None
    describe_rule: Callable[[Cfg, int], str | None] | None = None
    source: str = ""

    def setting(self, name: str) -> Setting | None:
        return next((s for s in self.settings if s.name == name), None)

    @property
    def defaults(self) -> dict[str, Any]:
        return {s.name: s.default for s in self.settings}

    def checked_settings(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """``given`` checked setting by setting, every default spelt out (in declared order)."""
        names = [s.name for s in self.settings]
        for key in given:
            if key not in names:
                close = difflib.get_close_matches(str(key), names, n=1, cutoff=0.6)
                hint = f"did you mean {close[0]}? " if close else ""
                raise SettingsError(
                    str(key),
                    f"unknown setting of representation {self.name}; {hint}its settings: "
                    f"{', '.join(names) or 'none'}",
                )
        return {s.name: s.check(given[s.name]) if s.name in given else s.default for s in self.settings}


class RepresentationNotFound(PluginNotFound):
    pass


class RepresentationLoadError(PluginLoadError):
    pass


REGISTRY: Registry[RepresentationSpec] = Registry(
    ENTRY_POINT_GROUP,
    "representation",
    RepresentationSpec,
    BUILTIN,
    not_found=RepresentationNotFound,
    load_error=RepresentationLoadError,
)


def representation_names() -> tuple[str, ...]:
    return REGISTRY.names()


def get_representation(name: str) -> RepresentationSpec:
    return REGISTRY.get(name)


def representation_version(name: str) -> str:
    """What a run records of its representation: the providing package and the spec's version."""
    package = REGISTRY.find(name).package
    version = get_representation(name).version
    return f"{package}; {version}" if version else package


def genome_key(value: Any) -> Genome:
    """A genome's JSON value as a hashable genome (lists to tuples, at every depth), to compare
    genomes read from records without the representation at hand."""
    if isinstance(value, list | tuple):
        return tuple(genome_key(v) for v in value)
    return value


def compile_representation(
    grammar: Grammar, facts: GrammarFacts, name: str, settings: Mapping[str, Any]
) -> Compiled:
    """Representation ``name`` compiled for a checked grammar with ``settings`` (checked against its
    declaration; unset ones at their defaults). Raises :class:`RepresentationNotFound` (with a
    "did you mean"), :class:`~gaitgram.backends.api.SettingsError` naming a setting, or
    :class:`~gaitgram.ge.mapper.MapperError`."""
    spec = get_representation(name)
    return spec.compile(grammar, facts, spec.checked_settings(settings))


def mapping_summary(compiled: Compiled, derivation: Derivation) -> dict[str, Any]:
    """What ``gaitgram map --json`` prints of a genome's derivation (everything but the tree):
    GE's record as it always was; another representation's names what its ``used`` counts and
    itself, and has no wraps unless it reads codons."""
    record = derivation.summary()
    if compiled.name == DEFAULT_REPRESENTATION:
        return record
    used = record.pop("used_codons")
    wraps = record.pop("wraps")
    summary = {"representation": compiled.name}
    for key, value in record.items():
        summary[key] = value
        if key == "reason":
            summary[f"used_{compiled.counts}"] = used
            if compiled.counts == "codons":
                summary["wraps"] = wraps
    return summary
