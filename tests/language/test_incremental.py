"""The incremental parser gives exactly ``parse(text)``: the same rules, annotations, joints,
spans and diagnostics, after any sequence of edits, by either of its two paths (reading the
new segments alone, or one full parse cut into segments)."""

from __future__ import annotations

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

from conftest import GRAMMARS
from gaitgram.analysis import check
from gaitgram.language import incremental as incremental_module
from gaitgram.language import parse
from gaitgram.language.incremental import IncrementalParser, segment_starts
from gaitgram.language.model import Grammar

PIECES = [
    "<a>",
    "<b>",
    "<a> ::=",
    "<b>::=",
    " ::= ",
    "|",
    " | ",
    "\n",
    "\n",
    "\n<c> ::= y\n",
    "  ",
    "#",
    "# c\n",
    "'",
    '"',
    "'x'",
    "\\",
    "int[",
    "float[",
    "flaot[",  # GG309, whose fix spans move with their segment
    "0..3",
    " step 0.5",
    "]",
    " | | ",
    "@",
    "@start <b>\n",
    "\n@joint hip_hind\n",
    "@backend",
    "@units rad\n",
    "@define n=3\n",
    "GE_RANGE:n",
    "GE_RANGE:2",
    " limits=",
    "-5..5",
    "x",
    "é",
    "😀",
    "\t",
    "\r\n",
]
SEEDS = [""] + [path.read_text() for path in sorted(GRAMMARS.glob("*.gg"))[:4]]
texts = st.one_of(st.sampled_from(SEEDS), st.lists(st.sampled_from(PIECES), max_size=40).map("".join))
edit = st.tuples(
    st.floats(0, 1), st.integers(0, 12), st.lists(st.sampled_from(PIECES), max_size=3).map("".join)
)


PARTS = ("rules", "annotations", "joints", "frequency", "start", "backend", "units", "defines", "diagnostics")


def same(incremental: IncrementalParser, text: str) -> Grammar:
    ours, full = incremental.parse(text), parse(text)
    for part in PARTS:
        assert getattr(ours, part) == getattr(full, part), part
    assert check(ours).diagnostics == check(full).diagnostics
    return ours


# A @joint put on the @frequency rule: its GG404 depends on the whole document (found by CI).
@example(text=SEEDS[1], edits=[(0.97, 0, "\n@joint hip_hind\n")], full_parse_at=0)
def any_edits_give_the_full_parse(text: str, edits, full_parse_at: int) -> None:
    incremental = IncrementalParser(full_parse_at=full_parse_at)
    same(incremental, text)
    for where, length, inserted in edits:
        start = round(where * len(text))
        text = text[:start] + inserted + text[start + length :]
        same(incremental, text)


EDITS = given(text=texts, edits=st.lists(edit, max_size=12), full_parse_at=st.sampled_from([0, 64]))
# 40 edit sequences (and the example above) in the default run, 150 in the slow set.
test_any_edits_give_the_full_parse = settings(max_examples=40, deadline=None)(
    EDITS(any_edits_give_the_full_parse)
)
test_any_edits_give_the_full_parse_at_length = pytest.mark.slow(
    settings(max_examples=150, deadline=None)(EDITS(any_edits_give_the_full_parse))
)


def test_a_5000_rule_document_reads_one_segment_per_edited_rule() -> None:
    from benchmarks.bench_check import generated_grammar

    text = generated_grammar(5_000)
    incremental = IncrementalParser()
    same(incremental, text)
    assert incremental.last_reads == "full"
    lines = text.split("\n")
    for line in (2, 2_500, 4_999):
        lines[line] = lines[line] + " | <r3>"
        text = "\n".join(lines)
        same(incremental, text)
        assert incremental.last_reads == 1


@pytest.mark.parametrize(
    ("text", "starts"),
    [
        ("<a> ::= x\n<b> ::= y\n", [0, 10]),
        ("<a> ::= x\n@joint hip\n<b> ::= y\n<c> ::= z\n", [0, 31]),  # @joint stays with <b>
        ("<a> ::= x <b> ::= y\n<c> ::= z\n", [0, 20]),  # a head mid-line starts no segment
        ("<a> ::= 'x\n<b> ::= y\n", [0, 11]),
        (" <a> ::= x\n<b> ::= y\n", [0]),  # an indented head is not at a line start
    ],
)
def test_segments_start_at_rule_lines_with_nothing_pending(text: str, starts: list[int]) -> None:
    assert segment_starts(text) == starts


class EditingADocument(RuleBasedStateMachine):
    """An editor's session: a document, edits anywhere (typing, deleting, pasting, replacing the
    whole text), and after each one the incremental parse equals the full parse."""

    def __init__(self) -> None:
        super().__init__()
        self.text = ""
        self.parser = IncrementalParser(full_parse_at=0)
        self.earlier: tuple[str, Grammar] | None = None

    @initialize(text=texts)
    def open_document(self, text: str) -> None:
        self.text = text

    @rule(
        where=st.floats(0, 1), inserted=st.lists(st.sampled_from(PIECES), min_size=1, max_size=3).map("".join)
    )
    def type_text(self, where: float, inserted: str) -> None:
        at = round(where * len(self.text))
        self.text = self.text[:at] + inserted + self.text[at:]

    @rule(where=st.floats(0, 1), length=st.integers(1, 40))
    def delete(self, where: float, length: int) -> None:
        at = round(where * len(self.text))
        self.text = self.text[:at] + self.text[at + length :]

    @rule(where=st.floats(0, 1), length=st.integers(0, 12), inserted=st.sampled_from(PIECES))
    def replace(self, where: float, length: int, inserted: str) -> None:
        at = round(where * len(self.text))
        self.text = self.text[:at] + inserted + self.text[at + length :]

    @rule(text=texts)
    def replace_everything(self, text: str) -> None:
        self.text = text

    @rule()
    def forget_what_was_kept(self) -> None:
        self.parser.reset()

    @rule(limit=st.sampled_from([0, 64]))
    def choose_when_to_read_everything(self, limit: int) -> None:
        self.parser.full_parse_at = limit  # 0: often one full parse cut into segments; 64: never

    @invariant()
    def the_incremental_parse_is_the_full_parse(self) -> None:
        latest = same(self.parser, self.text)
        if self.earlier is not None:  # the last result is left as it was, though segments moved on
            text, grammar = self.earlier
            full = parse(text)
            for part in PARTS:
                assert getattr(grammar, part) == getattr(full, part), f"an earlier result changed: {part}"
        self.earlier = (self.text, latest)


EditingADocument.TestCase.settings = settings(max_examples=60, stateful_step_count=12, deadline=None)
test_an_editing_session_always_parses_as_a_whole = EditingADocument.TestCase


@settings(max_examples=40, deadline=None)
@given(text=texts, edits=st.lists(edit, max_size=6))
def test_windows_of_any_size_give_the_full_parse(text: str, edits) -> None:
    """A document is read in windows of about ``WINDOW`` characters, each in place: with windows
    of one character (every segment read alone) the result is the same."""
    saved = incremental_module.WINDOW
    incremental_module.WINDOW = 1
    try:
        any_edits_give_the_full_parse(text, edits, 0)
    finally:
        incremental_module.WINDOW = saved


def test_a_parse_stopped_as_stale_keeps_what_it_read() -> None:
    """``stop`` is asked before each window: once it says yes the parse raises ``Stale``, and the
    next parse reads only the segments the stopped one had not."""
    from benchmarks.bench_check import generated_grammar

    text = generated_grammar(12_000)
    segments = len(segment_starts(text))
    assert len(text) > 5 * incremental_module.WINDOW
    asked: list[int] = []

    def stop() -> bool:
        asked.append(1)
        return len(asked) > 3  # three windows read, then the text is out of date

    incremental = IncrementalParser(full_parse_at=10**9)  # never one full read
    with pytest.raises(incremental_module.Stale):
        incremental.parse(text, stop)
    assert len(asked) == 4
    same(incremental, text)
    assert 0 < incremental.last_reads < segments - 3 * 1_000  # three windows held thousands
