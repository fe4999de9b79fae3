"""Output paths as the user meets them: every command that writes files checks them all before it
does any work, names them as they were written (never a temporary file beside them), writes to
devices such as /dev/null, and leaves nothing half-made when it fails.

Paths are relative to the working directory, as a user types them, so that the messages can be
compared exactly.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.cli import app

runner = CliRunner()
SINE_WALK = GRAMMARS / "sine-walk.gg"
GENOME = ["--genome", "5,17,3,99,1000,42,7,8,9,10,11,12,13", "--max-wraps", "10"]
IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0

#: A one-generation curve-match run: a backend that scores curves and judges no walks.
CURVE_GRAMMAR = """\
<gait> ::= <hip>;<elbow>
@joint hip_hind
<hip> ::= int[0..20]*sin(2*PI*t+float[0..3 step 0.5])
@joint elbow_fore
<elbow> ::= int[0..20]*sin(2*PI*t+float[0..3 step 0.5])
"""
CURVE_CONFIG = """\
generations = 1
population = 8
elite = 1
backend = "curve-match"

[backend_settings.targets]
hip_hind = "7*sin(2*PI*t+1.5)"
elbow_fore = "3*sin(2*PI*t+0.5)"
"""


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The working directory, holding a regular file to put paths under and a directory."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "plain").write_text("a file, not a directory\n")
    (tmp_path / "folder").mkdir()
    return tmp_path


def gaitgram(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "MUJOCO_GL": "egl", "NO_COLOR": "1", "COLUMNS": "300"}
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )


def curve_run(where: Path, strategy: str = "ge") -> Path:
    (where / "curve.gg").write_text(CURVE_GRAMMAR)
    (where / "curve.toml").write_text(CURVE_CONFIG)
    done = runner.invoke(
        app, ["evolve", "curve.gg", "-c", "curve.toml", "--strategy", strategy, "-o", strategy, "-q"]
    )
    assert done.exit_code == 0, done.stderr
    return where / strategy


def everything_in(directory: Path) -> set[str]:
    return {str(p.relative_to(directory)) for p in directory.rglob("*")}


# ---- file outputs -------------------------------------------------------------------------------

FILE_COMMANDS = {
    "compile": ["compile", str(SINE_WALK)],
    "plot": ["plot", str(SINE_WALK), *GENOME],
    "seed grammar": ["seed", "grammar", "--style", "free"],
    "render": ["render", str(SINE_WALK), *GENOME, "--fps", "2"],
}


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_a_file_output_is_checked_before_the_work(here: Path, command: str) -> None:
    """A missing directory, a file where a directory should be, a directory where the file
    should be: refused first (render would otherwise simulate and draw the whole gait), naming
    the path as written and the option to change."""
    args = FILE_COMMANDS[command]
    suffix = ".gif" if command == "render" else ".png" if command == "plot" else ".txt"
    before = everything_in(here)
    cases = {
        f"nodir/out{suffix}": "no such directory nodir; create it first, or choose another -o",
        f"plain/out{suffix}": "plain is not a directory; choose another -o",
    }
    for path, reason in cases.items():
        done = runner.invoke(app, [*args, "-o", path])
        assert done.exit_code == 2, done.stderr
        assert done.stderr == f"error: cannot write {path}: {reason}\n"
    (here / f"shelf{suffix}").mkdir()  # render and plot choose the format by the suffix
    done = runner.invoke(app, [*args, "-o", f"shelf{suffix}"])
    assert done.stderr == f"error: cannot write shelf{suffix}: is a directory; choose another -o\n"
    assert everything_in(here) == {*before, f"shelf{suffix}"}


def test_seed_derive_checks_its_output_before_reading_the_tracks(here: Path) -> None:
    track = here / "walk.csv"
    track.write_text("not read: the output is refused first\n")
    done = runner.invoke(app, ["seed", "derive", str(track), "-o", "nodir/walk.json"])
    assert done.exit_code == 2
    assert done.stderr == (
        "error: cannot write nodir/walk.json: no such directory nodir; create it first, or choose "
        "another -o\n"
    )


def test_render_checks_the_strip_before_rendering_and_writes_to_a_device(here: Path) -> None:
    render = ["render", str(SINE_WALK), *GENOME, "--fps", "2", "-o", "walk.gif"]
    missing = runner.invoke(app, [*render, "--strip", "nodir/strip.png"])
    assert missing.exit_code == 2
    assert missing.stderr == (
        "error: cannot write nodir/strip.png: no such directory nodir; create it first, or choose "
        "another --strip\n"
    )
    assert not (here / "walk.gif").exists()  # no animation without its strip
    folder = runner.invoke(app, [*render, "--strip", "folder"])
    assert folder.stderr == "error: cannot write folder: is a directory; choose another --strip\n"
    same = runner.invoke(app, [*render, "--strip", "walk.gif"])
    assert same.exit_code == 2
    assert same.stderr == "error: --strip walk.gif is the animation's own file; give the strip another name\n"

    done = gaitgram(*render, "--strip", "/dev/null", cwd=here)  # a device is written to, never "exists"
    assert done.returncode == 0, done.stderr
    assert "and /dev/null;" in done.stderr
    assert (here / "walk.gif").read_bytes()[:6] == b"GIF89a"
    assert not (here / "walk.png").exists()


def test_an_existing_output_needs_force_and_says_which(here: Path) -> None:
    (here / "walk.gif").write_bytes(b"mine")
    (here / "walk.png").write_bytes(b"mine too")
    render = ["render", str(SINE_WALK), *GENOME, "--fps", "2", "-o", "walk.gif"]
    done = runner.invoke(app, [*render, "--strip", "other.png"])
    assert done.stderr == "error: walk.gif exists; pass --force to overwrite it, or choose another -o\n"
    done = runner.invoke(app, ["render", str(SINE_WALK), *GENOME, "-o", "new.gif", "--strip", "walk.png"])
    assert done.stderr == "error: walk.png exists; pass --force to overwrite it, or choose another --strip\n"
    assert (here / "walk.gif").read_bytes() == b"mine"
    assert not (here / "new.gif").exists()


@pytest.mark.skipif(IS_ROOT, reason="root may write any file")
def test_a_read_only_grammar_is_not_rewritten(here: Path) -> None:
    """fmt and check --fix leave a read-only file alone and say so (a rename could replace it)."""
    grammar = here / "locked.gg"
    grammar.write_text("<a> ::=   x | | y\n")
    grammar.chmod(0o444)
    for args in (["fmt", "locked.gg"], ["check", "--fix", "locked.gg"]):
        done = runner.invoke(app, args)
        assert done.exit_code == 2
        assert "error: cannot write locked.gg: permission denied (the file is read-only)\n" in done.stderr
    assert grammar.read_text() == "<a> ::=   x | | y\n"


# ---- directory outputs --------------------------------------------------------------------------


def test_directory_outputs_are_checked_before_the_work(here: Path) -> None:
    """evolve, study and report make their directory (and its parents); a file in the way, or
    above it, is refused before the grammar or the runs are read."""
    (here / "study.toml").write_text('title = "t"\nruns = 1\n[[arm]]\nname = "a"\ngrammar = "missing.gg"\n')
    commands = {
        "evolve": (["evolve", "missing.gg", "-o"], "--out"),
        "study": (["study", "study.toml", "-o"], "-o"),
        "report": (["report", "missing-run", "-o"], "-o"),
    }
    before = everything_in(here)
    for name, (args, flag) in commands.items():
        done = runner.invoke(app, [*args, "plain"])
        assert done.exit_code == 2, (name, done.stderr)
        assert (
            done.stderr
            == f"error: cannot make the directory plain: a file of that name exists; choose another {flag}\n"
        )
        done = runner.invoke(app, [*args, "plain/sub"])
        assert (
            done.stderr == f"error: cannot write plain/sub: plain is not a directory; choose another {flag}\n"
        )
    assert everything_in(here) == before


@pytest.mark.skipif(IS_ROOT, reason="root may write in any directory")
def test_a_run_that_cannot_be_written_is_not_resumed(here: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A stopped run whose directory became read-only: refused before a generation is computed,
    not after, when its checkpoint cannot be written."""
    import contextlib

    from gaitgram.cli import evolve

    (here / "curve.gg").write_text(CURVE_GRAMMAR)
    (here / "curve.toml").write_text(CURVE_CONFIG.replace("generations = 1", "generations = 3"))
    with monkeypatch.context() as patch:  # stopped after its first generation, as by Ctrl-C
        checkpointed = (here / "ge" / "run-000" / "checkpoint.json").exists
        patch.setattr(evolve, "stop_on_interrupt", lambda: contextlib.nullcontext(checkpointed))
        stopped = runner.invoke(app, ["evolve", "curve.gg", "-c", "curve.toml", "-o", "ge", "-q"])
    assert stopped.exit_code == 130, stopped.stderr
    stats = (here / "ge" / "run-000" / "stats.jsonl").read_text()
    (here / "ge" / "run-000").chmod(0o555)
    try:
        done = runner.invoke(app, ["evolve", "--resume", "ge", "-q"])
    finally:
        (here / "ge" / "run-000").chmod(0o755)
    assert done.exit_code == 2
    assert done.stderr == f"error: cannot write in {Path('ge', 'run-000')}: permission denied\n"
    assert (here / "ge" / "run-000" / "stats.jsonl").read_text() == stats


def test_a_failed_report_leaves_nothing_behind(here: Path) -> None:
    """Drawing the gaits of a Pareto front needs the horse: after the tables were written, a
    curve-match front fails, and the report directory (and the parents made for it) goes."""
    pytest.importorskip("pymoo", reason="pymoo is not installed (pip install 'gaitgram[nsga2]')")
    curve_run(here, "nsga2")
    done = runner.invoke(app, ["report", "nsga2", "--gaits", "1", "-o", "reports/front"])
    assert done.exit_code == 2
    assert "gaits are drawn on the mujoco-horse backend" in done.stderr
    assert not (here / "reports").exists()
    kept = runner.invoke(app, ["report", "nsga2", "-o", "reports/front"])
    assert kept.exit_code == 0, kept.stderr
    again = runner.invoke(app, ["report", "nsga2", "-o", "reports/front"])
    assert again.exit_code == 2
    assert again.stderr == (
        "error: reports/front/summary.md exists; pass --force to overwrite it, or choose another -o\n"
    )


def test_a_failed_study_leaves_no_directories_behind(here: Path) -> None:
    (here / "broken.gg").write_text("<a> ::= <nope>\n")
    (here / "study.toml").write_text('title = "t"\nruns = 1\n[[arm]]\nname = "a"\ngrammar = "broken.gg"\n')
    done = runner.invoke(app, ["study", "study.toml", "-o", "studies/deep/one"])
    assert done.exit_code == 2
    assert "<nope> is not defined" in done.stderr
    assert not (here / "studies").exists()


# ---- inputs are never outputs --------------------------------------------------------------------

READS = ", which this command reads: an output never replaces an input; choose another"


def contents(directory: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(directory)): p.read_bytes() for p in sorted(directory.rglob("*")) if p.is_file()
    }


def test_a_report_is_never_written_over_or_into_what_it_reads(here: Path) -> None:
    """``report RUN -o RUN --force`` would replace the run's summary.json: refused under every
    spelling of the run directory (its runs too), for a study as for a run, before anything is
    read; a directory of its own inside one is fine, and one that holds them (docs/results/NAME)."""
    run = curve_run(here)
    (here / "link").symlink_to("ge")
    (here / "study" / "arms").mkdir(parents=True)
    (here / "study" / "study.json").write_text("{}")
    before = contents(here)
    spellings = {
        "ge": "is the run directory ge",
        "ge/": "is the run directory ge",
        "./ge": "is the run directory ge",
        str(run): "is the run directory ge",
        "ge/run-000/..": "is the run directory ge",
        "link": "is the run directory ge",
        "link/run-000": "is run-000 of the run directory ge",
        "ge/run-000/deeper": "is inside run-000 of the run directory ge",
    }
    for out, why in spellings.items():
        done = runner.invoke(app, ["report", "ge", "-o", out, "--force"])
        assert done.exit_code == 2, (out, done.stderr)
        assert done.stderr == f"error: -o {Path(out)} {why}{READS} -o\n", out
    by_link = runner.invoke(app, ["report", "link/", "-o", str(run), "--force"])
    assert by_link.stderr == f"error: -o {run} is the run directory link{READS} -o\n"
    for out in ("study", "study/arms", "study/arms/plain/report"):
        done = runner.invoke(app, ["report", "study", "-o", out])
        assert done.exit_code == 2
        assert f"error: -o {out} is " in done.stderr
        assert f"the study directory study{READS} -o" in done.stderr
    assert contents(here) == before
    assert not (here / "ge" / "run-000" / "deeper").exists()
    inside = runner.invoke(app, ["report", "ge", "-o", "ge/report"])
    assert inside.exit_code == 0, inside.stderr
    above = runner.invoke(app, ["report", "ge", "-o", ".", "--force"])
    assert above.exit_code == 0, above.stderr
    assert {k: v for k, v in contents(here).items() if k in before} == before  # no input touched


def test_a_file_output_is_never_an_input_however_it_is_spelt(here: Path) -> None:
    """The grammar, a genome file, a seed CSV, a track, a run's records: refused as outputs, by a
    symlink, a hard link, ``..`` or an absolute path too, with or without --force."""
    (here / "g.gg").write_bytes(SINE_WALK.read_bytes())
    (here / "hard.gg").hardlink_to(here / "g.gg")
    (here / "soft.gg").symlink_to("g.gg")
    (here / "genome.png").write_text(GENOME[1] + "\n")  # a genome file that looks like a plot
    (here / "seed.csv").write_bytes((GRAMMARS.parent / "seeds" / "horse_walk.csv").read_bytes())
    (here / "tracks").mkdir()
    (here / "tracks" / "walk.csv").write_text("a track\n")
    run = curve_run(here)
    cases = [
        (["compile", "g.gg", "-o", "g.gg"], "-o g.gg", "the grammar g.gg"),
        (["compile", "g.gg", "-o", "hard.gg"], "-o hard.gg", "the grammar g.gg"),
        (["compile", "g.gg", "-o", "soft.gg", "-t", "ponyge2"], "-o soft.gg", "the grammar g.gg"),
        (["compile", "g.gg", "-o", "folder/../g.gg"], "-o folder/../g.gg", "the grammar g.gg"),
        (["compile", "g.gg", "-o", str(here / "g.gg")], f"-o {here / 'g.gg'}", "the grammar g.gg"),
        (
            ["plot", "g.gg", "--genome-file", "genome.png", "-o", "genome.png"],
            "-o genome.png",
            "the --genome-file genome.png",
        ),
        (
            ["seed", "grammar", "--style", "free", "--seed", "seed.csv", "-o", "seed.csv"],
            "-o seed.csv",
            "the --seed CSV seed.csv",
        ),
        (
            ["seed", "derive", "tracks", "-o", "tracks/walk.csv"],
            "-o tracks/walk.csv",
            "walk.csv of the folder of tracks tracks",
        ),
        (
            ["seed", "derive", "tracks", "-o", "tracks/next.csv"],
            "-o tracks/next.csv",
            "next.csv of the folder of tracks tracks",
        ),  # it would be read as a track next time
        (
            ["seed", "derive", "tracks/walk.csv", "-o", "tracks/walk.csv"],
            "-o tracks/walk.csv",
            "the track tracks/walk.csv",
        ),
        (
            ["render", "--run", "ge", "-o", "ge/run-000/walk.gif"],
            "-o ge/run-000/walk.gif",
            "inside run-000 of the run directory ge",
        ),
        (
            ["render", "--run", "ge", "-o", "walk.gif", "--strip", "ge/config.toml"],
            "--strip ge/config.toml",
            "config.toml of the run directory ge",
        ),
        (
            ["render", "--run", "link", "-o", "walk.gif", "--strip", str(run / "summary.json")],
            f"--strip {run / 'summary.json'}",
            "summary.json of the run directory link",
        ),
    ]
    (here / "link").symlink_to("ge")
    before = contents(here)
    for args, named, what in cases:
        done = runner.invoke(app, [*args, "--force"])
        assert done.exit_code == 2, (args, done.stderr)
        assert done.stderr == f"error: {named} is {what}{READS} {named.split()[0]}\n", args
    plot = ["plot", "g.gg", "--genome-file", "genome.png", "--max-wraps", "10", "-o", "curves.png"]
    plotted = runner.invoke(app, plot)
    assert plotted.exit_code == 0, plotted.stderr  # beside its inputs is fine
    assert contents(here) == {**before, "curves.png": (here / "curves.png").read_bytes()}
    beside = runner.invoke(app, ["render", "--run", "ge", "-o", "ge/best.gif"])
    assert "which this command reads" not in beside.stderr  # a new file beside a run's records: fine
    assert "render draws the mujoco-horse backend" in beside.stderr  # (a curve-match run has no horse)


# ---- --walk on a backend that judges no walks -----------------------------------------------------


def test_walk_on_a_backend_without_walks_says_so(here: Path) -> None:
    curve_run(here)
    for command in (
        ["evaluate", "--run", "ge", "--walk"],
        ["render", "--run", "ge", "--walk", "-o", "w.gif"],
    ):
        done = runner.invoke(app, command)
        assert done.exit_code == 2
        assert done.stderr == (
            "error: the curve-match backend of ge does not judge walks (it declares no verdict); drop --walk "
            "to see the run's best gait\n"
        )
    assert not (here / "w.gif").exists()
