"""Runs that can never go silently wrong: each test is a wrong answer that once exited 0.

Every test here is written as a user meets the problem (the command line on
files) and fails on the gaitgram before the pipeline and run manifests: a
resume that silently changed meaning, a misspelt weight that scored nothing,
a configuration that could never work, a checkpoint edited by hand, a score of
NaN called ``ok``.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import pytest
from measured import summary_results
from typer.testing import CliRunner

from conftest import CURVE_GRAMMAR, CURVE_TARGETS, CURVE_TARGETS_TOML
from gaitgram.analysis import check
from gaitgram.backends.curve_match import CurveMatch
from gaitgram.cli import app
from gaitgram.configuration import RunConfig
from gaitgram.evolution.engine import advance, begin, run_context
from gaitgram.language import parse
from gaitgram.strategies.ge import GrammaticalEvolution
from gaitgram.strategies.registry import run_pipeline

runner = CliRunner()

GRAMMAR, TARGETS = CURVE_GRAMMAR, CURVE_TARGETS


def strict_json(text: str) -> object:
    """JSON as every other language reads it: NaN and Infinity are not JSON."""

    def refuse(token: str) -> None:
        raise ValueError(f"{token} is not valid JSON")

    return json.loads(text, parse_constant=refuse)


def write_setup(tmp_path: Path, grammar: str = GRAMMAR, **keys: object) -> tuple[Path, Path]:
    lines = [
        "generations = 3",
        "population = 12",
        "elite = 2",
        "init_max_depth = 6",
        'backend = "curve-match"',
    ]
    lines += [f"{k} = {json.dumps(v)}" for k, v in keys.items()]
    lines += ["", "[backend_settings.targets]"]
    config = tmp_path / "run.toml"
    config.write_text("\n".join(lines) + "\n" + CURVE_TARGETS_TOML)
    path = tmp_path / "g.gg"
    path.write_text(grammar)
    return path, config


def evolve(*args: str) -> object:
    return runner.invoke(app, ["evolve", *args, "-q"])


@pytest.fixture
def finished_run(tmp_path: Path) -> Path:
    grammar, config = write_setup(tmp_path)
    result = evolve(str(grammar), "-c", str(config), "-o", str(tmp_path / "run"))
    assert result.exit_code == 0, result.stderr
    return tmp_path / "run"


# ---- a resume never changes what the run means ------------------------------------------


@pytest.mark.parametrize(
    ("flags", "named"),
    [
        (["--seed", "3"], "seed: 0 -> 3"),
        (["--population", "20"], "population: 12 -> 20"),
        (["--generations", "9"], "generations: 3 -> 9"),
        (["--backend", "mujoco-horse"], "backend"),
    ],
)
def test_resume_refuses_a_flag_that_differs(finished_run: Path, flags: list[str], named: str) -> None:
    before = (finished_run / "run-000" / "checkpoint.json").read_bytes()
    result = evolve("--resume", str(finished_run), *flags)
    assert result.exit_code == 2
    assert "cannot resume" in result.stderr
    assert named in result.stderr
    assert (finished_run / "run-000" / "checkpoint.json").read_bytes() == before


def test_resume_accepts_flags_that_agree_and_threads(finished_run: Path) -> None:
    result = evolve("--resume", str(finished_run), "--seed", "0", "--generations", "3", "--threads", "1")
    assert result.exit_code == 0, result.stderr


def test_resume_refuses_an_edited_grammar_copy(finished_run: Path) -> None:
    copy = finished_run / "grammar.gg"
    copy.write_text(copy.read_text().replace("int[0..20]", "int[0..40]"))
    result = evolve("--resume", str(finished_run))
    assert result.exit_code == 2
    assert "grammar.gg was edited after the run started" in result.stderr


def test_resume_refuses_an_edited_config(finished_run: Path) -> None:
    config = finished_run / "config.toml"
    config.write_text(config.read_text().replace("mutation = 0.02", "mutation = 0.5"))
    result = evolve("--resume", str(finished_run))
    assert result.exit_code == 2
    assert "config.toml was edited" in result.stderr


def test_resume_refuses_a_different_grammar_argument(finished_run: Path, tmp_path: Path) -> None:
    other = tmp_path / "other.gg"
    other.write_text(GRAMMAR.replace("int[1..3]", "int[1..4]"))
    result = evolve(str(other), "--resume", str(finished_run))
    assert result.exit_code == 2
    assert "differs from the run's copy" in result.stderr
    same = evolve(str(tmp_path / "g.gg"), "--resume", str(finished_run))
    assert same.exit_code == 0, same.stderr


def test_resume_refuses_a_config_file_that_differs(finished_run: Path, tmp_path: Path) -> None:
    _, config = write_setup(tmp_path, tournament=2)
    result = evolve("--resume", str(finished_run), "-c", str(config))
    assert result.exit_code == 2
    assert "tournament: 3 -> 2" in result.stderr


DEFINED = GRAMMAR.replace("<k> ::= int[1..3]", "<k> ::= GE_RANGE:harmonics")


def test_resume_keeps_the_runs_defines_and_refuses_others(tmp_path: Path) -> None:
    grammar, config = write_setup(tmp_path, DEFINED)
    run = tmp_path / "run"
    first = evolve(str(grammar), "-c", str(config), "-o", str(run), "-D", "harmonics=3")
    assert first.exit_code == 0, first.stderr
    assert evolve("--resume", str(run)).exit_code == 0  # the saved value, not a missing one
    different = evolve("--resume", str(run), "-D", "harmonics=5")
    assert different.exit_code == 2
    assert "--define harmonics=5, but the run has harmonics=3" in different.stderr
    extra = evolve("--resume", str(run), "-D", "harmonics=3", "-D", "other=1")
    assert extra.exit_code == 2
    assert "--define other=1, but the run has not defined" in extra.stderr


def test_a_run_directory_without_its_manifest_is_refused(finished_run: Path) -> None:
    (finished_run / "manifest.json").unlink()
    result = evolve("--resume", str(finished_run))
    assert result.exit_code == 2
    assert "its manifest.json is missing, deleted or lost" in result.stderr
    assert "start a new run with another --out" in result.stderr


# ---- configuration checked before anything runs --------------------------------------------


BAD_CONFIGS = [
    # A misspelt weight once scored every gait as if the component did not exist.
    ("[[weight_schedule]]\nstart = 0\nweights = { rms_hip_hnid = 1.0 }\n", "did you mean rms_hip_hind?"),
    ("tail = inf\n", "tail: must be a finite number"),
    ("crossover = nan\n", "crossover"),
    ("tournament = 40\n", "tournament: a tournament of 40 is larger than the population of 12"),
    ("init_max_depth = 2\n", "init_max_depth: 2 is below the 3 levels"),
    ("max_depth = 2\n", "max_depth: 2 is below the 3 levels"),
    ("codon_size = 10\n", "codon_size: 10 is smaller than the 21 choices"),
    ("generatoins = 5\n", "did you mean generations?"),
    ("[[weight_schedule]]\nstart = 90\nweights = { rms_hip_hind = 1.0 }\n", "outside the run's generations"),
]


@pytest.mark.parametrize(("extra", "message"), BAD_CONFIGS)
def test_a_bad_config_is_refused_before_a_run_directory_exists(
    tmp_path: Path, extra: str, message: str
) -> None:
    grammar, config = write_setup(tmp_path)
    head, _, tables = config.read_text().partition("\n\n")
    if extra.startswith("["):
        config.write_text(f"{head}\n\n{tables}\n{extra}")
    else:  # the key replaces the setup's own
        kept = [line for line in head.splitlines() if line.split(" = ")[0] != extra.split(" = ")[0]]
        config.write_text("\n".join(kept) + "\n" + extra + "\n" + tables)
    result = evolve(str(grammar), "-c", str(config), "-o", str(tmp_path / "run"))
    assert result.exit_code == 2, result.stdout
    assert message in result.stderr
    assert not (tmp_path / "run").exists()
    assert "Traceback" not in result.stderr


@pytest.mark.parametrize(
    ("written", "flags", "message"),
    [  # a check of two keys blames the flag where a flag gave one
        ("elite = 7\n", ["--population", "7"], "error: --population: elite: 7 elites leave no room"),
        ("elite = 7\npopulation = 7\n", [], "run.toml:2:1: elite: 7 elites leave no room"),
    ],
)
def test_an_error_names_the_flag_or_the_line_that_caused_it(
    tmp_path: Path, written: str, flags: list[str], message: str
) -> None:
    grammar = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
    config = tmp_path / "run.toml"
    config.write_text("generations = 1\n" + written)
    result = evolve(str(grammar), "-c", str(config), *flags, "-o", str(tmp_path / "run"))
    assert result.exit_code == 2
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "run").exists()


def test_a_settings_table_that_is_no_table_is_refused_though_set_adds_to_it(tmp_path: Path) -> None:
    grammar = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
    config = tmp_path / "run.toml"
    config.write_text("backend_settings = 3\n")
    args = ["evaluate", str(grammar), "-c", str(config), "--set", "froude=0.5", "--genome", "1,2,3"]
    result = runner.invoke(app, args)
    assert result.exit_code == 2
    assert "run.toml:1:1: backend_settings: must be a table" in result.stderr
    assert "Traceback" not in result.stderr


@pytest.mark.parametrize(
    ("settings", "where", "message"),
    [
        ("[backend_settings]\nfrode = 0.4\n", ":6:1", "frode: unknown mujoco-horse setting; did you mean"),
        ("[backend_settings]\nfroude = 0.06\n  horizon_cycles = 100\n", ":7:3", "at most 120 s are allowed"),
        ("[backend_settings]\nfroude = inf\n", ":6:1", "froude: inf is not a finite number"),
        ("[backend_settings.weights]\nvelocty = 1.0\n", ":6:1", "weights.velocty: no fitness component"),
        ("backend_settings = { weights = { velocty = 1 } }\n", ":5:1", "weights.velocty: no fitness"),
        ("[backend_settings]\nbump_floors = [0, 30]\n", ":6:1", "bump_floors: seed 30 is one of the floors"),
        ("[[weight_schedule]]\nstart = 0\nweights = { strides = 2.0 }\n", None, "did you mean stride?"),
    ],
)
def test_bad_mujoco_settings_are_refused_with_the_key_named_where_it_is_written(
    tmp_path: Path, settings: str, where: str | None, message: str
) -> None:
    grammar = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
    config = tmp_path / "run.toml"
    config.write_text("generations = 1\npopulation = 4\nelite = 1\n\n" + settings)
    result = evolve(str(grammar), "-c", str(config), "-o", str(tmp_path / "run"))
    assert result.exit_code == 2
    assert message in result.stderr
    if where is not None:  # a backend setting: the file, and the line and column where it is written
        assert f"error: {config}{where}: [backend_settings] " in result.stderr
    assert not (tmp_path / "run").exists()


def test_a_curve_match_target_that_divides_by_zero_is_refused(tmp_path: Path) -> None:
    grammar, config = write_setup(tmp_path)
    config.write_text(config.read_text().replace(TARGETS["hip_hind"], "1/(t-t)"))
    result = evolve(str(grammar), "-c", str(config), "-o", str(tmp_path / "run"))
    assert result.exit_code == 2
    assert "targets.hip_hind" in result.stderr
    assert not (tmp_path / "run").exists()


def test_a_grammar_with_errors_is_never_evolved(tmp_path: Path) -> None:
    grammar, config = write_setup(tmp_path, GRAMMAR.replace("float[0..3 step 0.5]", "float[0..3 step 0]"))
    result = evolve(str(grammar), "-c", str(config), "-o", str(tmp_path / "run"))
    assert result.exit_code == 1
    assert "GG302" in result.stderr
    assert not (tmp_path / "run").exists()


# ---- every command scores through the run's own pipeline --------------------------------


def test_evaluate_run_reproduces_the_recorded_best_with_the_runs_codons(tmp_path: Path) -> None:
    grammar, config = write_setup(tmp_path, codons="eager", max_wraps=0)
    run = tmp_path / "run"
    assert evolve(str(grammar), "-c", str(config), "-o", str(run)).exit_code == 0
    best = json.loads((run / "run-000" / "best.json").read_text())
    result = runner.invoke(app, ["evaluate", "--run", str(run), "--json"])
    assert result.exit_code in (0, 1), result.stderr
    record = strict_json(result.stdout)
    assert record["phenotype"] == best["phenotype"]  # eager codons, no wraps: the run's mapping
    assert record["fitness"] == best["fitness"] == record["recorded_fitness"]
    # The command line's own defaults (lazy codons, 3 wraps) map the same genome to another gait:
    # that is what scoring outside the run's pipeline used to show.
    lazy = runner.invoke(app, ["map", str(grammar), "--genome", ",".join(map(str, best["genome"]))])
    assert lazy.stdout.splitlines()[0] != best["phenotype"]
    refused = runner.invoke(app, ["evaluate", "--run", str(run), "--codons", "lazy"])
    assert refused.exit_code == 2
    assert "drop --codons" in refused.stderr


def test_evaluate_applies_the_configs_weight_schedule(tmp_path: Path) -> None:
    grammar, config = write_setup(tmp_path)
    config.write_text(
        config.read_text()
        + "\n[[weight_schedule]]\nstart = 0\nweights = { rms_hip_hind = 1.0, rms_elbow_fore = 0.0 }\n"
    )
    genome = "3,7,0,2,5,1,4,2,6,0,9,1,2,3"
    result = runner.invoke(app, ["evaluate", str(grammar), "-c", str(config), "--genome", genome, "--json"])
    assert result.exit_code == 0, result.stderr
    record = strict_json(result.stdout)
    assert record["components"]["rms_elbow_fore"] > 0
    assert record["fitness"] == pytest.approx(record["components"]["rms_hip_hind"])


# ---- scores that are what they say --------------------------------------------------------


def test_curves_that_overflow_are_never_ok_and_json_stays_json(tmp_path: Path) -> None:
    huge = GRAMMAR.replace("<amp> ::= int[0..20]", "<amp> ::= 1e200 | 2e300")
    grammar, config = write_setup(tmp_path, huge)
    run = tmp_path / "run"
    result = evolve(str(grammar), "-c", str(config), "-o", str(run))
    assert result.exit_code == 0, result.stderr
    for line in (run / "run-000" / "stats.jsonl").read_text().splitlines():
        record = strict_json(line)
        assert record["invalid"] == 12  # every gait overflows: none may be called ok
        assert record["average"] is None
    best = strict_json((run / "run-000" / "best.json").read_text())
    assert best["status"] == "non-finite"
    assert math.isfinite(best["fitness"])


def test_radians_that_overflow_as_degrees_are_not_finite(tmp_path: Path) -> None:
    from gaitgram.motion.gait import MotionProblem, motion_batch

    batch = motion_batch([{"hip_hind": "1e307*sin(2*PI*t)"}], ["hip_hind"], units="rad")
    assert batch.problems == (MotionProblem.NON_FINITE,)


# ---- checkpoints are untrusted input --------------------------------------------------------


def _tamper(run: Path, change) -> None:
    path = run / "run-000" / "checkpoint.json"
    data = json.loads(path.read_text())
    change(data["checkpoint"])
    path.write_text(json.dumps(data))


def _set(key: str, value: object):
    def change(content: dict) -> None:
        content[key] = value

    return change


@pytest.mark.parametrize(
    "change",
    [
        lambda c: c["population"][0]["genome"].__setitem__(0, 7),  # a foreign genome
        lambda c: c["population"].pop(),  # a population of the wrong size
        _set("generation", 99),  # a generation beyond the run
        lambda c: c["population"][3]["evaluation"].__setitem__("fitness", 0.0),
        lambda c: c.pop("rng"),
        _set("history", "nonsense"),
    ],
    ids=["genome", "population-size", "generation", "fitness", "rng", "history"],
)
def test_a_tampered_checkpoint_is_refused_as_corrupt(finished_run: Path, change) -> None:
    _tamper(finished_run, change)
    result = evolve("--resume", str(finished_run))
    assert result.exit_code == 2
    assert "corrupt checkpoint" in result.stderr
    assert "Traceback" not in result.stderr


def test_a_checkpoint_from_another_run_is_refused(tmp_path: Path, finished_run: Path) -> None:
    (tmp_path / "b").mkdir()
    grammar, config = write_setup(tmp_path / "b", seed=4)
    other = tmp_path / "other"
    assert evolve(str(grammar), "-c", str(config), "-o", str(other)).exit_code == 0
    (finished_run / "run-000" / "checkpoint.json").write_bytes(
        (other / "run-000" / "checkpoint.json").read_bytes()
    )
    result = evolve("--resume", str(finished_run))
    assert result.exit_code == 2
    assert "belongs to another run" in result.stderr


@pytest.mark.parametrize("content", ["[]", '{"digest": "x", "checkpoint": {"version": 2}}', "{", "null"])
def test_a_malformed_checkpoint_is_refused(finished_run: Path, content: str) -> None:
    (finished_run / "run-000" / "checkpoint.json").write_text(content)
    result = evolve("--resume", str(finished_run))
    assert result.exit_code == 2
    assert "corrupt checkpoint" in result.stderr


# ---- stated options do what they say --------------------------------------------------------


def test_mutation_within_used_leaves_the_unused_tail_alone() -> None:
    config = RunConfig(
        population=20,
        elite=0,
        representation_settings={
            "crossover": 0.0,
            "mutation": 1.0,
            "mutation_within_used": True,
            "init_max_depth": 6,
            "tail": 3.0,
        },
        backend="curve-match",
        backend_settings={"targets": TARGETS},
    )
    evaluator = CurveMatch(TARGETS)

    def tails_after_one_generation(config: RunConfig) -> tuple[set, list]:
        pipeline = run_pipeline(check(parse(GRAMMAR)), config)
        strategy, context = GrammaticalEvolution(), run_context(pipeline, 0)
        state = begin(strategy, context, evaluator)
        after = advance(strategy, context, state, evaluator)
        return {i.genome[i.used :] for i in state.population}, after.population

    parents, children = tails_after_one_generation(config)
    assert all(c.genome[c.used :] in parents for c in children)  # tails came unchanged
    unmasked = {**config.representation_settings, "mutation_within_used": False}
    parents, children = tails_after_one_generation(replace(config, representation_settings=unmasked))
    assert any(c.genome[c.used :] not in parents for c in children)


# ---- failures are messages with exit codes -------------------------------------------------


def test_a_full_disk_mid_run_is_an_error_message_and_resumable(tmp_path: Path) -> None:
    import resource
    import signal
    import subprocess
    import sys

    grammar, config = write_setup(tmp_path)
    run = tmp_path / "run"

    def small_files() -> None:  # writes past 3 kB fail with EFBIG, as on a full disk
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (3_000, 3_000))

    command = [
        sys.executable,
        "-m",
        "gaitgram",
        "evolve",
        str(grammar),
        "-c",
        str(config),
        "-o",
        str(run),
        "-q",
    ]
    full = subprocess.run(command, capture_output=True, text=True, preexec_fn=small_files)
    assert full.returncode == 2
    assert "error: cannot write" in full.stderr
    assert f"gaitgram evolve --resume {run}" in full.stderr
    assert "Traceback" not in full.stderr
    resumed = subprocess.run(
        [*command[:3], "evolve", "--resume", str(run), "-q"], capture_output=True, text=True
    )
    assert resumed.returncode == 0, resumed.stderr


# ---- a run directory grows more runs, and never changes the ones it has ------------------


def test_resume_with_more_runs_adds_them_and_equals_a_fresh_run(tmp_path: Path, finished_run: Path) -> None:
    grown = evolve("--resume", str(finished_run), "--runs", "3")
    assert grown.exit_code == 0, grown.stderr
    grammar, config = tmp_path / "g.gg", tmp_path / "run.toml"
    fresh = evolve(str(grammar), "-c", str(config), "--runs", "3", "-o", str(tmp_path / "fresh"))
    assert fresh.exit_code == 0, fresh.stderr
    for run in range(3):
        name = f"run-{run:03d}/stats.csv"
        assert (finished_run / name).read_text() == (tmp_path / "fresh" / name).read_text()
    assert summary_results(finished_run / "summary.json") == summary_results(
        tmp_path / "fresh" / "summary.json"
    )
    fewer = evolve("--resume", str(finished_run), "--runs", "2")
    assert fewer.exit_code == 2
    assert "runs: 3 -> 2" in fewer.stderr


def test_a_directory_fingerprinted_with_its_run_count_still_opens_and_grows(finished_run: Path) -> None:
    """Directories made before the run count left the fingerprint (docs/results/ holds some) keep
    working: they open, resume, and grow, their checkpoints re-saved under the new fingerprint."""
    from gaitgram.evolution.checkpoint import load_checkpoint, save_checkpoint
    from gaitgram.evolution.rundir import RunDirectory, best_of_runs, fingerprint

    directory = RunDirectory.open(finished_run)
    legacy = fingerprint(directory.pipeline, directory.defines, with_runs=True)
    assert legacy != directory.fingerprint
    checkpoint = finished_run / "run-000" / "checkpoint.json"
    state = load_checkpoint(checkpoint, directory.pipeline, fingerprint=directory.fingerprint, run=0)
    save_checkpoint(checkpoint, state, fingerprint=legacy, run=0)
    manifest = json.loads((finished_run / "manifest.json").read_text())
    (finished_run / "manifest.json").write_text(json.dumps({**manifest, "fingerprint": legacy}))

    reopened = RunDirectory.open(finished_run)
    assert best_of_runs(reopened)[2].fitness == state.best.fitness
    assert evolve("--resume", str(finished_run)).exit_code == 0
    grown = reopened.grow(2)
    assert grown.config.runs == 2
    assert json.loads(checkpoint.read_text())["checkpoint"]["fingerprint"] == grown.fingerprint
    assert json.loads((finished_run / "manifest.json").read_text())["fingerprint"] == grown.fingerprint
    with pytest.raises(ValueError, match="never shrinks"):
        grown.grow(1)


def test_a_growth_killed_between_manifest_and_config_still_opens(finished_run: Path) -> None:
    """The manifest names the old and the new configuration, so the directory opens whichever of
    the two config.toml holds when a growth is killed."""
    from gaitgram.evolution.rundir import RunDirectory

    before = (finished_run / "config.toml").read_text()
    RunDirectory.open(finished_run).grow(2)
    (finished_run / "config.toml").write_text(before)  # as if killed before config.toml was replaced
    assert RunDirectory.open(finished_run).config.runs == 1
    assert RunDirectory.open(finished_run).grow(2).config.runs == 2


@pytest.mark.parametrize(
    ("config_text", "flags", "said"),
    [
        (
            "generations = 1\n\n  populaton = 4\n",
            [],
            "run.toml:3:3: unknown key 'populaton'; did you mean population?",
        ),
        ('generations = "a"  # how many\n', [], "run.toml:1:1: generations: must be an int, not 'a'"),
        (
            "generations = 1\nbackend_settings = { weights = { velocity = nan } }\n",
            [],
            "run.toml:2:1: [backend_settings]",
        ),
        ("[[weight_schedule]]\nstart = 0\nweights = 3\n", [], "run.toml:1:1: weight_schedule[0]"),
    ],
)
def test_a_bad_config_key_is_named_where_it_was_given(
    tmp_path: Path, config_text: str, flags: list[str], said: str
) -> None:
    grammar = Path(__file__).resolve().parents[2] / "grammars" / "sine-walk.gg"
    config = tmp_path / "run.toml"
    config.write_text(config_text)
    result = evolve(str(grammar), "-c", str(config), *flags, "-o", str(tmp_path / "run"))
    assert result.exit_code == 2
    assert said in result.stderr, result.stderr
    assert not (tmp_path / "run").exists()
