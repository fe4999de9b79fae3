"""``gaitgram render``: MP4 as well as GIF (by the output's suffix), two gaits side by side, and the
install command when the video extra is missing. Real renders of a few frames, read back."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from gaitgram.animation import labelled, side_by_side, write_strip
from gaitgram.cli import app

ROOT = Path(__file__).resolve().parents[2]
GRAMMAR = ROOT / "grammars" / "sine-walk.gg"
GENOME = "5,17,3,99,1000,42,7,8,9,10,11,12,13"
ENV = {**os.environ, "MUJOCO_GL": "egl", "COLUMNS": "300"}


def gaitgram(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args], cwd=cwd, capture_output=True, text=True, env=ENV
    )


def frames_written(stderr: str) -> int:
    found = re.search(r"wrote \S+ \((\d+) frames\)", stderr)
    assert found, stderr
    return int(found[1])


def read_video(path: Path) -> tuple[np.ndarray, dict]:
    iio = pytest.importorskip("imageio.v3", reason="imageio is not installed (pip install 'gaitgram[video]')")
    pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg is not installed")
    return iio.imread(path, index=None, plugin="FFMPEG"), iio.immeta(path, plugin="FFMPEG")


def test_render_writes_an_mp4_chosen_by_the_suffix(tmp_path: Path) -> None:
    pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg is not installed")
    rendered = gaitgram(
        "render", str(GRAMMAR), "--genome", GENOME, "--max-wraps", "10", "-o", "walk.MP4", "--fps", "5",
        cwd=tmp_path,
    )  # fmt: skip
    assert rendered.returncode == 0, rendered.stderr
    frames, meta = read_video(tmp_path / "walk.MP4")
    assert frames.shape == (frames_written(rendered.stderr), 360, 480, 3)
    assert frames.shape[0] > 10
    assert meta["codec"] == "h264"
    assert meta["fps"] == 5
    assert meta["pix_fmt"].startswith("yuv420p")  # what browsers and phones play
    assert frames[-1].std() > 10  # a picture, not a blank frame
    assert (tmp_path / "walk.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.slow  # two horse runs and three videos
def test_a_run_beside_the_seed_and_beside_another_run(tmp_path: Path) -> None:
    pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg is not installed")
    evolved = gaitgram(
        "evolve", str(GRAMMAR), "--generations", "1", "--population", "8", "-o", "r", "-q", cwd=tmp_path
    )
    assert evolved.returncode == 0, evolved.stderr
    side = gaitgram("render", "--run", "r", "--compare", "seed", "-o", "side.mp4", "--fps", "4", cwd=tmp_path)
    assert side.returncode == 0, side.stderr
    assert "beside walk seed" in side.stderr
    frames, _ = read_video(tmp_path / "side.mp4")
    assert frames.shape == (frames_written(side.stderr), 360, 480 + 4 + 480, 3)
    assert (frames[:, :, 480:484] > 200).all()  # the white gap between the two horses
    from PIL import Image

    assert Image.open(tmp_path / "side.png").size == (8 * 480, 2 * 360)  # the seed's strip below

    twice = gaitgram("render", "--run", "r", "--compare", "r", "-o", "same.gif", "--fps", "4", cwd=tmp_path)
    assert twice.returncode == 0, twice.stderr
    gif = Image.open(tmp_path / "same.gif")
    assert gif.n_frames == frames_written(twice.stderr)
    gif.seek(gif.n_frames // 2)
    picture = np.asarray(gif.convert("RGB"), dtype=float)
    left, right = picture[40:, :480], picture[40:, 484:]
    assert np.abs(left - right).mean() < 2  # one gait, drawn twice in step

    missing = gaitgram("render", "--run", "r", "--compare", "nowhere", "-o", "x.gif", cwd=tmp_path)
    assert missing.returncode == 2
    assert "--compare nowhere: no run directory, `seed` or body by that name" in missing.stderr
    assert not (tmp_path / "x.gif").exists()


@pytest.mark.slow  # a horse run and two bodies rendered
def test_a_run_beside_itself_on_a_smaller_body(tmp_path: Path) -> None:
    """``--compare shetland``: the same gait on the Shetland, Froude-scaled, filmed by its own camera
    (scaled with the body, so the two are drawn at about one size)."""
    from PIL import Image

    evolved = gaitgram(
        "evolve", str(GRAMMAR), "--generations", "1", "--population", "8", "-o", "r", "-q", cwd=tmp_path
    )
    assert evolved.returncode == 0, evolved.stderr
    side = gaitgram(
        "render", "--run", "r", "--compare", "shetland", "-o", "pony.gif", "--fps", "4", cwd=tmp_path
    )
    assert side.returncode == 0, side.stderr
    assert "on shetland (Froude-scaled)" in side.stderr
    gif = Image.open(tmp_path / "pony.gif")
    assert gif.size == (480 + 4 + 480, 360)
    gif.seek(0)  # standing, before either moves
    picture = np.asarray(gif.convert("RGB"), dtype=float)
    left, right = picture[40:, :480], picture[40:, 484:]
    assert np.abs(left - right).mean() > 2  # two different pictures
    unknown = gaitgram("render", "--run", "r", "--compare", "shetlnd", "-o", "x.gif", cwd=tmp_path)
    assert unknown.returncode == 2
    assert "did you mean 'shetland'?" in unknown.stderr
    assert "Traceback" not in unknown.stderr
    assert not (tmp_path / "x.gif").exists()


def test_side_by_side_holds_the_shorter_gaits_last_frame() -> None:
    short = [np.full((6, 4, 3), 10 * i, np.uint8) for i in range(2)]
    long = [np.full((6, 4, 3), 100 + i, np.uint8) for i in range(5)]
    frames = side_by_side(short, long, gap=2)
    assert len(frames) == 5
    assert all(f.shape == (6, 10, 3) for f in frames)
    assert (frames[4][:, :4] == 10).all()  # held
    assert (frames[4][:, 4:6] == 255).all()
    assert (frames[4][:, 6:] == 104).all()


def test_labels_and_strips(tmp_path: Path) -> None:
    pytest.importorskip("PIL", reason="Pillow is not installed")
    from PIL import Image

    frames = [np.zeros((120, 160, 3), np.uint8) for _ in range(9)]
    (shown,) = labelled(frames[:1], "walk seed")
    assert shown[:30, :120].max() > 200  # light text on a dark band, top left
    assert shown[60:].max() == 0
    write_strip(frames, tmp_path / "s.png", count=4, below=frames[:3], labels=("a", "b"))
    assert Image.open(tmp_path / "s.png").size == (4 * 160, 2 * 120)


runner = CliRunner()


def test_a_missing_video_extra_names_the_install_command(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "imageio", None)  # as if not installed
    monkeypatch.setenv("COLUMNS", "300")
    result = runner.invoke(app, ["render", str(GRAMMAR), "--genome", GENOME, "-o", str(tmp_path / "v.mp4")])
    assert result.exit_code == 2
    assert "MP4 videos need imageio, which is not installed: pip install 'gaitgram[video]'" in result.stderr
    assert not list(tmp_path.iterdir())  # refused before anything is rendered or written
    gif = runner.invoke(app, ["render", str(GRAMMAR), "--genome", GENOME, "-o", str(tmp_path / "v.webm")])
    assert gif.exit_code == 2
    assert "written as .gif or .mp4, chosen by the suffix" in gif.stderr
