"""Offscreen rendering of one gait: a GIF (or MP4 with ffmpeg) and a strip of frames like Fig. 1.

The gait is replayed with the evaluator's own control array, stepping in
Python (rollout records no pixels), so what is shown is what was scored.
Needs an OpenGL backend without a display: ``MUJOCO_GL=egl`` (set by the
command before MuJoCo is imported) works on the CPU here.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import mujoco
import numpy as np

from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator
from gaitgram.backends.mujoco_horse.model import STATE_SPEC


class RenderError(RuntimeError):
    pass


def render_frames(
    evaluator: HorseEvaluator, control: np.ndarray, *, fps: int = 25, width: int = 480, height: int = 360
) -> list[np.ndarray]:
    """RGB frames of one gait's control array [steps, actuators], a side view following the trunk."""
    model = evaluator.model
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, evaluator.initial_state, STATE_SPEC)
    mujoco.mj_forward(model, data)
    try:
        renderer = mujoco.Renderer(model, height=height, width=width)
    except Exception as error:  # no GL: the message from MuJoCo is the useful part
        raise RenderError(
            f"cannot render offscreen ({error}); set MUJOCO_GL=egl (or osmesa with libosmesa6 installed)"
        ) from None
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    camera.distance, camera.azimuth, camera.elevation = 4.5, 90.0, -8.0
    every = max(1, round(1.0 / (fps * model.opt.timestep)))
    frames = []
    with renderer:
        for step in range(control.shape[0]):
            data.ctrl[:] = control[step]
            mujoco.mj_step(model, data)
            if step % every == 0:
                camera.lookat[:] = data.xpos[evaluator.layout.trunk_body]
                camera.lookat[2] = 1.0
                renderer.update_scene(data, camera)
                frames.append(renderer.render().copy())
    return frames


def write_animation(frames: list[np.ndarray], path: Path, fps: int = 25) -> Path:
    """GIF through Pillow; MP4 through ffmpeg when the path ends in .mp4 and ffmpeg exists."""
    from PIL import Image

    if path.suffix.lower() == ".mp4":
        ffmpeg = shutil.which("ffmpeg")
        if ffmpeg is None:
            raise RenderError("MP4 needs ffmpeg (apt-get install ffmpeg); write a .gif instead")
        with tempfile.TemporaryDirectory() as tmp:
            for i, frame in enumerate(frames):
                Image.fromarray(frame).save(Path(tmp) / f"{i:05d}.png")
            subprocess.run(
                [
                    ffmpeg,
                    "-y",
                    "-loglevel",
                    "error",
                    "-framerate",
                    str(fps),
                    "-i",
                    str(Path(tmp) / "%05d.png"),
                    "-pix_fmt",
                    "yuv420p",
                    str(path),
                ],
                check=True,
            )
        return path
    images = [Image.fromarray(frame) for frame in frames]
    images[0].save(path, save_all=True, append_images=images[1:], duration=round(1000 / fps), loop=0)
    return path


def write_strip(frames: list[np.ndarray], path: Path, count: int = 8) -> Path:
    """``count`` evenly spaced frames side by side, as the paper's Fig. 1 shows a stride."""
    from PIL import Image

    chosen = [frames[i] for i in np.linspace(0, len(frames) - 1, count).round().astype(int)]
    Image.fromarray(np.concatenate(chosen, axis=1)).save(path)
    return path
