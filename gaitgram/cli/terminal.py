"""Where the command line writes text for people: plain text, unless a terminal will show colour.

rich draws the colours, but importing it costs ``gaitgram check`` a tenth of its start-up. Text
bound for a file or a pipe (a CI log, an editor, a test) is written without it, exactly as rich
would write it there: control codes removed and tabs expanded as rich does, no colour, no
wrapping. A terminal (or ``FORCE_COLOR``, ``TTY_COMPATIBLE=1``) gets a rich console, made on first
use. What is printed is a string or :class:`~gaitgram.analysis.report.Styled` text.
"""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING, TextIO

from rich.cells import cell_len

from gaitgram.analysis.report import Styled

if TYPE_CHECKING:
    from rich.console import Console

#: What rich removes from text before printing it: bell, backspace, vertical tab, form feed, CR.
_CONTROL_CODES = dict.fromkeys((7, 8, 11, 12, 13))
#: rich's default tab size.
TAB_SIZE = 8


def plain_text(text: str) -> str:
    """``text`` as rich writes it to a file: control codes removed, tabs expanded by cell width."""
    text = text.translate(_CONTROL_CODES)
    if "\t" not in text:
        return text
    lines = []
    for line in text.split("\n"):
        expanded = ""
        for i, part in enumerate(line.split("\t")):
            if i:
                expanded += " " * (TAB_SIZE - cell_len(expanded) % TAB_SIZE)
            expanded += part
        lines.append(expanded)
    return "\n".join(lines)


def shows_colour(stream: TextIO) -> bool:
    """Whether rich could style text on ``stream`` (its own test, less Jupyter and IDLE)."""
    compatible = os.environ.get("TTY_COMPATIBLE", "")
    if compatible in ("0", "1"):
        return compatible == "1"
    forced = os.environ.get("FORCE_COLOR")
    if forced is not None:
        return forced != ""
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # no isatty, or closed
        return False


class Terminal:
    """Standard output or standard error (read when printing: a test runner swaps them)."""

    def __init__(self, *, stderr: bool = False) -> None:
        self.stderr = stderr
        self._console: Console | None = None

    @property
    def stream(self) -> TextIO:
        return sys.stderr if self.stderr else sys.stdout

    def print(self, text: str | Styled, *, style: str | None = None, end: str = "\n") -> None:
        stream = self.stream
        if not shows_colour(stream):
            plain = text.plain if isinstance(text, Styled) else text
            stream.write(plain_text(plain + end))
            return
        from rich.text import Text  # only for a terminal

        rich_text = Text.assemble(*text.segments) if isinstance(text, Styled) else Text(text)
        self.console().print(rich_text, style=style, end=end)

    def console(self) -> Console:
        """The rich console behind this stream, for what only rich draws (a progress display)."""
        if self._console is None:
            from rich.console import Console  # only for a terminal, or a progress display

            self._console = Console(
                stderr=self.stderr, highlight=False, soft_wrap=True, markup=False, emoji=False
            )
        return self._console


#: Standard error, where every command says what failed and what it did.
err = Terminal(stderr=True)
