"""A command imports only what it uses: ``check``, ``fmt`` and ``map`` start without numpy, MuJoCo
or plotting (issue 28: ``gaitgram check`` of a small file in under 150 ms as a process).

This tests what is imported, not the time, which a busy machine would make flaky;
``python -m benchmarks check`` measures the time.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import GRAMMARS

HEAVY = ("numpy", "mujoco", "matplotlib", "scipy", "PIL", "dask", "hypothesis")

#: Run the command line in a fresh interpreter, then print which heavy packages it imported.
_PROBE = """
import json, sys
from gaitgram.cli import main
sys.argv = ["gaitgram", *json.loads(sys.argv[1])]
try:
    main()
except SystemExit as end:
    status = end.code
print(json.dumps({"status": status, "heavy": sorted(m for m in %r if m in sys.modules)}), file=sys.stderr)
"""


def imported(*args: str, watched: tuple[str, ...] = HEAVY) -> tuple[int, list[str]]:
    """The exit status of ``gaitgram ARGS`` and the ``watched`` modules it imported."""
    done = subprocess.run(
        [sys.executable, "-c", _PROBE % (watched,), json.dumps(args)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    report = json.loads(done.stderr.strip().splitlines()[-1])
    return report["status"], report["heavy"]


@pytest.fixture
def small(tmp_path: Path) -> Path:
    path = tmp_path / "small.gg"
    path.write_text("@start <curve>\n<curve> ::= sin(2*PI*t) | <curve> + 0.5\n")
    return path


@pytest.mark.parametrize(
    "args",
    [("check",), ("check", "--format", "json"), ("fmt", "--check"), ("map", "--genome", "1,2,3")],
    ids=["check", "check-json", "fmt", "map"],
)
def test_light_commands_import_no_numpy_mujoco_or_plotting(small: Path, args: tuple[str, ...]) -> None:
    command, *options = args
    status, heavy = imported(command, str(small), *options)
    assert status == 0
    assert heavy == []


def test_check_of_a_horse_grammar_imports_no_numpy() -> None:
    status, heavy = imported("check", str(GRAMMARS / "sine-walk.gg"))
    assert status == 0
    assert heavy == []


def test_check_to_a_pipe_starts_without_rich_consoles_pydantic_or_package_metadata() -> None:
    # Each of these cost `gaitgram check` 8-60 ms of its start-up (issue 28's 150 ms): a console
    # only colours a terminal, typer 0.29's coercion imports pydantic, importlib.metadata is read
    # only to record versions or list plug-ins, and package data is read by path (`packaged`).
    watched = ("rich.console", "rich.text", "pydantic", "importlib.metadata", "importlib.resources")
    status, found = imported("check", str(GRAMMARS / "sine-walk.gg"), watched=watched)
    assert status == 0
    assert found == []


def test_help_lists_the_lazily_loaded_commands_in_order() -> None:
    """The lazily loaded commands are the ones help lists, in the same order."""
    from typer.testing import CliRunner

    from gaitgram.cli import COMMANDS, app

    result = CliRunner().invoke(app, ["--help"])
    assert result.exit_code == 0
    listed = [line.split()[0] for line in result.stdout.split("Commands:")[1].splitlines() if line.strip()]
    assert listed == list(COMMANDS)


def test_the_console_script_keeps_what_its_import_built_out_of_the_collectors_reach() -> None:
    # The command line's modules live as long as its process; collections that walk them, the one
    # at exit included, were a tenth of `gaitgram check`'s time (gaitgram.collector.keep_for_good).
    probe = (
        "import gc, gaitgram.cli\n"
        "gaitgram.cli.main = lambda: print(gc.get_freeze_count(), gc.isenabled())\n"
        "from gaitgram.__main__ import main\n"
        "main()\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    frozen, enabled = done.stdout.split()
    assert int(frozen) > 10_000  # the grammar language, typer, lark: tens of thousands of objects
    assert enabled == "True"  # and the collector runs for what the command builds
