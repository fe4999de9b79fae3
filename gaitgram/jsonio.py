"""JSON that every parser accepts: no ``NaN`` or ``Infinity`` tokens, ever.

Python's :func:`json.dumps` writes non-finite floats as bare ``NaN`` and
``Infinity``, which strict parsers (``jq``, browsers, most languages) reject. A
non-finite number in gaitgram's output means "no value" (an average over no
viable gait, say), so it is written as ``null``; ``allow_nan=False`` then
guarantees that nothing else slipped through. Read back (:func:`loads`), a
non-finite number is therefore an edit or damage, refused wherever it is. Every record gaitgram
keeps in a file is one JSON object, read back by :func:`read_object`, which says what is wrong
with a file that holds none.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any


def finite_or_none(value: Any) -> Any:
    """``value`` with every non-finite float (at any depth) replaced by None."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {k: finite_or_none(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [finite_or_none(v) for v in value]
    return value


def dumps(value: Any, *, indent: int | None = None, ensure_ascii: bool = False) -> str:
    """Strict JSON text of ``value``; non-finite floats become ``null``."""
    return json.dumps(finite_or_none(value), indent=indent, ensure_ascii=ensure_ascii, allow_nan=False)


class NonFinite(ValueError):
    """A number in a JSON text that is not finite; the message says where (``a.b[2].c``) and what."""


def loads(text: str | bytes) -> Any:
    """JSON as gaitgram writes it, read back: ``NaN``, ``Infinity``, ``-Infinity`` and a number too
    large for a float (which :func:`json.loads` reads as infinity) are :class:`NonFinite`, naming
    the first one's key. Every reader of gaitgram's files refuses them alike, never reading one
    as "no value" (that is ``null``)."""
    found: list[_Bad] = []

    def bad(literal: str) -> _Bad:
        found.append(_Bad(literal))
        return found[-1]

    def number(literal: str) -> float | _Bad:
        value = float(literal)
        return value if math.isfinite(value) else bad(literal)

    data = json.loads(text, parse_constant=bad, parse_float=number)
    if found:
        where, literal = _first_bad(data, "")
        raise NonFinite(
            f"{where}: {literal} is not a finite number" if where else f"{literal} is not a finite number"
        )
    return data


class ObjectError(ValueError):
    """A file (or line) that holds no JSON object as gaitgram writes one: ``where`` names it,
    ``problem`` says what is wrong. ``damaged``: it is there but was edited or damaged (not text,
    not JSON, a non-finite number, no object); ``missing``: it is not there. Each reader adds what
    to do, which only it knows."""

    def __init__(self, where: str, problem: str, *, damaged: bool = False, missing: bool = False) -> None:
        super().__init__(f"{where} is missing" if missing else f"{where}: {problem}")
        self.where = where
        self.problem = problem
        self.damaged = damaged
        self.missing = missing


def read_object(path: Path, what: str = "a JSON object") -> dict[str, Any]:
    """The JSON object the UTF-8 file ``path`` holds, read as :func:`loads` reads; otherwise
    :class:`ObjectError` ("PATH: not WHAT" where it holds other JSON)."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ObjectError(str(path), "missing", missing=True) from None
    except UnicodeDecodeError as error:
        raise ObjectError(str(path), f"not UTF-8 text: {error}", damaged=True) from None
    except OSError as error:
        reason = error.strerror or str(error)  # "Is a directory", to read as part of a sentence
        raise ObjectError(str(path), f"cannot read it: {reason[:1].lower()}{reason[1:]}") from None
    return object_from(text, str(path), what)


def object_from(text: str | bytes, where: str, what: str = "a JSON object") -> dict[str, Any]:
    """The JSON object ``text`` (a file's, or a line's, named ``where``) holds; otherwise a damaged
    :class:`ObjectError`."""
    try:
        data = loads(text)
    except NonFinite as error:
        raise ObjectError(where, str(error), damaged=True) from None
    except ValueError as error:  # not JSON, or bytes that are not UTF-8
        raise ObjectError(where, f"not JSON: {error}", damaged=True) from None
    if not isinstance(data, dict):
        raise ObjectError(where, f"not {what}", damaged=True)
    return data


class _Bad:
    def __init__(self, literal: str) -> None:
        self.literal = literal


def _first_bad(value: Any, where: str) -> tuple[str, str]:
    if isinstance(value, _Bad):
        return where, value.literal
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for key, item in items:
        inner = f"{where}[{key}]" if isinstance(key, int) else f"{where}.{key}" if where else str(key)
        if isinstance(item, dict | list | _Bad):
            found = _first_bad(item, inner)
            if found[1]:
                return found
    return "", ""
