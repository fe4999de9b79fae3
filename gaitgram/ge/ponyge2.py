"""PonyGE2 compatibility: what PonyGE2 does to a phenotype after mapping.

PonyGE2's ``.pybnf`` grammars cannot express indentation, so their
phenotypes carry ``{:`` (newline, indent one level), ``:}`` (newline, dedent one
level) and ``{::}`` (newline at the same level), resolved by a filter after
mapping. gaitgram maps such a grammar to the unfiltered text, exactly as
PonyGE2's mapper does; :func:`python_filter` gives the text PonyGE2 then runs.
"""

from __future__ import annotations

__all__ = ["python_filter"]

_INDENT = "  "


def python_filter(text: str) -> str:
    """Resolve ``{:``, ``:}`` and ``{::}`` as PonyGE2 does, blank lines dropped.

    A left-to-right scan: each ``{:`` opens a level and each ``:}`` closes one,
    both becoming a newline indented to the new level (so ``{::}`` is a newline
    at the current level once the blank line between is dropped). Levels below
    zero indent by nothing, as in PonyGE2.
    """
    level = 0
    pieces: list[str] = []
    start = i = 0
    while i < len(text) - 1:
        pair = text[i : i + 2]
        if pair in ("{:", ":}"):
            level += 1 if pair == "{:" else -1
            pieces.append(text[start:i])
            pieces.append("\n" + _INDENT * level)
            i = start = i + 2
        else:
            i += 1
    pieces.append(text[start:])
    return "\n".join(line for line in "".join(pieces).split("\n") if line.strip())
