"""``gaitgram seed derive`` on the longest DeepLabCut CSV it reads: peak memory and time.

A synthetic walk of ``MAX_FRAMES`` frames (a horse walking past for hours) is written the way
DeepLabCut writes (full-precision floats), then measured in a fresh process, whose peak resident
memory is read from the kernel. Baseline: the file's own size; reading it into Python lists of
strings, as the first version of the reader did, took 15 times that (1.9 GB for a 127 MB file).
"""

from __future__ import annotations

import csv
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gaitgram.seed.dlc import KEYPOINTS, MAX_FRAMES

PERIOD, DUTY, SPEED = 16, 0.625, 1.5  # frames per stride, share in stance, pixels per frame


def write_walk(path: Path, frames: int) -> None:
    """Every hoof still for DUTY of its stride, then swinging one stride forward; the body steady."""
    t = np.arange(frames, dtype=np.float64)
    body = t * SPEED
    lands = {"LeftHindHoof": 0.0, "LeftFrontHoof": 0.25, "RightHindHoof": 0.5, "RightFrontHoof": 0.75}
    columns = []
    for index, keypoint in enumerate(KEYPOINTS):
        if keypoint in lands:
            phase = (t / PERIOD - lands[keypoint]) % 1.0
            swing = np.clip((phase - DUTY) / (1 - DUTY), 0, 1)
            x = (np.floor(t / PERIOD - lands[keypoint]) + lands[keypoint] + swing) * SPEED * PERIOD
        else:
            x = body + 10.0 * index
        columns += [x + 0.123456789012345, np.full(frames, 400.0 + 30 * index), np.full(frames, 0.99)]
    values = np.column_stack(columns)
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["scorer", *["DLC_benchmark"] * 3 * len(KEYPOINTS)])
        writer.writerow(["bodyparts", *[k for k in KEYPOINTS for _ in range(3)]])
        writer.writerow(["coords", *["x", "y", "likelihood"] * len(KEYPOINTS)])
        for frame, row in enumerate(values):
            writer.writerow([frame, *map(repr, row.tolist())])


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        track = Path(tmp) / "walk.csv"
        write_walk(track, MAX_FRAMES)
        size = track.stat().st_size
        start = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-m", "gaitgram", "seed", "derive", str(track), "-o", str(Path(tmp) / "w.json")],
            capture_output=True,
            text=True,
            check=False,
        )
        seconds = time.perf_counter() - start
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024  # Linux: KiB
    if done.returncode != 0:
        raise SystemExit(done.stderr)
    print(
        f"{MAX_FRAMES:,} frames, {size / 1e6:.0f} MB of CSV: {seconds:.1f} s, peak memory {peak / 1e6:.0f} MB"
    )
    print(f"  ({peak / size:.1f} bytes of memory per byte of CSV; {done.stderr.strip()[:60]}...)")
