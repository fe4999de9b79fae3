"""The grammar (``gaitgram.lark``) is the one place the number and range syntax is written: the
scanner, the range parser, the look-alike finder and the rewrites all take it from there."""

from __future__ import annotations

import re
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

import gaitgram
from gaitgram.analysis.rewrites import collapses
from gaitgram.language import parse
from gaitgram.language.look_alikes import look_alike_ranges
from gaitgram.language.model import RangeKind
from gaitgram.language.parser import grammar_text, terminal
from gaitgram.language.ranges import parse_range, range_token

#: The number syntax as the grammar writes it; the tests below find it nowhere else.
NUMBER = r"[+-]?(?:\d+(?:\.\d+)?|\.\d+)(?:[eE][+-]?\d+)?"


def test_annotation_and_range_numbers_are_the_grammars_one_number() -> None:
    assert f"NUMBER: /{NUMBER}/" in grammar_text()
    assert terminal("ARG_NUMBER").pattern == terminal("RANGE_NUMBER").pattern == NUMBER


def test_the_number_and_range_syntax_is_written_only_in_the_grammar() -> None:
    range_shape = terminal("RANGE").pattern
    package = Path(gaitgram.__file__).parent
    readers = ("language", "analysis", "ide")  # what reads .gg text (motion reads another language)
    for source in (path for reader in readers for path in (package / reader).rglob("*.py")):
        text = source.read_text(encoding="utf-8")
        assert r"\d+(?:\.\d+)?" not in text, f"{source} writes the number syntax itself"
        assert range_shape not in text.replace("\\\\", "\\"), f"{source} writes the RANGE token itself"
    # Text stops before a range: its look-ahead is the RANGE token's shape, in the grammar itself.
    assert f"(?!{range_shape})" in terminal("TEXT").pattern


def test_the_range_kinds_are_the_models() -> None:
    assert {kind.value for kind in RangeKind} == set(re.findall(r"\w+", terminal("RANGE_KIND").pattern))


@given(
    st.sampled_from(["int", "float"]),
    st.from_regex(NUMBER, fullmatch=True),
    st.from_regex(NUMBER, fullmatch=True),
)
def test_text_the_grammar_reads_as_a_range_is_no_look_alike(kind: str, low: str, high: str) -> None:
    text = f"{kind}[{low}..{high} step 1]"
    assert range_token().fullmatch(text)
    parse_range(text)  # whatever it says about the numbers, it reads them
    assert look_alike_ranges(text) == []
    assert [found.meant for found in look_alike_ranges(f"flaot[{low}..{high} step 1]")] == ["float"]


def test_runs_of_plain_numbers_collapse_and_a_number_with_an_exponent_ends_a_run() -> None:
    grammar = parse("<a> ::= 1 | 2 | 3 | 1e1 | 0.5 | 1 | 1.5\n")
    assert [fix.title for fix in collapses(grammar.source, grammar.rules[0])] == [
        "Collapse 3 values into int[1..3]",
        "Collapse 3 values into float[0.5..1.5 step 0.5]",
    ]
