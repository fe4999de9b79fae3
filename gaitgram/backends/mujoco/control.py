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
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from gaitgram.backends.mujoco.sensing import Sensing
from gaitgram.motion.feedback import ClosedLoop as Loop
from gaitgram.motion.feedback import Program, run_program, skeleton_program
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

    def finish(
        self, values: NDArray[np.float64], first: int, last: int, ramp: NDArray[np.float64] | None = None
    ) -> NDArray[np.float64]:
        """Curve values (radians) [gaits, steps, nu] of steps ``first..last-1`` as controls, in
        place: blended in over the ramp (``ramp``: :meth:`ramp`'s, computed ahead), around the
        neutral targets, within the control range."""
        ramp = self.ramp(first, last) if ramp is None else ramp
        if not (ramp.size and ramp[0] >= 1.0):  # it never falls: from 1 on, x * 1.0 is x, bit for bit
            values *= ramp[None, :, None]
        values += self.neutral[None, None, :]
        np.clip(values, self.low[None, None, :], self.high[None, None, :], out=values)
        return values

    def clock(
        self,
        first: int,
        last: int,
        frequencies: NDArray[np.float64],
        offsets: NDArray[np.float64] | None = None,
    ) -> NDArray[np.float64]:
        """Each actuator's unwrapped cycle phase (time x frequency - offset) at steps
        ``first..last-1``, [gaits, steps, nu]; or that of each of ``offsets`` [k], [gaits, steps, k]."""
        time = np.arange(first, last) * self.timestep
        offsets = self.offsets if offsets is None else offsets
        return time[None, :, None] * frequencies[:, None, None] - offsets[None, None, :]


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
        columns: NDArray[np.intp] | None = None,
    ) -> NDArray[np.float64]:
        """Curve values (radians) [gaits, last - first, actuators] for steps ``first..last-1`` from
        a table, at the reference frequency, or at each gait's own ``frequencies`` (Hz); of the
        actuators ``columns`` only (None: all), each the value it has among all."""
        steps = (slice(first, last),) if columns is None else (slice(first, last), columns)
        if frequencies is None:
            low, high, frac = self.lookup(samples, last)
            # One flat gather per interpolation end, straight into [gaits, steps, actuators] order.
            v_low = np.take(table, low[steps], axis=1)
            values = np.take(table, high[steps], axis=1)
            fraction = frac[steps]
        else:  # the same per distinct frequency (grammars evolve a few), gaits gathered by it
            width = self.actuation.nu if columns is None else len(columns)
            shape = (len(table), last - first, width)
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
        #: Each limb's phase offset (its actuators'; 0 for a limb that drives none), as the clock has it.
        self.limb_offsets = np.zeros(limbs)
        for limb, offset in zip(actuation.limb_index, actuation.offsets, strict=True):
            if limb >= 0:
                self.limb_offsets[limb] = offset

    def tick(
        self,
        ids: NDArray[np.intp] | slice,
        step: int,
        sensordata: NDArray[np.float64],
        frequencies: NDArray[np.float64],
    ) -> None:
        """Take in the hooves' contacts at ``step`` (the state the tick starts from, [ids, ...]):
        a landing restarts its limb's phase at this step. ``ids``: the gaits, or ``slice(None)``
        for all of them in order."""
        elapsed = (step - self._last_step) * self.actuation.timestep
        self._last_step = step
        down = sensordata[:, self.touch_columns] > self.above  # [ids, limbs]
        airborne = self.airborne[ids]  # a view for slice(None): written back in place
        was_up = airborne > 0  # seen up at the last tick (a hoof down reads 0)
        airborne += elapsed  # up since: the time it has been up, if it is still up or lands now
        landed = down & was_up & (airborne >= self.airborne_needed)
        if landed.any():
            # The limb's unwrapped clock at this step, as :meth:`Actuation.clock` computes it.
            clock = step * self.actuation.timestep * frequencies[:, None] - self.limb_offsets[None, :]
            shift = self.shift[ids]
            shift[landed] = -clock[landed]
            self.shift[ids] = shift
        np.copyto(airborne, 0.0, where=down)
        self.airborne[ids] = airborne

    def phases(
        self, ids: NDArray[np.intp] | slice, clock: NDArray[np.float64], limbs: NDArray[np.intp] | None = None
    ) -> NDArray[np.float64]:
        """The oscillator phases in [0, 1) [ids, steps, k] from the unwrapped clock of the same shape
        of ``limbs`` [k] (-1: none, which keeps the clock; by default each actuator's)."""
        limb = self.actuation.limb_index if limbs is None else limbs
        shift = np.where(limb[None, :] >= 0, self.shift[ids][:, np.maximum(limb, 0)], 0.0)
        phases = clock + shift[:, None, :]
        # np.mod(phases, 1.0) bit for bit (both round the same exact fraction), at a fraction of its cost.
        phases -= np.floor(phases)
        return phases


@dataclass(frozen=True, eq=False)
class _Samples:
    """A slot's samples per member [members, n + 1] (phases 0..1 inclusive), and the differences
    ``samples[:, k + 1] - samples[:, k]`` that interpolation between them adds (0 past the end)."""

    variable: str
    samples: NDArray[np.float64]
    deltas: NDArray[np.float64]
    starts: NDArray[np.intp]  # per member: its first sample's flat index, [members, 1, 1]

    @classmethod
    def of(cls, variable: str, samples: NDArray[np.float64]) -> _Samples:
        deltas = np.zeros_like(samples)
        np.subtract(samples[:, 1:], samples[:, :-1], out=deltas[:, :-1])
        starts = (np.arange(len(samples)) * samples.shape[1])[:, None, None]
        return cls(variable, samples, deltas, starts)

    def take(self, members: NDArray[np.intp]) -> _Samples:
        return _Samples(
            self.variable, self.samples[members], self.deltas[members], self.starts[: len(members)]
        )

    def at(self, phases: NDArray[np.float64]) -> NDArray[np.float64]:
        """Each member's samples read at ``phases`` [members, steps, width] in [0, 1], by linear
        interpolation: ``v + (next - v) * fraction`` of the two samples around each phase."""
        low, fraction = _positions(phases, self.samples.shape[1] - 1)
        low += self.starts  # flat indices
        v_low = self.samples.take(low)
        return v_low + self.deltas.take(low) * fraction

    def at_positions(
        self, low: NDArray[np.intp], fraction: NDArray[np.float64], where: NDArray[np.intp]
    ) -> NDArray[np.float64]:
        """As :meth:`at`, from :func:`_positions` computed once for every gait's phase columns
        ([ids, steps, columns]) and each member's share of them (``where``, flat, [members, steps,
        width]): the same numbers, without computing a limb's positions once per curve."""
        low = low.take(where)
        low += self.starts
        v_low = self.samples.take(low)
        return v_low + self.deltas.take(low) * fraction.take(where)


def _positions(phases: NDArray[np.float64], n: int) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """The sample below each phase in [0, 1] of a slot of ``n + 1`` samples, and the fraction past it."""
    position = phases * n
    low = np.minimum(position.astype(np.intp), n - 1)  # the floor: positions are not negative
    return low, position - low


@dataclass(frozen=True, eq=False)
class _Group:
    """Loops that share a skeleton, whatever their curve: each member is one gait's loop of one
    curve, driving ``width`` actuators (the curves of a group all drive as many). One skeleton
    run computes them all, element by element as a run per gait and curve would."""

    skeleton: tuple
    gaits: NDArray[np.intp]  # per member: its gait (position in the closed loop's group)
    curves: NDArray[np.intp]  # per member: its curve
    actuators: NDArray[np.intp]  # [members, width]: the actuators its curve drives
    constants: NDArray[np.float64]  # [members, k]
    slots: tuple[_Samples, ...]
    sensors: frozenset[str]  # the held sensors its skeleton reads
    program: Program  # the skeleton as it runs


@dataclass(frozen=True, eq=False)
class _Placed:
    """A group's members among the gaits a tick is asked for (``ids``): index arrays built once
    per set of gaits, not per tick."""

    group: _Group
    members: NDArray[np.intp]  # the group's members asked for
    rows: NDArray[np.intp]  # [members, 1]: each one's position in ``ids``
    actuators: NDArray[np.intp]  # [members, width]
    limbs: NDArray[np.intp]  # [members, width]: the limb of each actuator (a per-limb sensor's column)
    constants: tuple[NDArray[np.float64], ...]  # each constant as a column [members, 1, 1]
    slots: tuple[_Samples, ...]
    columns: NDArray[np.intp]  # [members, width]: the phase column of each actuator
    #: Flat indices [members, steps, width] of :meth:`share` and :meth:`targets`, per tick length.
    flat: dict[tuple[str, int], NDArray[np.intp]] = field(default_factory=dict)

    def share(self, steps: int, count: int) -> NDArray[np.intp]:
        """Flat indices of each member's actuators' phase columns in arrays [ids, steps, count]."""
        return self._flat("share", steps, count, self.columns)

    def targets(self, steps: int, nu: int) -> NDArray[np.intp]:
        """Flat indices of each member's actuators in controls [ids, steps, nu]."""
        return self._flat("targets", steps, nu, self.actuators)

    def _flat(self, what: str, steps: int, count: int, columns: NDArray[np.intp]) -> NDArray[np.intp]:
        where = self.flat.get((what, steps))
        if where is None:
            where = (self.rows[:, :, None] * steps + np.arange(steps)[None, :, None]) * count
            where = self.flat[what, steps] = where + columns[:, None, :]
        return where


class _Block:
    """What a closed loop computes ahead for steps ``first..last-1`` of the gaits it is asked for,
    since no sensor changes it: the open-loop curves' values, the ramp, the unwrapped clock, and
    the slots of ``t``. A tick reads its steps' share: each element is the value a tick's own
    computation would give (the operations are element by element). The slots of an oscillator's
    phase, which a landing moves, are read per tick from the clock kept here."""

    def __init__(self, first: int, last: int) -> None:
        self.first, self.last = first, last
        self.values: NDArray[np.float64] = np.empty(0)
        self.ramp: NDArray[np.float64] = np.empty(0)
        self.clock: NDArray[np.float64] = np.empty(0)
        #: The unwrapped clock of each phase column [ids, steps, columns], if a slot reads the phase.
        self.phase_clock: NDArray[np.float64] | None = None
        #: Per placed group, per slot: the values of a slot of ``t`` [members, steps, width], None
        #: for a slot of an oscillator's phase.
        self.slots: list[list[NDArray[np.float64] | None]] = []


#: Steps a closed loop computes ahead (:class:`_Block`): a chunk's worth of ticks.
BLOCK_STEPS = 125


class ClosedLoop:
    """Controls of gaits whose phenotypes read sensors, one group of gaits at a time.

    ``loops[g][c]`` is gait ``g``'s closed loop of curve ``c`` (``actuation.curves`` order), or
    None where the curve is open loop (played from ``table`` as :class:`OpenLoop` plays it).
    Every ``tick`` steps the held sensors are read from the last recorded step.

    Loops of one skeleton run together whatever their curve. What the held sensors do not change
    (the open-loop curves, the clock, the slots of ``t``) is computed for a block of steps ahead,
    and the index arrays that place each group among the gaits asked for once per set of gaits:
    per tick remain the sensors, the oscillators, the slots of their phase (a landing moves it)
    and one skeleton run per group."""

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
        self.scale = scale
        self.groups = self._groups(loops)
        self.variables = frozenset(slot.variable for group in self.groups for slot in group.slots)
        # An actuator's oscillator phase depends on its limb and phase offset alone: computed once
        # per such *phase column* (a limb's, for the horse), not once per curve it drives.
        keys: dict[tuple[int, float], int] = {}
        act = self.actuation
        pairs = zip(act.limb_index.tolist(), act.offsets.tolist(), strict=True)
        self._phase_column = np.array([keys.setdefault(key, len(keys)) for key in pairs], dtype=np.intp)
        self._phase_limbs = np.array([limb for limb, _ in keys], dtype=np.intp)
        self._phase_offsets = np.array([offset for _, offset in keys], dtype=np.float64)
        self._ids: NDArray[np.intp] | None = None
        self._ids_frequencies: NDArray[np.float64] = frequencies
        self._open_columns: NDArray[np.intp] | None = None
        self._placed: list[_Placed] = []
        self._rows: NDArray[np.intp] | slice = slice(None)  # ``ids``, or slice(None) for all in order
        self._block: _Block | None = None

    def _groups(self, loops: Sequence[Sequence[Loop | None]]) -> list[_Group]:
        act = self.actuation
        actuators = [np.flatnonzero(act.curve_index == c) for c in range(len(act.curves))]
        members: dict[tuple[tuple, int], list[tuple[int, int]]] = {}
        for c in range(len(act.curves)):
            for g, per_curve in enumerate(loops):
                loop = per_curve[c]
                if loop is not None:
                    members.setdefault((loop.skeleton, len(actuators[c])), []).append((g, c))
        groups: list[_Group] = []
        for (skeleton, _width), pairs in members.items():
            found = [loops[g][c] for g, c in pairs]
            first = found[0]
            assert first is not None
            slots = tuple(
                _Samples.of(slot.variable, np.stack([loop.slots[i].samples for loop in found]))  # type: ignore[union-attr]
                for i, slot in enumerate(first.slots)
            )
            constants = np.array([loop.constants for loop in found], dtype=np.float64)  # type: ignore[union-attr]
            groups.append(
                _Group(
                    skeleton,
                    np.array([g for g, _ in pairs], dtype=np.intp),
                    np.array([c for _, c in pairs], dtype=np.intp),
                    np.array([actuators[c] for _, c in pairs], dtype=np.intp),
                    constants.reshape(len(pairs), -1),
                    slots,
                    frozenset(step[1] for step in skeleton if step[0] == "sensor"),
                    skeleton_program(skeleton),
                )
            )
        return groups

    def _place(self, ids: NDArray[np.intp]) -> None:
        """The groups placed among the gaits ``ids`` (the same until a gait drops out)."""
        position = np.full(len(self.frequencies), -1)
        position[ids] = np.arange(len(ids))
        limb = self.actuation.limb_index
        placed = []
        for group in self.groups:
            rows = position[group.gaits]
            members = np.flatnonzero(rows >= 0)
            if not len(members):
                continue
            acts = group.actuators[members]
            placed.append(
                _Placed(
                    group,
                    members,
                    rows[members][:, None],
                    acts,
                    limb[acts],
                    tuple(column[:, None, None] for column in group.constants[members].T),
                    tuple(slot.take(members) for slot in group.slots),
                    self._phase_column[acts],
                )
            )
        self._ids, self._placed, self._block = ids.copy(), placed, None
        # All the gaits in order: read the oscillators' rows as views.
        everyone = len(ids) == len(self.frequencies) and bool((ids == np.arange(len(ids))).all())
        self._rows = slice(None) if everyone else ids
        self._ids_frequencies = self.frequencies[ids]
        # The actuators some gait plays open loop: only theirs are read from the table.
        covered = np.zeros(self.actuation.nu, dtype=np.intp)
        for where in placed:
            covered += np.bincount(where.actuators.ravel(), minlength=self.actuation.nu)
        opened = np.flatnonzero(covered < len(ids))
        self._open_columns = None if len(opened) == self.actuation.nu else opened

    def _ahead(self, ids: NDArray[np.intp], first: int) -> _Block:
        """Compute what the held sensors do not change for the steps from ``first`` on."""
        block = _Block(first, first + max(BLOCK_STEPS, self.tick))
        frequencies = self._ids_frequencies
        table = self.table if len(ids) == len(self.table) else self.table[ids]
        own = frequencies if self.own_frequencies else None
        columns = self._open_columns
        if columns is None:
            block.values = self.open_loop.values(table, self.samples, block.first, block.last, own)
        else:  # the others are the loops' alone
            block.values = np.zeros((len(ids), block.last - block.first, self.actuation.nu))
            block.values[:, :, columns] = self.open_loop.values(
                table, self.samples, block.first, block.last, own, columns
            )
        block.ramp = self.actuation.ramp(block.first, block.last)
        variables = [{slot.variable for slot in placed.slots} for placed in self._placed]
        if any("t" in used for used in variables):
            block.clock = self.actuation.clock(block.first, block.last, frequencies)
        if any(used - {"t"} for used in variables):
            offsets = self._phase_offsets
            block.phase_clock = self.actuation.clock(block.first, block.last, frequencies, offsets)
        for placed, used in zip(self._placed, variables, strict=True):
            clock = _gather(block.clock, placed) if "t" in used else None
            block.slots.append(
                [slot.at(np.mod(clock, 1.0)) if slot.variable == "t" else None for slot in placed.slots]  # type: ignore[arg-type]
            )
        return block

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
        if self._ids is None or ids.shape != self._ids.shape or not (ids == self._ids).all():
            self._place(ids)
        if self.oscillators is not None and first % self.tick == 0:  # a tick's first part (a chunk's
            # end may cut a tick in two)
            self.oscillators.tick(self._rows, first, sensordata, self._ids_frequencies)
        block = self._block
        if block is None or not block.first <= first < last <= block.last:
            block = self._block = self._ahead(ids, first)
        steps = slice(first - block.first, last - block.first)
        values = block.values[:, steps].copy()  # C order: its flat view takes the loops' results
        readings = (
            self.sensing.read(
                state,
                sensordata,
                ids=self._rows,
                frequencies=self._ids_frequencies,
                tick=first % self.tick == 0,
            )
            if self.sensing is not None
            else {}
        )
        # The phase columns' sample positions as this tick's landings left them, per slot length.
        positions: dict[int, tuple[NDArray[np.intp], NDArray[np.float64]]] = {}
        if block.phase_clock is not None:
            assert self.oscillators is not None
            phases = self.oscillators.phases(self._rows, block.phase_clock[:, steps], self._phase_limbs)
        failed: dict[int, int] = {}  # per gait (position in ids): the first curve not finite
        for placed, slots in zip(self._placed, block.slots, strict=True):
            group = placed.group
            held = {name: _held(readings[name], placed) for name in group.sensors}
            slot_values = []
            for slot, values_t in zip(placed.slots, slots, strict=True):
                if values_t is not None:
                    slot_values.append(values_t[:, steps])
                    continue
                n = slot.samples.shape[1] - 1
                if n not in positions:
                    positions[n] = _positions(phases, n)
                where = placed.share(last - first, len(self._phase_limbs))
                slot_values.append(slot.at_positions(*positions[n], where))
            result = run_program(group.program, placed.constants, slot_values, held)
            shape = (len(placed.members), last - first, placed.actuators.shape[1])
            if result.shape != shape:  # a skeleton of held sensors alone: one value per tick
                result = np.broadcast_to(result, shape)
            if self.scale != 1.0:
                result = result * self.scale
            finite = np.isfinite(result)
            if not finite.all():
                for member in np.flatnonzero(~finite.all(axis=(1, 2))):
                    row, curve = int(placed.rows[member, 0]), int(group.curves[placed.members[member]])
                    failed[row] = min(curve, failed.get(row, curve))
                result = np.where(finite, result, 0.0)
            values.reshape(-1)[placed.targets(last - first, self.actuation.nu)] = np.radians(result)
        failures: Failures = {row: self.actuation.curves[curve] for row, curve in failed.items()}
        return self.actuation.finish(values, first, last, block.ramp[steps]), failures


def _gather(values: NDArray[np.float64], placed: _Placed) -> NDArray[np.float64]:
    """Each member's actuators' share of values [ids, steps, nu]: [members, steps, width]."""
    return values[placed.rows, :, placed.actuators].transpose(0, 2, 1)


def _held(value: NDArray[np.float64], placed: _Placed) -> NDArray[np.float64]:
    """A held sensor's reading [ids] (a body's) or [ids, limbs] (per limb) for each member's
    actuators, broadcastable against [members, steps, width]."""
    if value.ndim == 2:
        return value[placed.rows, placed.limbs][:, None, :]
    return value[placed.rows][:, None, :]
