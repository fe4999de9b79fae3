"""Batched MuJoCo rollouts in chunks: the simulation half of every MuJoCo backend.

Gaits are simulated together on a ``mujoco.batch.Batch`` of ``group_size`` simulations, in chunks
of ``chunk_steps`` steps. After each chunk an observer takes the records in and says which gaits
failed; only the gaits still viable and not yet at their own end are simulated further, from
where they stopped. Memory is bounded by a chunk's records, whatever the population.

Chunking changes no bit of any result: ``Batch`` keeps each simulation's
``mjSTATE_INTEGRATION`` row between calls, the full physics state *and* ``qacc_warmstart``, the
solver's warm start (``mujoco.rollout`` records and accepts only ``mjSTATE_FULLPHYSICS``, without
the warm start: restarting it from a recorded state changes the trajectory). A controller is
asked for the controls of a chunk at once when it is open loop, and tick by tick, from the last
recorded step, when it is closed (:mod:`gaitgram.backends.mujoco.control`); ``Batch``'s cost per
call is small enough that a tick of a few steps runs at the raw rollout's speed.

:meth:`BatchRollout.raw` is the plain full-length ``mujoco.rollout`` of given controls: the
reference a chunked open-loop run is bit-identical to, and a benchmark's ceiling.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Protocol

import mujoco
import numpy as np
from mujoco import batch as mjbatch
from mujoco import rollout
from numpy.typing import NDArray

__all__ = ["STATE_SPEC", "BatchRollout", "Controller", "Forces", "Observer"]

#: Full physics state (time, qpos, qvel, act, ...): what rollouts start from and record.
STATE_SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS
_RECORD = int(STATE_SPEC)
_CTRL = int(mujoco.mjtState.mjSTATE_CTRL)
_CTRL_AND_FORCES = _CTRL | int(mujoco.mjtState.mjSTATE_XFRC_APPLIED)


class Controller(Protocol):
    """Controls for the simulations ``ids`` (positions in the group) at steps ``first..last-1`` (within
    one tick), from the state and sensors recorded at the step before the tick began ([ids, ...]:
    a tick cut by a chunk's end reads the same state in both parts); and the gaits
    (positions in ``ids``) whose controls could not be computed, each with what failed. ``tick``
    is how many steps a closed loop holds its controls (None: open loop, any range at once)."""

    tick: int | None

    def controls(
        self,
        ids: NDArray[np.intp],
        first: int,
        last: int,
        state: NDArray[np.float64],
        sensordata: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], Mapping[int, str]]: ...


#: Applied forces [ids, last - first, nbody * 6] (``xfrc_applied``: a push) for a chunk.
Forces = Callable[[NDArray[np.intp], int, int], NDArray[np.float64]]

#: Takes in a chunk: the simulations (positions in the group), the chunk's first step, its records
#: (state, sensors, controls; views into reused buffers: copy what you keep), Batch's warning
#: counters, MuJoCo errors and controller failures by position; returns which of them failed.
Observer = Callable[
    [
        NDArray[np.intp],
        int,
        NDArray[np.float64],
        NDArray[np.float64],
        NDArray[np.float64],
        NDArray[np.int32] | None,
        Mapping[int, str],
        Mapping[int, tuple[int, str]],
    ],
    NDArray[np.bool_],
]


class BatchRollout:
    """Rollouts of ``model`` from ``initial_state`` (a ``STATE_SPEC`` vector), on ``threads``."""

    def __init__(
        self,
        model: mujoco.MjModel,
        initial_state: NDArray[np.float64],
        *,
        threads: int,
        group_size: int,
        chunk_steps: int,
    ) -> None:
        if chunk_steps < 1 or group_size < 1:
            raise ValueError(
                f"chunk_steps and group_size must be at least 1, not {chunk_steps}, {group_size}"
            )
        self.model = model
        self.initial_state = initial_state
        self.threads = threads
        self.group_size = group_size
        self.chunk_steps = chunk_steps
        self.nstate = mujoco.mj_stateSize(model, STATE_SPEC)
        data = mujoco.MjData(model)
        mujoco.mj_setState(model, data, initial_state, STATE_SPEC)
        mujoco.mj_forward(model, data)
        #: What the records hold at step 0: the standing start.
        self.start_sensors = data.sensordata.copy()
        # Built on first use.
        self._pool: rollout.Rollout | None = None
        self._datas: list[mujoco.MjData] = []
        self._sim: mjbatch.Batch | None = None
        self._start_row: NDArray[np.float64] | None = None
        self._scratch: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
        #: Steps simulated so far, summed over simulations.
        self.simulated_steps = 0

    # ---- the raw reference ------------------------------------------------------------

    def raw(
        self, control: NDArray[np.float64], forces: NDArray[np.float64] | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The full-length ``mujoco.rollout`` of control arrays [gaits, steps, actuators]: states
        and sensors [gaits, steps, ...], no gait dropped; ``forces`` [gaits, steps, nbody * 6] are
        applied to the bodies."""
        if self._pool is None:
            self._pool = rollout.Rollout(nthread=self.threads)
            self._datas = [mujoco.MjData(self.model) for _ in range(self.threads)]
        size, steps = control.shape[:2]
        state = np.empty((size, steps, self.nstate))
        sensors = np.empty((size, steps, self.model.nsensordata))
        initial = self.initial_state[None, :]
        if forces is None:
            self._pool.rollout(self.model, self._datas, initial, control, state=state, sensordata=sensors)
        else:
            spec = mujoco.mjtState.mjSTATE_CTRL | mujoco.mjtState.mjSTATE_XFRC_APPLIED
            self._pool.rollout(
                self.model,
                self._datas,
                initial,
                np.concatenate([control, forces], axis=2),
                control_spec=int(spec),
                state=state,
                sensordata=sensors,
            )
        return state, sensors

    # ---- chunked rollouts ---------------------------------------------------------------

    def run(
        self,
        ends: NDArray[np.intp],
        controller: Controller,
        observe: Observer,
        forces: Forces | None = None,
    ) -> None:
        """Simulate one group of ``len(ends)`` gaits (at most ``group_size``), each to its step
        ``ends[g]`` unless ``observe`` says it failed; every chunk goes to ``observe``."""
        size = len(ends)
        if size > self.group_size:
            raise ValueError(f"a group of {size} gaits; at most {self.group_size}")
        sim = self._simulator()
        sim.state[:size] = self._start_row
        sim.warning[:size] = 0
        alive = np.arange(size, dtype=np.int32)  # simulation ids, also positions in the group
        # The state and sensors each simulation last recorded (a closed loop reads them).
        last_state = np.broadcast_to(self.initial_state, (size, self.nstate)).copy()
        last_sensors = np.broadcast_to(self.start_sensors, (size, len(self.start_sensors))).copy()
        first = 0
        while len(alive):
            last = min(first + self.chunk_steps, int(ends[alive].max()))
            state, sensors = self._chunk_buffers(len(alive), last - first)
            control = np.empty((len(alive), last - first, self.model.nu))
            errors: dict[int, str] = {}
            failures: dict[int, tuple[int, str]] = {}
            # Ticks at whole multiples of ``tick`` from step 0, whatever the chunks: a closed loop
            # reads the same steps however its simulation is cut.
            tick = controller.tick or self.chunk_steps
            # What the next tick reads: the chunk's gaits' rows, then views of the chunk's records.
            read_state, read_sensors = last_state[alive], last_sensors[alive]
            start = first
            while start < last:
                stop = min((start // tick + 1) * tick, last)
                held, failed = controller.controls(alive, start, stop, read_state, read_sensors)
                for position, what in failed.items():
                    failures.setdefault(position, (start, what))
                inputs, spec = held, _CTRL
                if forces is not None:
                    inputs = np.concatenate([held, forces(alive, start, stop)], axis=2)
                    spec = _CTRL_AND_FORCES
                if stop - start == last - first:  # the whole chunk at once: record in place
                    out = {_RECORD: state, "sensordata": sensors}
                else:
                    out = {
                        _RECORD: np.empty((len(alive), stop - start, self.nstate)),
                        "sensordata": np.empty((len(alive), stop - start, self.model.nsensordata)),
                    }
                try:
                    sim.rollout(
                        stop - start,
                        inputs,
                        control_spec=spec,
                        record=(_RECORD, "sensordata"),
                        ids=alive,
                        out=out,
                    )
                except mjbatch.SimulationError:  # MuJoCo raised in some simulations; the others ran
                    bad = np.flatnonzero(sim.status[alive] != 0)
                    errors.update({int(i): sim.error(int(alive[i])) for i in bad if int(i) not in errors})
                if out[_RECORD] is not state:
                    state[:, start - first : stop - first] = out[_RECORD]
                    sensors[:, start - first : stop - first] = out["sensordata"]
                control[:, start - first : stop - first] = held
                if controller.tick is not None and stop % tick == 0:  # a tick's end: the next reads here
                    read_state, read_sensors = state[:, stop - first - 1], sensors[:, stop - first - 1]
                start = stop
            if controller.tick is not None:  # the chunk's records are reused: keep what the next reads
                last_state[alive], last_sensors[alive] = read_state, read_sensors
            self.simulated_steps += len(alive) * (last - first)
            failed_now = observe(alive, first, state, sensors, control, sim.warning[alive], errors, failures)
            alive = alive[~failed_now & (ends[alive] > last)]
            first = last

    def _simulator(self) -> mjbatch.Batch:
        """The batch of ``group_size`` simulations that chunked rollouts run on."""
        if self._sim is None:
            self._sim = mjbatch.Batch(self.model, self.group_size, self.threads)
            # What mujoco.rollout starts from: the initial state, a zero warm start, no applied forces.
            data = mujoco.MjData(self.model)
            mujoco.mj_setState(self.model, data, self.initial_state, STATE_SPEC)
            row = np.empty(self._sim.nstate)
            mujoco.mj_getState(self.model, data, row, mujoco.mjtState.mjSTATE_INTEGRATION)
            self._start_row = row
        return self._sim

    def _chunk_buffers(self, gaits: int, steps: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Record arrays [gaits, steps, ...] for one chunk, views into buffers reused between chunks."""
        nstate, nsensor = self.nstate, self.model.nsensordata
        need = gaits * steps  # at most group_size x chunk_steps
        if self._scratch is None or self._scratch[0].size < need * nstate:
            self._scratch = (np.empty(need * nstate), np.empty(need * nsensor))
        states, sensors = self._scratch
        return (
            states[: gaits * steps * nstate].reshape(gaits, steps, nstate),
            sensors[: gaits * steps * nsensor].reshape(gaits, steps, nsensor),
        )

    def close(self) -> None:
        if self._pool is not None:
            self._pool.close()
            self._pool = None
        self._sim = None
