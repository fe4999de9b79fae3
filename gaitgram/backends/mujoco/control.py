"""Controls: a population's curves turned into actuator targets, open loop or closed.

:class:`Actuation` says how a walker's curves drive its actuators (which curve, at which phase
offset, around which neutral target, within which range, blended in over a ramp). An
:class:`OpenLoop` plays sampled curves of the cycle phase: every step's controls are known before
the simulation starts, so any range of steps is built at once. A :class:`ClosedLoop` plays
phenotypes that read sensors (:mod:`gaitgram.motion.feedback`): at every control tick it reads the
sensed state, and holds the controls' sensed part for the tick's steps while the curves of the
phase still move at every step (a zero-order hold, as dm_control holds an action over its
physics substeps).

Element by element, the same numpy operations build a step's controls whatever the range of
steps asked for, so a chunk's controls are bit-identical to the same steps of the full array, and
a closed loop's open-loop curves are bit-identical to an open loop's.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gaitgram.backends.mujoco.sensing import Sensing
from gaitgram.motion.feedback import ClosedLoop as Loop
from gaitgram.motion.feedback import run_skeleton
from gaitgram.motion.gait import MotionBatch

__all__ = ["Actuation", "ClosedLoop", "OpenLoop", "Oscillators"]

#: Per gait (its position among the gaits asked for), why its controls failed.
Failures = dict[int, str]


@dataclass(frozen=True, eq=False)
class Actuation:
    """How curves drive a walker's actuators. Per-actuator arrays have ``nu`` entries."""

    curves: tuple[str, ...]  # the walker's curves, in its order
    curve_index: NDArray[np.intp]  # per actuator: the curve (index into ``curves``) it plays
    offsets: NDArray[np.float64]  # per actuator: its limb's phase offset in the cycle
    limb_index: NDArray[np.intp]  # per actuator: its limb (index into ``limbs``), -1 for none
    limbs: tuple[str, ...]
    neutral: NDArray[np.float64]  # per actuator: the target that holds the standing pose (rad)
    low: NDArray[np.float64]
    high: NDArray[np.float64]
    timestep: float
    ramp_seconds: float

    @property
    def nu(self) -> int:
        return len(self.curve_index)

    def ramp(self, first: int, last: int) -> NDArray[np.float64]:
        """The blend-in factor of steps ``first..last-1``: 0 standing, 1 from the ramp's end on."""
        if not self.ramp_seconds:
            return np.ones(last - first)
        return np.clip(np.arange(first, last) * self.timestep / self.ramp_seconds, 0.0, 1.0)

    def finish(self, values: NDArray[np.float64], first: int, last: int) -> NDArray[np.float64]:
        """Curve values (radians) [gaits, steps, nu] of steps ``first..last-1`` as controls, in
        place: blended in over the ramp, around the neutral targets, within the control range."""
        values *= self.ramp(first, last)[None, :, None]
        values += self.neutral[None, None, :]
        np.clip(values, self.low[None, None, :], self.high[None, None, :], out=values)
        return values

    def clock(self, first: int, last: int, frequencies: NDArray[np.float64]) -> NDArray[np.float64]:
        """Each actuator's unwrapped cycle phase (time x frequency - offset) at steps
        ``first..last-1``, [gaits, steps, nu]."""
        time = np.arange(first, last) * self.timestep
        return time[None, :, None] * frequencies[:, None, None] - self.offsets[None, None, :]


class OpenLoop:
    """Sampled curves played at the cycle phase: controls for any range of steps at once."""

    def __init__(self, actuation: Actuation, *, reference_frequency: float, min_steps: int = 0) -> None:
        self.actuation = actuation
        self.reference_frequency = reference_frequency
        self.min_steps = min_steps
        self._lookups: dict[tuple[int, float], tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def table(self, batch: MotionBatch, rows: NDArray[np.intp]) -> NDArray[np.float64]:
        """Per gait, every actuator's curve samples in radians, flat: [gaits, actuators * samples]."""
        curves_by_name = {name: i for i, name in enumerate(batch.joints)}
        order = np.array([curves_by_name.get(name, -1) for name in self.actuation.curves])
        angles = np.concatenate([batch.angles[rows], np.zeros((len(rows), 1, batch.n_samples))], axis=1)
        per_curve = angles[:, order, :]  # [G, curves, S]; undriven curves read the zero row
        return np.radians(per_curve[:, self.actuation.curve_index, :]).reshape(len(rows), -1)  # [G, nu*S]

    def values(
        self,
        table: NDArray[np.float64],
        samples: int,
        first: int,
        last: int,
        frequencies: NDArray[np.float64] | None = None,
    ) -> NDArray[np.float64]:
        """Curve values (radians) [gaits, last - first, actuators] for steps ``first..last-1`` from
        a table, at the reference frequency, or at each gait's own ``frequencies`` (Hz)."""
        steps = slice(first, last)
        if frequencies is None:
            low, high, frac = self.lookup(samples, last)
            # One flat gather per interpolation end, straight into [gaits, steps, actuators] order.
            v_low = np.take(table, low[steps], axis=1)
            values = np.take(table, high[steps], axis=1)
            fraction = frac[steps]
        else:  # the same per distinct frequency (grammars evolve a few), gaits gathered by it
            shape = (len(table), last - first, self.actuation.nu)
            v_low, values, fraction = np.empty(shape), np.empty(shape), np.empty(shape)
            for value in np.unique(frequencies):
                gaits = np.flatnonzero(frequencies == value)
                low, high, frac = self.lookup(samples, last, float(value))
                v_low[gaits] = np.take(table[gaits], low[steps], axis=1)
                values[gaits] = np.take(table[gaits], high[steps], axis=1)
                fraction[gaits] = frac[steps]
        values -= v_low
        values *= fraction
        values += v_low
        return values

    def controls(
        self,
        table: NDArray[np.float64],
        samples: int,
        first: int,
        last: int,
        frequencies: NDArray[np.float64] | None = None,
    ) -> NDArray[np.float64]:
        """Controls [gaits, last - first, actuators] for steps ``first..last-1`` (:meth:`values`,
        finished)."""
        return self.actuation.finish(self.values(table, samples, first, last, frequencies), first, last)

    def lookup(
        self, samples: int, last: int, frequency: float | None = None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Flat sample indices [steps, actuators] around each step's phase at ``frequency`` (Hz; the
        reference by default), and the weight between them, for at least ``last`` steps."""
        frequency = self.reference_frequency if frequency is None else frequency
        cached = self._lookups.get((samples, frequency))
        if cached is None or len(cached[0]) < last:  # grown by doubling: a check's chunks reach far
            steps = max(last, self.min_steps, 2 * len(cached[0]) if cached is not None else 0)
            time = np.arange(steps) * self.actuation.timestep
            phase = np.mod(time[:, None] * frequency - self.actuation.offsets[None, :], 1.0)
            position = phase * samples  # [steps, nu], in samples
            low = np.floor(position).astype(np.intp) % samples
            nu = self.actuation.nu
            base = np.arange(nu)[None, :] * samples
            cached = (base + low, base + (low + 1) % samples, position - np.floor(position))
            self._lookups[(samples, frequency)] = cached
        return cached


class Oscillators:
    """Each gait's per-limb oscillator phase: the cycle phase, restarted at 0 when the limb's hoof
    lands after ``airborne`` seconds up (phase resetting). Kept between control ticks."""

    def __init__(
        self,
        gaits: int,
        touch_columns: NDArray[np.intp],
        above: float,
        airborne: float,
        actuation: Actuation,
    ) -> None:
        self.touch_columns = touch_columns
        self.above = above
        self.airborne_needed = airborne
        self.actuation = actuation
        limbs = len(actuation.limbs)
        self.shift = np.zeros((gaits, limbs))  # added to the unwrapped clock
        #: Per hoof, seconds since a tick last saw it down (0 while it is down).
        self.airborne = np.zeros((gaits, limbs))
        self._last_step = 0

    def tick(
        self,
        ids: NDArray[np.intp],
        step: int,
        sensordata: NDArray[np.float64],
        frequencies: NDArray[np.float64],
    ) -> None:
        """Take in the hooves' contacts at ``step`` (the state the tick starts from, [ids, ...]):
        a landing restarts its limb's phase at this step."""
        elapsed = (step - self._last_step) * self.actuation.timestep
        self._last_step = step
        down = sensordata[:, self.touch_columns] > self.above  # [ids, limbs]
        was_up = self.airborne[ids] > 0  # seen up at the last tick (a hoof down reads 0)
        airborne = np.where(was_up | ~down, self.airborne[ids] + elapsed, 0.0)
        landed = down & was_up & (airborne >= self.airborne_needed)
        if landed.any():
            # The limb's unwrapped clock at this step, as :meth:`Actuation.clock` computes it.
            limb_offsets = self._limb_offsets()
            clock = step * self.actuation.timestep * frequencies[:, None] - limb_offsets[None, :]
            shift = self.shift[ids]
            shift[landed] = -clock[landed]
            self.shift[ids] = shift
        self.airborne[ids] = np.where(down, 0.0, airborne)

    def _limb_offsets(self) -> NDArray[np.float64]:
        act = self.actuation
        offsets = np.zeros(len(act.limbs))
        for a, limb in enumerate(act.limb_index):
            if limb >= 0:
                offsets[limb] = act.offsets[a]
        return offsets

    def phases(self, ids: NDArray[np.intp], clock: NDArray[np.float64]) -> NDArray[np.float64]:
        """The oscillator phases in [0, 1) [ids, steps, nu] from the unwrapped clock of the same
        shape (actuators without a limb keep the clock)."""
        limb = self.actuation.limb_index
        shift = np.where(limb[None, :] >= 0, self.shift[ids][:, np.maximum(limb, 0)], 0.0)
        return np.mod(clock + shift[:, None, :], 1.0)


@dataclass(frozen=True, eq=False)
class _Group:
    """The gaits (positions in the closed loop's group) whose loops of one curve share a skeleton."""

    curve: int
    actuators: NDArray[np.intp]
    skeleton: tuple
    gaits: NDArray[np.intp]
    constants: NDArray[np.float64]  # [gaits, k]
    slots: tuple[tuple[str, NDArray[np.float64]], ...]  # per slot: its variable, samples [gaits, n + 1]
    scale: float  # degrees per unit of the phenotype


class ClosedLoop:
    """Controls of gaits whose phenotypes read sensors, one group of gaits at a time.

    ``loops[g][c]`` is gait ``g``'s closed loop of curve ``c`` (``actuation.curves`` order), or
    None where the curve is open loop (played from ``table`` as :class:`OpenLoop` plays it).
    Every ``tick`` steps the held sensors are read from the last recorded step."""

    def __init__(
        self,
        open_loop: OpenLoop,
        table: NDArray[np.float64],
        samples: int,
        frequencies: NDArray[np.float64],
        own_frequencies: bool,
        loops: Sequence[Sequence[Loop | None]],
        *,
        tick: int,
        sensing: Sensing | None,
        oscillators: Oscillators | None,
        scale: float = 1.0,
    ) -> None:
        self.open_loop = open_loop
        self.actuation = open_loop.actuation
        self.table = table
        self.samples = samples
        self.frequencies = frequencies
        self.own_frequencies = own_frequencies
        self.tick = tick
        self.sensing = sensing
        self.oscillators = oscillators
        self.groups = self._groups(loops, scale)
        self.variables = frozenset(v for group in self.groups for v, _ in group.slots)

    def _groups(self, loops: Sequence[Sequence[Loop | None]], scale: float) -> list[_Group]:
        act = self.actuation
        groups: list[_Group] = []
        for c in range(len(act.curves)):
            by_skeleton: dict[tuple, list[int]] = {}
            for g, per_curve in enumerate(loops):
                loop = per_curve[c]
                if loop is not None:
                    by_skeleton.setdefault(loop.skeleton, []).append(g)
            for skeleton, members in by_skeleton.items():
                first = loops[members[0]][c]
                slots = tuple(
                    (slot.variable, np.stack([loops[g][c].slots[i].samples for g in members]))  # type: ignore[union-attr]
                    for i, slot in enumerate(first.slots)  # type: ignore[union-attr]
                )
                constants = np.array([loops[g][c].constants for g in members], dtype=np.float64)  # type: ignore[union-attr]
                groups.append(
                    _Group(
                        c,
                        np.flatnonzero(act.curve_index == c),
                        skeleton,
                        np.asarray(members, dtype=np.intp),
                        constants.reshape(len(members), -1),
                        slots,
                        scale,
                    )
                )
        return groups

    def controls(
        self,
        ids: NDArray[np.intp],
        first: int,
        last: int,
        state: NDArray[np.float64],
        sensordata: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], Failures]:
        """Controls [ids, last - first, nu] for steps ``first..last-1`` (one tick at most) of the
        gaits ``ids``, from the state [ids, nstate] and sensors [ids, nsensordata] recorded at the
        step before ``first``; and the gaits (positions in ``ids``) whose controls are not finite."""
        frequencies = self.frequencies[ids]
        values = self.open_loop.values(
            self.table[ids], self.samples, first, last, frequencies if self.own_frequencies else None
        )
        readings = self.sensing.read(state, sensordata) if self.sensing is not None else {}
        clock = self.actuation.clock(first, last, frequencies) if self.variables else None
        phases: dict[str, NDArray[np.float64]] = {}
        if "t" in self.variables:
            phases["t"] = np.mod(clock, 1.0)  # type: ignore[arg-type]
        if self.oscillators is not None:
            if first % self.tick == 0:  # the tick's first part (a chunk's end may cut a tick in two)
                self.oscillators.tick(ids, first, sensordata, frequencies)
            phases["phase"] = self.oscillators.phases(ids, clock)  # type: ignore[arg-type]
        position = np.full(len(self.frequencies), -1)
        position[ids] = np.arange(len(ids))
        failures: Failures = {}
        limb = self.actuation.limb_index
        for group in self.groups:
            rows = position[group.gaits]
            keep = rows >= 0
            if not keep.any():
                continue
            rows = rows[keep]
            acts = group.actuators
            slot_values = [
                _interpolate(samples[keep], phases[variable][rows][:, :, acts])
                for variable, samples in group.slots
            ]
            held = {
                name: (value[rows][:, limb[acts]] if value.ndim == 2 else value[rows][:, None])[:, None, :]
                for name, value in readings.items()
            }
            result = run_skeleton(group.skeleton, group.constants[keep], slot_values, held)
            result = np.broadcast_to(result, (len(rows), last - first, len(acts)))
            if group.scale != 1.0:
                result = result * group.scale
            finite = np.isfinite(result).all(axis=(1, 2))
            for r in rows[~finite]:
                failures.setdefault(int(r), self.actuation.curves[group.curve])
            values[np.ix_(rows, np.arange(last - first), acts)] = np.radians(
                np.where(np.isfinite(result), result, 0.0)
            )
        return self.actuation.finish(values, first, last), failures


def _interpolate(samples: NDArray[np.float64], phases: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per gait, its slot's samples [gaits, n + 1] (phases 0..1 inclusive) read at ``phases``
    [gaits, steps, actuators] in [0, 1), by linear interpolation."""
    n = samples.shape[1] - 1
    position = phases * n
    low = np.minimum(np.floor(position).astype(np.intp), n - 1)
    fraction = position - low
    rows = np.arange(len(samples))[:, None, None]
    v_low = samples[rows, low]
    return v_low + (samples[rows, low + 1] - v_low) * fraction
