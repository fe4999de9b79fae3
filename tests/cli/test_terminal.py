"""Text for people written without rich where no terminal shows colour (``cli/terminal.py``): the
same bytes rich writes to a file, and rich's colours where a terminal (or FORCE_COLOR) asks."""

from __future__ import annotations

import io

import pytest
from hypothesis import given
from hypothesis import strategies as st
from rich.console import Console
from rich.text import Text

from gaitgram.analysis.report import Styled
from gaitgram.cli.terminal import Terminal, plain_text

# Text as diagnostics carry it: any characters, with tabs, newlines, control codes and wide ones.
texts = st.text(
    st.one_of(st.characters(), st.sampled_from("\t\n\r\x07\x08\x0b\x0c\x1b你好é")),
    max_size=60,
)


def as_rich_writes_it(text: str, end: str = "\n") -> str:
    out = io.StringIO()
    console = Console(file=out, highlight=False, soft_wrap=True, markup=False, emoji=False)
    console.print(Text(text), end=end)
    return out.getvalue()


@given(texts)
def test_plain_text_is_what_rich_writes_to_a_file(text: str) -> None:
    assert plain_text(text + "\n") == as_rich_writes_it(text)


@given(st.lists(st.tuples(texts, st.sampled_from([None, "bold", "bold red", "blue"])), max_size=5))
def test_styled_text_reads_as_its_segments_joined(segments: list[tuple[str, str | None]]) -> None:
    styled = Styled(list(segments))
    assert styled.plain == "".join(text for text, _ in segments)
    out = io.StringIO()
    console = Console(file=out, highlight=False, soft_wrap=True, markup=False, emoji=False)
    console.print(Text.assemble(*segments))
    assert plain_text(styled.plain + "\n") == out.getvalue()


def test_a_terminal_gets_colour_and_a_pipe_plain_text(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    styled = Styled([("error", "bold red"), (": it\tbroke", None)])
    monkeypatch.delenv("FORCE_COLOR", raising=False)
    monkeypatch.delenv("TTY_COMPATIBLE", raising=False)
    Terminal().print(styled)
    assert capsys.readouterr().out == "error: it\tbroke".expandtabs(8) + "\n"
    monkeypatch.setenv("FORCE_COLOR", "1")
    Terminal().print(styled)
    coloured = capsys.readouterr().out
    assert "\x1b[" in coloured  # ANSI colour codes
    assert "error" in coloured
    assert "broke" in coloured
