"""The words of a motion expression, without numpy: how a name and a number are spelt, and which
names the language knows (``t``, ``PI``, ``sin``, ...).

The linter and the editor read phenotype text in every grammar they check, and ``gaitgram check``
starts without numpy (``tests/cli/test_startup.py``); the stages that compute
(:mod:`~gaitgram.motion.vocabulary`, the parser, the machine) take their words from here, so the
language is still extended in one place: a function is an entry in :data:`FUNCTION_DOCS`, and
numpy's ufunc of the same name computes it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Collection, Iterator

__all__ = [
    "CONSTANTS",
    "FUNCTION_DOCS",
    "NAME_PATTERN",
    "NUMBER_PATTERN",
    "UNSUPPORTED",
    "VARIABLE",
    "WHITESPACE",
    "builtin",
    "reads",
    "words",
]

# expression.lark's terminals, spelt as the grammar spells them (a test compares them).
NUMBER_PATTERN = r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
NAME_PATTERN = r"[A-Za-z_][A-Za-z0-9_]*"
WHITESPACE = " \t\r\n"  # what the grammar ignores between tokens

#: Functions, each of one argument in radians, and why each is in the language. Only what the
#: paper's grammars derive: a wider vocabulary (tan, exp, log, sqrt, powers) would add
#: singularities and domain errors that no gait needs. Add an entry here to extend the language.
FUNCTION_DOCS: dict[str, str] = {
    "sin": "the sum-of-sines representation (Eq. 1, Fig. 2)",
    "cos": "cosine terms of the concatenating grammar (Fig. 2) and Fig. 5",
}

#: Named constants. The paper writes ``PI``; ``pi`` is accepted as well.
CONSTANTS: dict[str, float] = {"PI": math.pi, "pi": math.pi}

#: The phase of the gait cycle, in [0, 1).
VARIABLE = "t"

#: Functions people try that the language leaves out on purpose (a hint says so).
UNSUPPORTED = frozenset(
    {"tan", "exp", "log", "ln", "sqrt", "abs", "pow", "min", "max", "asin", "acos", "atan"}
)

_SPACE = f"[{re.escape(WHITESPACE)}]"
# A number is matched first, so that the ``e5`` of ``2e5`` is no name.
_WORD = re.compile(f"({NUMBER_PATTERN})|({NAME_PATTERN})(?:{_SPACE}*(\\())?")


def words(text: str) -> Iterator[tuple[str, int, int, bool]]:
    """The names in ``text``, which may be a piece of an expression (a grammar's terminal), as
    ``(name, start, end, called)``: ``called`` when a ``(`` follows it in ``text``."""
    for match in _WORD.finditer(text):
        if match.lastindex != 1:
            start, end = match.span(2)
            yield match.group(2), start, end, match.group(3) is not None


def builtin(name: str) -> bool:
    """Whether the language itself knows ``name``: the phase variable, a constant or a function."""
    return name == VARIABLE or name in CONSTANTS or name in FUNCTION_DOCS


def reads(text: str, names: Collection[str]) -> list[str]:
    """Which of ``names`` (a backend's sensors) ``text`` reads, in the order it first reads them."""
    return list(dict.fromkeys(name for name, _, _, called in words(text) if name in names and not called))
