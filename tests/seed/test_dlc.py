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
    from gaitgram.backends.mujoco_horse.targets import WALK_PHASE_OFFSETS, walk_targets
    from gaitgram.motion.seed_walk import load_seed

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
    from gaitgram.backends.mujoco_horse.targets import WALK_DUTY_LOW, WALK_FOOTFALLS

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


# ---- hostile tracks: non-finite values, ragged rows, bad options, oversize files ----------------

DERIVE = [sys.executable, "-m", "gaitgram", "seed", "derive"]


def derive(*args: str | Path) -> subprocess.CompletedProcess[str]:
    """``gaitgram seed derive`` in its own process, so that anything printed to stderr is seen."""
    return subprocess.run([*DERIVE, *map(str, args)], capture_output=True, text=True, check=False)


def edited(source: Path, target: Path, cells: dict[tuple[int, int], str]) -> Path:
    """A copy of a CSV track with some cells replaced: (line number, column number) -> text."""
    rows = list(csv.reader(source.open(newline="")))
    for (line, column), text in cells.items():
        rows[line - 1][column - 1] = text
    with target.open("w", newline="") as handle:
        csv.writer(handle).writerows(rows)
    return target


def column(keypoint: str, value: str) -> int:
    """The CSV column (1-based, after the frame number) of a landmark's x, y or likelihood."""
    return 2 + 3 * KEYPOINTS.index(keypoint) + ("x", "y", "likelihood").index(value)


def test_non_finite_values_are_missing_landmarks(tmp_path: Path) -> None:
    """inf, -inf, nan and absurd coordinates, and a non-finite likelihood, are read as missing
    landmarks (as a low likelihood is), interpolated over: the summary is the clean track's, and
    nothing is printed but the summary line."""
    clean = tmp_path / "clean.csv"
    synthetic_walk(clean)
    hostile = edited(
        clean,
        tmp_path / "hostile.csv",
        {
            (10, column("Poll", "y")): "inf",
            (14, column("Withers", "x")): "-inf",
            (20, column("LeftFrontHoof", "y")): "nan",
            (26, column("RightHindFetlock", "x")): "1e308",
            (30, column("Nostril", "x")): "-1e300",
            (34, column("LeftHock", "likelihood")): "inf",
            (34, column("LeftHock", "x")): "12345",  # a wild value behind the non-finite likelihood
        },
    )
    expected = derive(clean, "-o", tmp_path / "clean.json")
    assert expected.returncode == 0, expected.stderr
    done = derive(hostile, "-o", tmp_path / "hostile.json")
    assert done.returncode == 0, done.stderr
    assert done.stderr.startswith("1 clips"), done.stderr
    assert done.stderr.count("\n") == 1, done.stderr  # no warnings
    summary = json.loads((tmp_path / "hostile.json").read_text())
    assert summary == json.loads((tmp_path / "clean.json").read_text())


def test_a_gap_leaves_a_steady_angle_steady(tmp_path: Path) -> None:
    """The synthetic walk's fetlocks hold 30 degrees. A missing, infinite or unlikely cell of a
    limb's landmark where its path turns a corner (the frames about a hoof's landing, where a
    landmark interpolated on its own cuts the corner) leaves each fetlock curve at 30 degrees, as
    on the clean track (issue 39: one such cell made a fetlock's mean 33.1)."""
    clean = tmp_path / "clean.csv"
    synthetic_walk(clean)
    gaps = {
        (18, column("LeftFrontFetlock", "x")): "",
        (22, column("RightHindFetlock", "x")): "inf",
        (40, column("LeftFrontHoof", "x")): "nan",
        (55, column("LeftHock", "likelihood")): "0.1",
        (66, column("RightKnee", "y")): "-inf",
    }
    done = derive(edited(clean, tmp_path / "gaps.csv", gaps), "-o", tmp_path / "gaps.json")
    assert done.returncode == 0, done.stderr
    curves = json.loads((tmp_path / "gaps.json").read_text())["curves"]
    for joint in ("fetlock_fore", "fetlock_hind"):
        assert curves[joint]["mean"] == [PASTERN] * 20, joint
        assert curves[joint]["range_of_motion"] == 0, joint


def test_a_track_with_nothing_tracked_is_one_error_line(tmp_path: Path) -> None:
    """Every landmark under the likelihood threshold: no warning from numpy, one error naming the
    file and what to check."""
    clean = tmp_path / "walk.csv"
    synthetic_walk(clean)
    lines = len(clean.read_text().splitlines())
    cells = {(line, column(k, "likelihood")): "0.1" for line in range(4, lines + 1) for k in KEYPOINTS}
    done = derive(edited(clean, tmp_path / "untracked.csv", cells), "-o", tmp_path / "out.json")
    assert done.returncode == 2
    assert done.stderr.startswith("error: no walk strides found in untracked.csv: ")
    assert "likelihood" in done.stderr
    assert done.stderr.count("\n") == 1, done.stderr
    assert not (tmp_path / "out.json").exists()


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ("short", "{path}:13: 47 values where a frame has 49"),
        ("long", "{path}:13: 51 values where a frame has 49"),
        ("word", "{path}:13: column 5: 'oops' is not a number"),
        ("landmarks", "{path}:2: its landmarks are"),
        ("endless", "{path}:13: a line over 16,384 characters"),
    ],
)
def test_a_malformed_row_names_the_file_and_line(tmp_path: Path, change: str, message: str) -> None:
    clean = tmp_path / "walk.csv"
    synthetic_walk(clean)
    lines = clean.read_text().splitlines()
    fields = lines[12].split(",")
    lines[12] = {
        "short": ",".join(fields[:-2]),
        "long": ",".join([*fields, "1", "2"]),
        "word": ",".join([*fields[:4], "oops", *fields[5:]]),
        "landmarks": lines[12],
        "endless": ",".join(fields + ["1"] * 10_000),
    }[change]
    if change == "landmarks":
        lines[1] = lines[1].replace("Withers", "Wither")
    track = tmp_path / "track.csv"
    track.write_text("\n".join(lines) + "\n")
    done = derive(track, "-o", tmp_path / "out.json")
    assert done.returncode == 2
    assert done.stderr.startswith("error: " + message.format(path=track)), done.stderr
    assert "Traceback" not in done.stderr
    assert "sequence" not in done.stderr
    assert not (tmp_path / "out.json").exists()


def test_a_byte_order_mark_is_allowed(tmp_path: Path) -> None:
    """Excel and Windows tools save CSVs as UTF-8 with a byte order mark."""
    synthetic_walk(tmp_path / "walk.csv")
    (tmp_path / "bom.csv").write_bytes(b"\xef\xbb\xbf" + (tmp_path / "walk.csv").read_bytes())
    plain, marked = (
        derive(tmp_path / "walk.csv", "-o", tmp_path / "a.json"),
        derive(tmp_path / "bom.csv", "-o", tmp_path / "b.json"),
    )
    assert marked.returncode == 0, marked.stderr
    assert plain.returncode == 0, plain.stderr
    assert (tmp_path / "a.json").read_text() == (tmp_path / "b.json").read_text()


def test_bad_numeric_options_name_the_flag(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from gaitgram.cli import app

    synthetic_walk(tmp_path / "walk.csv")
    runner = CliRunner()
    for fps in ("inf", "-inf", "nan", "0", "-15", "1e9"):
        done = runner.invoke(
            app,
            ["seed", "derive", str(tmp_path / "walk.csv"), "-o", str(tmp_path / "out.json"), "--fps", fps],
        )
        assert done.exit_code == 2, (fps, done.stderr)
        assert "--fps" in done.stderr, (fps, done.stderr)
        assert "from 1 to 1000" in done.stderr, (fps, done.stderr)
        assert done.exception is None or isinstance(done.exception, SystemExit), (fps, done.exception)
    assert not (tmp_path / "out.json").exists()
    for command in ("fit", "grammar --style free"):
        threshold = runner.invoke(app, ["seed", *command.split(), "--threshold", "nan"])
        assert threshold.exit_code == 2
        assert "--threshold" in threshold.stderr
        assert "from 0 to 360 degrees" in threshold.stderr


def test_an_oversize_track_is_refused_without_reading_it_all(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Past MAX_FRAMES a track is refused (lowered here: the real limit is 500,000 frames, whose
    memory ``python -m benchmarks dlc`` measures), with a message saying why and what to do."""
    from typer.testing import CliRunner

    from gaitgram.cli import app
    from gaitgram.seed import dlc

    synthetic_walk(tmp_path / "walk.csv")  # 80 frames
    monkeypatch.setattr(dlc, "MAX_FRAMES", 50)
    read = []
    monkeypatch.setattr(dlc, "_numbers", lambda *args: read.append(1) or [0.0] * 48)
    done = CliRunner().invoke(
        app, ["seed", "derive", str(tmp_path / "walk.csv"), "-o", str(tmp_path / "o.json")]
    )
    assert done.exit_code == 2
    assert done.stderr == (
        f"error: {tmp_path / 'walk.csv'}: over 50 frames; tracks this long are refused (no walk lasts "
        "that long): split the video into clips\n"
    )
    assert len(read) == 50  # stopped at the limit
    assert not (tmp_path / "o.json").exists()


def write_h5(path: Path, csv_track: Path) -> None:
    """A DeepLabCut .h5 (pandas' "table" layout, as h5py sees it) holding a CSV track's values."""
    h5py = pytest.importorskip("h5py", reason="h5py (the dlc extra) is not installed")
    rows = list(csv.reader(csv_track.open(newline="")))[3:]
    values = np.array([[float(v) for v in row[1:]] for row in rows])
    table = np.zeros(len(values), dtype=[("index", "<i8"), ("values_block_0", "<f8", (values.shape[1],))])
    table["index"] = np.arange(len(values))
    table["values_block_0"] = values
    with h5py.File(path, "w") as data:
        data.create_dataset("df_with_missing/table", data=table)


def test_an_h5_track_reads_like_its_csv_and_is_bounded(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    clean = tmp_path / "walk.csv"
    synthetic_walk(clean)
    hostile = edited(clean, tmp_path / "hostile.csv", {(10, column("Poll", "y")): "inf"})
    write_h5(tmp_path / "walk.h5", hostile)
    expected = derive(clean, "-o", tmp_path / "csv.json")
    done = derive(tmp_path / "walk.h5", "-o", tmp_path / "h5.json")
    assert expected.returncode == 0, expected.stderr
    assert done.returncode == 0, done.stderr
    assert done.stderr.count("\n") == 1, done.stderr
    assert json.loads((tmp_path / "h5.json").read_text()) == json.loads((tmp_path / "csv.json").read_text())

    from gaitgram.seed import dlc

    monkeypatch.setattr(dlc, "MAX_FRAMES", 50)
    with pytest.raises(dlc.DlcError, match=r"walk\.h5: over 50 frames; .* split the video into clips"):
        read_clip(tmp_path / "walk.h5")
