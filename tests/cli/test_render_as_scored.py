"""``gaitgram render`` and a report's GIFs play a gait as it is scored, through the backend's render
hook: a closed loop (grammars/hybrid-feedback.gg) through its control loop, drawn from the states
it recorded; an open loop to the byte as before (a committed report's GIF, made again)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageSequence

from conftest import GRAMMARS, ROOT
from gaitgram.language import load
from gaitgram.seed.grammars import seed_genome

ENV = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl"), "COLUMNS": "300"}
FEEDBACK = GRAMMARS / "hybrid-feedback.gg"


def gaitgram(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args], cwd=cwd, capture_output=True, text=True, env=ENV
    )


def seed_with(grammar: Path, **picks: int) -> str:
    """The genome of the grammar's seed (every feedback gain 0), with ``picks`` chosen otherwise."""
    return ",".join(map(str, seed_genome(load(grammar), picks)))


def frames(path: Path) -> list[np.ndarray]:
    return [
        np.asarray(frame.convert("RGB"), dtype=float) for frame in ImageSequence.Iterator(Image.open(path))
    ]


def test_a_closed_loop_gait_is_drawn_as_it_is_scored(tmp_path: Path) -> None:
    """The feedback grammar's seed with its gains at the ends of their ranges (+1*pitch
    +0.1*pitch_rate -5*(load-1) on the hip, shoulder and fetlocks) is drawn through its loop: the
    same standing start as the seed with every gain 0 (its open-loop part), then another gait."""
    closed = seed_with(FEEDBACK, pitch_gain=20, pitch_rate_gain=20, load_gain=0)
    open_part = seed_with(FEEDBACK)
    assert closed != open_part
    for name, genome in (("closed", closed), ("open", open_part)):
        done = gaitgram(
            "render", str(FEEDBACK), "--genome", genome, "-o", f"{name}.gif", "--fps", "5", cwd=tmp_path
        )
        assert done.returncode == 0, done.stderr
        assert "Traceback" not in done.stderr
    looped, still = frames(tmp_path / "closed.gif"), frames(tmp_path / "open.gif")
    assert len(looped) == len(still) > 10
    assert np.array_equal(looped[0], still[0])  # both stand still before the first step
    apart = [np.abs(a - b).mean() for a, b in zip(looped, still, strict=True)]
    assert max(apart[len(apart) // 2 :]) > 2  # the feedback moved the horse otherwise


def test_an_open_loop_gif_is_the_committed_one_to_the_byte(tmp_path: Path) -> None:
    """Table 5's hybrid arm reported with --gaits 1 draws its best walk as the committed report did
    (docs/results/table5/walk-hybrid.gif, made when gaits were stepped from their control arrays)."""
    arm = ROOT / "docs" / "results" / "table5" / "runs" / "arms" / "hybrid"
    done = gaitgram("report", str(arm), "-o", "report", "--gaits", "1", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    made = (tmp_path / "report" / "walk-hybrid.gif").read_bytes()
    assert made == (ROOT / "docs" / "results" / "table5" / "walk-hybrid.gif").read_bytes()
