"""Numbers read exactly: ranges and annotation arguments mean the numbers written, exponents
included; values that would collapse or cannot be held are diagnostics; text that cannot be
encoded is refused when the grammar is checked, not when a later command writes it out."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from decimal import Decimal, localcontext
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from gaitgram.analysis import check
from gaitgram.language import parse
from gaitgram.language.diagnostics import Severity
from gaitgram.language.model import Grammar, RangeSpec
from gaitgram.language.ranges import MAX_RANGE_VALUES


def values(range_text: str) -> tuple[str, ...] | None:
    grammar = parse(f"<a> ::= {range_text}")
    assert not [d for d in grammar.diagnostics if d.is_error], grammar.diagnostics
    spec = grammar.rules[0].alternatives[0].range_values
    return None if spec is None else spec.values


def problems(text: str) -> list[tuple[str, str]]:
    """(code, the source text the diagnostic points at) of everything check reports."""
    grammar = parse(text)
    return [(d.code.code, grammar.source.slice(d.span)) for d in check(grammar).diagnostics]


# ---- 1. ranges are read exactly, exponents included ------------------------------------------


@pytest.mark.parametrize(
    ("range_text", "plain", "expected"),
    [
        ("float[0..1 step 2.5e-1]", "float[0..1 step 0.25]", ("0", "0.25", "0.5", "0.75", "1")),
        ("float[1e-1..4e-1 step 1e-1]", "float[0.1..0.4 step 0.1]", ("0.1", "0.2", "0.3", "0.4")),
        ("float[-2.5e-1..2.5e-1 step 2.5e-1]", "float[-0.25..0.25 step 0.25]", ("-0.25", "0", "0.25")),
        # 25e-3 is written to three decimals, so count values get five, as for 0.025
        ("float[0..25e-3 count 3]", "float[0..0.025 count 3]", ("0", "0.0125", "0.025")),
        ("int[1.5e1..18 step 1e0]", "int[15..18]", ("15", "16", "17", "18")),  # 1.5e1 is the whole 15
        ("int[0..1e2 step 2.5e1]", "int[0..100 step 25]", ("0", "25", "50", "75", "100")),
    ],
)
def test_exponents_are_read_to_the_value_written(
    range_text: str, plain: str, expected: tuple[str, ...]
) -> None:
    assert values(range_text) == values(plain) == expected


def test_a_count_range_takes_the_decimals_that_keep_its_values_apart() -> None:
    # Two decimals more than the bounds' would give 0, 0, 0, 0.01, ...: three are enough.
    got = values("float[0..1 count 1000]")
    assert got is not None
    assert len(set(got)) == 1000
    assert got[:3] == ("0", "0.001", "0.002")
    assert got[-1] == "1"


# ---- 2. values that collapse, or cannot be held, are errors ------------------------------------


@pytest.mark.parametrize(
    ("range_text", "code", "pointed_at"),
    [
        ("float[0..1e-300 count 5]", "GG307", "1e-300"),  # would read as 0: five zeros
        ("float[0..1e-400 count 5]", "GG307", "1e-400"),
        ("float[1e400..2 step 1]", "GG307", "1e400"),  # not finite as a double
        ("float[0..1 step 1e400]", "GG307", "1e400"),
        ("float[0..1 step 1e-400]", "GG307", "1e-400"),
        ("float[0.1 ± 1e-400% count 3]", "GG307", "1e-400"),
        ("float[1 ± 1e13% step 1]", "GG307", "1e13"),
        ("float[1..1.000000000000001 count 3]", "GG307", "1.000000000000001"),
        ("float[123456789012.5..123456789013 step 0.0001]", "GG307", None),
        ("float[2..2 count 3]", "GG306", None),
        ("float[5 ± 0% count 3]", "GG306", None),
        ("float[0 ± 10% count 3]", "GG306", None),
        ("float[0..1e-11 count 100000]", "GG306", None),  # 1e-16 apart: below 15 decimals
        ("float[0..1 count 1]", "GG308", None),
        ("float[7.7 ± 25% count 1]", "GG308", None),
        ("int[10.5 ± 10%]", "GG305", None),  # was silently just "10"
    ],
)
def test_collapsing_or_unrepresentable_ranges_are_errors(
    range_text: str, code: str, pointed_at: str | None
) -> None:
    grammar = parse(f"<a> ::= {range_text} | x")
    (problem,) = grammar.diagnostics
    assert problem.code.code == code
    assert problem.level is Severity.ERROR
    assert problem.hint
    assert grammar.source.slice(problem.span) == (pointed_at or range_text)
    assert grammar.rules[0].alternatives[0].range_values is None  # never a list with duplicates


def test_huge_sizes_are_reported_in_a_readable_message() -> None:
    (problem,) = parse("<a> ::= float[0..1 count 1e400]").diagnostics
    assert problem.code.code == "GG304"
    assert len(problem.message) < 120, problem.message
    (problem,) = parse("<a> ::= float[-1e12..1e12 step 1e-15]").diagnostics
    assert problem.code.code == "GG304"
    assert len(problem.message) < 120, problem.message


# ---- 3. degenerate forms -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("range_text", "expected"),
    [
        ("int[3..3]", ("3",)),
        ("float[2..2 step 0.5]", ("2",)),
        ("float[2..2 count 1]", ("2",)),
        ("int[4 ± 5%]", ("4",)),
        ("int[5 ± 0%]", ("5",)),
        ("float[5 ± 0% step 1]", ("5",)),
        ("float[-0..0 count 1]", ("0",)),
    ],
)
def test_a_range_of_one_value_is_that_value(range_text: str, expected: tuple[str, ...]) -> None:
    grammar = parse(f"<a> ::= {range_text}")
    assert not check(grammar).diagnostics
    assert values(range_text) == expected
    assert grammar.rules[0].choice_count == 1


def test_count_one_needs_equal_ends() -> None:
    assert [code for code, _ in problems("<a> ::= float[0..1 count 1]")] == ["GG308"]
    assert [code for code, _ in problems("<a> ::= float[3 ± 10% count 1]")] == ["GG308"]
    assert values("float[3 ± 0% count 1]") == ("3",)


# ---- 4. annotation numbers ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("annotation", "argument"),
    [
        ("@joint hip_hind limits=-1e400..5", "limits=-1e400..5"),
        ("@joint hip_hind limits=1e-400..5", "limits=1e-400..5"),
        ("@joint hip_hind limits=0.10000000000000001..1", "limits=0.10000000000000001..1"),
        ("@joint hip_hind free=99999999999999999999999", "free=99999999999999999999999"),
        ("@frequency limits=0.3..1e400", "limits=0.3..1e400"),
        ("@define n=99999999999999999999999", "n=99999999999999999999999"),
    ],
)
def test_absurd_annotation_numbers_are_errors_naming_the_argument(annotation: str, argument: str) -> None:
    grammar = parse(f"{annotation}\n<a> ::= 1\n")
    errors = [d for d in check(grammar).diagnostics if d.is_error]
    assert [(d.code.code, grammar.source.slice(d.span)) for d in errors] == [("GG402", argument)]
    assert f"'{argument.split('=')[0]}'" in errors[0].message
    for joint in grammar.joints:
        assert joint.limits is None or all(math.isfinite(x) for x in joint.limits)
    assert grammar.frequency is None or grammar.frequency.limits is None


def test_whole_numbers_may_be_written_with_an_exponent() -> None:
    grammar = parse("@define n=3e0\n@joint hip_hind free=1e3 limits=-2.5e1..3e1\n<a> ::= GE_RANGE:n\n")
    assert not [d for d in grammar.diagnostics if d.is_error], grammar.diagnostics
    assert grammar.defines == {"n": 3}
    (joint,) = grammar.joints
    assert joint.free == (1000, None)
    assert joint.limits == (-25, 30)
    assert [code for code, _ in problems("@joint hip_hind free=1.5\n<a> ::= 1\n")] == ["GG507", "GG402"]


# ---- 5. text that cannot be encoded ------------------------------------------------------------


def test_a_surrogate_escape_is_an_error_at_the_escape() -> None:
    assert problems('<a> ::= x"\\ud800"y | b') == [("GG103", "\\ud800")]
    assert problems("<a> ::= x\\U0000dfff") == [("GG103", "\\U0000dfff")]
    assert problems("@start '\\udc00'\n<a> ::= x") == [("GG402", "'\\udc00'"), ("GG103", "\\udc00")]


def test_a_surrogate_pair_escape_says_what_to_write() -> None:
    grammar = parse('<a> ::= "\\ud83d\\ude00"')
    (problem,) = grammar.diagnostics
    assert problem.code.code == "GG103"
    assert grammar.source.slice(problem.span) == "\\ud83d\\ude00"
    assert "\\U0001F600" in problem.message


def test_a_lone_surrogate_in_a_string_given_to_the_library_is_an_error_at_it() -> None:
    grammar = parse("<a> ::= x\ud800y | <b>\n<b> ::= \udc00\ud83d\n")
    spans = [(d.code.code, grammar.source.slice(d.span)) for d in grammar.diagnostics]
    assert spans == [("GG109", "\ud800"), ("GG109", "\udc00\ud83d")]
    assert all(d.code.syntax for d in grammar.diagnostics)  # fmt leaves such text alone


# ---- the command line, on files ----------------------------------------------------------------


def gaitgram(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "200"}
    return subprocess.run(
        [sys.executable, "-m", "gaitgram", *args], capture_output=True, text=True, env=env, cwd=cwd
    )


def test_check_reports_numbers_and_escapes_on_a_file(tmp_path: Path) -> None:
    path = tmp_path / "numbers.gg"
    path.write_text(
        "<a> ::= float[0..1e-300 count 5] | float[2..2 count 3] | <b>\n"
        "@joint hip_hind limits=-1e400..5\n"
        '<b> ::= x"\\ud800"\n',
        encoding="utf-8",
    )
    run = gaitgram("check", "numbers.gg", cwd=tmp_path)
    assert run.returncode == 1
    assert "Traceback" not in run.stderr
    out = run.stdout
    assert "numbers.gg:1:18: error[GG307] 1e-300 in 'float[0..1e-300 count 5]' is too small" in out
    assert "numbers.gg:1:36: error[GG306]" in out
    assert "numbers.gg:2:17: error[GG402] 'limits': -1e400 is beyond ±1e12" in out
    assert "numbers.gg:3:11: error[GG103]" in out


#: Numbers as a user may write them, each meaning a checked number (so the range reads), but
#: spelt so that arithmetic in a decimal context would round, or int() would refuse.
PADDED = "1." + "0" * 150


@pytest.mark.parametrize(
    ("text", "status", "expected"),
    [
        ("<a> ::= int[1 ± 0e-400%]\n", 0, None),  # 0 % of 1: the range of one value
        (f"<a> ::= float[{PADDED} ± 5% count 3]\n", 0, None),
        (f"<a> ::= float[2 ± {PADDED}e1% step 0.1]\n", 0, None),
        (f"<a> ::= float[0e-999999999..{PADDED} count 3]\n", 0, None),
        ("<a> ::= float[0..1 step 0." + "0" * 150 + "1]\n", 1, ":1:25: error[GG307]"),
        ("<a> ::= GE_RANGE:" + "9" * 5000 + "\n", 1, ":1:9: error[GG105] GE_RANGE:9"),
        ("<a> ::= GE_RANGE:" + "0" * 5000 + "7\n", 0, None),
        ("<a> ::= GE_RANGE:\u00b2\n", 1, ":1:9: error[GG105] GE_RANGE:\u00b2: the size must be a number"),
        ("<a> ::= int[1..1e999999999999999999999999]\n", 1, ":1:16: error[GG307]"),
        ("<a> ::= float[0..1 count 1e999999999]\n", 1, ":1:9: error[GG304]"),
    ],
)
def test_check_reads_extreme_numerals_in_a_file_as_diagnostics_never_a_traceback(
    tmp_path: Path, text: str, status: int, expected: str | None
) -> None:
    (tmp_path / "extreme.gg").write_text(text, encoding="utf-8")
    run = gaitgram("check", "extreme.gg", cwd=tmp_path)
    assert "Traceback" not in run.stderr, run.stderr
    assert run.returncode == status, run.stdout + run.stderr
    if expected is None:
        assert "1 file OK" in run.stderr
    else:
        assert f"extreme.gg{expected}" in run.stdout


def test_map_refuses_a_surrogate_instead_of_crashing_and_reads_exponents(tmp_path: Path) -> None:
    (tmp_path / "surrogate.gg").write_text('<a> ::= x"\\ud800"y | b\n', encoding="utf-8")
    run = gaitgram("map", "surrogate.gg", "--genome", "0", cwd=tmp_path)
    assert run.returncode == 1
    assert "Traceback" not in run.stderr
    assert "UnicodeEncodeError" not in run.stderr
    assert "error[GG103]" in run.stderr

    (tmp_path / "step.gg").write_text("<a> ::= float[0..1 step 2.5e-1]\n", encoding="utf-8")
    run = gaitgram("map", "step.gg", "--genome", "1", "--json", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert '"phenotype": "0.25"' in run.stdout


# ---- 6b. the values read are the exact decimals, however they are spelt ------------------------


def exponent_spelling(value: Decimal) -> str:
    """The same number with its digits and exponent as written: 0.25 as 25e-2, 1.50 as 150e-2."""
    sign, digits, exponent = value.as_tuple()
    return ("-" if sign else "") + "".join(map(str, digits)) + f"e{exponent}"


def spellings(value: Decimal) -> list[str]:
    """Plain, scientific and digits-and-exponent texts of one decimal, all with its exponent."""
    return [format(value, "f"), format(value, "e"), exponent_spelling(value)]


def spec(range_text: str) -> RangeSpec:
    grammar: Grammar = parse(f"<a> ::= {range_text}")
    assert not grammar.diagnostics, (range_text, grammar.diagnostics)
    found = grammar.rules[0].alternatives[0].range_values
    assert found is not None
    return found


@settings(max_examples=80)
@given(
    places=st.integers(0, 6),
    data=st.data(),
    steps=st.integers(0, 40),
    spelling=st.integers(0, 2),
)
def test_step_values_are_the_exact_decimals_in_any_spelling(
    places: int, data: st.DataObject, steps: int, spelling: int
) -> None:
    quantum = Decimal(1).scaleb(-places)
    low = data.draw(st.decimals(-1000, 1000, places=places), label="low")
    step = data.draw(st.decimals(quantum, 100, places=places), label="step")
    with localcontext() as context:
        context.prec = 60
        high = low + step * steps
        exact = [low + step * i for i in range(steps + 1)]
    plain = spec(f"float[{format(low, 'f')}..{format(high, 'f')} step {format(step, 'f')}]")
    spelt = spec(
        f"float[{spellings(low)[spelling]}..{spellings(high)[spelling]} step {spellings(step)[spelling]}]"
    )
    assert plain.values == spelt.values
    assert [Decimal(v) for v in plain.values] == exact
    for text in plain.values:  # printed as a person would: no exponent, no trailing zeros
        assert "e" not in text.lower()
        assert not ("." in text and text.endswith("0"))
        assert Decimal(repr(float(text))) == Decimal(text)  # and a double reads it back unchanged


@settings(max_examples=80)
@given(
    places=st.integers(0, 5),
    data=st.data(),
    count=st.integers(2, 40),
    spelling=st.integers(0, 2),
)
def test_count_values_are_the_exact_fractions_rounded_as_documented(
    places: int, data: st.DataObject, count: int, spelling: int
) -> None:
    low = data.draw(st.decimals(-1000, 1000, places=places), label="low")
    high = data.draw(st.decimals(low, 1001, places=places), label="high")
    assume(low != high)
    written = places + 2  # two more decimals than the bounds are written with
    width = (Fraction(high) - Fraction(low)) / (count - 1)
    assume(width >= Fraction(1, 10**written))  # then those decimals keep the values apart
    expected = [round(Fraction(low) + width * i, written) for i in range(count)]
    plain = spec(f"float[{format(low, 'f')}..{format(high, 'f')} count {count}]")
    spelt = spec(f"float[{spellings(low)[spelling]}..{spellings(high)[spelling]} count {count}]")
    assert plain.values == spelt.values
    assert [Fraction(Decimal(v)) for v in plain.values] == expected


# ---- 6c. no number-like text makes anything but diagnostics ------------------------------------

DIGITS = st.text("0123456789", max_size=22)
EXPONENT = st.one_of(
    st.just(""),
    st.builds("".join, st.tuples(st.sampled_from("eE"), st.sampled_from(["", "+", "-"]), DIGITS)),
    st.sampled_from(["e400", "e-400", "e308", "e-324", "e999999999999", "e-999999999999"]),
)
NUMBER = st.one_of(
    st.builds(
        lambda sign, whole, fraction, exponent: f"{sign}{whole}{fraction}{exponent}",
        st.sampled_from(["", "-", "+", "--"]),
        DIGITS,
        st.one_of(st.just(""), st.builds(lambda d: "." + d, DIGITS)),
        EXPONENT,
    ),
    st.sampled_from(["0", "-0", "1", "0.5", "1e12", "1e-15", "1e3", "100001", ".", "1.", "e5"]),
)
FORMS = [
    "float[{a}..{b} step {c}]",
    "float[{a}..{b} count {c}]",
    "float[{a} ± {b}% count {c}]",
    "float[{a} +- {b}% step {c}]",
    "int[{a}..{b}]",
    "int[{a}..{b} step {c}]",
    "int[{a} ± {b}%]",
]


@settings(max_examples=120)
@given(form=st.sampled_from(FORMS), a=NUMBER, b=NUMBER, c=NUMBER)
def test_number_like_text_gives_diagnostics_never_exceptions(form: str, a: str, b: str, c: str) -> None:
    text = (
        f"@define n={a}\n"
        f"@joint hip_hind limits={a}..{b} free={c}\n"
        f"<a> ::= {form.format(a=a, b=b, c=c)} | 2*{form.format(a=a, b=b, c=c)} | <f> | GE_RANGE:n\n"
        f"@frequency limits={b}..{c}\n"
        f"<f> ::= {c}\n"
    )
    grammar = check(parse(text)).grammar
    for rule in grammar.rules:
        for alternative in rule.alternatives:
            for symbol in alternative.symbols:
                found = getattr(symbol, "spec", None)
                if found is None:
                    continue
                assert 1 <= found.size <= MAX_RANGE_VALUES
                numbers = [Decimal(v) for v in found.values]
                assert len(set(numbers)) == found.size  # never duplicates
                assert all(abs(n) <= 10**12 for n in numbers)
                doubles = [float(v) for v in found.values]
                held = [Decimal(repr(x)) for x in doubles]  # what a double reads back
                assert held == numbers
                assert len(set(doubles)) == found.size  # so distinct as the gait sees them
    for joint in grammar.joints:
        assert joint.limits is None or all(math.isfinite(x) for x in joint.limits)
        assert joint.free is None or all(isinstance(x, int | None) for x in joint.free)
    if grammar.frequency is not None and grammar.frequency.limits is not None:
        assert all(math.isfinite(x) for x in grammar.frequency.limits)
    assert all(isinstance(v, int) and 0 <= v <= 10**12 for v in grammar.defines.values())
