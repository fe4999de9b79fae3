"""Animations and strips of frames, whoever drew the frames: a GIF or an MP4, a strip like the
paper's Fig. 1, labels, two gaits side by side.

Frames are RGB arrays [height, width, 3] of ``uint8``, as a backend's render hook
(``BackendSpec.render``) gives them; nothing here knows what they show. Pillow writes GIFs and
strips, imageio with its ffmpeg MP4s (the ``video`` extra), each imported when needed.
"""

from __future__ import annotations

import io
import tempfile
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from gaitgram.extras import require
from gaitgram.fileio import write_output

__all__ = [
    "FORMATS",
    "RenderError",
    "animation_format",
    "encode_animation",
    "labelled",
    "require_writers",
    "side_by_side",
    "strip",
    "strip_png",
    "write_animation",
    "write_strip",
]


class RenderError(RuntimeError):
    """Frames that cannot be drawn or written (no offscreen OpenGL, an unknown format); says why."""


#: What ``render`` writes, by the output's suffix.
FORMATS = {".gif": "GIF", ".mp4": "MP4 (H.264)"}


def animation_format(path: Path) -> str:
    """The output's suffix (``.gif`` or ``.mp4``, any case), or a :class:`RenderError` saying which
    suffixes there are."""
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise RenderError(
            f"{path}: an animation is written as {' or '.join(FORMATS)}, chosen by the suffix of "
            f"the output, not {suffix or 'no suffix'}"
        )
    return suffix


def require_writers(path: Path) -> None:
    """Import what writing ``path`` needs (a :class:`~gaitgram.extras.MissingExtra` naming the
    extra if it is not installed): imageio and its ffmpeg for MP4, Pillow for GIF and strips."""
    if animation_format(path) == ".mp4":
        require("imageio", "MP4 videos")
        require("imageio_ffmpeg", "MP4 videos")
    require("PIL", "GIFs and strips of frames")


def encode_animation(frames: Sequence[np.ndarray], suffix: str, fps: int = 25) -> bytes:
    """The frames as a looping GIF (Pillow) or an H.264 MP4 (imageio with the ffmpeg that
    imageio-ffmpeg ships, ``yuv420p`` so that browsers and phones play it)."""
    if suffix == ".mp4":
        iio = require("imageio.v2", "MP4 videos")
        require("imageio_ffmpeg", "MP4 videos")
        with tempfile.TemporaryDirectory() as tmp:
            target = Path(tmp) / "animation.mp4"
            writer = iio.get_writer(
                target,
                format="FFMPEG",
                mode="I",
                fps=fps,
                codec="libx264",
                pixelformat="yuv420p",
                macro_block_size=2,  # yuv420p needs even sizes; frames are never resized
                output_params=["-movflags", "+faststart"],  # playable while it downloads
                ffmpeg_log_level="error",
            )
            with writer:
                for frame in frames:
                    writer.append_data(frame)
            return target.read_bytes()
    from PIL import Image

    images = [Image.fromarray(frame) for frame in frames]
    out = io.BytesIO()
    images[0].save(
        out, format="GIF", save_all=True, append_images=images[1:], duration=round(1000 / fps), loop=0
    )
    return out.getvalue()


def write_animation(frames: Sequence[np.ndarray], path: Path, fps: int = 25) -> Path:
    """GIF or MP4 by the suffix of ``path``, written as ``open(path, "w")`` would, never half-written."""
    write_output(path, encode_animation(frames, animation_format(path), fps))
    return path


def labelled(frames: Sequence[np.ndarray], text: str) -> list[np.ndarray]:
    """The frames with ``text`` written in their top left corner, light on a dark band."""
    from PIL import Image, ImageDraw, ImageFont

    try:
        font = ImageFont.load_default(size=18)
    except TypeError:  # Pillow before 10.1: one bitmap size
        font = ImageFont.load_default()
    out = []
    for frame in frames:
        image = Image.fromarray(frame)
        draw = ImageDraw.Draw(image)
        left, top, right, bottom = draw.textbbox((10, 8), text, font=font)
        draw.rectangle((left - 6, top - 4, right + 6, bottom + 4), fill=(20, 20, 20))
        draw.text((10, 8), text, font=font, fill=(245, 245, 245))
        out.append(np.asarray(image))
    return out


def side_by_side(left: Sequence[np.ndarray], right: Sequence[np.ndarray], gap: int = 4) -> list[np.ndarray]:
    """Two gaits' frames in one picture, in step: frame ``i`` of each, a white gap between. The
    shorter animation holds its last frame until the longer one ends."""
    if not left or not right:
        raise RenderError("nothing to show side by side: a gait has no frames")
    height = max(left[0].shape[0], right[0].shape[0])
    spacer = np.full((height, gap, 3), 255, dtype=np.uint8)
    frames = []
    for i in range(max(len(left), len(right))):
        a, b = left[min(i, len(left) - 1)], right[min(i, len(right) - 1)]
        frames.append(np.concatenate([_pad(a, height), spacer, _pad(b, height)], axis=1))
    return frames


def _pad(frame: np.ndarray, height: int) -> np.ndarray:
    if frame.shape[0] == height:
        return frame
    return np.concatenate([frame, np.full((height - frame.shape[0], *frame.shape[1:]), 255, np.uint8)])


def strip(frames: Sequence[np.ndarray], count: int = 8) -> np.ndarray:
    """``count`` evenly spaced frames side by side, as the paper's Fig. 1 shows a stride."""
    chosen = [frames[i] for i in np.linspace(0, len(frames) - 1, count).round().astype(int)]
    return np.concatenate(chosen, axis=1)


def write_strip(
    frames: Sequence[np.ndarray],
    path: Path,
    count: int = 8,
    *,
    below: Sequence[np.ndarray] = (),
    labels: Sequence[str] = (),
) -> Path:
    """:func:`strip_png`, written as ``open(path, "w")`` would, never half-written."""
    write_output(path, strip_png(frames, count, below=below, labels=labels))
    return path


def strip_png(
    frames: Sequence[np.ndarray],
    count: int = 8,
    *,
    below: Sequence[np.ndarray] = (),
    labels: Sequence[str] = (),
) -> bytes:
    """A PNG of :func:`strip`; with ``below``, a second gait's strip under the first; ``labels``
    names the rows, in their top left corner."""
    from PIL import Image

    rows = [strip(frames, count)] + ([strip(below, count)] if len(below) else [])
    rows = [labelled([row], text)[0] for row, text in zip(rows, labels, strict=False)] + rows[len(labels) :]
    width = max(row.shape[1] for row in rows)
    rows = [
        np.concatenate([r, np.full((r.shape[0], width - r.shape[1], 3), 255, np.uint8)], axis=1) for r in rows
    ]
    out = io.BytesIO()
    Image.fromarray(np.concatenate(rows, axis=0)).save(out, format="PNG")
    return out.getvalue()
