"""The ``mujoco-horse`` settings, checked without importing MuJoCo.

A run's ``[backend_settings]`` are checked before its directory is made, so a
misspelt key or a weight that no component has is refused up front instead of
scoring every gait 0 or allocating terabytes an hour into a study.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from gaitgram.backends.api import SettingsError
from gaitgram.backends.mujoco_horse.bodies import UnknownBody, body_named
from gaitgram.backends.mujoco_horse.targets import (
    CYCLE_FREQUENCIES,
    DEFAULT_FROUDE,
    DEFAULT_WEIGHTS,
    walk_targets,
)

#: The fitness components a weight may name.
WEIGHT_NAMES: frozenset[str] = frozenset(DEFAULT_WEIGHTS)
#: Longest simulated time per gait: past this a typo (``cycles = 3000``) would cost hours and gigabytes.
MAX_SIMULATED_SECONDS = 120.0
MAX_THREADS = 1024
#: Lowest Froude number the walk targets are read at (slower than this is standing still).
MIN_FROUDE = 0.05
MAX_FROUDE = 2.5


#: The bump floors (seeds of ``model.bumpy_model``) that the robustness trial tests kept gaits on:
#: a fitness may not be scored on them (``bump_floors``), or gaits would be tested on the floors
#: they were chosen on.
TEST_FLOORS: tuple[int, ...] = tuple(range(26, 36))
#: Most bump floors a fitness may score on: each is another simulation of every gait.
MAX_BUMP_FLOORS = 10
#: The largest ``speed_margin``: the walk criterion allows 10 % either side of the target speed.
MAX_SPEED_MARGIN = 0.1
#: The range of ``bump_height`` (m): from bumps finer than a hoof's sole is thick to the height of
#: a fetlock, past which no walk on a 500 kg horse is to be had.
BUMP_HEIGHTS = (0.005, 0.1)
#: The bumps' height when ``bump_height`` is left out: the robustness trial's turf
#: (``model.BUMP_HEIGHT``, not imported: this module does not import MuJoCo).
DEFAULT_BUMP_HEIGHT = 0.02


#: Unscored time after the ramp, rounded up to whole cycles of the gait: from rest, the horse
#: settles to a steady speed 1.3-1.8 s after the ramp (docs/fitness.md, "Warm-up").
DEFAULT_WARMUP_SECONDS = 1.5
#: Cycles after the ramp that a gait a run keeps is checked over: it must stay upright (and, if it
#: is a walk, walk) for all of them.
DEFAULT_HORIZON_CYCLES = 20
MIN_HORIZON_CYCLES = 20


@dataclass(frozen=True)
class HorseSettings:
    froude: float = DEFAULT_FROUDE
    ramp_seconds: float = 0.5  # controls blend in from the standing pose
    warmup_seconds: float = DEFAULT_WARMUP_SECONDS  # after the ramp, in whole own cycles, not scored
    cycles: int = 3  # own cycles scored after the warm-up
    horizon_cycles: int = DEFAULT_HORIZON_CYCLES  # own cycles after the ramp a kept gait is checked over
    threads: int = 0  # 0: all cores
    weights: Mapping[str, float] | None = None
    #: The body walked (bodies.toml); None is the horse, and is not spelt out in a run's settings,
    #: so that runs made before bodies existed keep their fingerprints.
    body: str | None = None
    #: The body the grammar's own cycle frequencies are meant for (None: this one): they are played
    #: on ``body`` scaled by dynamic similarity, sqrt(h_of / h_body), as ``retarget --scaling froude``
    #: plays a gait. A run started from a horse's population on a pony sets "horse", so that its
    #: first generation is the horse's gaits Froude-scaled; not spelt out when None.
    frequencies_of: str | None = None
    #: Seeds of bump floors (``model.bumpy_model``) each gait is also played on: its fitness is the
    #: mean over the flat floor and these, and a gait that falls on one is unviable. None: the flat
    #: floor alone, not spelt out, so that the runs scored on it keep their fingerprints.
    bump_floors: tuple[int, ...] | None = None
    #: How far above the walk's target speed (a share of it) the fitness aims its speed and stride
    #: terms; the walk criterion keeps the target. None: no margin, not spelt out (runs made
    #: before it keep their fingerprints). docs/fitness.md, "Margins".
    speed_margin: float | None = None
    #: The full height (m) of the bumps on the ``bump_floors``: the robustness trial's turf is 2 cm
    #: (``model.BUMP_HEIGHT``), its graded rungs 4 and 6 cm. None: 2 cm, not spelt out (runs made
    #: before it keep their fingerprints). docs/fitness.md, "Scoring on bumps".
    bump_height: float | None = None

    def __post_init__(self) -> None:
        _check(self)

    @classmethod
    def from_mapping(cls, settings: Mapping[str, Any]) -> HorseSettings:
        """Read a ``[backend_settings]`` table; raises :class:`SettingsError` naming the key."""
        known = (
            "froude",
            "ramp_seconds",
            "warmup_seconds",
            "cycles",
            "horizon_cycles",
            "threads",
            "weights",
            "body",
            "frequencies_of",
            "bump_floors",
            "speed_margin",
            "bump_height",
        )
        for key in settings:
            if key not in known:
                raise SettingsError(str(key), f"unknown mujoco-horse setting{_suggest(str(key), known)}")
        values: dict[str, Any] = {}
        for key in ("froude", "ramp_seconds", "warmup_seconds", "speed_margin", "bump_height"):
            if key in settings:
                values[key] = _number(key, settings[key])
        for key in ("cycles", "horizon_cycles", "threads"):
            if key in settings:
                values[key] = _integer(key, settings[key])
        if "weights" in settings:
            values["weights"] = weights_table("weights", settings["weights"])
        if "body" in settings:
            if not isinstance(settings["body"], str):
                raise SettingsError("body", f"must be the name of a body, not {settings['body']!r}")
            values["body"] = settings["body"]
        if "frequencies_of" in settings:
            if not isinstance(settings["frequencies_of"], str):
                raise SettingsError(
                    "frequencies_of", f"must be the name of a body, not {settings['frequencies_of']!r}"
                )
            values["frequencies_of"] = settings["frequencies_of"]
        if "bump_floors" in settings:
            values["bump_floors"] = _floor_seeds(settings["bump_floors"])
        if values.get("bump_height") == DEFAULT_BUMP_HEIGHT:  # the default spelt out: the same run
            values["bump_height"] = None
        return cls(**values)

    @property
    def simulated_seconds(self) -> float:
        """Simulated time of the longest check, a kept gait's over the horizon, at the target's
        cycle frequency."""
        targets = walk_targets(self.froude, body_named(self.body).nominal_hip_height)
        return self.ramp_seconds + self.horizon_cycles / targets.stride_frequency


#: Fewest warm-up cycles: every hoof must have landed once before the first scored cycle, since a
#: stride is measured from one footfall to the next (the standing start is no footfall).
MIN_WARMUP_CYCLES = 2


def weights_in_force(
    given: Mapping[str, float] | None, settings: Mapping[str, float] | None
) -> Mapping[str, float]:
    """The fitness weights that score a gait: those given for the generation (a weight schedule's
    stage), else the run's ``weights`` setting, else the backend's defaults."""
    return given or settings or DEFAULT_WEIGHTS


def warmup_cycles(seconds: float, frequency: float) -> int:
    """Whole cycles of a gait at ``frequency`` (Hz) that last at least ``seconds``, and at least
    :data:`MIN_WARMUP_CYCLES`."""
    return max(MIN_WARMUP_CYCLES, math.ceil(seconds * frequency - 1e-9))


def max_warmup_cycles(seconds: float) -> int:
    """The warm-up cycles of the fastest gait the backend plays."""
    return warmup_cycles(seconds, CYCLE_FREQUENCIES[1])


def weights_table(key: str, value: Any) -> dict[str, float]:
    """A table of fitness weights: known component names, finite numbers >= 0."""
    if not isinstance(value, Mapping):
        raise SettingsError(key, "must be a table of component = weight")
    weights = {}
    for name, weight in value.items():
        if name not in WEIGHT_NAMES:
            raise SettingsError(
                f"{key}.{name}",
                f"no fitness component is called {name!r}{_suggest(str(name), sorted(WEIGHT_NAMES))}",
            )
        number = _number(f"{key}.{name}", weight)
        if number < 0:
            raise SettingsError(f"{key}.{name}", f"a weight must be >= 0, not {number}")
        weights[str(name)] = number
    return weights


def _check(s: HorseSettings) -> None:
    for key in ("body", "frequencies_of"):
        try:
            body_named(getattr(s, key))
        except UnknownBody as error:
            raise SettingsError(key, str(error)) from None
    if not MIN_FROUDE <= s.froude <= MAX_FROUDE:
        raise SettingsError("froude", f"must be in [{MIN_FROUDE}, {MAX_FROUDE}], not {s.froude}")
    if s.speed_margin is not None and not 0 <= s.speed_margin <= MAX_SPEED_MARGIN:
        raise SettingsError(
            "speed_margin",
            f"must be a share of the target speed in [0, {MAX_SPEED_MARGIN}] (0.04: aim 4 % faster), "
            f"not {s.speed_margin}",
        )
    if s.bump_height is not None:
        low, high = BUMP_HEIGHTS
        if not low <= s.bump_height <= high:
            raise SettingsError(
                "bump_height",
                f"must be the bumps' full height in metres in [{low}, {high}] (0.04: 4 cm), "
                f"not {s.bump_height}",
            )
        if not s.bump_floors:
            raise SettingsError(
                "bump_height",
                "sizes the bumps of the bump_floors, and no bump_floors are set: add bump_floors = [0] "
                "(or more seeds), or leave bump_height out",
            )
    if not 0 <= s.ramp_seconds <= 10:
        raise SettingsError("ramp_seconds", f"must be in [0, 10] seconds, not {s.ramp_seconds}")
    if not 0 <= s.warmup_seconds <= 10:
        raise SettingsError("warmup_seconds", f"must be in [0, 10] seconds, not {s.warmup_seconds}")
    if not 1 <= s.cycles <= 100:
        raise SettingsError("cycles", f"must be a whole number in [1, 100], not {s.cycles}")
    longest = max_warmup_cycles(s.warmup_seconds) + s.cycles
    if not max(MIN_HORIZON_CYCLES, longest) <= s.horizon_cycles <= 200:
        raise SettingsError(
            "horizon_cycles",
            f"must be a whole number from {max(MIN_HORIZON_CYCLES, longest)} (at least {MIN_HORIZON_CYCLES}, "
            f"and no fewer than the warm-up and scored cycles of the fastest gait, {longest}) to 200, not "
            f"{s.horizon_cycles}",
        )
    if not 0 <= s.threads <= MAX_THREADS:
        raise SettingsError("threads", f"must be in [0, {MAX_THREADS}] (0: all cores), not {s.threads}")
    if s.simulated_seconds > MAX_SIMULATED_SECONDS:
        raise SettingsError(
            "horizon_cycles",
            f"{s.horizon_cycles} cycles at Froude number {s.froude} simulate {s.simulated_seconds:.0f} s "
            f"for a kept gait; at most {MAX_SIMULATED_SECONDS:.0f} s are allowed (a shorter horizon, or a "
            "faster gait)",
        )


def _floor_seeds(value: Any) -> tuple[int, ...]:
    """``bump_floors``: distinct seeds, none a test floor of the robustness trial."""
    if not isinstance(value, list | tuple) or not value:
        raise SettingsError(
            "bump_floors",
            f"must be a list of floor seeds, such as [0, 1, 2], not {value!r} (leave it out to score "
            "on the flat floor alone)",
        )
    seeds = tuple(_integer("bump_floors", seed) for seed in value)
    if any(seed < 0 for seed in seeds) or len(set(seeds)) != len(seeds):
        raise SettingsError("bump_floors", f"must be distinct whole numbers >= 0, not {list(seeds)}")
    if len(seeds) > MAX_BUMP_FLOORS:
        raise SettingsError(
            "bump_floors",
            f"at most {MAX_BUMP_FLOORS} floors (each is another simulation of every gait), not {len(seeds)}",
        )
    tested = [seed for seed in seeds if seed in TEST_FLOORS]
    if tested:
        raise SettingsError(
            "bump_floors",
            f"seed {tested[0]} is one of the floors the robustness trial tests kept gaits on "
            f"({TEST_FLOORS[0]}-{TEST_FLOORS[-1]}): gaits scored on it would be tested on the floor they "
            f"were chosen on; choose seeds outside {TEST_FLOORS[0]}-{TEST_FLOORS[-1]}",
        )
    return seeds


def _number(key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise SettingsError(key, f"must be a number, not {value!r}")
    number = float(value)
    if not math.isfinite(number):
        raise SettingsError(key, f"must be a finite number, not {value!r}")
    return number


def _integer(key: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise SettingsError(key, f"must be a whole number, not {value!r}")
    return value


def _suggest(name: str, known: Any) -> str:
    close = difflib.get_close_matches(name, list(known), n=1)
    return f"; did you mean {close[0]}?" if close else f"; known: {', '.join(known)}"
