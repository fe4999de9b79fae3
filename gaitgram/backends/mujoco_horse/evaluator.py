"""The ``mujoco-horse`` evaluator: a generation's gaits as batches of MuJoCo rollouts, in chunks.

The physics half of the dm_control split: this module steps MuJoCo and records,
per step, what the task measures (:class:`~gaitgram.backends.mujoco_horse.measures.Recording`);
the task (:mod:`~gaitgram.backends.mujoco_horse.task`) turns recordings into
measures, a fitness and walk verdicts.

A gait is played from the standing horse: the curves blend in over the ramp, then
the whole cycles of its own that last ``warmup_seconds`` settle it (unscored; at least
``MIN_WARMUP_CYCLES``, :func:`~gaitgram.backends.mujoco_horse.settings.warmup_cycles`), then
``cycles`` cycles are scored. :meth:`HorseEvaluator.evaluate` simulates that much;
:meth:`HorseEvaluator.verify` goes on to ``horizon_cycles`` and checks that the gait stays
upright (and, for a walk, a walk) for every one of them: the check that the gaits a run keeps
must pass. With
``bump_floors``, each gait that stands is also scored on those floors of bumps, each by an
evaluator of its own on that floor's model, and its fitness is the mean (:func:`on_floors`).

A generation is simulated in groups of at most ``group_size`` gaits, each group
in chunks of ``chunk_steps`` steps (0.25 s simulated). After each chunk the
recorded states and sensors are checked for the unviable criteria (fell,
flipped, unstable) and the records are kept; only the gaits still viable and not
yet at their own end are simulated further, from where they stopped. Memory is
bounded by a group's records, whatever the population.

The simulation itself is the generic MuJoCo layer's (:mod:`gaitgram.backends.mujoco`):
batched, chunked rollouts (:mod:`~gaitgram.backends.mujoco.rollout`), controls open loop or
closed (:mod:`~gaitgram.backends.mujoco.control`), sensors read as the horse declares them
(``sensors.toml``, :mod:`~gaitgram.backends.mujoco.sensing`). Chunking changes no bit of any
result; the verdict is the first failure in time, checked per step, so it does not depend on
when a gait is dropped. ``tests/backends/test_chunked_rollout.py`` checks that chunked and
one-chunk evaluations, and the raw full-length ``mujoco.rollout``, agree to the bit with one and
two threads. A gait that cannot be scored gets a status and the worst fitness; so does one with
any non-finite measure, and one whose closed loop computes a non-finite control.

A closed loop (a phenotype that reads sensors) is controlled at :data:`CONTROL_SECONDS`: its
sensed terms are computed from the last recorded step every tick and held for the tick's
steps, while its curves of the phase move at every step. A grammar without sensors is played
open loop exactly as before.
"""

from __future__ import annotations

import copy
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import mujoco
import numpy as np

from gaitgram.backends.api import WORST_FITNESS, Evaluation, GaitStatus, unusable_evaluations
from gaitgram.backends.mujoco.control import Actuation, ClosedLoop, OpenLoop, Oscillators
from gaitgram.backends.mujoco.rollout import BatchRollout, Forces
from gaitgram.backends.mujoco.sensing import Sensing, touchdown_reader
from gaitgram.backends.mujoco_horse.joints import CATALOGUE, SENSORS
from gaitgram.backends.mujoco_horse.measures import (
    HOOVES,
    CycleMeasures,
    Recording,
    cycle_edges,
    measure_cycles,
    window,
)
from gaitgram.backends.mujoco_horse.model import (
    BUMP_HEIGHT,
    LIMBS,
    STATE_SPEC,
    HorseLayout,
    bumpy_model,
    horse_layout,
    load_model,
)
from gaitgram.backends.mujoco_horse.settings import HorseSettings, warmup_cycles, weights_in_force
from gaitgram.backends.mujoco_horse.targets import WALK_TERMS, GaitTargets, walk_targets
from gaitgram.backends.mujoco_horse.task import (
    fitness_components,
    footfall_error,
    walk_terms,
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
#: A closed loop's control period (s): its sensed terms are read every 10 ms (100 Hz, every 5
#: physics steps of 2 ms) and held in between; a horse's fastest reflexes take 20-30 ms.
CONTROL_SECONDS = 0.01

#: Called after each chunk with the batch rows simulated, the chunk's first step and its records
#: (views into reused buffers: copy what you keep).
ChunkObserver = Callable[[np.ndarray, int, np.ndarray, np.ndarray], None]


@dataclass(frozen=True)
class _Standing:
    """What the records hold at step 0: the horse standing at rest."""

    trunk: tuple[float, float, float, float]  # x, z, pitch, roll
    contact: np.ndarray  # per hoof
    hoof_x: np.ndarray


class _Records:
    """Per gait of a group, what the rollout has recorded so far (entry 0: the standing start)
    and its first failure, if any."""

    def __init__(self, size: int, steps: int, start: _Standing) -> None:
        #: Per failed gait: its verdict and the step it failed in.
        self.failures: dict[int, tuple[Evaluation, int]] = {}
        self.trunk = np.empty((4, size, steps + 1))  # x, z, pitch, roll
        self.trunk[:, :, 0] = np.array(start.trunk)[:, None]
        self.contact = np.empty((size, steps + 1, len(HOOVES)), dtype=bool)
        self.contact[:, 0] = start.contact
        self.hoof_x = np.empty((size, steps + 1, len(HOOVES)))
        self.hoof_x[:, 0] = start.hoof_x
        self.power = np.zeros((size, steps + 1))

    def recording(self, gait: int, steps: int, frequency: float, evaluator: HorseEvaluator) -> Recording:
        end = steps + 1
        return Recording(
            timestep=evaluator.dt,
            frequency=frequency,
            ramp_steps=evaluator.ramp_steps,
            trunk_x=self.trunk[0, gait, :end],
            trunk_z=self.trunk[1, gait, :end],
            pitch=self.trunk[2, gait, :end],
            roll=self.trunk[3, gait, :end],
            contact=self.contact[gait, :end],
            hoof_x=self.hoof_x[gait, :end],
            power=self.power[gait, :end],
        )


class HorseEvaluator:
    def __init__(
        self,
        settings: HorseSettings | None = None,
        *,
        chunk_steps: int | None = None,
        group_size: int = GROUP_SIZE,
        model: mujoco.MjModel | None = None,
    ) -> None:
        self.settings = settings or HorseSettings()
        #: The horse's model, or a variant of its world (another floor: ``robustness.py``).
        self.model = load_model(self.settings.body) if model is None else model
        self.layout: HorseLayout = horse_layout(self.settings.body)
        self.targets: GaitTargets = walk_targets(self.settings.froude, self.layout.hip_height)
        #: What the grammar's own frequencies are multiplied by on this body (``frequencies_of``).
        self.frequency_scale = (
            1.0
            if self.settings.frequencies_of in (None, self.settings.body or "horse")
            else math.sqrt(horse_layout(self.settings.frequencies_of).hip_height / self.layout.hip_height)
        )
        self.threads = self.settings.threads or os.cpu_count() or 1
        self.dt = self.model.opt.timestep
        self.ramp_steps = round(self.settings.ramp_seconds / self.dt)
        self.scored = self.settings.cycles
        self.horizon = self.settings.horizon_cycles
        #: Steps of an evaluation at the target's frequency (gaits that evolve theirs differ).
        self.nstep = int(self._stage_steps(np.array([self.targets.stride_frequency]))[0])
        if (chunk_steps is not None and chunk_steps < 1) or group_size < 1:
            raise ValueError(
                f"chunk_steps and group_size must be at least 1, not {chunk_steps}, {group_size}"
            )
        self.chunk_steps = chunk_steps or max(1, round(CHUNK_SECONDS / self.dt))
        self.group_size = group_size
        #: Steps a closed loop holds its sensed terms (:data:`CONTROL_SECONDS`).
        self.tick = max(1, round(CONTROL_SECONDS / self.dt))
        self.initial_state = self.layout.initial_state(self.model)
        layout = self.layout
        self.actuation = Actuation(
            curves=layout.curves,
            curve_index=np.asarray(layout.actuator_curve_index),
            offsets=np.array(
                [self.targets.phase_offsets.get(limb, 0.0) if limb else 0.0 for limb in layout.actuator_limb]
            ),
            limb_index=np.array([LIMBS.index(limb) if limb else -1 for limb in layout.actuator_limb]),
            limbs=LIMBS,
            neutral=np.asarray(layout.neutral_ctrl),
            low=np.asarray(layout.ctrl_low),
            high=np.asarray(layout.ctrl_high),
            timestep=self.dt,
            ramp_seconds=self.settings.ramp_seconds,
        )
        self.open_loop = OpenLoop(
            self.actuation, reference_frequency=self.targets.stride_frequency, min_steps=self.nstep
        )
        self.rollout = BatchRollout(
            self.model,
            self.initial_state,
            threads=self.threads,
            group_size=group_size,
            chunk_steps=self.chunk_steps,
        )
        sensors = self.layout.sensors
        self._trunk_pos = sensors["trunk_pos"]
        self._trunk_quat = sensors["trunk_quat"]
        self._hoof_touch = np.array([sensors[f"hoof_{limb}"].start for limb in HOOVES])
        self._hoof_x = np.array([sensors[f"hoof_pos_{limb}"].start for limb in HOOVES])
        self._gap_steps = max(1, round(TOUCHDOWN_GAP_SECONDS / self.dt))
        nq, nv = self.model.nq, self.model.nv
        self._hinge_vel = slice(1 + nq + self.layout.root_dofs, 1 + nq + nv)  # joint speeds in a state vector
        # The actuators' joint positions and speeds in a state vector: slices where they run in order
        # (read as views of the records, not copied out of them).
        self._act_q = _columns(1 + np.asarray(self.layout.actuator_qpos))
        self._act_v = _columns(1 + nq + np.asarray(self.layout.actuator_dof))
        self._start = self._standing_records()

    @property
    def simulated_steps(self) -> int:
        """Steps simulated by ``evaluate`` and ``verify`` so far, summed over gaits (for benchmarks)."""
        return self.rollout.simulated_steps

    @simulated_steps.setter
    def simulated_steps(self, value: int) -> None:
        self.rollout.simulated_steps = value

    @cached_property
    def floors(self) -> tuple[tuple[int, HorseEvaluator], ...]:
        """Per bump floor a gait is also scored on (``bump_floors``): its seed and its evaluator,
        built on first use (whoever only plays gaits, as ``simulate`` does, plays them on the flat)."""
        return tuple(
            (
                seed,
                HorseEvaluator(
                    replace(self.settings, bump_floors=None, bump_height=None),
                    chunk_steps=self.chunk_steps,
                    group_size=self.group_size,
                    model=copy.copy(
                        bumpy_model(self.settings.body, seed, height=self.settings.bump_height or BUMP_HEIGHT)
                    ),
                ),
            )
            for seed in self.settings.bump_floors or ()
        )

    def _warmup(self, frequencies: np.ndarray) -> np.ndarray:
        """Per gait, its warm-up cycles: whole cycles lasting ``warmup_seconds``."""
        return np.array([warmup_cycles(self.settings.warmup_seconds, f) for f in frequencies], dtype=int)

    def _steps(self, frequencies: np.ndarray, cycles: np.ndarray | int) -> np.ndarray:
        """Per gait, the steps that ``cycles`` of its own cycles after the ramp take."""
        counts = np.broadcast_to(cycles, frequencies.shape)
        return np.array(
            [
                cycle_edges(f, self.dt, self.ramp_steps, int(c))[-1]
                for f, c in zip(frequencies, counts, strict=True)
            ]
        )

    def _stage_steps(self, frequencies: np.ndarray) -> np.ndarray:
        """Per gait, the steps an evaluation simulates: the ramp, the warm-up and the scored cycles."""
        return self._steps(frequencies, self._warmup(frequencies) + self.scored)

    def _standing_records(self) -> _Standing:
        data = mujoco.MjData(self.model)
        mujoco.mj_setState(self.model, data, self.initial_state, STATE_SPEC)
        mujoco.mj_forward(self.model, data)
        pitch, roll = _tilt(data.sensordata[self._trunk_quat])
        position = data.sensordata[self._trunk_pos]
        return _Standing(
            (float(position[0]), float(position[2]), float(pitch), float(roll)),
            data.sensordata[self._hoof_touch] > CONTACT_FORCE,
            data.sensordata[self._hoof_x].copy(),
        )

    # ---- controls ---------------------------------------------------------------------

    def frequencies(self, batch: MotionBatch, rows: np.ndarray) -> np.ndarray:
        """Each gait's cycle frequency (Hz): its own where the grammar evolves it, else the target's."""
        if batch.frequencies is None:
            return np.full(len(rows), self.targets.stride_frequency)
        chosen = np.asarray(batch.frequencies, dtype=float)[rows] * self.frequency_scale
        return np.where(np.isfinite(chosen), chosen, self.targets.stride_frequency)

    def controls(self, batch: MotionBatch, rows: np.ndarray, cycles: int | None = None) -> np.ndarray:
        """Control arrays [gaits, steps, actuators] for ``cycles`` cycles after the ramp (by default
        the warm-up and scored ones) of the longest gait: neutral pose plus each limb's curve at its
        phase. All steps at once (rendering, the raw reference); evaluation builds the same values
        a chunk at a time. An open loop's only: a closed loop's controls exist only as it is
        played (:meth:`play`)."""
        if _closed(batch, rows):
            raise ValueError("a closed-loop gait has no controls before it is played: use play()")
        frequencies = self.frequencies(batch, rows)
        ends = self._stage_steps(frequencies) if cycles is None else self._steps(frequencies, cycles)
        steps = int(ends.max())
        return self.open_loop.controls(
            self.open_loop.table(batch, rows), batch.n_samples, 0, steps, self._own(batch, frequencies)
        )

    def _own(self, batch: MotionBatch, frequencies: np.ndarray) -> np.ndarray | None:
        """The per-gait frequencies to play, or None when every gait plays the target's."""
        return None if batch.frequencies is None else frequencies

    def controller(self, batch: MotionBatch, rows: np.ndarray) -> _OpenController | ClosedLoop:
        """What plays the gaits ``rows`` of ``batch``: their curves open loop, or, where any of them
        reads sensors, a closed loop (the open-loop curves of a closed-loop grammar are played as
        an open loop plays them)."""
        frequencies = self.frequencies(batch, rows)
        own = self._own(batch, frequencies)
        table = self.open_loop.table(batch, rows)
        if not _closed(batch, rows):
            return _OpenController(self.open_loop, table, batch.n_samples, own)
        assert batch.loops is not None
        by_joint = {name: j for j, name in enumerate(batch.joints)}
        loops = [
            tuple(
                batch.loops[g][by_joint[curve]] if curve in by_joint else None
                for curve in self.actuation.curves
            )
            for g in rows
        ]
        read = frozenset().union(*(loop.sensors for row in loops for loop in row if loop is not None))
        sensing = None
        if read:
            tick_seconds = self.tick * float(self.model.opt.timestep)
            sensing = Sensing(
                self.model,
                SENSORS,
                read,
                limbs=LIMBS,
                facts=self._facts,
                gaits=len(rows),
                tick_seconds=tick_seconds,
            )
        oscillators = None
        if any("phase" in loop.variables for row in loops for loop in row if loop is not None):
            columns, above, airborne = touchdown_reader(self.model, SENSORS.get("phase"), LIMBS)  # type: ignore[arg-type]
            oscillators = Oscillators(len(rows), columns, above, airborne, self.actuation)
        return ClosedLoop(
            self.open_loop,
            table,
            batch.n_samples,
            frequencies,
            own is not None,
            loops,
            tick=self.tick,
            sensing=sensing,
            oscillators=oscillators,
            scale=batch.loop_scale,
        )

    @cached_property
    def _facts(self) -> dict[str, float]:
        """What the sensors' read tables may name of the body."""
        weight = self.layout.total_mass * -float(self.model.opt.gravity[2])
        return {
            "standing_height": self.layout.standing_height,
            "quarter_weight": weight / 4,
            "target_speed": self.targets.velocity,
        }

    # ---- simulation -------------------------------------------------------------------

    def simulate(
        self, control: np.ndarray, forces: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The raw full-length ``mujoco.rollout`` of control arrays [gaits, steps, actuators]:
        states (``STATE_SPEC``) and sensors [gaits, steps, ...], no gait dropped. ``evaluate`` does
        not use it; it is the reference that chunked evaluation is bit-identical to, and the
        benchmark's ceiling. ``forces`` [gaits, steps, nbody * 6] are applied to the bodies
        (``xfrc_applied``: a push)."""
        return self.rollout.raw(control, forces)

    def play(
        self,
        batch: MotionBatch,
        rows: np.ndarray,
        cycles: int | None = None,
        forces: np.ndarray | None = None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every gait ``rows`` played for ``cycles`` cycles after the ramp (by default the warm-up
        and scored ones) of the longest, through the chunked control loop, none dropped: states,
        sensors and controls [gaits, steps, ...], as :meth:`simulate` gives them. For an open loop
        the same bits as ``simulate(controls(...))``; for a closed loop the only way to see it.
        ``forces`` [gaits, steps, nbody * 6] are applied to the bodies."""
        rows = np.asarray(rows, dtype=np.intp)
        frequencies = self.frequencies(batch, rows)
        ends = self._stage_steps(frequencies) if cycles is None else self._steps(frequencies, cycles)
        steps = int(ends.max())
        nstate = mujoco.mj_stateSize(self.model, STATE_SPEC)
        states = np.empty((len(rows), steps, nstate))
        sensors = np.empty((len(rows), steps, self.model.nsensordata))
        controls = np.empty((len(rows), steps, self.model.nu))
        for start in range(0, len(rows), self.group_size):
            group = np.arange(start, min(start + self.group_size, len(rows)))
            controller = self.controller(batch, rows[group])

            def keep(ids, first, state, sensordata, control, *_, group=group) -> np.ndarray:
                span = slice(first, first + state.shape[1])
                states[group[ids], span] = state
                sensors[group[ids], span] = sensordata
                controls[group[ids], span] = control
                return np.zeros(len(ids), dtype=bool)

            push = None if forces is None else _forces_of(forces[group])
            self.rollout.run(np.full(len(group), steps), controller, keep, push)
        return states, sensors, controls

    @property
    def control_period(self) -> float:
        """Seconds a closed loop holds its sensed terms."""
        return self.tick * self.dt

    # ---- evaluation ---------------------------------------------------------------------

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        """Score each gait over its warm-up and scored cycles (its walk not yet ``sustained``)."""
        return self._evaluate(batch, weights, None)

    def verify(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        """As :meth:`evaluate`, simulated on to the horizon: a gait that falls before it is unviable,
        one that stays up has ``checked_cycles`` = the horizon and, if it walks in every cycle after
        the warm-up, ``walk_sustained`` and ``walk`` 1. Its fitness is the same as ``evaluate``'s."""
        return self._evaluate(batch, weights, self.horizon)

    def ends_at(self, batch: MotionBatch, rows: np.ndarray, cycles: int | None = None) -> np.ndarray:
        """Per gait ``rows`` of ``batch``, the step its play ends at after ``cycles`` cycles after
        the ramp (None: its warm-up and scored ones)."""
        return self._ends(self.frequencies(batch, rows), cycles)

    def ends(self, frequencies: np.ndarray) -> np.ndarray:
        """Per gait at ``frequencies``, the steps an evaluation simulates if it does not fall."""
        return self._stage_steps(frequencies)

    def _ends(self, frequencies: np.ndarray, cycles: int | None) -> np.ndarray:
        """Per gait, the step its simulation ends at: after ``cycles`` (None: its warm-up and scored
        cycles)."""
        return self._stage_steps(frequencies) if cycles is None else self._steps(frequencies, cycles)

    def _evaluate(
        self, batch: MotionBatch, weights: Mapping[str, float] | None, cycles: int | None
    ) -> list[Evaluation]:
        results: dict[int, Evaluation] = {**unusable_evaluations(batch), **unreadable_evaluations(batch)}
        rows = np.array([g for g in range(len(batch)) if g not in results], dtype=np.intp)
        if len(rows):
            active = weights_in_force(weights, self.settings.weights)
            evaluations = self.evaluate_rows(batch, rows, active, cycles=cycles)
            if self.settings.bump_floors:
                evaluations = self._on_floors(batch, rows, evaluations, active)
            for row, evaluation in zip(rows, evaluations, strict=True):
                results[int(row)] = evaluation
        return [results[g] for g in range(len(batch))]

    def _on_floors(
        self, batch: MotionBatch, rows: np.ndarray, flat: list[Evaluation], weights: Mapping[str, float]
    ) -> list[Evaluation]:
        """``flat``, the evaluations of ``rows`` on the flat floor, with the gaits that stood also
        scored on each bump floor (over their warm-up and scored cycles, whatever ``flat`` checked):
        :func:`on_floors`. A gait that fails on a floor is not played on the floors after it: its
        evaluation is that failure's whatever they would say."""
        standing = [k for k, evaluation in enumerate(flat) if evaluation.status.viable]
        seeds = [seed for seed, _ in self.floors]
        bumpy: dict[int, list[Evaluation]] = {k: [] for k in standing}
        for _, floor in self.floors:
            if not standing:
                break
            played = floor.evaluate_rows(batch, rows[standing], weights)
            for k, evaluation in zip(standing, played, strict=True):
                bumpy[k].append(evaluation)
            self.simulated_steps += floor.simulated_steps
            floor.simulated_steps = 0
            standing = [k for k in standing if bumpy[k][-1].status.viable]
        combined = list(flat)
        for k, found in bumpy.items():
            combined[k] = on_floors(flat[k], found, seeds[: len(found)])
        return combined

    def evaluate_rows(
        self,
        batch: MotionBatch,
        rows: np.ndarray,
        weights: Mapping[str, float],
        *,
        cycles: int | None = None,
        on_chunk: ChunkObserver | None = None,
        forces: np.ndarray | None = None,
    ) -> list[Evaluation]:
        """Simulate and score the gaits ``rows`` of ``batch`` (all usable) for ``cycles`` cycles
        after the ramp (None: each its warm-up and scored ones), a group at a time; ``forces``
        [rows, steps, nbody * 6] are applied to the bodies (a push), as long as they last."""
        evaluations: list[Evaluation] = []
        for start in range(0, len(rows), self.group_size):
            group = np.asarray(rows[start : start + self.group_size], dtype=np.intp)
            push = None if forces is None else _forces_of(forces[start : start + len(group)])
            evaluations += self._evaluate_group(batch, group, weights, cycles, on_chunk, push)
        return evaluations

    def _evaluate_group(
        self,
        batch: MotionBatch,
        rows: np.ndarray,
        weights: Mapping[str, float],
        cycles: int | None,
        on_chunk: ChunkObserver | None,
        forces: Forces | None = None,
    ) -> list[Evaluation]:
        frequencies = self.frequencies(batch, rows)
        ends = self._ends(frequencies, cycles)  # per gait: its last step
        records = _Records(len(rows), int(ends.max()), self._start)

        def observe(alive, first, state, sensors, control, warnings, errors, failures) -> np.ndarray:
            if on_chunk is not None:
                on_chunk(rows[alive], first, state, sensors)
            failed = self._observe(
                records, alive, first, ends[alive] - first, state, sensors, control, warnings, errors
            )
            for position, (step, curve) in failures.items():
                gait = int(alive[position])
                earlier = records.failures.get(gait)
                if earlier is None or earlier[1] > step:
                    records.failures[gait] = (
                        Evaluation.unviable(
                            GaitStatus.NON_FINITE,
                            f"the closed loop of {curve} is not finite at {step * self.dt:.3f} s",
                        ),
                        step,
                    )
                failed[position] = True
            return failed

        self.rollout.run(ends, self.controller(batch, rows), observe, forces)
        return self._verdicts(records, ends, frequencies, weights, cycles)

    def score(
        self,
        state: np.ndarray,
        sensors: np.ndarray,
        control: np.ndarray,
        weights: Mapping[str, float],
        frequencies: np.ndarray | None = None,
        cycles: int | None = None,
    ) -> list[Evaluation]:
        """Score full-length records [gaits, steps, ...] (``simulate``'s) as evaluation would, each
        gait up to its own end (at the target's frequency, or at ``frequencies``).

        Without ``Batch``'s warning counters, a rollout that MuJoCo stopped is told by its repeated
        records (time stops advancing), so a warning in the very last step goes unnoticed here."""
        gaits = state.shape[0]
        if frequencies is None:
            frequencies = np.full(gaits, self.targets.stride_frequency)
        ends = self._ends(frequencies, cycles)
        if state.shape[1] < ends.max():
            raise ValueError(f"records of {state.shape[1]} steps; the slowest gait needs {ends.max()}")
        records = _Records(gaits, int(ends.max()), self._start)
        self._observe(records, np.arange(gaits), 0, ends, state, sensors, control, None, None)
        return self._verdicts(records, ends, frequencies, weights, cycles)

    def recordings(
        self, state: np.ndarray, sensors: np.ndarray, control: np.ndarray, frequencies: np.ndarray
    ) -> list[Recording]:
        """What the task measures, from full-length records [gaits, steps, ...] (``simulate``'s) of
        gaits played at ``frequencies``, failures or not: for measurements beyond the fitness."""
        gaits, steps = state.shape[:2]
        records = _Records(gaits, steps, self._start)
        self._record(records, np.arange(gaits), 0, state, sensors, control)
        return [records.recording(g, steps, float(frequencies[g]), self) for g in range(gaits)]

    @property
    def gap_steps(self) -> int:
        """Steps off the ground before a contact is a new footfall."""
        return self._gap_steps

    def _observe(
        self,
        records: _Records,
        gaits: np.ndarray,
        first: int,
        remaining: np.ndarray,
        state: np.ndarray,
        sensors: np.ndarray,
        control: np.ndarray,
        warnings: np.ndarray | None,
        errors: Mapping[int, str] | None,
    ) -> np.ndarray:
        """Take in one chunk of records of ``gaits`` (indices into the records) starting at step
        ``first``, each valid for its ``remaining`` steps (past its end a gait's steps are not its
        own); returns which of them failed in it."""
        failed = self._failures(records, gaits, first, remaining, state, sensors, warnings)
        for i, message in (errors or {}).items():  # records of a simulation that raised mean nothing
            records.failures[int(gaits[i])] = (
                Evaluation.unviable(GaitStatus.UNSTABLE, f"MuJoCo error: {message}"),
                first + state.shape[1],
            )
            failed[i] = True
        self._record(records, gaits, first, state, sensors, control)
        return failed

    def _failures(
        self,
        records: _Records,
        gaits: np.ndarray,
        first: int,
        remaining: np.ndarray,
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
        own = np.arange(steps)[None, :] < np.minimum(remaining, steps)[:, None]  # steps that are theirs
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
                broken & own,
                (speed > UNSTABLE_SPEED) & own,
                (up_z < FLIP_COSINE) & own,
                (trunk_z < FALL_HEIGHT * self.layout.standing_height) & own,
            )
        # A MuJoCo warning stops a rollout: its later records repeat the last one. Batch's counters
        # tell it even when the warning came in the chunk's last step, where no repeat shows.
        time = state[:, :, 0]
        frozen = (time[:, 1:] == time[:, :-1]) & own[:, 1:]
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
            records.failures[int(gaits[i])] = (evaluation, first + k + 1)
        return failed

    def _record(
        self,
        records: _Records,
        gaits: np.ndarray,
        first: int,
        state: np.ndarray,
        sensors: np.ndarray,
        control: np.ndarray,
    ) -> None:
        """Keep one chunk's share of what the task measures: trunk position and tilt, hoof
        contacts and positions, and the actuators' total absolute power, per step."""
        steps = slice(first + 1, first + 1 + state.shape[1])
        trunk = self._trunk_pos.start
        records.trunk[0, gaits, steps] = sensors[:, :, trunk]
        records.trunk[1, gaits, steps] = sensors[:, :, trunk + 2]
        records.trunk[2, gaits, steps], records.trunk[3, gaits, steps] = _tilt(
            sensors[:, :, self._trunk_quat]
        )
        records.contact[gaits, steps] = sensors[:, :, self._hoof_touch] > CONTACT_FORCE
        records.hoof_x[gaits, steps] = sensors[:, :, self._hoof_x]

        # Actuator power: |force x joint speed| per step, from the position servos' law.
        model = self.model
        act_q = state[:, :, self._act_q]  # views of the records where they can be: never written
        act_v = state[:, :, self._act_v]
        kp = -model.actuator_biasprm[:, 1]
        kv = -model.actuator_biasprm[:, 2]
        with np.errstate(all="ignore"):  # in place: these arrays are gaits x steps x actuators
            force = control * model.actuator_gainprm[:, 0]
            force -= act_q * kp
            force -= kv * act_v
            np.clip(force, model.actuator_forcerange[:, 0], model.actuator_forcerange[:, 1], out=force)
            force *= act_v
            np.abs(force, out=force)
            records.power[gaits, steps] = force.sum(axis=2)

    def _verdicts(
        self,
        records: _Records,
        ends: np.ndarray,
        frequencies: np.ndarray,
        weights: Mapping[str, float],
        cycles: int | None,
    ) -> list[Evaluation]:
        """Each gait's evaluation: its first failure, or its recording measured and judged."""
        found = []
        stage = self._stage_steps(frequencies)
        for g in range(len(ends)):
            if g in records.failures:
                failure, step = records.failures[g]
                if step > stage[g]:  # past what evaluate simulates: the horizon's check failed
                    failure = Evaluation.unviable(
                        failure.status,
                        f"{failure.detail}, after the scored cycles, within the {cycles}-cycle horizon",
                    )
                found.append(failure)
            else:
                recording = records.recording(g, int(ends[g]), float(frequencies[g]), self)
                found.append(self._judge(recording, weights, cycles))
        return found

    def _judge(self, recording: Recording, weights: Mapping[str, float], cycles: int | None) -> Evaluation:
        """Score a recording (of ``cycles`` cycles after the ramp, None: its warm-up and scored ones);
        any non-finite measure, component or fitness is not a score."""
        warmup = warmup_cycles(self.settings.warmup_seconds, recording.frequency)
        scored = measure_cycles(recording, warmup, warmup + self.scored, self._gap_steps)
        means = window(scored)
        components = fitness_components(
            means,
            self.targets,
            self.layout.total_mass,
            footfall_error(scored),
            self.settings.speed_margin or 0.0,
        )
        measured = {
            "measured_velocity": means.velocity,
            "measured_duty_factor": means.duty_factor,
            "measured_stride": means.stride_length,
            "measured_frequency": means.stride_frequency,
            "measured_work": float(np.mean(scored.work)),
            "measured_speed_spread": means.speed_spread,
        }
        fitness = weighted_fitness(components, weights)
        values = {**measured, **components, "fitness": fitness}
        bad = [f"{name} = {value}" for name, value in values.items() if not math.isfinite(value)]
        if bad:
            return Evaluation.unviable(GaitStatus.NON_FINITE, f"non-finite {', '.join(bad)}")
        terms = walk_terms(scored, self.targets)
        if cycles is not None:  # verified: every cycle after the warm-up, to the horizon
            horizon = walk_terms(measure_cycles(recording, warmup, cycles, self._gap_steps), self.targets)
            terms["sustained"] = all(terms.values()) and all(horizon.values())
        else:
            terms["sustained"] = False
        verdicts = {f"walk_{term.name}": float(terms[term.name]) for term in WALK_TERMS}
        components = {
            **components,
            **measured,
            **verdicts,
            "walk": float(all(terms.values())),  # reported, never weighted
            "checked_cycles": float(warmup + self.scored if cycles is None else cycles),
        }
        return Evaluation(min(fitness, WORST_FITNESS), GaitStatus.OK, components, cycles=_series(scored))

    def close(self) -> None:
        self.rollout.close()
        for _, floor in self.__dict__.get("floors", ()):
            floor.close()


def on_floors(flat: Evaluation, bumpy: Sequence[Evaluation], seeds: Sequence[int]) -> Evaluation:
    """A gait's evaluation on the flat floor and on bump floors ``seeds`` as one (``bump_floors``):
    unviable, as on the first floor it failed on (named), if it failed on any; else the flat floor's
    measures and verdicts, scored by the mean fitness over all the floors (``bumps_fitness``: the
    bump floors' mean). A walk is still judged on the flat floor, where the criterion is defined."""
    for seed, evaluation in zip(seeds, bumpy, strict=True):
        if not evaluation.status.viable:
            return replace(evaluation, detail=f"on bump floor {seed}: {evaluation.detail}")
    bumps = float(np.mean([evaluation.fitness for evaluation in bumpy]))
    fitness = (flat.fitness + bumps * len(bumpy)) / (1 + len(bumpy))
    return replace(flat, fitness=fitness, components={**flat.components, "bumps_fitness": bumps})


def _columns(indices: np.ndarray) -> np.ndarray | slice:
    """Column indices as a slice where they run in order (a slice reads a view, indices a copy)."""
    if len(indices) and np.array_equal(indices, np.arange(indices[0], indices[0] + len(indices))):
        return slice(int(indices[0]), int(indices[0]) + len(indices))
    return indices


def _tilt(quat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Trunk pitch (nose up positive) and roll, degrees, from (w, x, y, z) quaternions [..., 4]."""
    w, x, y, z = np.moveaxis(quat, -1, 0)
    with np.errstate(all="ignore"):
        pitch = -np.degrees(np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0)))
        roll = np.degrees(np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
    return pitch, roll


def _series(scored: CycleMeasures) -> dict[str, tuple[float, ...]]:
    """Each scored cycle's measures, for reports that show the spread: a hoof that closed no
    stride in a cycle counts 0, as in the window's means."""
    lengths = np.nan_to_num(scored.stride_length).mean(axis=1)
    frequencies = np.nan_to_num(scored.stride_frequency).mean(axis=1)
    series = {
        "speed": scored.speed,
        "duty_factor": scored.duty_factor.mean(axis=1),
        **{f"duty_factor_{hoof}": scored.duty_factor[:, h] for h, hoof in enumerate(HOOVES)},
        "stride_length": lengths,
        "stride_frequency": frequencies,
        "work": scored.work,
    }
    return {name: tuple(float(v) for v in values) for name, values in series.items()}


class _OpenController:
    """An open loop as the rollout asks for it: a chunk's controls at once."""

    tick = None

    def __init__(self, open_loop: OpenLoop, table: np.ndarray, samples: int, own: np.ndarray | None) -> None:
        self.open_loop, self.table, self.samples, self.own = open_loop, table, samples, own

    def controls(
        self, ids: np.ndarray, first: int, last: int, state: np.ndarray, sensordata: np.ndarray
    ) -> tuple[np.ndarray, dict[int, str]]:
        everyone = len(ids) == len(self.table)
        table = self.table if everyone else self.table[ids]
        own = self.own if self.own is None or everyone else self.own[ids]
        return self.open_loop.controls(table, self.samples, first, last, own), {}


def unreadable_evaluations(batch: MotionBatch) -> dict[int, Evaluation]:
    """The gaits whose closed loops read a sensor their joint cannot (a hoof's load in a neck curve),
    already scored: index -> evaluation (the linter says so before a run)."""
    found: dict[int, Evaluation] = {}
    if batch.loops is None:
        return found
    for g, row in enumerate(batch.loops):
        for joint, loop in zip(batch.joints, row, strict=True):
            if loop is None or batch.problems[g] is not None:
                continue
            known = CATALOGUE.get(joint)
            group = known.group if known is not None else ""
            for name in sorted(loop.sensors | loop.variables):
                sensor = SENSORS.get(name)
                if sensor is not None and not sensor.readable_by(group):
                    found[g] = Evaluation.unviable(
                        GaitStatus.INVALID_MOTION,
                        f"{joint}: reads {name!r}, a limb's sensor, but {joint} drives no limb",
                    )
                    break
            if g in found:
                break
    return found


def _closed(batch: MotionBatch, rows: np.ndarray) -> bool:
    """Whether any of the gaits ``rows`` reads a sensor."""
    loops = batch.loops
    return loops is not None and any(any(loop is not None for loop in loops[g]) for g in rows)


def _forces_of(forces: np.ndarray) -> Forces:
    """Applied forces [gaits, steps, nbody * 6] as the rollout asks for them, a chunk at a time
    (zero past their end)."""

    def chunk(ids: np.ndarray, first: int, last: int) -> np.ndarray:
        out = np.zeros((len(ids), last - first, forces.shape[2]))
        stop = min(last, forces.shape[1])
        if stop > first:
            out[:, : stop - first] = forces[ids, first:stop]
        return out

    return chunk


def load(settings: Mapping[str, Any] | None = None) -> HorseEvaluator:
    return HorseEvaluator(HorseSettings.from_mapping(settings or {}))
