"""Study files are checked whole before anything runs: every arm's pipeline is built (grammar,
configuration, backend and strategy settings), the arms are comparable, and an error names the
file's line and column, the arm and the key, or the flag when only the flag makes it wrong.
Nothing is made when a study is refused."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR as GRAMMAR
from conftest import CURVE_STUDY as STUDY
from conftest import CURVE_TARGETS_TOML
from gaitgram.cli import app
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.fileio import DirectoryLock

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
    assert "s.toml:17:1: arm" in error
    assert "name: must be 1-64 letters, digits" in error


@pytest.mark.parametrize(
    ("text", "where"),
    [
        (BASE.replace("elite = 1\n", "elite = 1\nruns = 5\n"), "s.toml:9:1: [settings]: runs"),
        (
            BASE.replace("mutation = 0.2", "mutation = 0.2\nruns = 5"),
            "s.toml:25:1: arm 'mutant': [arm.settings]: runs",
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
    assert "arm.toml:1:1 (the config of " in error
    assert "s.toml:23:1: arm 'mutant'): runs" in error


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
        f"s.toml:26:1: arm 'mutant': [strategy_settings] {key}: backend 'curve-match' reports no component"
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


@pytest.mark.parametrize(
    ("old", "new", "where", "what"),
    [
        (
            "seed = 7",
            "seed = -7",
            "s.toml:3:1: seed",
            "must be a whole number in [0, 9_223_372_036_854_775_807]",
        ),
        # a seed no run can take is the study file's, on its line, not an arm's (issue 39)
        ("seed = 7", "seed = 99999999999999999999", "s.toml:3:1: seed: must", "not 99999999999999999999"),
        (
            'grammar = "g.gg"\n[arm',
            'grammar = "g.gg"\ndefines = { n = 99999999999999999999 }\n[arm',
            "s.toml:23:1: arm 'mutant': defines: n = 99999999999999999999",
            "from 1 to 100,000",
        ),
        (
            'title = "tiny"',
            'title = "tiny"\ntitel = "x"',
            "s.toml:2:1: unknown key 'titel'",
            "did you mean title",
        ),
        ("population = 12", "population = 1", "s.toml:7:1: arm 'plain': population", "[2, 1_000_000]"),
        ("population = 12", "population = 2", "s.toml:7:1: arm 'plain': tournament", "larger than"),
        ('name = "mutant"', 'name = "plain"', "s.toml:21:1: two arms are named 'plain'", "must differ"),
        (
            'grammar = "g.gg"\n[arm',
            'gramar = "g.gg"\n[arm',
            "s.toml:22:1: arm 'mutant': unknown key",
            "grammar",
        ),
        ('grammar = "g.gg"\n[arm', 'grammar = "h.gg"\n[arm', "s.toml:22:1: arm 'mutant': grammar", "h.gg"),
        (
            'grammar = "g.gg"\n[arm',
            'grammar = "g\\u0000.gg"\n[arm',
            "s.toml:22:1: arm 'mutant': grammar",
            "NUL",
        ),
        ("seed = 7", 'seed = 7\nconfig = "c\\u0000.toml"', "s.toml:4:1: config", "NUL"),
        ("mutation = 0.2", "mutation = 2.0", "s.toml:24:1: arm 'mutant': mutation", "[0, 1]"),
        ("mutation = 0.2", "mutation = 0.2\nelite = 12", "s.toml:25:1: arm 'mutant': elite", "no room"),
        ("mutation = 0.2", "mutation = 0.2\nstrategy = 3", "s.toml:25:1: arm 'mutant': strategy", "not 3"),
        (
            "1.5)",
            "1.5",
            "s.toml:13:1: arm 'plain': [backend_settings] targets.hip_hind",
            "unexpected end of text",
        ),
    ],
)
def test_an_error_names_the_line_and_column_of_the_key_at_fault(
    tmp_path: Path, old: str, new: str, where: str, what: str
) -> None:
    """In the study file's ``[settings]``, an ``[[arm]]`` (the right one of several), its
    ``[arm.settings]``, or a cross-field check blamed on the key the file wrote."""
    assert BASE.count(old) == 1
    error = refused(tmp_path, BASE.replace(old, new))
    assert where in error
    assert what in error


def test_an_error_in_an_arms_config_file_names_that_files_line(tmp_path: Path) -> None:
    (tmp_path / "arm.toml").write_text("# the arm's own settings\n\ncrossover = 1.5\n")
    text = BASE.replace(
        'grammar = "g.gg"\n[arm.settings]', 'grammar = "g.gg"\nconfig = "arm.toml"\n[arm.settings]'
    )
    error = refused(tmp_path, text)
    assert "arm.toml:3:1: arm 'mutant': crossover: must be a probability in [0, 1], not 1.5" in error


def test_an_arms_backend_settings_add_to_the_studys_and_its_strategy_settings_replace_them(
    tmp_path: Path,
) -> None:
    """``backend_settings`` of an arm add to the study's key by key at every depth: a pony arm keeps
    the study's weights, and an arm that changes one weight keeps the others. A strategy's settings
    belong to its strategy: an arm's replace the study's (a GE arm need not inherit NSGA-II's)."""
    from gaitgram.study.spec import load_study

    grammar = Path(__file__).resolve().parents[2] / "grammars" / "hybrid.gg"
    path = tmp_path / "s.toml"
    path.write_text(
        "[settings.backend_settings]\n"
        "weights = { velocity = 1.0, duty_factor = 1.0, stride = 1.0, frequency = 0.0, energy = 1.0 }\n"
        "[settings.strategy_settings]\n"
        'objectives = ["velocity", "duty_factor"]\n'
        "[[arm]]\n"
        'name = "horse"\n'
        'strategy = "nsga2"\n'
        f"grammar = {str(grammar)!r}\n"
        "[[arm]]\n"
        'name = "pony"\n'
        'strategy = "nsga2"\n'
        f"grammar = {str(grammar)!r}\n"
        'settings = { backend_settings = { body = "pony", weights = { energy = 0.1 } } }\n'
        "[[arm]]\n"
        'name = "ge"\n'
        f"grammar = {str(grammar)!r}\n"
        "settings = { strategy_settings = {} }\n"
    )
    horse, pony, ge = load_study(path).arms
    assert pony.config.backend_settings["body"] == "pony"
    assert horse.config.backend_settings["weights"]["energy"] == 1.0
    assert pony.config.backend_settings["weights"] == {
        **horse.config.backend_settings["weights"],
        "energy": 0.1,
    }
    assert pony.config.strategy_settings["objectives"] == ["velocity", "duty_factor"]
    assert ge.config.strategy_settings == {}


def tree(path: Path) -> dict[str, bytes]:
    return {str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*")) if p.is_file()}


def test_check_prints_the_plan_and_progress_and_writes_nothing(tmp_path: Path) -> None:
    """``--check`` before hours are spent: the arms, their budgets and how many runs the
    directory has finished; the error a run would give; and not a file written or changed."""
    (tmp_path / "g.gg").write_text(GRAMMAR)
    (tmp_path / "s.toml").write_text(BASE)
    out = tmp_path / "out"
    fresh = runner.invoke(app, ["study", str(tmp_path / "s.toml"), "-o", str(out), "--check"])
    assert fresh.exit_code == 0, fresh.output
    assert "plain" in fresh.stdout
    assert "mutant" in fresh.stdout
    assert "34" in fresh.stdout  # the budget: 12 + 2 x 11
    assert "ready: 6 runs, nothing written" in fresh.stdout
    assert not out.exists()
    assert study(str(tmp_path / "s.toml"), "-o", str(out), "--runs", "2").exit_code == 0
    before = tree(out)
    partial = runner.invoke(app, ["study", str(tmp_path / "s.toml"), "-o", str(out), "--check"])
    assert partial.exit_code == 0, partial.output
    assert "2/3" in partial.stdout
    assert "4 of 6 runs finished; running it grows arms from 2 to 3 runs; continue with" in partial.stdout
    done = runner.invoke(app, ["study", str(tmp_path / "s.toml"), "-o", str(out), "--check", "--runs", "2"])
    assert "holds this study: 4 of 4 runs finished, complete" in done.stdout
    with DirectoryLock(out):  # as a running study holds it
        running = runner.invoke(app, ["study", str(tmp_path / "s.toml"), "-o", str(out), "--check"])
    assert "another gaitgram is running it now" in running.stdout
    other = runner.invoke(
        app, ["study", str(tmp_path / "s.toml"), "-o", str(out), "--check", "--generations", "3"]
    )
    assert other.exit_code == 2
    assert "arm 'plain' differs" in other.stderr
    assert "generations: 2 -> 3" in other.stderr
    assert tree(out) == before  # nothing grown, locked or rewritten
    shutil.rmtree(out / "arms" / "mutant")  # an arm deleted to run it again from scratch
    again = runner.invoke(app, ["study", str(tmp_path / "s.toml"), "-o", str(out), "--check"])
    assert "0/3" in again.stdout
    assert "mutant start from scratch (no directory)" in again.stdout


def test_a_study_runs_only_with_a_directory(tmp_path: Path) -> None:
    (tmp_path / "g.gg").write_text(GRAMMAR)
    (tmp_path / "s.toml").write_text(BASE)
    result = runner.invoke(app, ["study", str(tmp_path / "s.toml")])
    assert result.exit_code == 2
    assert "only --check runs without one" in result.stderr
