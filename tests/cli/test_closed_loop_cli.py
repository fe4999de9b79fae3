"""``gaitgram map`` and ``gaitgram plot`` on closed-loop phenotypes (the bundled feedback and reset
grammars): they say in one line which curves read which sensors and that these are no fixed curves,
``map`` splits each such curve into what it plays open loop, its phase terms and its feedback terms,
and ``plot`` draws the nominal curve (every sensor at rest), labelled so."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.backends.registry import get_backend
from gaitgram.cli import app
from gaitgram.motion.expression import Motion, compile_motion
from gaitgram.motion.gait import sensed_curve
from gaitgram.pipeline import sensors_of

runner = CliRunner()

FEEDBACK = GRAMMARS / "hybrid-feedback.gg"
RESET = GRAMMARS / "hybrid-reset.gg"
#: Codons that take each curve's second alternative: four limb curves read pitch, pitch_rate and load.
GENOME = ",".join(["3"] * 400)
SENSORS = sensors_of(get_backend("mujoco-horse"))
assert SENSORS is not None


def mapped(grammar: Path, *args: str):
    return runner.invoke(app, ["map", str(grammar), "--genome", GENOME, *args])


def test_map_says_which_curves_read_which_sensors_in_one_line() -> None:
    result = mapped(FEEDBACK)
    assert result.exit_code == 0, result.stderr
    notes = [line for line in result.stderr.splitlines() if line.startswith("closed loop:")]
    assert notes == [
        "closed loop: shoulder_fore, fetlock_fore, hip_hind, fetlock_hind read the sensors pitch, "
        "pitch_rate, load, so their curves cannot be plotted as a fixed curve; a plot shows the "
        "nominal curve, every sensor at rest"
    ]
    hip = next(line for line in result.stderr.splitlines() if line.startswith("  hip_hind:"))
    assert hip.endswith("; feedback -0.7*pitch -0.07*pitch_rate -3.5*(load-1)")
    assert "pitch" not in hip.split("; feedback")[0]  # the open-loop part reads no sensor
    assert "hip_hind: " in result.stdout  # the phenotypes on standard output as before
    assert "closed loop" not in result.stdout


def test_map_json_splits_each_closed_curve_into_parts_that_sum_back_to_it() -> None:
    result = mapped(FEEDBACK, "--json")
    assert result.exit_code == 0, result.stderr
    record = json.loads(result.stdout)
    loop = record["closed_loop"]
    assert loop["sensors"] == ["pitch", "pitch_rate", "load"]
    assert set(loop["curves"]) == {"shoulder_fore", "fetlock_fore", "hip_hind", "fetlock_hind"}
    rng = np.random.default_rng(7)
    phases = np.linspace(0, 1, 50, endpoint=False)
    readings = {name: rng.normal(size=50) for name in SENSORS.names}
    for joint, parts in loop["curves"].items():
        assert parts["phased"] == []
        whole = compile_motion(record["joints"][joint], SENSORS.names)
        summed = compile_motion(parts["open_loop"] + "".join(parts["feedback"]), SENSORS.names)
        assert isinstance(whole, Motion)
        assert isinstance(summed, Motion)
        expected = whole.evaluate(phases, {n: readings[n] for n in whole.sensors}).values
        got = summed.evaluate(phases, {n: readings[n] for n in summed.sensors}).values
        np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-9)


def test_map_of_the_reset_grammar_names_the_phase_terms_apart() -> None:
    record = json.loads(mapped(RESET, "--json").stdout)
    curves = record["closed_loop"]["curves"]
    assert "phase" in record["closed_loop"]["sensors"]
    scapula = curves["scapula_fore"]  # played at its limb's phase, without feedback
    assert scapula["feedback"] == []
    assert scapula["phased"]
    assert all("phase" in term for term in scapula["phased"])
    assert "phase" not in scapula["open_loop"]


def test_map_of_an_open_loop_phenotype_says_nothing_of_loops() -> None:
    result = mapped(GRAMMARS / "hybrid.gg")
    assert result.exit_code == 0, result.stderr
    assert "closed loop" not in result.stderr
    assert "closed_loop" not in json.loads(mapped(GRAMMARS / "hybrid.gg", "--json").stdout)


def test_plot_draws_a_closed_loop_nominal_and_says_so(tmp_path: Path) -> None:
    out = tmp_path / "curves.png"
    result = runner.invoke(app, ["plot", str(FEEDBACK), "--genome", GENOME, "-o", str(out)])
    assert result.exit_code == 0, result.stderr
    assert out.read_bytes().startswith(b"\x89PNG")
    assert (
        "closed loop: shoulder_fore, fetlock_fore, hip_hind, fetlock_hind read the sensors" in result.stderr
    )


def test_the_plotted_nominal_curve_is_the_one_runs_sample() -> None:
    from gaitgram.motion.plot import NOMINAL, curves_figure

    record = json.loads(mapped(FEEDBACK, "--json").stdout)
    joints = list(record["joints"])[:-1]  # the joints, without @frequency
    figure = curves_figure(joints, record["joints"], None, samples=64, title="feedback", sensors=SENSORS)
    assert "closed loop, drawn nominal (every sensor at rest)" in figure.get_suptitle()
    panels = {axes.get_title(): axes for axes in figure.axes}
    assert "hip_hind (closed loop)" in panels
    assert "elbow_fore" in panels  # an open-loop curve keeps its title
    (line,) = [ln for ln in panels["hip_hind (closed loop)"].get_lines() if ln.get_label() == NOMINAL]
    values, _, problem, _ = sensed_curve(record["joints"]["hip_hind"], 64, SENSORS)
    assert problem is None
    np.testing.assert_array_equal(line.get_ydata(), values)
    # at rest (pitch 0, pitch rate 0, load 1) the feedback terms add nothing: the open-loop part alone
    open_loop = record["closed_loop"]["curves"]["hip_hind"]["open_loop"]
    plain = compile_motion(open_loop)
    assert isinstance(plain, Motion)
    np.testing.assert_allclose(values, plain.evaluate(np.arange(64) / 64).values, atol=1e-9)
