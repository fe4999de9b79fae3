"""Sensors in the editor services, as plain data: hover over a sensor in a curve's text, completion
of the sensors a joint may read, and semantic tokens that mark them, on the bundled closed-loop
grammar."""

from __future__ import annotations

import itertools

from conftest import GRAMMARS
from gaitgram.analysis import check
from gaitgram.ide import completion, hover
from gaitgram.ide.tokens import TokenType, sensor_spans, tokens
from gaitgram.language import parse

FEEDBACK = (GRAMMARS / "hybrid-feedback.gg").read_text()
RESULT = check(parse(FEEDBACK))
LINES = FEEDBACK.split("\n")


def line_starting(prefix: str) -> int:
    return next(i for i, line in enumerate(LINES) if line.startswith(prefix))


def test_hover_over_a_sensor_shows_what_it_reads() -> None:
    at = FEEDBACK.index("(load-1)") + 2
    found = hover.hover(RESULT, at)
    assert found is not None
    assert found.span is not None
    assert FEEDBACK[found.span.start : found.span.end] == "load"
    text = found.markdown
    assert "**`load`**: a sensor of mujoco-horse, in share" in text
    assert "hoof load" in text  # its description, from sensors.toml
    assert "per limb" in text
    assert "forelimb, hindlimb" in text
    assert "nominal reading (at rest) 1" in text
    pitch = hover.hover(RESULT, FEEDBACK.index("*pitch+") + 3)
    assert pitch is not None
    assert "in deg" in pitch.markdown
    assert "of the whole body" in pitch.markdown


def test_hover_over_a_periodic_sensor_says_it_is_a_phase() -> None:
    text = (GRAMMARS / "hybrid-reset.gg").read_text()
    result = check(parse(text))
    at = text.index("PI*phase)") + len("PI*")
    found = hover.hover(result, at + 1)
    assert found is not None
    assert "periodic: a phase in [0, 1)" in found.markdown


def test_hover_over_other_terminal_text_is_not_a_sensor() -> None:
    # ``pitch`` in a comment is no curve's text, and ``t`` is the phase, not a sensor.
    assert hover.hover(RESULT, FEEDBACK.index("trunk pitch") + 7) is None
    at = FEEDBACK.index("2*PI*t)") + 5
    found = hover.hover(RESULT, at)
    assert found is None or "sensor" not in found.markdown


def complete_after(prefix: str, typed: str) -> completion.Completions:
    model = completion.CompletionModel.of(RESULT)
    line = line_starting(prefix)
    text = LINES[line] + typed
    return completion.complete(model, line, text, len(text))


def sensor_items(found: completion.Completions) -> dict[str, completion.Completion]:
    return {i.label: i for i in found.items if i.kind is completion.CompletionKind.SENSOR}


def test_completion_in_a_limb_curve_offers_every_sensor_with_its_unit() -> None:
    found = complete_after("<feedback> ::=", "+0.2*pi")
    sensors = sensor_items(found)
    assert list(sensors) == [
        "pitch",
        "pitch_rate",
        "height",
        "speed",
        "pace",
        "cycle_pace",
        "load",
        "contact",
        "phase",
    ]
    assert sensors["pitch_rate"].detail == "deg/s"
    assert sensors["load"].documentation is not None
    assert "hoof load" in sensors["load"].documentation
    line = LINES[line_starting("<feedback> ::=")] + "+0.2*pi"
    assert line[found.start : found.end] == "pi"  # the name typed, not "0.2*pi"
    assert any(i.kind is completion.CompletionKind.RULE for i in found.items)  # rules still offered


def test_completion_in_a_neck_curve_leaves_out_per_limb_sensors() -> None:
    assert list(sensor_items(complete_after("<neck_mid> ::=", "+"))) == [
        "pitch",
        "pitch_rate",
        "height",
        "speed",
        "pace",
        "cycle_pace",
    ]


def test_no_sensors_outside_a_curve_or_in_the_frequency() -> None:
    assert sensor_items(complete_after("<prog> ::=", ";")) == {}
    assert sensor_items(complete_after("<frequency> ::=", "+")) == {}
    assert sensor_items(complete_after("<feedback> ::=", "+<p")) == {}  # a rule reference is typed


def test_semantic_tokens_mark_each_sensor_and_keep_the_terminal_around_it() -> None:
    found = tokens(RESULT.grammar, sensor_spans(RESULT))
    line = line_starting("<feedback> ::=")
    start = sum(len(x) + 1 for x in LINES[:line])
    end = start + len(LINES[line])
    shown = [(FEEDBACK[t.start : t.start + t.length], t.type) for t in found if start <= t.start < end]
    assert shown == [
        ("<feedback>", TokenType.RULE),
        ("::=", TokenType.OPERATOR),
        ("+", TokenType.STRING),
        ("<pitch_gain>", TokenType.RULE),
        ("*", TokenType.STRING),
        ("pitch", TokenType.SENSOR),
        ("+", TokenType.STRING),
        ("<pitch_rate_gain>", TokenType.RULE),
        ("*", TokenType.STRING),
        ("pitch_rate", TokenType.SENSOR),
        ("+", TokenType.STRING),
        ("<load_gain>", TokenType.RULE),
        ("*(", TokenType.STRING),
        ("load", TokenType.SENSOR),
        ("-1)", TokenType.STRING),
    ]
    ordered = [(t.start, t.start + t.length) for t in found]
    assert all(a[1] <= b[0] for a, b in itertools.pairwise(ordered))  # no overlaps


def test_without_a_backend_the_installed_backends_sensors_are_known() -> None:
    text = FEEDBACK.replace("@backend mujoco-horse\n", "")
    result = check(parse(text))
    found = hover.hover(result, text.index("(load-1)") + 2)
    assert found is not None
    assert "a sensor of mujoco-horse" in found.markdown
    assert len(sensor_spans(result)) == len(sensor_spans(RESULT))
