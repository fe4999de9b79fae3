"""JSON that every parser accepts: no ``NaN`` or ``Infinity`` tokens, ever.

Python's :func:`json.dumps` writes non-finite floats as bare ``NaN`` and
``Infinity``, which strict parsers (``jq``, browsers, most languages) reject. A
non-finite number in gaitgram's output means "no value" (an average over no
viable gait, say), so it is written as ``null``; ``allow_nan=False`` then
guarantees that nothing else slipped through.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
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
