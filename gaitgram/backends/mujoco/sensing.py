"""Reading a backend's declared sensors (:mod:`gaitgram.backends.sensors`) from MuJoCo's state.

A sensor's ``read`` table names one of a few kinds, each a small function of the recorded state
vector (``mjSTATE_FULLPHYSICS``: time, qpos, qvel, ...) and ``sensordata``; what a kind needs of
the body (its standing height, its weight) comes from the walker as named facts, so that this
module knows no horse:

* ``sensor``: one value of a MuJoCo sensor (``index`` into it), as a share of a fact (``per``),
  ``minus`` a fact;
* ``pitch``: the pitch (degrees, nose up positive) of a ``framequat`` sensor;
* ``joint_velocity``: a joint's velocity times ``scale``;
* ``touch``: a touch sensor, per limb (``{limb}`` in its name), as a share of a fact (``per``)
  or as 0/1 ``above`` a force;
* ``oscillator``: the limb's phase, which the controller keeps (:mod:`.control`); here only the
  touchdown it resets at is read (a ``touch`` ``above`` a force).

Any kind but the oscillator may be averaged over the gait's own cycle (``average_cycles = k``):
an exponential average, updated at each control tick, whose time constant is k cycles of the
gait, starting from the sensor's nominal reading. A stride moves an instantaneous reading within
the cycle (the trunk surges and brakes at every footfall); its average moves from stride to
stride, which is what a gait's corrections of its own pace need.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, replace

import mujoco
import numpy as np
from numpy.typing import NDArray

from gaitgram.backends.sensors import Sensor, SensorCatalogue

__all__ = ["Sensing", "SensingError", "pitch_degrees"]


class SensingError(ValueError):
    """A sensor declaration the model cannot read (a missing MuJoCo sensor, an unknown kind)."""


def pitch_degrees(quat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Pitch (nose up positive, degrees) of (w, x, y, z) quaternions [..., 4]."""
    w, x, y, z = quat[..., 0], quat[..., 1], quat[..., 2], quat[..., 3]  # read at every control tick
    with np.errstate(all="ignore"):
        return -np.degrees(np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0)))


def _fact(
    facts: Mapping[str, float], read: Mapping[str, object], key: str, sensor: str, default: float
) -> float:
    """The walker's fact that ``read[key]`` names (``default`` when it names none)."""
    if key not in read:
        return default
    name = str(read[key])
    if name not in facts:
        known = ", ".join(sorted(facts)) or "none"
        raise SensingError(
            f"sensor {sensor}: {key} names {name!r}, which the walker does not give (it gives {known})"
        )
    return float(facts[name])


@dataclass(frozen=True)
class _Reader:
    name: str
    kind: str
    columns: NDArray[np.intp]  # into a state row ("joint_velocity") or a sensordata row (others)
    scale: float = 1.0
    offset: float = 0.0
    above: float | None = None
    per_limb: bool = False
    #: Cycles of the gait in the time constant of the reading's exponential average (None: raw).
    average_cycles: float | None = None
    nominal: float = 0.0


class Sensing:
    """Reads ``names`` of ``catalogue`` from records of ``model``: body sensors as [gaits], per-limb
    ones as [gaits, limbs] (``limbs`` order). ``facts`` are the walker's numbers a ``read`` table
    may name (``standing_height``, ``quarter_weight``, ``target_speed``). Averaged readings
    (``average_cycles``) are kept for ``gaits`` gaits between reads, updated every
    ``tick_seconds``."""

    def __init__(
        self,
        model: mujoco.MjModel,
        catalogue: SensorCatalogue,
        names: Collection[str],
        *,
        limbs: Sequence[str],
        facts: Mapping[str, float],
        gaits: int = 1,
        tick_seconds: float | None = None,
    ) -> None:
        self.limbs = tuple(limbs)
        self._readers = [
            self._reader(model, sensor, facts)
            for sensor in catalogue
            if sensor.name in names and sensor.read.get("kind") != "oscillator"
        ]
        self.tick_seconds = float(model.opt.timestep) if tick_seconds is None else tick_seconds
        #: Each averaged reading per gait (and limb): what the last tick left.
        self.averages = {
            reader.name: np.full((gaits, len(self.limbs)) if reader.per_limb else gaits, reader.nominal)
            for reader in self._readers
            if reader.average_cycles is not None
        }

    def _reader(self, model: mujoco.MjModel, sensor: Sensor, facts: Mapping[str, float]) -> _Reader:
        reader = self._raw_reader(model, sensor, facts)
        if "average_cycles" not in sensor.read:
            return reader
        cycles = sensor.read["average_cycles"]
        if isinstance(cycles, bool) or not isinstance(cycles, int | float) or not 0 < cycles <= 100:
            raise SensingError(
                f"sensor {sensor.name}: average_cycles must be a number of cycles in (0, 100], not {cycles!r}"
            )
        return replace(reader, average_cycles=float(cycles), nominal=sensor.nominal)

    def _raw_reader(self, model: mujoco.MjModel, sensor: Sensor, facts: Mapping[str, float]) -> _Reader:
        read = dict(sensor.read)
        kind = read.get("kind")
        try:
            if kind == "joint_velocity":
                joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, read["joint"])
                if joint < 0:
                    raise SensingError(f"sensor {sensor.name}: the model has no joint {read['joint']!r}")
                column = 1 + model.nq + int(model.jnt_dofadr[joint])  # qvel in a FULLPHYSICS state row
                return _Reader(sensor.name, kind, np.array([column]), float(read.get("scale", 1.0)))
            names = (
                [read["sensor"].format(limb=limb) for limb in self.limbs]
                if sensor.per_limb
                else [read["sensor"]]
            )
            starts = [self._sensor_start(model, sensor.name, name) for name in names]
            if kind == "sensor":
                index = int(read.get("index", 0))
                minus = _fact(facts, read, "minus", sensor.name, 0.0)
                scale = 1.0 / _fact(facts, read, "per", sensor.name, 1.0)
                return _Reader(sensor.name, kind, np.array([s + index for s in starts]), scale, offset=-minus)
            if kind == "pitch":
                return _Reader(sensor.name, kind, np.arange(starts[0], starts[0] + 4))
            if kind == "touch":
                above = read.get("above")
                scale = 1.0 / _fact(facts, read, "per", sensor.name, 1.0)
                return _Reader(
                    sensor.name,
                    kind,
                    np.array(starts),
                    scale,
                    above=None if above is None else float(above),
                    per_limb=sensor.per_limb,
                )
        except KeyError as missing:
            raise SensingError(f"sensor {sensor.name}: its read table lacks {missing}") from None
        raise SensingError(f"sensor {sensor.name}: unknown read kind {kind!r}")

    @staticmethod
    def _sensor_start(model: mujoco.MjModel, sensor: str, name: str) -> int:
        index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, name)
        if index < 0:
            raise SensingError(f"sensor {sensor}: the model has no MuJoCo sensor {name!r}")
        return int(model.sensor_adr[index])

    def read(
        self,
        state: NDArray[np.float64],
        sensordata: NDArray[np.float64],
        *,
        ids: NDArray[np.intp] | slice = slice(None),
        frequencies: NDArray[np.float64] | None = None,
        tick: bool = True,
    ) -> dict[str, NDArray[np.float64]]:
        """The readings at one step of the gaits ``ids`` (of the ``gaits``; ``slice(None)``: all in
        order): ``state`` [ids, nstate], ``sensordata`` [ids, nsensordata]. A ``tick`` (the first
        read of a control tick) moves the averaged readings towards the raw ones by the share of
        a time constant of ``frequencies[ids]``'s cycles that a tick lasts; a read that is not
        (a tick's second part, cut by a chunk's end) gives them as the tick left them."""
        readings = self._raw(state, sensordata)
        for reader in self._readers:
            if reader.average_cycles is None:
                continue
            kept = self.averages[reader.name]
            if tick:
                if frequencies is None:
                    raise ValueError(f"sensor {reader.name} is averaged over the cycle: give the frequencies")
                weight = -np.expm1(-self.tick_seconds * frequencies / reader.average_cycles)
                before = kept[ids]
                kept[ids] = before + (weight[:, None] if reader.per_limb else weight) * (
                    readings[reader.name] - before
                )
            readings[reader.name] = kept[ids]
        return readings

    def _raw(
        self, state: NDArray[np.float64], sensordata: NDArray[np.float64]
    ) -> dict[str, NDArray[np.float64]]:
        readings: dict[str, NDArray[np.float64]] = {}
        for reader in self._readers:
            if reader.kind == "joint_velocity":
                readings[reader.name] = state[:, reader.columns[0]] * reader.scale
            elif reader.kind == "pitch":
                readings[reader.name] = pitch_degrees(sensordata[:, reader.columns])
            elif reader.kind == "sensor":
                values = sensordata[:, reader.columns[0]]
                if reader.scale != 1.0:  # a share of a fact (``per``): the others' bits untouched
                    values = values * reader.scale
                readings[reader.name] = values + reader.offset
            else:  # touch
                values = sensordata[:, reader.columns]
                if reader.above is not None:
                    values = (values > reader.above).astype(np.float64)
                else:
                    values = values * reader.scale
                readings[reader.name] = values if reader.per_limb else values[:, 0]
        return readings


def touchdown_reader(
    model: mujoco.MjModel, sensor: Sensor, limbs: Sequence[str]
) -> tuple[NDArray[np.intp], float, float]:
    """An oscillator's touchdown: the touch sensors' columns per limb, the force above which a hoof
    is down, and how long it must have been up for its landing to count (s)."""
    read = sensor.read
    try:
        columns = np.array(
            [Sensing._sensor_start(model, sensor.name, read["sensor"].format(limb=limb)) for limb in limbs]
        )
        return columns, float(read["above"]), float(read.get("airborne_seconds", 0.0))
    except KeyError as missing:
        raise SensingError(f"sensor {sensor.name}: its read table lacks {missing}") from None
