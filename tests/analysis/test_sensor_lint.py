"""The names a grammar's curves read, checked statically (GG508 to GG512): on the bundled
closed-loop grammar edited as a user would, through ``gaitgram check`` and the library, and the
pipeline's refusal of a backend that lacks the sensors a grammar reads."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.analysis import check
from gaitgram.analysis.motion_text import name_uses, sensors_lacking
from gaitgram.backends.registry import get_backend
from gaitgram.language import parse

runner = CliRunner()

FEEDBACK = (GRAMMARS / "hybrid-feedback.gg").read_text()
FEEDBACK_TERM = "<feedback> ::= +<pitch_gain>*pitch+<pitch_rate_gain>*pitch_rate+<load_gain>*(load-1)"
assert FEEDBACK_TERM in FEEDBACK  # the edits below start from the bundled grammar as it is


def app():  # imported late: the CLI module is heavy, and only these tests need it
    from gaitgram.cli import app

    return app


def records(path: Path) -> list[dict]:
    result = runner.invoke(app(), ["check", "--format", "json", str(path)])
    return json.loads(result.stdout)


def written(tmp_path: Path, text: str, name: str = "edited.gg") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def line_of(text: str, needle: str) -> tuple[int, int]:
    """1-based line and column of ``needle`` in ``text``, counted here, not by the linter."""
    at = text.index(needle)
    return text.count("\n", 0, at) + 1, at - (text.rfind("\n", 0, at) + 1) + 1


def test_the_bundled_grammars_check_clean_under_strict() -> None:
    grammars = sorted(map(str, GRAMMARS.glob("*.gg")))
    assert any(g.endswith("hybrid-feedback.gg") for g in grammars)
    assert any(g.endswith("hybrid-reset.gg") for g in grammars)
    done = subprocess.run(
        [sys.executable, "-m", "gaitgram", "check", "--strict", *grammars],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr


def test_a_misspelt_sensor_is_an_error_on_its_name_with_a_did_you_mean_and_a_fix(tmp_path: Path) -> None:
    text = FEEDBACK.replace("*pitch+", "*pich+")
    path = written(tmp_path, text)
    result = runner.invoke(app(), ["check", str(path)])
    assert result.exit_code == 1
    line, column = line_of(text, "pich+")
    assert f"{path}:{line}:{column}: error[GG508] unknown name 'pich'" in result.stdout
    assert "did you mean 'pitch'?" in result.stdout
    (record,) = [r for r in records(path) if r["code"] == "GG508"]
    assert (record["line"], record["column"], record["end_column"]) == (line, column, column + 4)
    assert record["data"] == {"name": "pich"}
    assert "shoulder_fore" in record["message"]  # whose curve reads it
    (fix,) = record["fixes"]
    assert fix["edits"][0]["text"] == "pitch"
    fixed = runner.invoke(app(), ["check", "--fix", "--unsafe-fixes", str(path)])
    assert fixed.exit_code == 0, fixed.stdout + fixed.stderr
    assert path.read_text() == FEEDBACK


def test_unknown_names_and_functions_in_joint_curves(tmp_path: Path) -> None:
    text = FEEDBACK.replace(
        "<num_scapula_fore> | <num_scapula_fore>+0.06*(<funcs>)",
        "<num_scapula_fore>+Sin(t) | <num_scapula_fore>+0.06*(<funcs>)+tan(time)+wobble",
    )
    found = {(r["code"], r["data"].get("name")): r for r in records(written(tmp_path, text))}
    assert set(found) == {("GG508", "Sin"), ("GG508", "tan"), ("GG508", "time"), ("GG508", "wobble")}
    assert found["GG508", "Sin"]["hint"] == "did you mean 'sin'?"
    assert found["GG508", "Sin"]["fixes"][0]["edits"][0]["text"] == "sin"
    assert found["GG508", "time"]["fixes"][0]["edits"][0]["text"] == "t"
    assert "leaves tan out" in found["GG508", "tan"]["hint"]
    assert found["GG508", "wobble"]["fixes"] == []  # nothing near: no guess
    assert "pitch" in found["GG508", "wobble"]["hint"]  # the backend's sensors are among the known names


def test_names_outside_the_curves_are_not_motion_text(tmp_path: Path) -> None:
    # The start rule joins the curves with ';', and neither an unreachable rule nor an unreachable
    # joint rule is derived: none of them is read.
    text = FEEDBACK + "<spare> ::= wobble\n@joint tail\n<tail> ::= wag\n"
    codes = {r["code"] for r in records(written(tmp_path, text))}
    assert "GG508" not in codes
    assert "GG204" in codes


def test_a_sensor_the_backend_lacks(tmp_path: Path) -> None:
    text = FEEDBACK.replace("@backend mujoco-horse", "@backend curve-match")
    path = written(tmp_path, text)
    lacking = [r for r in records(path) if r["code"] == "GG509"]
    assert [r["data"]["name"] for r in lacking] == ["pitch", "pitch_rate", "load"]
    assert all(r["severity"] == "error" and r["data"]["backend"] == "curve-match" for r in lacking)
    assert "mujoco-horse has one" in lacking[0]["message"]
    assert "@backend mujoco-horse" in lacking[0]["hint"]
    assert line_of(text, "pitch+")[0] == lacking[0]["line"]


def test_a_per_limb_sensor_in_a_neck_curve(tmp_path: Path) -> None:
    text = FEEDBACK.replace(
        "<neck_mid> ::= <num_neck_mid> |", "<neck_mid> ::= <num_neck_mid><feedback> |"
    ).replace("<neck_atlas> ::= <num_neck_atlas> |", "<neck_atlas> ::= <num_neck_atlas><feedback> |")
    path = written(tmp_path, text)
    result = runner.invoke(app(), ["check", str(path)])
    assert result.exit_code == 1
    barred = [r for r in records(path) if r["code"] == "GG510"]
    assert [r["data"] for r in barred] == [{"name": "load", "joint": "neck_mid"}]  # pitch: the whole body
    (record,) = barred
    assert "neck_mid, neck_atlas" in record["message"]
    assert "(neck)" in record["message"]
    line, column = line_of(text, "load-1")
    assert (record["line"], record["column"]) == (line, column)
    assert "pitch, pitch_rate, height, speed" in record["hint"]


def test_the_frequency_rule_reads_no_sensor(tmp_path: Path) -> None:
    text = FEEDBACK.replace(
        "<frequency> ::= float[0.6..1.3 step 0.05]", "<frequency> ::= float[0.6..1.3 step 0.05]+0*speed"
    )
    (record,) = [r for r in records(written(tmp_path, text)) if r["code"] == "GG511"]
    assert record["data"] == {"name": "speed"}
    assert record["severity"] == "error"


def test_sensors_without_a_backend_are_an_info_and_still_checked_by_name(tmp_path: Path) -> None:
    text = FEEDBACK.replace("@backend mujoco-horse\n", "")
    found = records(written(tmp_path, text))
    (info,) = [r for r in found if r["code"] == "GG512"]
    assert info["severity"] == "info"
    assert "pitch, pitch_rate, load" in info["message"]
    assert info["hint"] == "declare the backend, e.g. @backend mujoco-horse"
    assert not [r for r in found if r["severity"] == "error"]
    misspelt = [
        r for r in records(written(tmp_path, text.replace("*(load-1)", "*(lod-1)"))) if r["code"] == "GG508"
    ]
    assert [r["data"]["name"] for r in misspelt] == ["lod"]
    assert "did you mean 'load'?" in misspelt[0]["hint"]  # among every installed backend's sensors


def test_names_are_found_through_quotes_and_escapes() -> None:
    grammar = parse("@backend mujoco-horse\n@joint hip_hind\n<a> ::= 'pi'tch+\"2*\"t+lo\\x61d+speed\n")
    uses = name_uses(grammar, check(grammar).facts)
    shown = [(u.name, grammar.source.slice(u.span)) for u in uses]
    assert shown[0] == ("pitch", "pi'tch")
    assert ("t", "t") in shown
    assert ("speed", "speed") in shown
    escaped = next(u for u in uses if u.name == "load")  # spelt through an escape: the whole terminal
    assert grammar.source.slice(escaped.span).startswith("'pi'tch")
    assert all(u.readers == ("hip_hind",) for u in uses)


def test_the_library_check_reports_what_the_cli_does() -> None:
    result = check(parse(FEEDBACK.replace("@backend mujoco-horse", "@backend curve-match")))
    assert [d.data["name"] for d in result.diagnostics if d.code.code == "GG509"] == [
        "pitch",
        "pitch_rate",
        "load",
    ]
    clean = check(parse(FEEDBACK))
    assert not [d for d in clean.diagnostics if d.code.code.startswith("GG5")]


def test_sensors_lacking_is_what_the_pipeline_refuses() -> None:
    grammar = parse(FEEDBACK)
    facts = check(grammar).facts
    assert sensors_lacking(grammar, facts, get_backend("mujoco-horse").sensors) == []
    assert sensors_lacking(grammar, facts, get_backend("curve-match").sensors) == [
        "pitch",
        "pitch_rate",
        "load",
    ]


GRAMMAR_WITH_FEEDBACK = """\
@backend mujoco-horse
<g> ::= <hip>
@joint hip_hind
<hip> ::= <a>*sin(2*PI*t)+0.1*pitch+<a>*(load-1)
<a> ::= int[0..9]
"""


@pytest.mark.parametrize("where", ["config", "flag"])
def test_a_run_on_a_backend_without_the_sensors_is_refused_naming_them(tmp_path: Path, where: str) -> None:
    grammar = written(tmp_path, GRAMMAR_WITH_FEEDBACK, "feedback.gg")
    config = tmp_path / "run.toml"
    config.write_text(
        ('backend = "curve-match"\n' if where == "config" else "")
        + 'generations = 1\npopulation = 10\n[backend_settings.targets]\nhip_hind = "sin(2*PI*t)"\n'
    )
    flags = ["--backend", "curve-match"] if where == "flag" else []
    result = runner.invoke(
        app(), ["evolve", str(grammar), "-c", str(config), *flags, "-o", str(tmp_path / "run")]
    )
    assert result.exit_code == 2
    assert "read the sensors pitch, load, which backend 'curve-match' lacks" in result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "run").exists()


def test_checking_a_closed_loop_grammar_starts_without_numpy() -> None:
    # The sensors come from the backend's catalogue (TOML) and the names from gaitgram.motion.names:
    # `gaitgram check` stays as light on a closed loop as on an open one (tests/cli/test_startup.py).
    probe = (
        "import sys\nfrom gaitgram.cli import main\n"
        f"sys.argv = ['gaitgram', 'check', {str(GRAMMARS / 'hybrid-feedback.gg')!r}]\n"
        "try:\n    main()\nexcept SystemExit as end:\n    assert end.code == 0, end.code\n"
        "print('numpy' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "False"
