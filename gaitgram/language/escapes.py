"""Backslash escapes in terminal text.

PonyGE2 decodes every piece of terminal text, quoted or not, with Python's
``unicode-escape`` codec. That codec reads its input as Latin-1, so it garbles
any non-ASCII character; here each escape is decoded on its own and the rest
of the text is left alone, which gives the same result on ASCII and the right
one on everything else.
"""

from __future__ import annotations

import codecs
import re
from dataclasses import dataclass

_ESCAPE = re.compile(
    r"""\\(?:
        u[dD][89abAB][0-9A-Fa-f]{2}\\u[dD][c-fC-F][0-9A-Fa-f]{2}  # a UTF-16 surrogate pair, refused whole
      | N\{[^}\n]*\}? | U[0-9A-Fa-f]{0,8} | u[0-9A-Fa-f]{0,4} | x[0-9A-Fa-f]{0,2}
      | [0-7]{1,3} | \n | . | $
    )""",
    re.VERBOSE | re.DOTALL,
)


_SIMPLE = {
    "\\": "\\",
    "'": "'",
    '"': '"',
    "a": "\a",
    "b": "\b",
    "f": "\f",
    "n": "\n",
    "r": "\r",
    "t": "\t",
    "v": "\v",
    "\n": "",
}


@dataclass(frozen=True, slots=True)
class EscapeError:
    """An escape that does not decode; offsets are relative to the text given."""

    start: int
    end: int
    message: str
    #: The escape to write instead, where one says what was meant (a surrogate pair's \\U escape).
    replacement: str | None = None


def unescape(text: str) -> tuple[str, list[EscapeError]]:
    """Decode escapes as Python's ``unicode-escape`` does, reporting the bad ones.

    Unknown escapes such as ``\\w`` stay as they are (PCRE grammars rely on it).
    A bad escape is kept verbatim in the result and reported.
    """
    if "\\" not in text:
        return text, []
    errors: list[EscapeError] = []

    def decode(match: re.Match[str]) -> str:
        escape = match.group()
        if len(escape) == 2 and escape[1] not in "01234567":
            # One-character escapes: known ones decode, unknown ones (\w, \( ...) stay.
            return _SIMPLE.get(escape[1], escape)
        try:
            decoded = codecs.decode(escape, "unicode_escape")
        except UnicodeDecodeError as exc:
            reason = "a backslash at the end of the text" if escape == "\\" else exc.reason
            errors.append(EscapeError(match.start(), match.end(), f"invalid escape {escape!r}: {reason}"))
            return escape
        if _SURROGATE.search(decoded):
            errors.append(
                EscapeError(
                    match.start(), match.end(), _surrogate_message(escape, decoded), _pair_escape(decoded)
                )
            )
            return escape
        return decoded

    return _ESCAPE.sub(decode, text), errors


#: UTF-16 surrogates: code points that are not characters, and that UTF-8 cannot encode.
_SURROGATE = re.compile("[\ud800-\udfff]")


def _pair_escape(decoded: str) -> str | None:
    """``\\U0001F600`` for a high and a low surrogate, the character UTF-16 would have meant."""
    if len(decoded) != 2:
        return None
    char = decoded.encode("utf-16-le", "surrogatepass").decode("utf-16-le")
    return f"\\U{ord(char):08X}"


def _surrogate_message(escape: str, decoded: str) -> str:
    """Why a surrogate escape is refused, with the escape to write instead where there is one."""
    if len(decoded) == 2:  # a high and a low surrogate: what UTF-16 would have meant
        char = (decoded.encode("utf-16-le", "surrogatepass")).decode("utf-16-le")
        return (
            f"invalid escape {escape!r}: a UTF-16 surrogate pair is not text (it cannot be encoded "
            f"as UTF-8); write \\U{ord(char):08X} for {char!r}"
        )
    return (
        f"invalid escape {escape!r}: U+{ord(decoded):04X} is a lone UTF-16 surrogate, not a character "
        "(it cannot be encoded as UTF-8)"
    )
