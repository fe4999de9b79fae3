"""Frames of played gaits, drawn offscreen from the states a rollout recorded: the rendering half of
every MuJoCo backend.

A gait is drawn from what playing it recorded (``STATE_SPEC`` rows, entry ``k`` the state after
step ``k + 1``), never by stepping it again: a closed loop has no control array before it is
played, and a drawing made from the records shows the gait exactly as it was scored. The frame
of step ``k`` shows the state *before* that step, forwarded (``mj_forward``): what ``mj_step``'s
own forward pass computed when the step was taken, so a drawing from the records is the same, to
the byte, as one made while stepping. Needs an OpenGL without a display (``MUJOCO_GL=egl``, set by
the command before MuJoCo is imported).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from gaitgram.animation import RenderError
from gaitgram.backends.mujoco.rollout import STATE_SPEC

__all__ = ["Camera", "draw_plays", "frame_every"]


@dataclass(frozen=True)
class Camera:
    """A side view that follows a body: ``distance`` (m) away, at ``azimuth`` and ``elevation``
    (degrees), looking at the body's position with its height fixed at ``height`` (m)."""

    body: int
    distance: float = 4.5
    azimuth: float = 90.0
    elevation: float = -8.0
    height: float = 1.0


def frame_every(model: mujoco.MjModel, fps: int) -> int:
    """How many physics steps one frame at ``fps`` frames per second spans (at least one)."""
    return max(1, round(1.0 / (fps * model.opt.timestep)))


def draw_plays(
    model: mujoco.MjModel,
    initial_state: NDArray[np.float64],
    plays: Sequence[NDArray[np.float64]],
    camera: Camera,
    *,
    every: int,
    width: int,
    height: int,
) -> list[list[NDArray[np.uint8]]]:
    """RGB frames of each play: ``states`` [steps, nstate] recorded from ``initial_state``, a frame
    at every ``every``-th step, from the state before it."""
    try:
        renderer = mujoco.Renderer(model, height=height, width=width)
    except Exception as error:  # no GL: the message from MuJoCo is the useful part
        raise RenderError(
            f"cannot render offscreen ({error}); set MUJOCO_GL=egl (or osmesa with libosmesa6 installed)"
        ) from None
    view = mujoco.MjvCamera()
    view.type = mujoco.mjtCamera.mjCAMERA_FREE
    view.distance, view.azimuth, view.elevation = camera.distance, camera.azimuth, camera.elevation
    data = mujoco.MjData(model)
    drawn = []
    with renderer:
        for states in plays:
            frames = []
            for step in range(0, len(states), every):
                mujoco.mj_setState(model, data, initial_state if step == 0 else states[step - 1], STATE_SPEC)
                mujoco.mj_forward(model, data)
                view.lookat[:] = data.xpos[camera.body]
                view.lookat[2] = camera.height
                renderer.update_scene(data, view)
                frames.append(renderer.render().copy())
            drawn.append(frames)
    return drawn
