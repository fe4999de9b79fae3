"""The ``mujoco-horse`` evaluator: a generation's gaits as batches of MuJoCo rollouts, in chunks.

A generation is simulated in groups of at most ``group_size`` gaits, each group
in chunks of ``chunk_steps`` steps (0.25 s simulated). After each chunk the
recorded states and sensors are checked for the unviable criteria (fell,
flipped, unstable) and the measures are accumulated; only the gaits still
viable are simulated further, from where they stopped. Memory is bounded by a
group's chunk, whatever the population or the simulated time.

Chunking changes no bit of any result. The gaits run on ``mujoco.batch.Batch``,
which keeps each simulation's ``mjSTATE_INTEGRATION`` row between calls: the
full physics state *and* ``qacc_warmstart``, the solver's warm start.
(``mujoco.rollout`` records and accepts only ``mjSTATE_FULLPHYSICS``, without
the warm start: restarting it from a recorded state changes the trajectory.)
The verdict is the first failure in time, checked per step, so it does not
depend on when a gait is dropped; the measures are per-step quantities summed
in a fixed order. ``tests/backends/test_chunked_rollout.py`` checks that chunked
and one-chunk evaluations, and the raw full-length ``mujoco.rollout``, agree to
the bit with one and two threads. A gait that cannot be scored gets a status
and the worst fitness; so does one with any non-finite measure.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from typing import Any

import mujoco
import numpy as np
from mujoco import batch as mjbatch
from mujoco import rollout

from gaitgram.backends.api import WORST_FITNESS, Evaluation, GaitStatus, unusable_evaluations
from gaitgram.backends.mujoco_horse.model import STATE_SPEC, HorseLayout, horse_layout, load_model
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.backends.mujoco_horse.task import (
    DEFAULT_WEIGHTS,
    GaitMetrics,
    GaitTargets,
    fitness_components,
    is_walk,
    walk_targets,
    weighted_fitness,
)
from gaitgram.motion.gait import MotionBatch

#: Trunk lower than this share of its standing height: the horse fell.
FALL_HEIGHT = 0.55
#: Trunk up-axis this far from vertical (cosine): the horse flipped (about 60 degrees).
FLIP_COSINE = 0.5
#: Joint speeds past this (rad/s) mean the integration diverged.
UNSTABLE_SPEED = 200.0
#: A hoof is on the ground when its touch sensor reads more than this (N).
CONTACT_FORCE = 5.0
#: A hoof's contact starts a new footfall only after this long off the ground (s): contact
#: chatter within a stance is not a stride.
TOUCHDOWN_GAP_SECONDS = 0.2
#: Simulated time between checks for unviable gaits (rounded to whole steps).
CHUNK_SECONDS = 0.25
#: Gaits simulated together: bounds the memory of a chunk (controls, records) whatever the population.
GROUP_SIZE = 256

_RECORD = int(STATE_SPEC)  # mujoco.rollout's state spec: the recorded states are the same arrays
_HOOVES = ("fore_left", "fore_right", "hind_left", "hind_right")

#: Called after each chunk with the batch rows simulated, the chunk's first step and its records
#: (views into reused buffers: copy what you keep).
ChunkObserver = Callable[[np.ndarray, int, np.ndarray, np.ndarray], None]


class _Tally:
    """What the gaits of a group have shown so far: each one's first failure, and the running
    measures of the others. Measures are kept per step (power) or as exact integer counts
    (contacts), so that the chunk length cannot change a bit of them."""

    def __init__(self, size: int, scored_steps: int) -> None:
        self.failures: dict[int, Evaluation] = {}
        self.start_x = np.full(size, np.nan)
        self.end_x = np.full(size, np.nan)
        self.contacts = np.zeros(size, dtype=np.int64)
        # Footfalls per gait and hoof: the last step in contact (the horse starts standing), and
        # the scored touchdowns' count, first and last step and hoof x.
        self.last_contact = np.full((size, len(_HOOVES)), -1, dtype=np.int64)
        self.touchdowns = np.zeros((size, len(_HOOVES)), dtype=np.int64)
        self.first_step = np.zeros((size, len(_HOOVES)), dtype=np.int64)
        self.last_step = np.zeros((size, len(_HOOVES)), dtype=np.int64)
        self.first_x = np.zeros((size, len(_HOOVES)))
        self.last_x = np.zeros((size, len(_HOOVES)))
        self.power = np.zeros((size, scored_steps))  # per scored step: sum over actuators of |force x speed|


class HorseEvaluator:
    def __init__(
        self,
        settings: HorseSettings | None = None,
        *,
        chunk_steps: int | None = None,
        group_size: int = GROUP_SIZE,
    ) -> None:
        self.settings = settings or HorseSettings()
        self.model = load_model()
        self.layout: HorseLayout = horse_layout()
        self.targets: GaitTargets = walk_targets(self.settings.froude, self.layout.hip_height)
        self.threads = self.settings.threads or os.cpu_count() or 1
        self.dt = self.model.opt.timestep
        self.period = 1.0 / self.targets.stride_frequency
        self.ramp_steps = round(self.settings.ramp_seconds / self.dt)
        self.scored_steps = round(self.settings.cycles * self.period / self.dt)
        self.nstep = self.ramp_steps + self.scored_steps
        if (chunk_steps is not None and chunk_steps < 1) or group_size < 1:
            raise ValueError(
                f"chunk_steps and group_size must be at least 1, not {chunk_steps}, {group_size}"
            )
        self.chunk_steps = chunk_steps or max(1, round(CHUNK_SECONDS / self.dt))
        self.group_size = group_size
        self.initial_state = self.layout.initial_state(self.model)
        # Built on first use, from ``self.model`` as it is then.
        self._pool: rollout.Rollout | None = None  # raw full-length rollouts (simulate)
        self._datas: list[mujoco.MjData] = []
        self._sim: mjbatch.Batch | None = None  # chunked rollouts (evaluate)
        self._start_row: np.ndarray | None = None
        self._offsets = np.array(
            [self.targets.phase_offsets.get(limb, 0.0) if limb else 0.0 for limb in self.layout.actuator_limb]
        )
        self._phase, self._ramp = self._step_phases()
        self._curve_of_actuator = np.asarray(self.layout.actuator_curve_index)
        self._lookups: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self._buffers: tuple[np.ndarray, np.ndarray] | None = None
        self._scratch: tuple[np.ndarray, np.ndarray] | None = None
        self._neutral = np.asarray(self.layout.neutral_ctrl)[None, None, :]
        self._ctrl_low = np.asarray(self.layout.ctrl_low)[None, None, :]
        self._ctrl_high = np.asarray(self.layout.ctrl_high)[None, None, :]
        sensors = self.layout.sensors
        self._trunk_pos = sensors["trunk_pos"]
        self._trunk_quat = sensors["trunk_quat"]
        self._hoof_touch = np.array([sensors[f"hoof_{limb}"].start for limb in _HOOVES])
        self._hoof_x = np.array([sensors[f"hoof_pos_{limb}"].start for limb in _HOOVES])
        self._gap_steps = max(1, round(TOUCHDOWN_GAP_SECONDS / self.dt))
        nq, nv = self.model.nq, self.model.nv
        self._hinge_vel = slice(1 + nq + self.layout.root_dofs, 1 + nq + nv)  # joint speeds in a state vector
        self._act_q = 1 + np.asarray(self.layout.actuator_qpos)
        self._act_v = 1 + nq + np.asarray(self.layout.actuator_dof)

    # ---- controls ---------------------------------------------------------------------

    def _step_phases(self) -> tuple[np.ndarray, np.ndarray]:
        """Per actuator and step, the cycle phase its limb is at; and the ramp-in factor per step."""
        time = np.arange(self.nstep) * self.dt
        offsets = self._offsets
        phase = np.mod(time[None, :] * self.targets.stride_frequency - offsets[:, None], 1.0)  # [nu, nstep]
        ramp = (
            np.clip(time / self.settings.ramp_seconds, 0.0, 1.0)
            if self.settings.ramp_seconds
            else np.ones_like(time)
        )
        return phase, ramp

    def controls(self, batch: MotionBatch, rows: np.ndarray) -> np.ndarray:
        """Control arrays [gaits, steps, actuators]: neutral pose plus each limb's curve at its phase.

        All ``nstep`` steps at once (for rendering one gait); evaluation builds the same values a
        chunk at a time."""
        return self._control_steps(
            self._curve_table(batch, rows), batch.n_samples, 0, self.nstep, self._frequencies(batch, rows)
        )

    def _frequencies(self, batch: MotionBatch, rows: np.ndarray) -> np.ndarray | None:
        """Each gait's cycle frequency (Hz) where the grammar evolves it; None: the target's for all."""
        if batch.frequencies is None:
            return None
        chosen = np.asarray(batch.frequencies, dtype=float)[rows]
        return np.where(np.isfinite(chosen), chosen, self.targets.stride_frequency)

    def _curve_table(self, batch: MotionBatch, rows: np.ndarray) -> np.ndarray:
        """Per gait, every actuator's curve samples in radians, flat: [gaits, actuators * samples]."""
        curves_by_name = {name: i for i, name in enumerate(batch.joints)}
        order = np.array([curves_by_name.get(name, -1) for name in self.layout.curves])
        angles = np.concatenate([batch.angles[rows], np.zeros((len(rows), 1, batch.n_samples))], axis=1)
        per_curve = angles[:, order, :]  # [G, curves, S]; undriven curves read the zero row
        return np.radians(per_curve[:, self._curve_of_actuator, :]).reshape(len(rows), -1)  # [G, nu*S]

    def _control_steps(
        self, table: np.ndarray, samples: int, first: int, last: int, frequencies: np.ndarray | None = None
    ) -> np.ndarray:
        """Controls [gaits, last - first, actuators] for steps ``first..last-1`` from a curve table,
        at the target's cycle frequency, or at each gait's own ``frequencies`` (Hz).

        Element by element the same operations whatever the step range, so a chunk's controls are
        bit-identical to the same steps of the full array."""
        steps = slice(first, last)
        if frequencies is None:
            low, high, frac = self._lookup(samples)
            # One flat gather per interpolation end, straight into [gaits, steps, actuators] order.
            v_low = np.take(table, low[steps], axis=1)
            control = np.take(table, high[steps], axis=1)
            fraction = frac[steps]
        else:
            low, high, fraction = self._own_lookup(samples, first, last, frequencies)
            gait = np.arange(len(table))[:, None, None]
            v_low = table[gait, low]
            control = table[gait, high]
        control -= v_low
        control *= fraction
        control += v_low
        control *= self._ramp[None, steps, None]
        control += self._neutral
        np.clip(control, self._ctrl_low, self._ctrl_high, out=control)
        return control

    def _lookup(self, samples: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Flat sample indices [steps, actuators] around each step's phase, and the weight between them."""
        cached = self._lookups.get(samples)
        if cached is None:
            position = self._phase.T * samples  # [nstep, nu], in samples
            low = np.floor(position).astype(np.intp) % samples
            base = np.arange(self.model.nu)[None, :] * samples
            cached = (base + low, base + (low + 1) % samples, position - np.floor(position))
            self._lookups[samples] = cached
        return cached

    def _own_lookup(
        self, samples: int, first: int, last: int, frequencies: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """As :meth:`_lookup`, per gait at its own frequency: [gaits, steps, actuators] each."""
        time = np.arange(first, last) * self.dt
        phase = np.mod(time[None, :, None] * frequencies[:, None, None] - self._offsets[None, None, :], 1.0)
        position = phase * samples
        floor = np.floor(position)
        low = floor.astype(np.intp) % samples
        base = np.arange(self.model.nu)[None, None, :] * samples
        return base + low, base + (low + 1) % samples, position - floor

    # ---- simulation -------------------------------------------------------------------

    def simulate(self, control: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The raw full-length ``mujoco.rollout`` of control arrays [gaits, nstep, actuators]: states
        (``STATE_SPEC``) and sensors [gaits, nstep, ...], no gait dropped. ``evaluate`` does not use
        it; it is the reference that chunked evaluation is bit-identical to, and the benchmark's
        ceiling. The output buffers are reused between calls."""
        if self._pool is None:
            self._pool = rollout.Rollout(nthread=self.threads)
            self._datas = [mujoco.MjData(self.model) for _ in range(self.threads)]
        size = control.shape[0]
        if self._buffers is None or self._buffers[0].shape[0] != size:
            nstate = mujoco.mj_stateSize(self.model, STATE_SPEC)
            self._buffers = (
                np.empty((size, self.nstep, nstate)),
                np.empty((size, self.nstep, self.model.nsensordata)),
            )
        state, sensors = self._buffers
        self._pool.rollout(
            self.model, self._datas, self.initial_state[None, :], control, state=state, sensordata=sensors
        )
        return state, sensors

    def _simulator(self) -> mjbatch.Batch:
        """The batch of ``group_size`` simulations that chunked evaluation runs on."""
        if self._sim is None:
            self._sim = mjbatch.Batch(self.model, self.group_size, self.threads)
            # What mujoco.rollout starts from: the initial state, a zero warm start, no applied forces.
            data = mujoco.MjData(self.model)
            mujoco.mj_setState(self.model, data, self.initial_state, STATE_SPEC)
            row = np.empty(self._sim.nstate)
            mujoco.mj_getState(self.model, data, row, mujoco.mjtState.mjSTATE_INTEGRATION)
            self._start_row = row
        return self._sim

    def _chunk_buffers(self, gaits: int, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """Record arrays [gaits, steps, ...] for one chunk, views into buffers reused between chunks."""
        nstate = mujoco.mj_stateSize(self.model, STATE_SPEC)
        nsensor = self.model.nsensordata
        need = gaits * steps  # at most group_size x chunk_steps
        if self._scratch is None or self._scratch[0].size < need * nstate:
            self._scratch = (np.empty(need * nstate), np.empty(need * nsensor))
        states, sensors = self._scratch
        return (
            states[: gaits * steps * nstate].reshape(gaits, steps, nstate),
            sensors[: gaits * steps * nsensor].reshape(gaits, steps, nsensor),
        )

    # ---- evaluation ---------------------------------------------------------------------

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        results: dict[int, Evaluation] = unusable_evaluations(batch)
        rows = np.array([g for g in range(len(batch)) if g not in results], dtype=np.intp)
        if len(rows):
            active = weights or self.settings.weights or DEFAULT_WEIGHTS
            for row, evaluation in zip(rows, self.evaluate_rows(batch, rows, active), strict=True):
                results[int(row)] = evaluation
        return [results[g] for g in range(len(batch))]

    def evaluate_rows(
        self,
        batch: MotionBatch,
        rows: np.ndarray,
        weights: Mapping[str, float],
        *,
        on_chunk: ChunkObserver | None = None,
    ) -> list[Evaluation]:
        """Simulate and score the gaits ``rows`` of ``batch`` (all usable), a group at a time."""
        evaluations: list[Evaluation] = []
        for start in range(0, len(rows), self.group_size):
            group = np.asarray(rows[start : start + self.group_size], dtype=np.intp)
            evaluations += self._evaluate_group(batch, group, weights, on_chunk)
        return evaluations

    def _evaluate_group(
        self,
        batch: MotionBatch,
        rows: np.ndarray,
        weights: Mapping[str, float],
        on_chunk: ChunkObserver | None,
    ) -> list[Evaluation]:
        size = len(rows)
        sim = self._simulator()
        table = self._curve_table(batch, rows)
        frequencies = self._frequencies(batch, rows)
        tally = _Tally(size, self.scored_steps)
        sim.state[:size] = self._start_row
        sim.warning[:size] = 0
        alive = np.arange(size, dtype=np.int32)  # simulation ids, also indices into rows and tally
        for first in range(0, self.nstep, self.chunk_steps):
            if not len(alive):
                break
            last = min(first + self.chunk_steps, self.nstep)
            everyone = len(alive) == size
            control = self._control_steps(
                table if everyone else table[alive],
                batch.n_samples,
                first,
                last,
                frequencies if frequencies is None or everyone else frequencies[alive],
            )
            state, sensors = self._chunk_buffers(len(alive), last - first)
            errors = None
            try:
                sim.rollout(
                    last - first,
                    control,
                    record=(_RECORD, "sensordata"),
                    ids=alive,
                    out={_RECORD: state, "sensordata": sensors},
                )
            except mjbatch.SimulationError:  # MuJoCo raised in some simulations; the others ran
                errors = {i: sim.error(int(alive[i])) for i in np.flatnonzero(sim.status[alive] != 0)}
            if on_chunk is not None:
                on_chunk(rows[alive], first, state, sensors)
            failed = self._observe(tally, alive, first, state, sensors, control, sim.warning[alive], errors)
            alive = alive[~failed]
        return self._verdicts(tally, weights)

    def score(
        self, state: np.ndarray, sensors: np.ndarray, control: np.ndarray, weights: Mapping[str, float]
    ) -> list[Evaluation]:
        """Score full-length records [gaits, nstep, ...] (``simulate``'s) as evaluation would.

        Without ``Batch``'s warning counters, a rollout that MuJoCo stopped is told by its repeated
        records (time stops advancing), so a warning in the very last step goes unnoticed here."""
        if state.shape[1] != self.nstep:
            raise ValueError(f"records of {state.shape[1]} steps; a simulation has {self.nstep}")
        tally = _Tally(state.shape[0], self.scored_steps)
        self._observe(tally, np.arange(state.shape[0]), 0, state, sensors, control, None, None)
        return self._verdicts(tally, weights)

    def _observe(
        self,
        tally: _Tally,
        gaits: np.ndarray,
        first: int,
        state: np.ndarray,
        sensors: np.ndarray,
        control: np.ndarray,
        warnings: np.ndarray | None,
        errors: Mapping[int, str] | None,
    ) -> np.ndarray:
        """Take in one chunk of records of ``gaits`` (indices into the tally) starting at step
        ``first``; returns which of them failed in it."""
        failed = self._failures(tally, gaits, first, state, sensors, warnings)
        for i, message in (errors or {}).items():  # records of a simulation that raised mean nothing
            tally.failures[int(gaits[i])] = Evaluation.unviable(
                GaitStatus.UNSTABLE, f"MuJoCo error: {message}"
            )
            failed[i] = True
        self._measure(tally, gaits, first, state, sensors, control)
        return failed

    def _failures(
        self,
        tally: _Tally,
        gaits: np.ndarray,
        first: int,
        state: np.ndarray,
        sensors: np.ndarray,
        warnings: np.ndarray | None,
    ) -> np.ndarray:
        """Record each gait's first failure in the chunk, if any; the earliest step wins, and at
        one step unstable before flipped before fell."""
        steps = state.shape[1]
        trunk_z = sensors[:, :, self._trunk_pos.start + 2]
        quat = sensors[:, :, self._trunk_quat]
        gaits_steps = state.shape[:2]
        with np.errstate(all="ignore"):
            # Per step, but only for the gaits (or chunks) where a whole-chunk check finds something.
            if np.isfinite(state).all() and np.isfinite(sensors).all():
                broken = np.zeros(gaits_steps, dtype=bool)
            else:
                broken = ~(np.isfinite(state).all(axis=2) & np.isfinite(sensors).all(axis=2))
            speed = np.zeros(gaits_steps)
            peak = np.abs(state[:, :, self._hinge_vel]).max(axis=(1, 2))  # NaN propagates
            fast = np.flatnonzero(~(peak <= UNSTABLE_SPEED))
            speed[fast] = np.abs(state[fast][:, :, self._hinge_vel]).max(axis=2)
            up_z = 1 - 2 * (quat[:, :, 1] ** 2 + quat[:, :, 2] ** 2)  # z component of the trunk's up axis
            tests = (
                broken,
                speed > UNSTABLE_SPEED,
                up_z < FLIP_COSINE,
                trunk_z < FALL_HEIGHT * self.layout.standing_height,
            )
        # A MuJoCo warning stops a rollout: its later records repeat the last one. Batch's counters
        # tell it even when the warning came in the chunk's last step, where no repeat shows.
        time = state[:, :, 0]
        frozen = time[:, 1:] == time[:, :-1]
        stopped = warnings[:, :, 1].any(axis=1) if warnings is not None else frozen.any(axis=1)
        repeats = frozen.any(axis=1)
        stop_step = np.full(len(stopped), steps - 1)
        if repeats.any():
            stop_step[repeats] = frozen[repeats].argmax(axis=1)
        never = steps
        firsts = [np.where(test.any(axis=1), test.argmax(axis=1), never) for test in tests]
        firsts.insert(2, np.where(stopped, stop_step, never))
        candidates = np.stack(firsts)  # [criteria, gaits] in precedence order
        step = candidates.min(axis=0)
        failed = step < never
        for i in np.flatnonzero(failed):
            k = int(step[i])
            seconds = (first + k + 1) * self.dt  # simulated time at the end of the failing step
            criterion = int(np.argmax(candidates[:, i] == k))
            if criterion == 0:
                evaluation = Evaluation.unviable(
                    GaitStatus.UNSTABLE, f"the simulation diverged at {seconds:.3f} s (non-finite state)"
                )
            elif criterion == 1:
                evaluation = Evaluation.unviable(
                    GaitStatus.UNSTABLE,
                    f"the simulation diverged at {seconds:.3f} s (a joint at {speed[i, k]:.0f} rad/s)",
                )
            elif criterion == 2:
                raised = np.flatnonzero(warnings[i, :, 1]) if warnings is not None else []
                what = mujoco.mjtWarning(int(raised[0])).name if len(raised) else "a MuJoCo warning"
                evaluation = Evaluation.unviable(
                    GaitStatus.UNSTABLE, f"the simulation diverged at {seconds:.3f} s ({what})"
                )
            elif criterion == 3:
                degrees = math.degrees(math.acos(float(np.clip(up_z[i, k], -1, 1))))
                evaluation = Evaluation.unviable(
                    GaitStatus.FLIPPED, f"trunk tilted {degrees:.0f} degrees at {seconds:.3f} s"
                )
            else:
                evaluation = Evaluation.unviable(
                    GaitStatus.FELL, f"trunk down to {trunk_z[i, k]:.2f} m at {seconds:.3f} s"
                )
            tally.failures[int(gaits[i])] = evaluation
        return failed

    def _measure(
        self,
        tally: _Tally,
        gaits: np.ndarray,
        first: int,
        state: np.ndarray,
        sensors: np.ndarray,
        control: np.ndarray,
    ) -> None:
        """Accumulate one chunk's share of the measures: trunk x at the ramp's end and at the last
        step, hoof contacts and actuator power over the scored steps."""
        last = first + state.shape[1]
        ramp = self.ramp_steps
        trunk_x = sensors[:, :, self._trunk_pos.start]
        self._footfalls(tally, gaits, first, sensors)  # every chunk: contacts in the ramp carry over
        if first <= ramp < last:
            tally.start_x[gaits] = trunk_x[:, ramp - first]
        if last == self.nstep:
            tally.end_x[gaits] = trunk_x[:, -1]
        begin = max(first, ramp)
        if begin >= last:
            return
        scored = slice(begin - first, last - first)
        touches = sensors[:, scored][:, :, self._hoof_touch]
        tally.contacts[gaits] += np.count_nonzero(touches > CONTACT_FORCE, axis=(1, 2))

        # Actuator power: |force x joint speed| per step, from the position servos' law.
        model = self.model
        act_q = state[:, scored][:, :, self._act_q]
        act_v = state[:, scored][:, :, self._act_v]
        kp = -model.actuator_biasprm[:, 1]
        kv = -model.actuator_biasprm[:, 2]
        with np.errstate(all="ignore"):  # in place: these arrays are gaits x steps x actuators
            force = control[:, scored] * model.actuator_gainprm[:, 0]
            act_q *= kp
            force -= act_q
            force -= kv * act_v
            np.clip(force, model.actuator_forcerange[:, 0], model.actuator_forcerange[:, 1], out=force)
            force *= act_v
            np.abs(force, out=force)
            tally.power[gaits, begin - ramp : last - ramp] = force.sum(axis=2)

    def _footfalls(self, tally: _Tally, gaits: np.ndarray, first: int, sensors: np.ndarray) -> None:
        """Count touchdowns in the scored steps of a chunk: a hoof's contact that starts after at
        least ``_gap_steps`` off the ground. Integer steps and recorded positions only, carried
        between chunks, so that the chunk length cannot change them."""
        steps = sensors.shape[1]
        step = np.arange(first, first + steps)[None, :, None]
        contact = sensors[:, :, self._hoof_touch] > CONTACT_FORCE  # [gaits, steps, hooves]
        carried = tally.last_contact[gaits][:, None, :]
        latest = np.maximum(np.maximum.accumulate(np.where(contact, step, -1), axis=1), carried)
        before = np.concatenate([carried, latest[:, :-1]], axis=1)  # last contact before each step
        touchdown = contact & (step - before > self._gap_steps) & (step >= self.ramp_steps)
        tally.last_contact[gaits] = latest[:, -1]
        count = touchdown.sum(axis=1)  # [gaits, hooves]
        if not count.any():
            return
        hoof_x = sensors[:, :, self._hoof_x]
        firsts = touchdown.argmax(axis=1)
        lasts = steps - 1 - touchdown[:, ::-1].argmax(axis=1)
        rows, hooves = np.nonzero(count)
        new = tally.touchdowns[gaits[rows], hooves] == 0
        at_first = firsts[rows, hooves]
        at_last = lasts[rows, hooves]
        g_new, h_new = gaits[rows[new]], hooves[new]
        tally.first_step[g_new, h_new] = first + at_first[new]
        tally.first_x[g_new, h_new] = hoof_x[rows[new], at_first[new], hooves[new]]
        tally.last_step[gaits[rows], hooves] = first + at_last
        tally.last_x[gaits[rows], hooves] = hoof_x[rows, at_last, hooves]
        tally.touchdowns[gaits] += count

    def _strides(self, tally: _Tally) -> tuple[np.ndarray, np.ndarray]:
        """Per gait, the mean over hooves of stride length (m) and stride frequency (Hz) between
        successive touchdowns; a hoof with fewer than two touchdowns took no measurable stride
        and counts as 0 for both."""
        strides = tally.touchdowns - 1
        stepped = strides > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            length = np.where(stepped, (tally.last_x - tally.first_x) / strides, 0.0)
            period = (tally.last_step - tally.first_step) * self.dt / strides
            frequency = np.where(stepped, 1.0 / period, 0.0)
        return length.mean(axis=1), frequency.mean(axis=1)

    def _verdicts(self, tally: _Tally, weights: Mapping[str, float]) -> list[Evaluation]:
        """Each gait's evaluation: its first failure, or its measures scored."""
        seconds = self.scored_steps * self.dt
        with np.errstate(all="ignore"):
            velocity = (tally.end_x - tally.start_x) / seconds
            duty = tally.contacts / (len(_HOOVES) * self.scored_steps)
            # Per-step sums, then over the steps in order: the same additions for any chunk length.
            work = tally.power.sum(axis=1) * self.dt / self.settings.cycles
        length, frequency = self._strides(tally)
        return [
            tally.failures.get(g)
            or self._judge(
                GaitMetrics(
                    float(velocity[g]), float(duty[g]), float(length[g]), float(frequency[g]), float(work[g])
                ),
                weights,
            )
            for g in range(len(velocity))
        ]

    def _judge(self, metrics: GaitMetrics, weights: Mapping[str, float]) -> Evaluation:
        """Score measured metrics; any non-finite measure, component or fitness is not a score."""
        components = fitness_components(metrics, self.targets, self.layout.total_mass)
        measured = {
            "measured_velocity": metrics.velocity,
            "measured_duty_factor": metrics.duty_factor,
            "measured_stride": metrics.stride_length,
            "measured_frequency": metrics.stride_frequency,
            "measured_work": metrics.work_per_cycle,
        }
        fitness = weighted_fitness(components, weights)
        values = {**measured, **components, "fitness": fitness}
        bad = [f"{name} = {value}" for name, value in values.items() if not math.isfinite(value)]
        if bad:
            return Evaluation.unviable(GaitStatus.NON_FINITE, f"non-finite {', '.join(bad)}")
        walk = float(is_walk(metrics, self.targets))  # reported, never weighted
        components = {**components, **measured, "walk": walk}
        return Evaluation(min(fitness, WORST_FITNESS), GaitStatus.OK, components)

    def close(self) -> None:
        if self._pool is not None:
            self._pool.close()
            self._pool = None
        self._sim = None


def load(settings: Mapping[str, Any] | None = None) -> HorseEvaluator:
    return HorseEvaluator(HorseSettings.from_mapping(settings or {}))
