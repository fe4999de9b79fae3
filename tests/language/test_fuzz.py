"""No input makes the reader or the linter raise, hang or lose its place."""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from gaitgram.analysis import check
from gaitgram.cli import app
from gaitgram.language import parse
from gaitgram.language.source import SourceError, decode_source, read_source

# Text made of the language's own pieces finds far more corners than random characters.
PIECES = [
    "<a>",
    "<b>",
    "<a> ::=",
    "<b>::=",
    " ::= ",
    "|",
    " | ",
    "\n",
    "  ",
    "#",
    "# c\n",
    "'",
    '"',
    "'x'",
    "\\",
    "\\n",
    "\\x4",
    "\\u00e9",
    "int[",
    "float[",
    "0..3",
    "..",
    " step ",
    " count ",
    "±",
    "+-",
    "%",
    "]",
    "@",
    "@start",
    "@joint",
    "@backend",
    "@units",
    "@define",
    " hip_hind",
    " limits=",
    "-5..5",
    " free=",
    "GE_RANGE:",
    "3",
    "n",
    "=",
    "<",
    ">",
    "x",
    "é",
    "\t",
    "\r\n",
]
texts = st.one_of(st.text(max_size=200), st.lists(st.sampled_from(PIECES), max_size=60).map("".join))


@settings(max_examples=400)
@given(texts)
def test_any_text_parses_and_checks_without_raising(text: str) -> None:
    result = check(parse(text))
    for diagnostic in result.diagnostics:
        assert 0 <= diagnostic.span.start <= diagnostic.span.end <= len(result.grammar.source.text)
        assert diagnostic.message


# ---- numbers: extreme numerals spliced into every place the language reads a number -----------


@st.composite
def spelt(draw: st.DrawFn) -> str:
    """A small number (a value a range may have) spelt with long runs of zeros, or as digits
    and a far-off exponent: ``1.000…0``, ``0.5000…0e0``, ``15000…0e-300``, ``0e-400``.
    Such spellings are the same small number, which arithmetic in a decimal context rounds."""
    units, scale = draw(st.integers(-999, 999)), draw(st.integers(0, 3))
    padding = draw(st.sampled_from([0, 1, 20, 150, 150]))
    digits, exponent = str(abs(units)) + "0" * padding, -scale - padding
    if units == 0:
        exponent = draw(st.sampled_from([0, -400, 400, -(10**20), 10**20]))
    sign = "-" if units < 0 else draw(st.sampled_from(["", "+"]))
    if abs(exponent) > 1000 or draw(st.booleans()):
        return f"{sign}{digits}e{exponent}"
    if exponent >= 0:
        return f"{sign}{digits}{'0' * exponent}"
    digits = digits.rjust(-exponent + 1, "0")
    return f"{sign}{digits[:exponent]}.{digits[exponent:]}"


@st.composite
def extreme(draw: st.DrawFn) -> str:
    """A numeral far out of range: thousands of digits, exponents past what a double, a decimal
    context or int() takes, zeros padding either end."""
    small = st.text("0123456789", min_size=1, max_size=3)
    whole = draw(st.one_of(small, st.integers(16, 5000).map(lambda n: "9" * n)))
    padding = st.sampled_from([0, 1, 150])
    fraction = draw(st.one_of(st.just(""), small.map(lambda d: "." + d)))
    exponent = draw(
        st.one_of(
            st.just(""),
            st.integers(-(10**30), 10**30).map(str),
            st.sampled_from(["400", "-400", "+308", "-324", "999999999", "-999999999"]),
        )
    )
    sign = draw(st.sampled_from(["", "-", "+"]))
    mark = draw(st.sampled_from("eE"))
    zeros = "0" * draw(padding)
    return f"{sign}{zeros}{whole}{fraction}{zeros if fraction else ''}" + (
        f"{mark}{exponent}" if exponent else ""
    )


#: What a number is not in this language, but is in others'.
NOT_NUMBERS = st.sampled_from(["nan", "NaN", "inf", "-Infinity", "1e", ".", "0x10", "1_000", "١٢", "²"])
NUMERALS = st.one_of(spelt(), spelt(), extreme(), NOT_NUMBERS)
NUMBER_SYNTAX = [
    "int[{a}..{b}]",
    "int[{a}..{b} step {c}]",
    "int[{a} ± {b}%]",
    "float[{a}..{b} step {c}]",
    "float[{a}..{b} count {c}]",
    "float[{a} ± {b}% count {c}]",
    "float[{a} +- {b}% step {c}]",
    "GE_RANGE:{whole}",
    "GE_RANGE:n",
    "\n@define n={a}\n",
    "\n@joint hip_hind limits={a}..{b} free={c}..\n",
    "\n@joint hip_hind free={a}..{b}\n",
    "\n@frequency limits={a}..{b}\n",
]
numbers_in_syntax = st.builds(
    lambda form, a, b, c, whole: form.format(a=a, b=b, c=c, whole=whole),
    st.sampled_from(NUMBER_SYNTAX),
    NUMERALS,
    NUMERALS,
    NUMERALS,
    st.one_of(
        st.text("0123456789", min_size=1, max_size=8),
        st.integers(1, 6000).map(lambda n: "9" * n),
        st.text(min_size=1, max_size=3).filter(str.isdigit),
    ),
)
texts_with_numbers = st.lists(st.one_of(st.sampled_from(PIECES), numbers_in_syntax), max_size=25).map("".join)


in_a_grammar = numbers_in_syntax.map(lambda piece: f"<a> ::= <b> | {piece}\n<b> ::= 1 | GE_RANGE:n\n")


def checks_without_raising(text: str) -> None:
    result = check(parse(text))
    for diagnostic in result.diagnostics:
        assert 0 <= diagnostic.span.start <= diagnostic.span.end <= len(text)
        assert diagnostic.message


@settings(max_examples=400)
@given(in_a_grammar)
def test_extreme_numbers_in_each_numeric_place_give_diagnostics_never_exceptions(text: str) -> None:
    checks_without_raising(text)


@settings(max_examples=200)
@given(texts_with_numbers)
def test_extreme_numbers_spliced_into_any_text_give_diagnostics_never_exceptions(text: str) -> None:
    checks_without_raising(text)


@settings(max_examples=150)
@given(in_a_grammar)
def test_check_on_a_file_with_extreme_numbers_reports_and_exits_0_or_1(text: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "numbers.gg"
        path.write_text(text, encoding="utf-8")
        result = CliRunner().invoke(app, ["check", str(path)])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    assert result.exit_code in (0, 1), result.output
    if result.exit_code == 1:
        assert re.search(rf"^{re.escape(str(path))}:\d+:\d+: error\[GG\d+\] ", result.stdout, re.MULTILINE)


@given(st.binary(max_size=300))
def test_any_bytes_decode_or_give_a_source_error(data: bytes) -> None:
    try:
        source = decode_source(data, "fuzz.gg")
    except SourceError as error:
        assert error.path == "fuzz.gg"  # noqa: PT017 (decoding either succeeds or explains why)
        assert error.message  # noqa: PT017
    else:
        check(parse(source))


def test_truncated_vector_grammars_never_raise(vector_grammar: Path) -> None:
    text = vector_grammar.read_text()
    for cut in range(0, len(text), max(1, len(text) // 97)):
        check(parse(text[:cut]))


def test_bad_utf8_reports_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "bad.gg"
    path.write_bytes(b"<a> ::= x\n<b> ::= \xff\n")
    with pytest.raises(SourceError, match=r"line 2, column 9: not valid UTF-8"):
        read_source(path)


def test_binary_directory_missing_and_huge_files_are_refused(tmp_path: Path) -> None:
    (tmp_path / "bin.gg").write_bytes(b"<a> ::= \x00\x01")
    (tmp_path / "huge.gg").write_bytes(b"#" * (9 * 1024 * 1024))
    with pytest.raises(SourceError, match="NUL"):
        read_source(tmp_path / "bin.gg")
    with pytest.raises(SourceError, match="directory"):
        read_source(tmp_path)
    with pytest.raises(SourceError, match="no such file"):
        read_source(tmp_path / "missing.gg")
    with pytest.raises(SourceError, match="refused"):
        read_source(tmp_path / "huge.gg")


def test_deeply_nested_and_long_grammars_do_not_overflow() -> None:
    chain = "\n".join(f"<r{i}> ::= <r{i + 1}> x | y" for i in range(5000)) + "\n<r5000> ::= <r0>"
    result = check(parse(chain))
    assert result.facts.rule("r0").productive
    loop = "\n".join(f"<r{i}> ::= <r{i + 1}>" for i in range(5000)) + "\n<r5000> ::= <r0>"
    assert {d.code.code for d in check(parse(loop)).diagnostics} >= {"GG203", "GG205"}
