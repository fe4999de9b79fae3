"""Bodies as data, gaits retargeted between them by dynamic similarity, and seeded transfer.

The model tests every body must pass are in test_horse_model.py (parametrised over the bodies);
here: the seed gait walks on every body, the targets and frequencies follow sqrt(g / h), playing
a gait on its own body is the identity, and the commands and a run started from another's
population work end to end.
"""

from __future__ import annotations

import json
import math
import shutil
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import GRAMMARS
from gaitgram.backends.api import GaitStatus, SettingsError
from gaitgram.backends.mujoco_horse.bodies import BODIES, REFERENCE_BODY, UnknownBody, body_named
from gaitgram.backends.mujoco_horse.model import horse_layout, load_model, master_spec
from gaitgram.backends.mujoco_horse.retarget import frequency_ratio, retarget
from gaitgram.backends.mujoco_horse.settings import HorseSettings
from gaitgram.backends.mujoco_horse.targets import walk_targets
from gaitgram.backends.registry import get_backend
from gaitgram.cli import app
from gaitgram.evolution.checkpoint import load_checkpoint
from gaitgram.evolution.retarget import RetargetError
from gaitgram.evolution.retarget import retarget as retarget_run
from gaitgram.evolution.rundir import RunDirectory
from gaitgram.evolution.session import run_session
from gaitgram.pipeline import Pipeline
from gaitgram.report.stats import wilson_interval
from gaitgram.seed import load_seed

runner = CliRunner()
HYBRID = str(GRAMMARS / "hybrid.gg")
OTHER_BODIES = [name for name in BODIES if name != REFERENCE_BODY]


# --- bodies as data ----------------------------------------------------------------------------


def test_the_reference_body_is_horse_xml_unchanged() -> None:
    default, named = load_model(), load_model(REFERENCE_BODY)
    for field in ("body_mass", "body_inertia", "body_pos", "geom_size", "jnt_range", "actuator_gainprm"):
        np.testing.assert_array_equal(getattr(default, field), getattr(named, field), err_msg=field)
    assert default.opt.timestep == named.opt.timestep


@pytest.mark.parametrize("name", OTHER_BODIES)
def test_a_body_keeps_the_horses_joints_and_scales_by_the_documented_laws(name: str) -> None:
    """Same joints, limits, actuators; masses by M, gains by m·ℓ, time by sqrt(ℓ) (docs/bodies.md)."""
    horse, body = load_model(), load_model(name)
    assert [horse.joint(j).name for j in range(horse.njnt)] == [body.joint(j).name for j in range(body.njnt)]
    np.testing.assert_array_equal(horse.jnt_range, body.jnt_range)  # angles are size-free
    np.testing.assert_array_equal(horse.actuator_ctrlrange, body.actuator_ctrlrange)
    mass_ratio = BODIES[name].mass / BODIES[REFERENCE_BODY].mass
    np.testing.assert_allclose(body.body_mass[1:], horse.body_mass[1:] * mass_ratio, rtol=1e-9)
    lengths = horse_layout(name).hip_height / horse_layout().hip_height
    # A servo's gain over the horse's: mass times its segment's length scale, which lies between
    # the limb's and the trunk's; the time step follows the limb's natural period.
    gain = body.actuator_gainprm[:, 0] / horse.actuator_gainprm[:, 0]
    assert np.all(gain > 0)
    assert gain.min() == pytest.approx(mass_ratio * lengths, rel=0.1)
    assert body.opt.timestep == pytest.approx(horse.opt.timestep * math.sqrt(lengths), rel=0.1)


def test_an_unknown_body_is_refused_with_the_names_there_are() -> None:
    with pytest.raises(UnknownBody, match="did you mean 'shetland'"):
        body_named("shetlnd")
    with pytest.raises(SettingsError, match=r"body.*did you mean 'draft'"):
        HorseSettings.from_mapping({"body": "drfat"})
    result = runner.invoke(app, ["evaluate", HYBRID, "--genome", "1,2,3", "--set", "body=pnoy"])
    assert result.exit_code == 2
    assert "did you mean 'pony'" in result.output
    assert "Traceback" not in result.output


def test_the_body_is_not_spelt_out_in_a_horse_runs_settings() -> None:
    """Runs of revision 4 without a body keep their fingerprints."""
    check = get_backend("mujoco-horse").check_settings
    assert "body" not in check({})
    assert check({"body": "draft"})["body"] == "draft"


# --- targets by dynamic similarity -------------------------------------------------------------


@pytest.mark.parametrize("name", list(BODIES))
def test_targets_and_frequency_follow_sqrt_g_over_h(name: str) -> None:
    horse_hip, hip = horse_layout().hip_height, horse_layout(name).hip_height
    ratio = frequency_ratio(REFERENCE_BODY, name)
    assert ratio == pytest.approx(math.sqrt(horse_hip / hip), rel=1e-12)
    if name == REFERENCE_BODY:
        assert ratio == 1.0
    evaluator = get_backend("mujoco-horse").load({"body": name, "threads": 1})
    try:
        targets = evaluator.targets
    finally:
        evaluator.close()
    froude = HorseSettings.from_mapping({}).froude
    assert targets.velocity == pytest.approx(froude * math.sqrt(9.81 * hip), rel=1e-3)  # Fr = v / sqrt(g h)
    horse = walk_targets(froude, horse_hip)
    assert targets.stride_frequency / horse.stride_frequency == pytest.approx(ratio, rel=1e-9)
    assert targets.stride_length / hip == pytest.approx(horse.stride_length / horse_hip, rel=1e-9)


@pytest.mark.parametrize("name", list(BODIES))
def test_the_seed_gait_walks_on_every_body(name: str) -> None:
    """The horse's seed, at each body's own target frequency, is a walk by criterion v2 over
    the 20-cycle horizon, at the body's target speed and frequency."""
    evaluator = get_backend("mujoco-horse").load({"body": name, "threads": 2})
    try:
        (checked,) = evaluator.verify(load_seed().motion_batch())
        targets = evaluator.targets
    finally:
        evaluator.close()
    assert checked.status is GaitStatus.OK, checked.detail
    c = checked.components
    assert c["walk"] == 1.0, {k: v for k, v in c.items() if k.startswith("walk_")}
    assert c["checked_cycles"] == 20.0
    assert c["measured_velocity"] == pytest.approx(targets.velocity, rel=0.1)
    assert c["measured_frequency"] == pytest.approx(targets.stride_frequency, rel=0.02)


def test_retargeting_to_the_same_body_is_the_identity() -> None:
    motion = replace(load_seed().motion_batch(), frequencies=np.array([0.93]))
    settings = {"cycles": 3}
    played_settings, played = retarget(settings, motion, REFERENCE_BODY, "froude")
    assert played_settings == {"cycles": 3, "body": REFERENCE_BODY}
    np.testing.assert_array_equal(played.frequencies, motion.frequencies)
    assert played.angles is motion.angles


def test_froude_and_unscaled_frequencies() -> None:
    motion = load_seed().motion_batch()  # no frequency of its own: played at the target
    _, froude = retarget({}, motion, "shetland", "froude")
    assert froude.frequencies is None  # the body's own target, which scales as sqrt(g / h)
    _, unscaled = retarget({}, motion, "shetland", "unscaled")
    horse_target = walk_targets(HorseSettings.from_mapping({}).froude, horse_layout().hip_height)
    np.testing.assert_allclose(unscaled.frequencies, [horse_target.stride_frequency])
    own = replace(motion, frequencies=np.array([0.9]))
    _, scaled = retarget({}, own, "draft", "froude")
    np.testing.assert_allclose(scaled.frequencies, [0.9 * frequency_ratio(None, "draft")])
    with pytest.raises(ValueError, match="no frequency scaling"):
        retarget({}, motion, "draft", "stretched")


def test_frequencies_of_another_body_are_played_froude_scaled() -> None:
    """``frequencies_of = "horse"`` on the Shetland plays a grammar's 0.95 Hz as the horse's 0.95 Hz
    retargeted: exactly the gait given sqrt(h_horse / h_shetland) times the frequency."""
    ratio = frequency_ratio("horse", "shetland")
    seed = load_seed().motion_batch()
    backend = get_backend("mujoco-horse")
    scaled = backend.load({"body": "shetland", "frequencies_of": "horse", "threads": 1})
    plain = backend.load({"body": "shetland", "threads": 1})
    try:
        (a,) = scaled.evaluate(replace(seed, frequencies=np.array([0.95])))
        (b,) = plain.evaluate(replace(seed, frequencies=np.array([0.95 * ratio])))
    finally:
        scaled.close()
        plain.close()
    assert a.fitness == b.fitness
    assert a.components == b.components
    assert a.components["measured_frequency"] == pytest.approx(0.95 * ratio, rel=0.02)
    with pytest.raises(SettingsError, match=r"frequencies_of.*did you mean 'horse'"):
        HorseSettings.from_mapping({"body": "pony", "frequencies_of": "hrose"})
    assert "frequencies_of" not in backend.check_settings({"body": "pony"})  # old fingerprints hold


# --- a run's gaits on another body -------------------------------------------------------------


@pytest.fixture(scope="module")
def horse_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("retarget") / "horse"
    made = runner.invoke(
        app, ["evolve", HYBRID, "--generations", "2", "--population", "8", "--seed", "3", "-o", str(out)]
    )
    assert made.exit_code == 0, made.output
    return out


def test_a_runs_best_checked_over_a_longer_horizon(horse_run: Path) -> None:
    """``evaluate --run DIR --horizon N``: the run's best gait checked over N cycles, not the run's
    20: the same fitness if it stays up, unviable (exit 1) if it falls before the end."""
    recorded = runner.invoke(app, ["evaluate", "--run", str(horse_run), "--json"])
    assert recorded.exit_code == 0, recorded.output
    longer = runner.invoke(app, ["evaluate", "--run", str(horse_run), "--horizon", "30", "--json"])
    record = json.loads(longer.stdout)
    if longer.exit_code == 0:
        assert record["components"]["checked_cycles"] == 30.0
        assert record["fitness"] == record["recorded_fitness"] == json.loads(recorded.stdout)["fitness"]
    else:
        assert longer.exit_code == 1, longer.output
        assert record["status"] != "ok"
    short = runner.invoke(app, ["evaluate", "--run", str(horse_run), "--horizon", "2"])
    assert short.exit_code == 2
    assert "horizon_cycles" in short.stderr
    assert "Traceback" not in short.output


def test_a_runs_best_played_on_its_own_body_scores_as_recorded(horse_run: Path) -> None:
    directory = RunDirectory.open(horse_run)
    pipeline = directory.pipeline
    state = load_checkpoint(
        directory.checkpoints[0], pipeline, fingerprint=directory.fingerprints, run=0, with_memory=False
    )
    best = state.best
    played = retarget_run(pipeline, [best.genome], state.generation, REFERENCE_BODY, "froude")
    assert played.individuals[0].evaluation.fitness == best.evaluation.fitness
    assert played.individuals[0].evaluation.components == best.evaluation.components
    with pytest.raises(RetargetError, match="did you mean 'draft'"):
        retarget_run(pipeline, [best.genome], state.generation, "draf", "froude")


def test_retarget_command(horse_run: Path) -> None:
    result = runner.invoke(app, ["retarget", "--run", str(horse_run), "--to", "shetland", "--json"])
    assert result.exit_code == 0, result.output
    record = json.loads(result.output)
    playings = {p["playing"]: p for p in record["played"]}
    assert set(playings) == {"as evolved", "froude", "unscaled"}
    evolved = playings["as evolved"]["frequency"]
    assert playings["unscaled"]["frequency"] == pytest.approx(evolved)
    ratio = frequency_ratio(None, "shetland")
    assert playings["froude"]["frequency"] == pytest.approx(evolved * ratio, rel=1e-9)
    each = runner.invoke(
        app, ["retarget", "--run", str(horse_run), "--to", "shetland", "--each-run", "--json"]
    )
    assert each.exit_code == 0, each.output
    (only,) = json.loads(each.output)["runs"]  # one run, finished
    assert only["played"] == record["played"]  # the best of one run is that run's best
    summary = json.loads(each.output)["summary"]
    assert summary["runs"] == 1
    for name in ("froude", "unscaled"):
        walks = summary["playings"][name]["walks"]
        assert walks == int(
            playings[name]["components"].get("walk", 0) >= 0.5 and playings[name]["status"] == "ok"
        )
        assert summary["playings"][name]["wilson95"] == pytest.approx(list(wilson_interval(walks, 1)))
        assert summary["playings"][name]["median_fitness"] == playings[name]["fitness"]
    (paired,) = summary["paired"]
    assert (paired["first"], paired["second"], paired["pairs"]) == ("froude", "unscaled", 1)
    assert paired["first_lower"] == int(playings["froude"]["fitness"] < playings["unscaled"]["fitness"])
    printed = runner.invoke(app, ["retarget", "--run", str(horse_run), "--to", "shetland", "--each-run"])
    assert "froude vs unscaled, paired by run: fitness lower under froude in" in printed.output
    assert "runs' bests are a walk on shetland (Wilson 95 %:" in printed.output
    table = runner.invoke(app, ["retarget", "--run", str(horse_run), "--to", "draft", "--scaling", "froude"])
    assert table.exit_code == 0, table.output
    assert "froude" in table.output
    assert "unscaled" not in table.output
    wrong = runner.invoke(app, ["retarget", "--run", str(horse_run), "--to", "zebra"])
    assert wrong.exit_code == 2
    assert "no body is called 'zebra'" in wrong.output
    assert "Traceback" not in wrong.output


@pytest.mark.parametrize("each_run", [[], ["--each-run"]])
def test_a_misspelt_body_is_named_alike_wherever_it_is_given(horse_run: Path, each_run: list[str]) -> None:
    """The body is checked where the bodies are defined, once: retarget --to says what evaluate's
    --set body= and a run's config say, with the same "did you mean"."""
    said = "no body is called 'drfat'; did you mean 'draft'?"
    retargeted = runner.invoke(app, ["retarget", "--run", str(horse_run), "--to", "drfat", *each_run])
    evaluated = runner.invoke(app, ["evaluate", HYBRID, "--genome", "1,2,3", "--set", "body=drfat"])
    for result in (retargeted, evaluated):
        assert result.exit_code == 2, result.output
        assert said in " ".join(result.stderr.split())
        assert "Traceback" not in result.output


# --- seeded transfer ---------------------------------------------------------------------------


def test_retarget_each_run_without_scipy_gives_the_counts_and_says_how_to_get_the_tests(
    horse_run: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from gaitgram.cli import retarget as command
    from gaitgram.extras import MissingExtra

    def missing(module: str, purpose: str) -> None:
        raise MissingExtra(module, purpose)

    monkeypatch.setattr(command, "require", missing)
    each = runner.invoke(app, ["retarget", "--run", str(horse_run), "--to", "pony", "--each-run", "--json"])
    assert each.exit_code in (0, 1), each.output
    summary = json.loads(each.output)["summary"]
    assert summary["paired"] == []
    assert "wilson95" not in summary["playings"]["froude"]
    assert summary["playings"]["froude"]["walks"] in (0, 1)
    assert "pip install" in summary["note"]


def test_a_run_started_from_another_begins_with_its_final_population(horse_run: Path, tmp_path: Path) -> None:
    config = tmp_path / "pony.toml"
    config.write_text('[backend_settings]\nbody = "pony"\n')
    out = tmp_path / "pony"
    made = runner.invoke(
        app,
        [
            *("evolve", HYBRID, "--config", str(config), "--generations", "1", "--population", "8"),
            *("--seed", "4", "--start-from", str(horse_run), "-o", str(out), "-q"),
        ],
    )
    assert made.exit_code == 0, made.output
    source = RunDirectory.open(horse_run)
    final = load_checkpoint(
        source.checkpoints[0], source.pipeline, fingerprint=source.fingerprints, run=0, with_memory=False
    )
    started = RunDirectory.open(out)
    assert started.config.start_from == str(horse_run.resolve())
    assert started.config.backend_settings["body"] == "pony"
    history = [json.loads(line) for line in (out / "run-000" / "stats.jsonl").read_text().splitlines()]
    # Generation 0 is the source's final population re-scored on the pony, not random trees.
    first = load_checkpoint(
        started.checkpoints[0], started.pipeline, fingerprint=started.fingerprints, run=0, with_memory=False
    )
    assert first.generation == 1
    assert history
    source_genomes = {tuple(i.genome) for i in final.population}
    assert {tuple(i.genome) for i in first.population} & source_genomes  # elites carried over


def _start_from(source: Path, grammar: str, out: Path, *flags: str) -> str:
    """The output of a one-generation run of 8 gaits started from ``source``; exit 2 expected."""
    result = runner.invoke(
        app,
        [
            *("evolve", grammar, "--generations", "1", "--population", "8", *flags),
            *("--start-from", str(source), "-o", str(out), "-q"),
        ],
    )
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    assert not out.exists()
    return result.output


def test_a_transfer_is_refused_from_another_grammar_or_too_small_a_population(
    horse_run: Path, tmp_path: Path
) -> None:
    assert "another grammar" in _start_from(horse_run, str(GRAMMARS / "sinusoidal.gg"), tmp_path / "x")
    bigger = _start_from(horse_run, HYBRID, tmp_path / "y", "--population", "20")
    assert "fewer than this run's population" in bigger
    assert "start_from" in _start_from(horse_run, HYBRID, tmp_path / "z", "--strategy", "cma-es")


def test_a_transfer_is_refused_from_an_unfinished_run(horse_run: Path, tmp_path: Path) -> None:
    finished = RunDirectory.open(horse_run).pipeline
    pipeline = Pipeline.build(finished.checked, replace(finished.config, generations=4))
    unfinished = tmp_path / "unfinished"
    directory = RunDirectory.create(unfinished, pipeline, defines={}, origin=HYBRID)
    generations: list[int] = []
    evaluator = pipeline.load_evaluator()
    try:
        run_session(
            directory,
            evaluator,
            resume=False,
            on_generation=lambda generation, _: generations.append(generation),
            should_stop=lambda: len(generations) >= 2,
        )
    finally:
        evaluator.close()
    said = _start_from(unfinished, HYBRID, tmp_path / "w")
    assert "has reached generation 1 of 4; start from it when it has finished" in said


def test_every_body_builds_from_the_one_xml() -> None:
    """Each model is horse.xml edited by MjSpec: a body's spec compiles, and has the same tree."""
    reference = master_spec()
    for name in OTHER_BODIES:
        spec = master_spec(name)
        assert [b.name for b in spec.bodies] == [b.name for b in reference.bodies]
        assert isinstance(spec.compile(), mujoco.MjModel)


def test_retarget_each_run_plays_the_first_runs_of_an_arm_grown_since(
    horse_run: Path, tmp_path: Path
) -> None:
    """``--each-run --runs N``: the figures an arm gave at N runs, after it grew."""
    grown = Path(shutil.copytree(horse_run, tmp_path / "grown"))
    more = runner.invoke(app, ["evolve", "--resume", str(grown), "--runs", "2", "-q"])
    assert more.exit_code == 0, more.output

    def played(run_dir: Path, *flags: str) -> dict:
        result = runner.invoke(
            app, ["retarget", "--run", str(run_dir), "--to", "pony", "--each-run", "--json", *flags]
        )
        assert result.exit_code in (0, 1), result.output
        return json.loads(result.output)

    then, now, first = played(horse_run), played(grown), played(grown, "--runs", "1")
    assert [r["run"] for r in now["runs"]] == [0, 1]
    assert {**first, "run": None} == {**then, "run": None}  # run 0 alone, as the arm gave it with one run
    refused = runner.invoke(
        app, ["retarget", "--run", str(grown), "--to", "pony", "--each-run", "--runs", "3"]
    )
    assert refused.exit_code == 2
    assert "asks for its first 3 runs, but it plans 2" in refused.output
    alone = runner.invoke(app, ["retarget", "--run", str(grown), "--to", "pony", "--runs", "1"])
    assert alone.exit_code == 2
    assert "add --each-run" in alone.output
