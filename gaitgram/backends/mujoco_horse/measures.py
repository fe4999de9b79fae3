"""What a gait did, measured from a recording: cycles, footfalls, strides, phases, steadiness.

Physics-free (dm_control's split of physics and task): the rollout records a few
arrays per step (:class:`Recording`), and everything the fitness and the walk
criterion need is a plain function of them, testable on synthetic recordings
with known answers. Sources and definitions: ``docs/fitness.md``.

Time is counted in simulation steps. Entry ``k`` of a recorded array is the
value after ``k`` steps (entry 0: the standing start). Cycle ``c`` of a gait
played at frequency ``f`` spans steps ``edges[c]..edges[c+1]``, with
``edges[c] = ramp + round(c / (f dt))``: cycles are the gait's own, counted from
the end of the ramp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: The four hooves, in the walk's lateral footfall sequence (the order of every per-hoof axis).
HOOVES: tuple[str, ...] = ("hind_left", "fore_left", "hind_right", "fore_right")
#: The hoof whose touchdown starts a stride for the footfall phases (the walk's first footfall).
LEAD = 0


@dataclass(frozen=True, eq=False)
class Recording:
    """What a rollout records of one gait: per step, the trunk, the hooves and the actuator power.

    Arrays have ``steps + 1`` entries (entry 0 is the start). ``contact`` and ``hoof_x`` have a
    column per hoof in :data:`HOOVES` order. ``power`` entry ``k`` is the actuators' total
    absolute power during step ``k`` (W; entry 0 is unused).
    """

    timestep: float  # s
    frequency: float  # Hz: the cycle frequency the gait was played at
    ramp_steps: int  # steps of the blend-in from the standing pose; cycle 0 starts here
    trunk_x: FloatArray  # m, forward
    trunk_z: FloatArray  # m, up
    pitch: FloatArray  # degrees, nose up positive
    roll: FloatArray  # degrees
    contact: NDArray[np.bool_]  # [steps + 1, 4]: the hoof pushes on the ground
    hoof_x: FloatArray  # [steps + 1, 4], m
    power: FloatArray  # W

    @property
    def steps(self) -> int:
        return len(self.trunk_x) - 1

    def cycle_edges(self, cycles: int) -> NDArray[np.intp]:
        """The steps at which cycles ``0..cycles`` begin (``cycles + 1`` edges)."""
        return cycle_edges(self.frequency, self.timestep, self.ramp_steps, cycles)

    def cycles_recorded(self) -> int:
        """Whole cycles the recording covers after the ramp."""
        period = 1.0 / (self.frequency * self.timestep)
        count = max(0, math.floor((self.steps - self.ramp_steps) / period) + 1)
        while count and self.ramp_steps + round(count * period) > self.steps:
            count -= 1
        return count


def cycle_edges(frequency: float, timestep: float, ramp_steps: int, cycles: int) -> NDArray[np.intp]:
    period = 1.0 / (frequency * timestep)
    return np.array([ramp_steps + round(c * period) for c in range(cycles + 1)], dtype=np.intp)


def steps_for(frequency: float, timestep: float, ramp_steps: int, cycles: int) -> int:
    """Steps to simulate for ``cycles`` whole cycles after the ramp."""
    return int(cycle_edges(frequency, timestep, ramp_steps, cycles)[-1])


# ---- footfalls and strides ---------------------------------------------------------------


def touchdowns(contact: NDArray[np.bool_], gap_steps: int) -> list[NDArray[np.intp]]:
    """Per hoof, the steps at which a footfall begins: a contact after at least ``gap_steps``
    steps off the ground. The horse starts standing, so contact before step 0 is assumed and a
    hoof that never lifts has no footfall."""
    found = []
    for hoof in range(contact.shape[1]):
        down = np.flatnonzero(contact[:, hoof])
        previous = np.concatenate(([-1], down[:-1]))  # the last contact before each contact step
        found.append(down[(down - previous) > gap_steps].astype(np.intp))
    return found


@dataclass(frozen=True)
class Stride:
    """One hoof's stride: from one footfall to the next."""

    hoof: int
    start: int  # step of the first footfall
    end: int  # step of the next
    length: float  # forward distance the hoof moved between them, m


def strides(recording: Recording, falls: list[NDArray[np.intp]]) -> list[Stride]:
    """Every stride of every hoof: successive footfalls."""
    found = []
    for hoof, steps in enumerate(falls):
        x = recording.hoof_x[steps, hoof]
        for i in range(len(steps) - 1):
            found.append(Stride(hoof, int(steps[i]), int(steps[i + 1]), float(x[i + 1] - x[i])))
    return found


def footfall_phases(falls: list[NDArray[np.intp]], start: int, end: int) -> FloatArray:
    """For the lead hoof's stride from step ``start`` to ``end``: when each hoof first lands in it,
    as a share of the stride (the lead hoof at 0); NaN for a hoof that does not land in it."""
    phases = np.full(len(falls), math.nan)
    for hoof, steps in enumerate(falls):
        inside = steps[(steps >= start) & (steps < end)]
        if len(inside):
            phases[hoof] = (inside[0] - start) / (end - start)
    return phases


# ---- per cycle -----------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class CycleMeasures:
    """Each cycle measured on its own: arrays with one entry per cycle (first axis).

    A stride belongs to the cycle its closing footfall lands in; a cycle in which a hoof
    closes no stride has NaN for that hoof's stride length and frequency.
    """

    first: int  # index of the first cycle measured (cycles before it are warm-up)
    speed: FloatArray  # m/s: trunk displacement over the cycle's duration
    duty_factor: FloatArray  # [cycles, 4]: share of the cycle's steps each hoof is down
    stride_length: FloatArray  # [cycles, 4], m: mean over the hoof's strides closing in the cycle
    stride_frequency: FloatArray  # [cycles, 4], Hz: 1 / mean duration of those strides
    work: FloatArray  # J: actuator work over the cycle
    power: FloatArray  # W: mean actuator power over the cycle
    pitch: FloatArray  # [cycles, 2]: lowest and highest trunk pitch, degrees
    roll: FloatArray  # [cycles, 2]: lowest and highest trunk roll, degrees
    #: Per lead-hoof stride closing in the cycle: the cycle index and each hoof's phase.
    stride_cycles: NDArray[np.intp]
    phases: FloatArray  # [strides, 4]
    #: Every stride (of any hoof) closing in the cycles: cycle, length (m), frequency (Hz).
    all_strides: FloatArray  # [n, 3]

    def __len__(self) -> int:
        return len(self.speed)


def measure_cycles(recording: Recording, first: int, last: int, gap_steps: int) -> CycleMeasures:
    """Measure cycles ``first..last-1`` of ``recording`` (which must cover them)."""
    edges = recording.cycle_edges(last)
    if edges[-1] > recording.steps:
        raise ValueError(f"the recording covers {recording.cycles_recorded()} cycles, not {last}")
    dt = recording.timestep
    falls = touchdowns(recording.contact, gap_steps)
    count = last - first
    speed = np.empty(count)
    duty = np.empty((count, len(HOOVES)))
    length = np.full((count, len(HOOVES)), math.nan)
    frequency = np.full((count, len(HOOVES)), math.nan)
    work = np.empty(count)
    power = np.empty(count)
    pitch = np.empty((count, 2))
    roll = np.empty((count, 2))
    by_cycle: list[list[Stride]] = [[] for _ in range(count)]
    for stride in strides(recording, falls):
        c = int(np.searchsorted(edges, stride.end, side="right")) - 1 - first
        if 0 <= c < count:
            by_cycle[c].append(stride)
    lead_cycles, lead_phases, every = [], [], []
    for c in range(count):
        a, b = int(edges[first + c]), int(edges[first + c + 1])
        seconds = (b - a) * dt
        speed[c] = (recording.trunk_x[b] - recording.trunk_x[a]) / seconds
        duty[c] = recording.contact[a + 1 : b + 1].mean(axis=0)
        work[c] = float(recording.power[a + 1 : b + 1].sum()) * dt
        power[c] = work[c] / seconds
        pitch[c] = recording.pitch[a : b + 1].min(), recording.pitch[a : b + 1].max()
        roll[c] = recording.roll[a : b + 1].min(), recording.roll[a : b + 1].max()
        for hoof in range(len(HOOVES)):
            mine = [s for s in by_cycle[c] if s.hoof == hoof]
            if mine:
                length[c, hoof] = float(np.mean([s.length for s in mine]))
                frequency[c, hoof] = 1.0 / (float(np.mean([s.end - s.start for s in mine])) * dt)
        for s in by_cycle[c]:
            every.append((c, s.length, 1.0 / ((s.end - s.start) * dt)))
            if s.hoof == LEAD:
                lead_cycles.append(c)
                lead_phases.append(footfall_phases(falls, s.start, s.end))
    return CycleMeasures(
        first=first,
        speed=speed,
        duty_factor=duty,
        stride_length=length,
        stride_frequency=frequency,
        work=work,
        power=power,
        pitch=pitch,
        roll=roll,
        stride_cycles=np.array(lead_cycles, dtype=np.intp),
        phases=np.array(lead_phases).reshape(-1, len(HOOVES)),
        all_strides=np.array(every, dtype=float).reshape(-1, 3),
    )


# ---- over a window of cycles ---------------------------------------------------------------


@dataclass(frozen=True)
class WindowMeasures:
    """Means over a window of cycles: what the fitness scores."""

    velocity: float  # m/s
    duty_factor: float  # mean over hooves
    stride_length: float  # m, mean over hooves (a hoof that took no stride counts 0)
    stride_frequency: float  # Hz, mean over hooves (0 for a hoof that took no stride)
    power: float  # W, mean actuator power
    #: (max - min) of the per-cycle speeds over the window, m/s: how far from steady
    speed_spread: float


def window(measures: CycleMeasures) -> WindowMeasures:
    """The window's means. Strides: per hoof, the mean over every stride closing in the window,
    then the mean over hooves; a hoof with none took no measurable stride and counts as 0 (a gait
    that drags its hooves has stride 0, not a missing value)."""
    lengths, frequencies = [], []
    for hoof in range(len(HOOVES)):
        taken = ~np.isnan(measures.stride_length[:, hoof])
        if taken.any():
            lengths.append(float(np.mean(measures.stride_length[taken, hoof])))
            frequencies.append(float(np.mean(measures.stride_frequency[taken, hoof])))
        else:
            lengths.append(0.0)
            frequencies.append(0.0)
    return WindowMeasures(
        velocity=float(np.mean(measures.speed)),
        duty_factor=float(np.mean(measures.duty_factor)),
        stride_length=float(np.mean(lengths)),
        stride_frequency=float(np.mean(frequencies)),
        power=float(np.mean(measures.power)),
        speed_spread=float(np.ptp(measures.speed)) if len(measures.speed) else 0.0,
    )
