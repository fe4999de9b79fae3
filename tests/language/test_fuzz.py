"""No input makes the reader or the linter raise, hang or lose its place."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gaitgram.analysis import check
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
