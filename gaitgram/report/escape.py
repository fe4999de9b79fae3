"""How a report writes a name it did not choose, one function per format.

Names in a report come from its inputs: run directories (any character a file name may hold),
study titles, descriptors and disturbances read from the runs' files. Each format writes them as
text that means exactly that text, never markup: Markdown (:func:`markdown`), LaTeX
(:func:`latex`) and HTML (:func:`html`) escape them, and show a character that would break a line
or turn text around (:func:`printable`) as its escape; CSV and JSON keep them raw, quoted by the
csv and json modules, so that a reader gets the name back exactly.

The escapes leave ordinary names as they are (``beta_front``, ``ge-hybrid``, ``a & b``): the
committed reports under docs/results keep their bytes.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Mapping
from html import escape
from typing import Any

#: Characters that would break a line or a table, or turn text around: controls (NUL, line feed,
#: tab, ...), line and paragraph separators, bidirectional embeddings, overrides and isolates,
#: and lone surrogates (a file name's undecodable bytes).
_UNPRINTABLE = re.compile("[\x00-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069\ud800-\udfff]")


def encodable(value: Any) -> Any:
    """``value`` with every text in it (at any depth, keys too) one that UTF-8 can write: a lone
    surrogate (a byte of a file name that is not UTF-8, or a JSON escape of half a character) as
    its escape, ``\\xff`` for the byte."""
    if isinstance(value, str):
        if not _SURROGATE.search(value):
            return value
        try:
            return value.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
        except UnicodeEncodeError:  # not a byte of a file name: half of a character
            return value.encode("utf-8", "backslashreplace").decode("utf-8")
    if isinstance(value, Mapping):
        return {encodable(k): encodable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [encodable(v) for v in value]
    return value


_SURROGATE = re.compile("[\ud800-\udfff]")


def printable(text: str) -> str:
    """``text`` with every character that would break a line or a layout shown as its Python
    escape (``\\n``, ``\\x00``, ``\\u202e``): what a person reads is what the name holds."""
    return _UNPRINTABLE.sub(lambda match: ascii(match.group())[1:-1], text)


#: Markdown's markup characters wherever they are (``|`` splits a table's row, ``$`` opens GitHub's
#: mathematics, ``~`` strikes through).
_MARKUP = frozenset("\\`*|$~#")
#: What CommonMark reads as a character reference.
_REFERENCE = re.compile(r"&#?[0-9A-Za-z]+;")


def markdown(text: str) -> str:
    """``text`` as literal Markdown inline text, in a table's cell or in prose: :func:`printable`,
    then every character CommonMark or GitHub would read as markup backslash-escaped. An ``_``
    between letters, a ``<`` before a space, a ``&`` that starts no reference and a ``[ ]`` that
    makes no link (``](`` or ``][``) are markup to no one and stay as they are; whitespace at
    either end is a character reference, so that a cell keeps it and ``**`` around the name still
    makes it strong."""
    text = printable(text)
    out = []
    last = len(text) - 1
    for i, char in enumerate(text):
        if char in _MARKUP:
            out.append("\\" + char)
        elif char == "_" and not (0 < i < last and text[i - 1].isalnum() and text[i + 1].isalnum()):
            out.append("\\_")
        elif char == "<" and i < last and not text[i + 1].isspace():
            out.append("\\<")
        elif char == "]" and i < last and text[i + 1] in "([":
            out.append("\\]")
        elif char == "&" and _REFERENCE.match(text, i):
            out.append("\\&")
        elif (i == 0 or i == last) and unicodedata.category(char) == "Zs":
            out.append(f"&#{ord(char)};")
        else:
            out.append(char)
    return "".join(out)


#: LaTeX's ten special characters, each as text.
_LATEX = {
    "\\": r"\textbackslash{}",
    "&": r"\&",
    "%": r"\%",
    "$": r"\$",
    "#": r"\#",
    "_": r"\_",
    "{": r"\{",
    "}": r"\}",
    "~": r"\textasciitilde{}",
    "^": r"\textasciicircum{}",
}
_LATEX_SPECIAL = re.compile("[" + re.escape("".join(_LATEX)) + "]")


def latex(text: str) -> str:
    """``text`` as LaTeX text: :func:`printable`, and each special character escaped (in one pass,
    so that no escape is escaped again)."""
    return _LATEX_SPECIAL.sub(lambda match: _LATEX[match.group()], printable(text))


def html(text: str, *, quote: bool = True) -> str:
    """``text`` as HTML text (or, with ``quote``, an attribute's value): :func:`printable`, then
    ``& < >`` (and quotes) as references."""
    return escape(printable(text), quote=quote)
