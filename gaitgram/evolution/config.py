"""Run parameters: the paper's Table 1 by default, overridable from TOML and flags.

One frozen :class:`RunConfig` is resolved before a run starts and written to
the run directory; nothing else reads parameters from anywhere (no global
parameter dict). Errors in a config file name the file, the key and the fix.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from gaitgram.ge.mapper import CodonMode


class ConfigError(ValueError):
    """A config file or flag that cannot be used; the message says where and how to fix it."""


@dataclass(frozen=True)
class WeightStage:
    """Fitness weights from generation ``start`` on (the paper's Table 2)."""

    start: int
    weights: Mapping[str, float]


@dataclass(frozen=True)
class RunConfig:
    generations: int = 50
    population: int = 75
    runs: int = 1
    seed: int = 0
    max_wraps: int = 3
    codons: CodonMode = CodonMode.LAZY
    codon_size: int = 100_000
    elite: int = 7
    tournament: int = 3
    init_max_depth: int = 10
    grow_probability: float = 0.5
    tail: float = 0.5
    crossover: float = 0.9
    fixed_point: bool = True
    crossover_within_used: bool = True
    mutation: float = 0.02
    mutation_within_used: bool = False
    max_depth: int | None = None
    samples: int = 256  # samples per cycle of each joint curve
    backend: str | None = None  # None: the grammar's @backend, else mujoco-horse
    backend_settings: Mapping[str, Any] = field(default_factory=dict)
    weight_schedule: tuple[WeightStage, ...] = ()

    def __post_init__(self) -> None:
        checks = [
            (self.generations >= 1, "generations must be at least 1"),
            (self.population >= 2, "population must be at least 2"),
            (self.runs >= 1, "runs must be at least 1"),
            (self.seed >= 0, "seed must be a non-negative integer"),
            (self.max_wraps >= 0, "max_wraps must be >= 0"),
            (0 <= self.elite < self.population, "elite must be >= 0 and smaller than the population"),
            (self.tournament >= 1, "tournament must be at least 1"),
            (self.init_max_depth >= 1, "init_max_depth must be at least 1"),
            (0 <= self.grow_probability <= 1, "grow_probability must be in [0, 1]"),
            (0 <= self.crossover <= 1, "crossover must be a probability in [0, 1]"),
            (0 <= self.mutation <= 1, "mutation must be a probability in [0, 1]"),
            (self.codon_size >= 2, "codon_size must be at least 2"),
            (self.samples >= 8, "samples must be at least 8"),
            (self.tail >= 0, "tail must be >= 0"),
        ]
        for ok, message in checks:
            if not ok:
                raise ConfigError(message)

    def weights_at(self, generation: int) -> dict[str, float]:
        """The weights in force at ``generation``: the last stage that has started."""
        current: dict[str, float] = {}
        for stage in sorted(self.weight_schedule, key=lambda s: s.start):
            if stage.start <= generation:
                current = dict(stage.weights)
        return current

    def to_toml(self) -> str:
        """The resolved config, as a TOML file that :func:`load_config` reads back."""
        lines = ["# gaitgram evolve: the resolved configuration of this run", ""]
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("backend_settings", "weight_schedule") or value is None:
                continue
            lines.append(f"{f.name} = {_toml_value(value)}")
        if self.backend_settings:
            lines += ["", "[backend_settings]"]
            lines += [
                f"{k} = {_toml_value(v)}" for k, v in self.backend_settings.items() if not isinstance(v, dict)
            ]
            for k, v in self.backend_settings.items():
                if isinstance(v, dict):
                    lines += ["", f"[backend_settings.{k}]"] + [
                        f"{_key(kk)} = {_toml_value(vv)}" for kk, vv in v.items()
                    ]
        for stage in self.weight_schedule:
            lines += ["", "[[weight_schedule]]", f"start = {stage.start}"]
            lines += [f"weights.{_key(k)} = {_toml_value(v)}" for k, v in stage.weights.items()]
        return "\n".join(lines) + "\n"

    def as_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data["codons"] = self.codons.value
        return data


def _key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() else '"' + key + '"'


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, float):
        return repr(value)
    return str(value)


_FIELDS = {f.name: f for f in fields(RunConfig)}


def load_config(path: Path | None, overrides: Mapping[str, Any] | None = None) -> RunConfig:
    """Defaults, then the TOML file, then ``overrides`` (command-line flags, None = not given)."""
    data: dict[str, Any] = {}
    if path is not None:
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except OSError as error:
            raise ConfigError(f"{path}: cannot read: {error.strerror or error}") from None
        except tomllib.TOMLDecodeError as error:
            raise ConfigError(f"{path}: not valid TOML: {error}") from None
    where = str(path) if path else "config"
    values: dict[str, Any] = {}
    for key, value in data.items():
        if key not in _FIELDS:
            close = [
                name for name in _FIELDS if name.replace("_", "") == key.replace("_", "").replace("-", "")
            ]
            hint = f"; did you mean {close[0]}?" if close else f"; known keys: {', '.join(sorted(_FIELDS))}"
            raise ConfigError(f"{where}: unknown key {key!r}{hint}")
        values[key] = value
    for key, value in (overrides or {}).items():
        if value is None:
            continue
        if key == "backend_settings":  # flags add to the file's backend table
            values[key] = {**values.get(key, {}), **value}
        else:
            values[key] = value
    return _build(values, where)


def _build(values: dict[str, Any], where: str) -> RunConfig:
    converted: dict[str, Any] = {}
    for key, value in values.items():
        if key == "weight_schedule":
            converted[key] = _schedule(value, where)
        elif key == "backend_settings":
            if not isinstance(value, dict):
                raise ConfigError(f"{where}: backend_settings must be a table")
            converted[key] = value
        elif key == "codons":
            try:
                converted[key] = CodonMode(value)
            except ValueError:
                raise ConfigError(f"{where}: codons must be 'lazy' or 'eager', not {value!r}") from None
        else:
            converted[key] = _typed(key, value, where)
    try:
        return RunConfig(**converted)
    except ConfigError as error:
        raise ConfigError(f"{where}: {error}") from None


def _typed(key: str, value: Any, where: str) -> Any:
    default = getattr(RunConfig(), key)
    if key in ("max_depth", "backend") and value is None:
        return None
    expected: type = type(default) if default is not None else (int if key == "max_depth" else str)
    if expected is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if not isinstance(value, expected) or (expected is int and isinstance(value, bool)):
        raise ConfigError(f"{where}: {key} must be {expected.__name__}, not {value!r}")
    return value


def _schedule(value: Any, where: str) -> tuple[WeightStage, ...]:
    if not isinstance(value, list):
        raise ConfigError(f"{where}: weight_schedule must be an array of tables [[weight_schedule]]")
    stages = []
    for i, stage in enumerate(value):
        if (
            not isinstance(stage, dict)
            or not isinstance(stage.get("start"), int)
            or not isinstance(stage.get("weights"), dict)
        ):
            raise ConfigError(f"{where}: weight_schedule[{i}] needs start = N and a weights table")
        weights = {}
        for name, weight in stage["weights"].items():
            if isinstance(weight, bool) or not isinstance(weight, int | float) or weight < 0:
                raise ConfigError(f"{where}: weight_schedule[{i}].weights.{name} must be a number >= 0")
            weights[name] = float(weight)
        stages.append(WeightStage(stage["start"], weights))
    return tuple(stages)


def with_overrides(config: RunConfig, **changes: Any) -> RunConfig:
    return replace(config, **{k: v for k, v in changes.items() if v is not None})
