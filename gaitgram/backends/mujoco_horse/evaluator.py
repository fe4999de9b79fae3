"""The ``mujoco-horse`` evaluator: a generation's gaits as one batch of MuJoCo rollouts.

Control arrays for the whole batch are built in one vectorised step (joint
curves sampled over the cycle, looked up at each step's phase per limb), the
batch runs through ``mujoco.rollout`` on a persistent thread pool, and the
metrics are computed from the recorded states and sensors with numpy.
Rollouts are deterministic per trajectory, so results do not depend on the
thread count. A gait that cannot be scored gets a status and the worst fitness.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from typing import Any

import mujoco
import numpy as np
from mujoco import rollout

from gaitgram.backends.api import WORST_FITNESS, Evaluation, GaitStatus, unusable_evaluations
from gaitgram.backends.mujoco_horse.model import STATE_SPEC, HorseLayout, horse_layout, load_model
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.backends.mujoco_horse.task import (
    DEFAULT_WEIGHTS,
    GaitMetrics,
    GaitTargets,
    fitness_components,
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


class HorseEvaluator:
    def __init__(self, settings: HorseSettings | None = None) -> None:
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
        self.initial_state = self.layout.initial_state(self.model)
        self._pool = rollout.Rollout(nthread=self.threads)
        self._datas = [mujoco.MjData(self.model) for _ in range(self.threads)]
        self._phase, self._ramp = self._step_phases()
        self._curve_of_actuator = np.asarray(self.layout.actuator_curve_index)
        self._lookups: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self._buffers: tuple[np.ndarray, np.ndarray] | None = None
        self._neutral = np.asarray(self.layout.neutral_ctrl)[None, None, :]
        self._ctrl_low = np.asarray(self.layout.ctrl_low)[None, None, :]
        self._ctrl_high = np.asarray(self.layout.ctrl_high)[None, None, :]

    # ---- controls ---------------------------------------------------------------------

    def _step_phases(self) -> tuple[np.ndarray, np.ndarray]:
        """Per actuator and step, the cycle phase its limb is at; and the ramp-in factor per step."""
        time = np.arange(self.nstep) * self.dt
        offsets = np.array(
            [self.targets.phase_offsets.get(limb, 0.0) if limb else 0.0 for limb in self.layout.actuator_limb]
        )
        phase = np.mod(time[None, :] * self.targets.stride_frequency - offsets[:, None], 1.0)  # [nu, nstep]
        ramp = (
            np.clip(time / self.settings.ramp_seconds, 0.0, 1.0)
            if self.settings.ramp_seconds
            else np.ones_like(time)
        )
        return phase, ramp

    def controls(self, batch: MotionBatch, rows: np.ndarray) -> np.ndarray:
        """Control arrays [gaits, steps, actuators]: neutral pose plus each limb's curve at its phase."""
        curves_by_name = {name: i for i, name in enumerate(batch.joints)}
        order = np.array([curves_by_name.get(name, -1) for name in self.layout.curves])
        angles = np.concatenate([batch.angles[rows], np.zeros((len(rows), 1, batch.n_samples))], axis=1)
        per_curve = angles[:, order, :]  # [G, curves, S]; undriven curves read the zero row
        # One flat gather per interpolation end, straight into [gaits, steps, actuators] order.
        flat = np.radians(per_curve[:, self._curve_of_actuator, :]).reshape(len(rows), -1)  # [G, nu*S]
        low, high, frac = self._lookup(batch.n_samples)
        v_low = np.take(flat, low, axis=1)
        control = np.take(flat, high, axis=1)
        control -= v_low
        control *= frac
        control += v_low
        control *= self._ramp[None, :, None]
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

    # ---- evaluation ---------------------------------------------------------------------

    def simulate(self, control: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Roll out a batch of control arrays; the output buffers are reused between generations
        (a generation's states are tens of MB; allocating them anew costs page faults every time)."""
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

    def evaluate(
        self, batch: MotionBatch, *, generation: int = 0, weights: Mapping[str, float] | None = None
    ) -> list[Evaluation]:
        results: dict[int, Evaluation] = unusable_evaluations(batch)
        rows = np.array([g for g in range(len(batch)) if g not in results], dtype=np.intp)
        if len(rows):
            control = self.controls(batch, rows)
            state, sensors = self.simulate(control)
            active = weights or self.settings.weights or DEFAULT_WEIGHTS
            for row, evaluation in zip(rows, self.score(state, sensors, control, active), strict=True):
                results[int(row)] = evaluation
        return [results[g] for g in range(len(batch))]

    def score(
        self, state: np.ndarray, sensors: np.ndarray, control: np.ndarray, weights: Mapping[str, float]
    ) -> list[Evaluation]:
        layout, model = self.layout, self.model
        nq = model.nq
        trunk_pos = sensors[:, :, layout.sensors["trunk_pos"]]
        trunk_quat = sensors[:, :, layout.sensors["trunk_quat"]]
        # A diverged rollout's NaN or inf persists to its last state (NaN never recovers), so the
        # last states and the NaN-propagating speed maximum find it without a pass over all.
        finite = np.isfinite(state[:, -1]).all(axis=1) & np.isfinite(sensors[:, -1]).all(axis=1)
        with np.errstate(all="ignore"):
            speed = np.abs(state[:, :, 1 + nq + 6 : 1 + nq + model.nv]).max(axis=(1, 2))
            finite &= np.isfinite(speed)
            height = trunk_pos[:, :, 2].min(axis=1)
            x, y = trunk_quat[:, :, 1], trunk_quat[:, :, 2]
            up_z = 1 - 2 * (x**2 + y**2)  # z component of the trunk's up axis
            upright = up_z.min(axis=1)
        scored = slice(self.ramp_steps, self.nstep)
        start_x = trunk_pos[:, self.ramp_steps, 0]
        end_x = trunk_pos[:, -1, 0]
        seconds = self.scored_steps * self.dt
        velocity = (end_x - start_x) / seconds
        touches = np.stack(
            [
                sensors[:, scored, layout.sensors[f"hoof_{limb}"]][:, :, 0]
                for limb in ("fore_left", "fore_right", "hind_left", "hind_right")
            ],
            axis=2,
        )
        duty = (touches > CONTACT_FORCE).mean(axis=(1, 2))
        # Actuator work: |force x joint speed| summed over steps, from the position servos' law.
        act_q = state[:, scored, 1 + np.asarray(layout.actuator_qpos)]
        act_v = state[:, scored, 1 + nq + np.asarray(layout.actuator_dof)]
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
            work = force.sum(axis=(1, 2)) * self.dt / self.settings.cycles
        evaluations = []
        for g in range(state.shape[0]):
            if not finite[g] or speed[g] > UNSTABLE_SPEED:
                evaluations.append(Evaluation.unviable(GaitStatus.UNSTABLE, "the simulation diverged"))
            elif upright[g] < FLIP_COSINE:
                evaluations.append(
                    Evaluation.unviable(
                        GaitStatus.FLIPPED,
                        f"trunk tilted {math.degrees(math.acos(np.clip(upright[g], -1, 1))):.0f} degrees",
                    )
                )
            elif height[g] < FALL_HEIGHT * layout.standing_height:
                evaluations.append(Evaluation.unviable(GaitStatus.FELL, f"trunk down to {height[g]:.2f} m"))
            else:
                metrics = GaitMetrics(
                    float(velocity[g]), float(duty[g]), float(velocity[g] * self.period), float(work[g])
                )
                components = fitness_components(metrics, self.targets, layout.total_mass)
                measured = {
                    "measured_velocity": metrics.velocity,
                    "measured_duty_factor": metrics.duty_factor,
                    "measured_stride": metrics.stride_length,
                    "measured_work": metrics.work_per_cycle,
                }
                fitness = weighted_fitness(components, weights)
                evaluations.append(
                    Evaluation(min(fitness, WORST_FITNESS), GaitStatus.OK, {**components, **measured})
                )
        return evaluations

    def close(self) -> None:
        self._pool.close()


def load(settings: Mapping[str, Any] | None = None) -> HorseEvaluator:
    return HorseEvaluator(HorseSettings.from_mapping(settings or {}))
