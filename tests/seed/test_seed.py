"""The seed data, its Fourier analysis, the six grammar styles, and the commands."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS, ROOT
from gaitgram.analysis import check
from gaitgram.backends.api import GaitStatus
from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.joints import SENSORS
from gaitgram.backends.mujoco_horse.seed_fit import CHAINS, FootPath, fit_seed
from gaitgram.backends.registry import get_backend
from gaitgram.cli import app
from gaitgram.ge import compile_mapper
from gaitgram.ge.initialisation import random_tree
from gaitgram.language import load
from gaitgram.motion import compile_motion, phase_grid
from gaitgram.seed import SeedError, build_seed, load_seed, read_seed_csv
from gaitgram.seed.grammars import TARGET_FREQUENCY, Style, seed_genome, write_grammar

runner = CliRunner()


def test_shipped_csvs_are_the_seed_fitted_to_the_horse() -> None:
    """The CSVs are ``fit_seed(build_seed())``, rounded; the optimiser may differ in the last
    digits between platforms, so the comparison allows a hundredth of a degree."""
    shipped = (ROOT / "seeds" / "horse_walk.csv").read_text()
    assert (ROOT / "gaitgram" / "motion" / "horse_walk.csv").read_text() == shipped
    fitted = fit_seed(build_seed())
    for joint, values in load_seed().angles.items():
        np.testing.assert_allclose(values, fitted.angles[joint], atol=0.01, err_msg=joint)
    recipe = build_seed()
    for joint in ("neck_proximal", "neck_mid", "neck_atlas"):  # the fit changes only the limbs
        np.testing.assert_allclose(load_seed().angles[joint], recipe.angles[joint], atol=1e-4)


def test_the_seed_walks_like_a_horse_on_the_horse() -> None:
    """The seed refitted to the real walk is a walk by criterion v2, checked over the horizon, at
    the target's speed, stride, frequency and the DLC_Horse walks' duty factor (docs/fitness.md)."""
    evaluator = get_backend("mujoco-horse").load({"threads": 2})
    try:
        (scored,) = evaluator.evaluate(load_seed().motion_batch())
        (checked,) = evaluator.verify(load_seed().motion_batch())
    finally:
        evaluator.close()
    assert checked.status is GaitStatus.OK, checked.detail
    assert checked.fitness == scored.fitness  # the check adds cycles, never changes the score
    c = checked.components
    targets = evaluator.targets
    assert c["walk"] == 1.0, {k: v for k, v in c.items() if k.startswith("walk_")}
    assert c["checked_cycles"] == 20.0
    assert scored.components["walk_sustained"] == 0.0  # only the check can establish it
    assert c["measured_velocity"] == pytest.approx(targets.velocity, rel=0.05)
    assert c["measured_stride"] == pytest.approx(targets.stride_length, rel=0.05)
    assert c["measured_frequency"] == pytest.approx(targets.stride_frequency, rel=0.02)
    assert 0.55 <= c["measured_duty_factor"] <= 0.62  # the DLC walks' IQR: 0.55-0.63
    assert checked.fitness == pytest.approx(0.189, abs=5e-4)  # docs/fitness.md quotes it
    assert len(checked.cycles["speed"]) == 3
    assert np.ptp(checked.cycles["speed"]) < 0.02 * targets.velocity  # steady


def test_seed_curves_are_within_joint_limits_with_published_ranges() -> None:
    seed = load_seed()
    assert list(seed.angles) == list(CATALOGUE.names)
    for joint, values in seed.angles.items():
        low, high = CATALOGUE.get(joint).limits
        assert low <= values.min(), joint
        assert values.max() <= high, joint
    assert np.ptp(seed.angles["neck_proximal"]) == pytest.approx(15, abs=0.1)  # a recipe curve
    for joint in CHAINS["fore_left"] + CHAINS["hind_left"]:  # fitted with a margin (less filtering)
        low, high = CATALOGUE.get(joint).limits
        assert low + FootPath().margin / 2 <= seed.angles[joint].min(), joint
        assert seed.angles[joint].max() <= high - FootPath().margin / 2, joint


@pytest.mark.parametrize("style", list(Style))
def test_shipped_grammars_are_regenerated_exactly_and_pass_strict(style: Style) -> None:
    path = GRAMMARS / f"{style.value}.gg"
    command = f"gaitgram seed grammar --style {style.value} -o grammars/{style.value}.gg"
    assert path.read_text() == write_grammar(style, load_seed(), command=command, frequency=TARGET_FREQUENCY)
    result = check(load(path))
    assert not result.diagnostics, result.diagnostics
    assert {j.joint for j in result.grammar.joints} == set(CATALOGUE.names)


@pytest.mark.parametrize("style", list(Style))
def test_every_joint_phenotype_compiles(style: Style) -> None:
    checked = check(load(GRAMMARS / f"{style.value}.gg"))
    mapper = compile_mapper(checked.grammar, max_wraps=0)
    rng = np.random.default_rng(0)
    for _ in range(20):
        tree = random_tree(checked.facts, rng, max_depth=8)
        mapped = mapper.map_fast(tree.genome)
        assert mapped.valid
        assert len(mapped.joints) == 13  # 12 joints and the @frequency rule
        for joint, text in mapped.joints.items():
            assert not hasattr(compile_motion(text, SENSORS.names), "status"), (joint, text)


@pytest.mark.parametrize("style", [Style.NUMERICAL, Style.CONCATENATING, Style.HYBRID, Style.JOINT_FREEDOM])
def test_seed_genome_derives_the_seed(style: Style) -> None:
    grammar = load(GRAMMARS / f"{style.value}.gg")
    mapped = compile_mapper(grammar).map_fast(seed_genome(grammar))
    seed = load_seed()
    joints = dict(mapped.joints)
    assert joints.pop("@frequency") == "0.95"  # the target's, to the range's step
    for joint, text in joints.items():
        curve = compile_motion(text).evaluate(phase_grid(100)).values
        error = np.abs(curve - seed.angles[joint])  # only sub-threshold terms missing
        assert error.max() < 3.0, joint
        assert np.sqrt(np.mean(error**2)) < 1.0, joint


def test_seed_fit_cli() -> None:
    result = runner.invoke(app, ["seed", "fit"])
    assert result.exit_code == 0
    assert "<seed_neck_atlas> ::= -0.09+3.39*sin(2*2*PI*t-0.31)" in result.stdout  # a recipe curve
    records = [json.loads(line) for line in runner.invoke(app, ["seed", "fit", "--json"]).stdout.splitlines()]
    assert len(records) == 12
    # Fitted limb curves have many small harmonics: dropping those under 1 degree costs up to ~2.
    assert all(r["rms_error"] < 1.0 and r["max_error"] < 3.0 for r in records)


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("", "empty"),
        ("time,hip\n0,1\n", "header must be phase"),
        ("phase,hip\n0,1\n0.5,x\n", ":3: 'x' is not a number"),
        # a damaged number is named by its line and column, as in every file gaitgram reads
        ("phase,hip\n0,1\n0.25,inf\n0.5,1\n0.75,2\n", ":3: hip: 'inf' is not a finite number"),
        ("phase,hip\nnan,1\n0.25,1\n0.5,1\n0.75,2\n", ":2: phase: 'nan' is not a finite number"),
        ("phase,hip\n0,1,2\n", ":2: 3 values"),
        ("phase,hip\n0,1\n0.5,2\n", "at least 4 samples"),
        ("phase,hip\n0.5,1\n0.2,2\n0.3,1\n0.4,2\n", "phases must increase"),
    ],
)
def test_bad_seed_csvs(tmp_path: Path, content: str, message: str) -> None:
    path = tmp_path / "seed.csv"
    path.write_text(content)
    with pytest.raises(SeedError, match=message):
        read_seed_csv(path)
    result = runner.invoke(app, ["seed", "fit", str(path)])
    assert result.exit_code == 2
    assert "error:" in result.stderr


def test_seed_grammar_cli_never_overwrites(tmp_path: Path) -> None:
    out = tmp_path / "h.gg"
    assert runner.invoke(app, ["seed", "grammar", "--style", "hybrid", "-o", str(out)]).exit_code == 0
    out.write_text("mine")
    assert runner.invoke(app, ["seed", "grammar", "--style", "hybrid", "-o", str(out)]).exit_code == 2
    assert out.read_text() == "mine"


def test_plot_writes_png_and_svg(tmp_path: Path) -> None:
    grammar = load(GRAMMARS / "hybrid.gg")
    genome = ",".join(map(str, seed_genome(grammar)))
    for name in ("c.png", "c.svg"):
        result = runner.invoke(
            app, ["plot", str(GRAMMARS / "hybrid.gg"), "--genome", genome, "-o", str(tmp_path / name)]
        )
        assert result.exit_code == 0, result.stderr
    assert (tmp_path / "c.png").read_bytes()[:4] == b"\x89PNG"
    assert "<svg" in (tmp_path / "c.svg").read_text()
    bad = runner.invoke(
        app,
        [
            "plot",
            str(GRAMMARS / "hybrid.gg"),
            "--genome",
            "1",
            "--max-wraps",
            "0",
            "-o",
            str(tmp_path / "x.png"),
        ],
    )
    assert bad.exit_code == 1


def test_curves_figure_has_a_panel_per_joint_and_shows_errors() -> None:
    from gaitgram.motion.plot import curves_figure

    figure = curves_figure(
        list(CATALOGUE.names), {"hip_hind": "10*sin(2*PI*t)", "elbow_fore": "1/0"}, load_seed().angles
    )
    assert len(figure.axes) == 12
    texts = [t.get_text() for ax in figure.axes for t in ax.texts]
    assert any("division by zero" in t for t in texts)


def test_seed_fit_output_parses_as_gg_rules() -> None:
    from gaitgram.language import parse

    output = runner.invoke(app, ["seed", "fit"]).stdout
    grammar = parse("<all> ::= " + "".join(f"<seed_{j}>" for j in CATALOGUE.names) + "\n" + output)
    assert not grammar.diagnostics, grammar.diagnostics
    assert len(grammar.rules) == 13


@pytest.mark.parametrize("path", sorted(GRAMMARS.glob("*.gg")), ids=lambda p: p.name)
def test_bundled_grammars_give_finite_curves(path: Path) -> None:
    """A few hundred genomes each (sensibly initialised, as evolution starts) to sampled curves."""
    from gaitgram.backends.registry import get_backend
    from gaitgram.ge.initialisation import ramped_population
    from gaitgram.motion.gait import MotionProblem, motion_batch
    from gaitgram.pipeline import sensors_of

    checked = check(load(path))
    trees = ramped_population(checked.facts, np.random.default_rng(5), 300, max_depth=8)
    mapped = compile_mapper(checked.grammar, max_wraps=0).map_many([t.genome for t in trees])
    batch = motion_batch(
        [m.joints for m in mapped], CATALOGUE.names, sensors=sensors_of(get_backend("mujoco-horse"))
    )
    usable = batch.angles[batch.usable]
    assert np.isfinite(usable).all()
    if path.name == "free.gg":  # Fig. 5 divides freely: such curves are flagged, never passed on
        assert set(batch.problems) <= {None, MotionProblem.INVALID_MOTION, MotionProblem.NON_FINITE}
        assert batch.usable.sum() > 150
    else:
        assert batch.usable.all(), [d for d in batch.details if d]
