"""Footfall timing and angles from DeepLabCut tracks: a synthetic walk of known timing and
geometry is recovered; bad files get clear errors; a real clip of the public data set (when its
repository has been fetched) reads as a walk."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gaitgram.seed.dlc import KEYPOINTS, measure, read_clip, summarise

FPS, PERIOD_FRAMES, DUTY, STRIDES = 15, 16, 0.625, 5  # every event on a frame: exact answers
LANDS = {"LeftHind": 0.0, "LeftFront": 0.25, "RightHind": 0.5, "RightFront": 0.75}
PASTERN = 30.0  # degrees the pastern turns from the cannon: the fetlock angle to recover


def hoof_x(frame: np.ndarray, lands: float, speed: float) -> np.ndarray:
    """A hoof still on the ground for DUTY of each stride, then swinging forward one stride."""
    stride = speed * PERIOD_FRAMES
    phase = (frame / PERIOD_FRAMES - lands) % 1.0
    cycles = np.floor(frame / PERIOD_FRAMES - lands)
    swing = np.clip((phase - DUTY) / (1 - DUTY), 0, 1)
    return (cycles + lands) * stride + swing * stride


def synthetic_walk(path: Path, direction: int = 1) -> None:
    frames = np.arange(STRIDES * PERIOD_FRAMES)
    speed = 20.0  # pixels per frame
    body = frames * speed
    points: dict[str, np.ndarray] = {}
    points["Withers"] = np.column_stack([body + 300, np.full_like(body, 400)])
    points["Hip"] = np.column_stack([body, np.full_like(body, 400)])
    points["Poll"] = np.column_stack([body + 450, np.full_like(body, 300)])
    points["Nostril"] = np.column_stack([body + 500, np.full_like(body, 420)])
    for limb, lands in LANDS.items():
        end = "Front" if "Front" in limb else "Hind"
        side = "Left" if limb.startswith("Left") else "Right"
        x = hoof_x(frames, lands, speed) + (300 if end == "Front" else 0)
        hoof = np.column_stack([x, np.full_like(x, 900)])
        turn = math.radians(PASTERN)  # the pastern points this much forward of straight down
        fetlock = hoof - 60 * np.array([math.sin(turn), math.cos(turn)])  # image y down: up is -y
        upper = fetlock - np.array([0.0, 200.0])
        points[f"{side}{end}Hoof"] = hoof
        points[f"{side}{end}Fetlock"] = fetlock
        points[f"{side}{'Knee' if end == 'Front' else 'Hock'}"] = upper
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["scorer", *["DLC_test"] * 48])
        writer.writerow(["bodyparts", *[k for k in KEYPOINTS for _ in range(3)]])
        writer.writerow(["coords", *["x", "y", "likelihood"] * 16])
        for frame in frames:
            row = []
            for keypoint in KEYPOINTS:
                x, y = points[keypoint][frame]
                row += [direction * x + (2000 if direction < 0 else 0), y, 0.99]
            writer.writerow([frame, *row])


@pytest.mark.parametrize("direction", [1, -1], ids=["walking-right", "walking-left"])
def test_a_synthetic_walk_is_recovered(tmp_path: Path, direction: int) -> None:
    path = tmp_path / "walk.csv"
    synthetic_walk(path, direction)
    summary = summarise(measure([read_clip(path, FPS)]))
    assert summary["stride_frequency_hz"] == pytest.approx(FPS / PERIOD_FRAMES, rel=0.02)
    assert summary["duty_factor"]["median"] == pytest.approx(DUTY, abs=0.001)
    offsets = summary["phase_after_left_hind"]
    for limb, lands in LANDS.items():
        assert offsets[f"{limb}Hoof"]["median"] == pytest.approx(lands, abs=0.001)
    fetlock = summary["curves"]["fetlock_fore"]
    assert np.mean(fetlock["mean"]) == pytest.approx(PASTERN, abs=0.5)  # positive: pastern forward
    assert fetlock["range_of_motion"] == pytest.approx(0, abs=0.5)


def test_the_cli_writes_the_summary_and_refuses_bad_tracks(tmp_path: Path) -> None:
    synthetic_walk(tmp_path / "walk.csv")
    out = tmp_path / "summary.json"
    run = [sys.executable, "-m", "gaitgram", "seed", "derive"]
    done = subprocess.run([*run, str(tmp_path / "walk.csv"), "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert json.loads(out.read_text())["strides"] > 0
    again = subprocess.run([*run, str(tmp_path / "walk.csv"), "-o", str(out)], capture_output=True, text=True)
    assert again.returncode == 2
    assert "exists" in again.stderr
    bad = tmp_path / "bad.csv"
    bad.write_text("frame,x\n1,2\n")
    refused = subprocess.run([*run, str(bad), "-o", str(tmp_path / "b.json")], capture_output=True, text=True)
    assert refused.returncode == 2
    assert "not a DeepLabCut CSV" in refused.stderr
    assert "Traceback" not in refused.stderr
    assert not (tmp_path / "b.json").exists()
    missing = subprocess.run(
        [*run, str(tmp_path / "gone.h5"), "-o", str(tmp_path / "c.json")], capture_output=True, text=True
    )
    assert missing.returncode == 2
    assert "no such file" in missing.stderr


MIRROR = Path("/work/.mirror/NarimanNiknejad+DLC_Horse/repo")


@pytest.mark.skipif(not MIRROR.exists(), reason="the DLC_Horse repository has not been fetched here")
def test_a_real_clip_reads_as_a_walk(tmp_path: Path) -> None:
    pytest.importorskip("h5py", reason="h5py (the dlc extra) is not installed")
    listed = subprocess.run(
        ["git", "--git-dir", str(MIRROR), "ls-tree", "-r", "--name-only", "HEAD"],
        capture_output=True,
        text=True,
    )
    name = next(line for line in listed.stdout.splitlines() if line.endswith(".h5"))
    clip = tmp_path / "clip.h5"
    clip.write_bytes(
        subprocess.run(["git", "--git-dir", str(MIRROR), "show", f"HEAD:{name}"], capture_output=True).stdout
    )
    summary = summarise(measure([read_clip(clip)]))
    assert summary["strides"] >= 2
    assert 0.5 < summary["stride_frequency_hz"] < 1.6  # a walk, at 15 fps


def test_the_seed_agrees_with_the_measured_walks() -> None:
    """seeds/dlc_walk.json (derived from 169 real walks) against the bundled seed and the walk the
    backend imposes: the agreement seeds/README.md claims."""
    from gaitgram.backends.mujoco_horse.task import WALK_PHASE_OFFSETS, walk_targets
    from gaitgram.seed.data import load_seed

    measured = json.loads((Path(__file__).resolve().parents[2] / "seeds" / "dlc_walk.json").read_text())
    assert measured["clips"] == 169
    lands = measured["phase_after_left_hind"]
    for hoof, limb in [
        ("LeftFrontHoof", "fore_left"),
        ("RightHindHoof", "hind_right"),
        ("RightFrontHoof", "fore_right"),
    ]:
        assert lands[hoof]["median"] == pytest.approx(WALK_PHASE_OFFSETS[limb], abs=0.03)
    assert measured["duty_factor"]["median"] == pytest.approx(walk_targets().duty_factor, abs=0.06)
    # Walk criterion v2 judges footfalls and duty factor by these very measurements.
    from gaitgram.backends.mujoco_horse.task import WALK_DUTY_LOW, WALK_FOOTFALLS

    for hoof, limb in [
        ("LeftFrontHoof", "fore_left"),
        ("RightHindHoof", "hind_right"),
        ("RightFrontHoof", "fore_right"),
    ]:
        assert WALK_FOOTFALLS[limb] == pytest.approx(lands[hoof]["median"], abs=0.001)
    assert measured["duty_factor"]["iqr"][0] == WALK_DUTY_LOW
    # The refitted seed swings its fetlocks more than the real walks' mean curve, within about 15 % of
    # their median range in a single stride (the model's limbs need larger joint excursions for a
    # stride of the real length: docs/fitness.md).
    seed = load_seed()
    for joint in ("fetlock_fore", "fetlock_hind"):
        seed_range = float(np.ptp(seed.angles[joint]))
        curve = measured["curves"][joint]
        assert curve["range_of_motion"] < seed_range, joint
        assert seed_range == pytest.approx(curve["median_stride_range"], rel=0.15), joint
