"""Study files are checked whole before anything runs: every arm's pipeline is built (grammar,
configuration, backend and strategy settings), the arms are comparable, and an error names the
file, the arm and the key, or the flag when only the flag makes it wrong. Nothing is made when a
study is refused."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR as GRAMMAR
from conftest import CURVE_STUDY as STUDY
from conftest import CURVE_TARGETS_TOML
from gaitgram.cli import app
from gaitgram.evolution.rundir import RunDirectory

runner = CliRunner()


def study(*args: str) -> object:
    return runner.invoke(app, ["study", *args, "-q"])


def refused(tmp_path: Path, text: str, *flags: str) -> str:
    """The error for a study file (exit 2, nothing made beside the files the test wrote)."""
    (tmp_path / "g.gg").write_text(GRAMMAR)
    (tmp_path / "s.toml").write_text(text)
    before = sorted(p.name for p in tmp_path.iterdir())
    result = study(str(tmp_path / "s.toml"), "-o", str(tmp_path / "out"), *flags)
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no directory, no temporary left
    return result.stderr


BASE = STUDY.format(generations=2)


@pytest.mark.parametrize("name", ["abc\\n", "abc\\r", "a/b", "..", ".hidden", ""])
def test_an_arm_name_that_cannot_name_a_directory_is_refused(tmp_path: Path, name: str) -> None:
    error = refused(tmp_path, BASE.replace('name = "plain"', f'name = "{name}"'))
    assert "s.toml: arm" in error
    assert "name: must be 1-64 letters, digits" in error


@pytest.mark.parametrize(
    ("text", "where"),
    [
        (BASE.replace("elite = 1\n", "elite = 1\nruns = 5\n"), "s.toml: [settings]: runs"),
        (
            BASE.replace("mutation = 0.2", "mutation = 0.2\nruns = 5"),
            "s.toml: arm 'mutant': [arm.settings]: runs",
        ),
    ],
)
def test_runs_under_a_table_is_refused_not_ignored(tmp_path: Path, text: str, where: str) -> None:
    error = refused(tmp_path, text)
    assert where in error
    assert "move `runs = N` above the study's first [table]" in error


def test_runs_in_an_arms_config_file_is_refused(tmp_path: Path) -> None:
    (tmp_path / "arm.toml").write_text("runs = 4\n")
    error = refused(
        tmp_path,
        BASE.replace(
            'grammar = "g.gg"\n[arm.settings]', 'grammar = "g.gg"\nconfig = "arm.toml"\n[arm.settings]'
        ),
    )
    assert "arm 'mutant': config" in error
    assert "arm.toml: runs" in error


def test_arms_at_different_budgets_are_refused_before_they_run(tmp_path: Path) -> None:
    error = refused(tmp_path, BASE.replace("mutation = 0.2", "mutation = 0.2\ngenerations = 3"))
    assert "s.toml: the arms would run at different budgets" in error
    assert "plain: 34 (12 + 2 x 11), mutant: 45 (12 + 3 x 11)" in error


@pytest.mark.parametrize(
    ("strategy", "settings", "key", "hint"),
    [
        ("nsga2", '{ objectives = ["rms_hip_hnd", "rms_elbow_fore"] }', "objectives[0]", "rms_hip_hind"),
        (
            "map-elites",
            '{ descriptors = [{ name = "rms_elbow_for", low = 0.0, high = 10.0 }] }',
            "descriptors[0].name",
            "rms_elbow_fore",
        ),
    ],
)
def test_a_misspelt_objective_or_descriptor_is_refused_before_anything_runs(
    tmp_path: Path, strategy: str, settings: str, key: str, hint: str
) -> None:
    text = BASE.replace(
        "mutation = 0.2", f'mutation = 0.2\nstrategy = "{strategy}"\nstrategy_settings = {settings}'
    )
    error = refused(tmp_path, text)
    assert (
        f"s.toml: arm 'mutant': [strategy_settings] {key}: backend 'curve-match' reports no component"
        in error
    )
    assert f"did you mean {hint}?" in error


WEIGHTED = (
    """\
runs = 1

[settings]
generations = 50
population = 12
elite = 1
init_max_depth = 6
backend = "curve-match"

[settings.backend_settings.targets]
"""
    + CURVE_TARGETS_TOML
    + """
[[settings.weight_schedule]]
start = 0
weights = { rms_hip_hind = 1.0 }

[[settings.weight_schedule]]
start = 11
weights = { rms_hip_hind = 2.0 }

[[settings.weight_schedule]]
start = 21
weights = { rms_hip_hind = 3.0 }

[[arm]]
name = "freedom"
grammar = "g.gg"
"""
)

FREEDOM = GRAMMAR.replace("@joint elbow_fore\n", "@joint elbow_fore free=11..31\n")


def test_generations_scale_joint_freedom_as_they_scale_the_weights(tmp_path: Path) -> None:
    """Table 3's design, shorter: a joint held until generation 11 of 50 is held until 2 of 10
    (as the weight stage of generation 11 starts at 2), not for the whole run."""
    (tmp_path / "g.gg").write_text(FREEDOM)
    (tmp_path / "s.toml").write_text(WEIGHTED)
    result = study(str(tmp_path / "s.toml"), "-o", str(tmp_path / "out"), "--generations", "10")
    assert result.exit_code == 0, result.stderr
    arm = RunDirectory.open(tmp_path / "out" / "arms" / "freedom")
    assert [s.start for s in arm.config.weight_schedule] == [0, 2, 4]
    assert [arm.pipeline.frozen_at(g) for g in (1, 2, 6, 7)] == [{"elbow_fore"}, set(), set(), {"elbow_fore"}]
    copy = (tmp_path / "out" / "arms" / "freedom" / "grammar.gg").read_text()
    assert "@joint elbow_fore free=2..6\n" in copy
    assert "scaled from the 50 generations of the study file" in copy
    again = study(str(tmp_path / "s.toml"), "-o", str(tmp_path / "out"), "--generations", "10")
    assert again.exit_code == 0, again.stderr  # the same command finds the same scaled grammar


def test_an_error_the_flags_cause_names_the_flag(tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(FREEDOM)
    error = refused(tmp_path, WEIGHTED, "--generations", "2")
    assert error.startswith("error: --generations 2 on arm 'freedom' of")
    assert "weight stages" in error
    assert "give --generations 4 or more" in error
    assert "--runs" in refused(tmp_path, WEIGHTED, "--runs", "20000")
