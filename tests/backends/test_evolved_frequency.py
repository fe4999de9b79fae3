"""An evolved cycle frequency: a grammar's ``@frequency`` rule sets each gait's stride frequency.

From the annotation (language) through the mapper and the motion batch to the horse, whose
measured stride frequency follows it; and the refusals on the way.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from gaitgram.analysis import check
from gaitgram.backends.api import GaitStatus
from gaitgram.backends.mujoco_horse import CATALOGUE
from gaitgram.backends.mujoco_horse.evaluator import HorseEvaluator, HorseSettings
from gaitgram.cli import app
from gaitgram.configuration import RunConfig
from gaitgram.language import parse
from gaitgram.language.model import FREQUENCY
from gaitgram.motion.gait import MotionBatch, MotionProblem, motion_batch
from gaitgram.pipeline import Pipeline, PipelineError
from gaitgram.seed import load_seed

GRAMMAR = """\
@start <prog>
@backend mujoco-horse
<prog> ::= <f>;<hip>
@frequency limits=0.6..1.9
<f> ::= float[0.6..1.8 step 0.6] | 2.5 | 0.2*t+1
@joint hip_hind limits=-30..30
<hip> ::= 5*sin(2*PI*t)
"""


def seed_batch(frequencies: list[float] | None, copies: int = 1) -> MotionBatch:
    seed = load_seed()
    samples = np.arange(256) / 256
    angles = np.array(
        [np.interp(samples, np.append(seed.phases, 1), np.append(c, c[0])) for c in seed.angles.values()]
    )
    count = copies if frequencies is None else len(frequencies)
    return MotionBatch(
        tuple(seed.angles),
        np.repeat(angles[None], count, axis=0),
        (None,) * count,
        (None,) * count,
        None if frequencies is None else np.array(frequencies),
    )


def test_the_annotation_declares_the_frequency_rule_and_the_mapper_cuts_its_text() -> None:
    grammar = parse(GRAMMAR)
    assert not grammar.has_errors, grammar.diagnostics
    assert grammar.frequency is not None
    assert (grammar.frequency.rule, grammar.frequency.limits) == ("f", (0.6, 1.9))
    pipeline = Pipeline.build(check(grammar), RunConfig())
    mapped = pipeline.map([[1, 0], [3, 0], [4, 0]])
    assert [m.joints[FREQUENCY] for m in mapped] == ["1.2", "2.5", "0.2*t+1"]
    batch = pipeline.motion(mapped, 0)
    assert batch.frequencies is not None
    assert batch.frequencies[0] == 1.2
    # Outside the limits, and depending on t: not a frequency, so not a usable gait.
    assert batch.problems[1:] == (MotionProblem.INVALID_MOTION, MotionProblem.INVALID_MOTION)
    assert "outside the allowed 0.6..1.9 Hz" in str(batch.details[1])
    assert "depends on t" in str(batch.details[2])
    assert np.isnan(batch.frequencies[1:]).all()


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("@frequency\n@frequency\n<f> ::= 1\n", "more than once"),
        ("@frequency\n<f> ::= 1\n@frequency\n<g> ::= 1\n", "more than once"),
        ("@frequency\n@joint hip_hind\n<f> ::= 1\n", "cannot derive the frequency too"),
        ("@frequency limits=2..1\n<f> ::= 1\n", "is empty"),
        ("@frequency 1.2\n<f> ::= 1\n", "no more positional"),
    ],
)
def test_misused_annotations_are_diagnostics(text: str, message: str) -> None:
    grammar = parse("<prog> ::= <f>\n" + text)
    assert any(message in d.message for d in grammar.diagnostics), grammar.diagnostics


def test_a_backend_that_imposes_the_frequency_refuses_the_grammar() -> None:
    text = "@backend curve-match\n<prog> ::= <f>;<a>\n@frequency\n<f> ::= 1\n@joint a\n<a> ::= sin(2*PI*t)\n"
    with pytest.raises(PipelineError, match="imposes the cycle frequency"):
        Pipeline.build(check(parse(text)), RunConfig(backend_settings={"targets": {"a": "sin(2*PI*t)"}}))
    wide = GRAMMAR.replace("limits=0.6..1.9", "limits=0.1..9")
    with pytest.raises(PipelineError, match=r"reach beyond the 0\.3\.\.3 Hz"):
        Pipeline.build(check(parse(wide)), RunConfig())


@pytest.fixture(scope="module")
def horse() -> HorseEvaluator:
    evaluator = HorseEvaluator(HorseSettings(threads=2))
    yield evaluator
    evaluator.close()


def test_the_targets_frequency_given_per_gait_scores_bit_identically(horse: HorseEvaluator) -> None:
    """The per-gait control path at the imposed frequency is the shared path, bit for bit."""
    imposed = horse.evaluate(seed_batch(None))
    own = horse.evaluate(seed_batch([horse.targets.stride_frequency]))
    assert own == imposed


def test_the_horse_steps_at_the_evolved_frequency(horse: HorseEvaluator) -> None:
    """Each gait is played at its own frequency in one batch; footfalls show it."""
    wanted = [0.8, 0.95]
    results = horse.evaluate(seed_batch(wanted))
    for frequency, result in zip(wanted, results, strict=True):
        assert result.status is GaitStatus.OK, result.detail
        assert result.components["measured_frequency"] == pytest.approx(frequency, rel=0.1)
    # Alone in its batch, each gait scores as it did beside the other.
    assert [horse.evaluate(seed_batch([f]))[0] for f in wanted] == results


def test_chunking_changes_no_bit_with_evolved_frequencies() -> None:
    short = HorseSettings(cycles=1, ramp_seconds=0.1, threads=1)
    whole = HorseEvaluator(short, chunk_steps=10_000)
    chunked = HorseEvaluator(short, chunk_steps=7)
    try:
        batch = seed_batch([0.7, 1.0, 1.5, 2.2])
        assert chunked.evaluate(batch) == whole.evaluate(batch)
    finally:
        whole.close()
        chunked.close()


def test_evaluate_cli_plays_a_grammar_with_an_evolved_frequency(tmp_path: Path) -> None:
    grammar = tmp_path / "f.gg"
    grammar.write_text(GRAMMAR)
    config = tmp_path / "run.toml"
    config.write_text("[backend_settings]\ncycles = 1\nramp_seconds = 0.1\n")
    result = CliRunner().invoke(
        app, ["evaluate", str(grammar), "--genome", "1,0", "--config", str(config), "--json"]
    )
    assert result.exit_code == 0, result.output
    assert '"measured_frequency"' in result.output


def test_motion_batch_without_a_frequency_rule_carries_none() -> None:
    batch = motion_batch([{"hip_hind": "1"}], CATALOGUE.names)
    assert batch.frequencies is None
    assert dataclasses.replace(batch).frequencies is None
