"""``gaitgram report --watch``: a study still running is reported over its finished runs, again as
more finish, its page reloading itself; once all have, the report is the ordinary one."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.report.make import HTML, watch_report
from gaitgram.report.records import ReportError, load_arms

runner = CliRunner()
REFRESH = re.compile(r'<meta http-equiv="refresh" content="(\d+)">')


def unfinish(study: Path, arm: str, run: int, keep: int) -> tuple[Path, str]:
    """The run's stats cut to ``keep`` generations, as while it runs; the file and its text."""
    stats = study / "arms" / arm / f"run-{run:03d}" / "stats.jsonl"
    text = stats.read_text()
    stats.write_text("".join(text.splitlines(keepends=True)[:keep]))
    return stats, text


def test_a_running_study_is_reported_over_its_finished_runs_until_all_have(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    finished = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "final")])
    assert finished.exit_code == 0, finished.stderr
    gamma, gamma_text = unfinish(study, "gamma", 2, 2)
    beta = [unfinish(study, "beta_front", run, 1 + run % 2) for run in range(3)]  # no run finished

    pages: list[str] = []
    summaries: list[str] = []

    def sleep(seconds: float) -> None:
        assert seconds == 5
        pages.append((tmp_path / "watched" / HTML).read_text())
        summaries.append((tmp_path / "watched" / "summary.md").read_text())
        if len(pages) == 1:
            gamma.write_text(gamma_text)  # gamma's last run finishes
        elif len(pages) == 2:
            pass  # nothing new: the report is not made again
        else:
            for path, text in beta:
                path.write_text(text)

    messages: list[str] = []
    watch_report([study], tmp_path / "watched", interval=5, sleep=sleep, progress=messages.append)
    assert len(pages) == 3
    assert messages == [
        f"5 of 9 runs finished: wrote {tmp_path / 'watched' / HTML}",
        f"6 of 9 runs finished: wrote {tmp_path / 'watched' / HTML}",
        f"9 of 9 runs finished: wrote {tmp_path / 'watched' / HTML}",
    ]
    first = pages[0]
    assert REFRESH.findall(first) == ["5"]
    assert first.index("Study in progress") < first.index('<section id="summary"')  # said first
    assert "5 of 9 runs finished" in first
    assert "alpha 3 of 3, gamma 2 of 3" in first
    assert "<td>beta_front</td>" not in first  # no run of it finished: left out
    assert "| gamma | 2 |" in summaries[0]
    assert "6 of 9 runs finished" in pages[1]
    assert "| gamma | 3 |" in summaries[1]
    assert pages[2] == pages[1]  # nothing finished in between: not made again
    final = tmp_path / "watched"
    assert not REFRESH.findall((final / HTML).read_text())
    for name in ("summary.md", "summary.csv", "summary.json", "tables.tex", HTML):
        assert (final / name).read_bytes() == (tmp_path / "final" / name).read_bytes(), name


def test_watch_on_a_finished_study_is_the_ordinary_report(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    ordinary = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "a")])
    watched = runner.invoke(app, ["report", "--watch", str(study), "-o", str(tmp_path / "b")])
    assert watched.exit_code == 0, watched.stderr
    assert watched.stdout == ordinary.stdout
    assert "9 of 9 runs finished" in watched.stderr
    assert (tmp_path / "b" / HTML).read_bytes() == (tmp_path / "a" / HTML).read_bytes()


def test_only_a_plain_report_refuses_unfinished_runs(tmp_path: Path) -> None:
    study = write_hand_made_study(tmp_path / "study")
    unfinish(study, "alpha", 1, 2)
    with pytest.raises(ReportError, match="the run has 1 of its 2 generations"):
        load_arms([study])
    arms, _ = load_arms([study], finished_only=True)
    alpha = next(a for a in arms if a.name == "alpha")
    assert alpha.numbers == (0, 2)
    assert alpha.planned_runs == 3
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "r")])
    assert result.exit_code == 2
    assert "finish it first" in result.stderr


def test_ctrl_c_stops_a_watch_leaving_a_page_that_no_longer_reloads(tmp_path: Path) -> None:
    """As the user meets it: ``report --watch`` in a process of its own, a real SIGINT once its first
    page is written. It says what it kept, exits 130 and leaves the report of the runs finished so
    far whole, its page saying the watch stopped instead of reloading itself forever; the same
    command with --force carries on once the last run has finished."""
    study = write_hand_made_study(tmp_path / "study")
    gamma, gamma_text = unfinish(study, "gamma", 2, 2)
    out = tmp_path / "watched"
    command = [
        sys.executable,
        "-m",
        "gaitgram",
        "report",
        str(study),
        "-o",
        str(out),
        "--watch",
        "--interval",
        "1",
    ]
    environment = {**os.environ, "NO_COLOR": "1", "COLUMNS": "400"}
    watching = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=environment,
        # Ctrl-C as a terminal delivers it: a suite started in the background (``pytest &``) ignores
        # SIGINT, which its children inherit, and Python then never raises KeyboardInterrupt.
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        assert watching.stderr is not None
        said = watching.stderr.readline()  # its first page written whole, and said (then it sleeps)
        assert said.endswith(f"runs finished: wrote {out / HTML}\n"), said
        assert REFRESH.findall((out / HTML).read_text()) == ["1"]
        watching.send_signal(signal.SIGINT)
        _, rest = watching.communicate(timeout=120)
        stderr = said + rest
    finally:
        watching.kill()
    assert watching.returncode == 130, stderr
    assert stderr.splitlines()[-1] == (
        f"interrupted: {out / HTML} is the report of the 8 of 9 runs finished so far, and no longer "
        "reloads itself; `gaitgram report --watch` again follows the study"
    )
    page = (out / HTML).read_text()
    assert not REFRESH.findall(page)
    assert "8 of 9 runs finished" in page
    assert "was stopped here and this page no longer reloads itself" in page
    assert "reloads itself every" not in page
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]  # nothing left over
    gamma.write_text(gamma_text)
    again = runner.invoke(app, ["report", str(study), "-o", str(out), "--watch", "--force"])
    assert again.exit_code == 0, again.stderr
    assert "9 of 9 runs finished" in again.stderr
    assert "Study in progress" not in (out / HTML).read_text()
