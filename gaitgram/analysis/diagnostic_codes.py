"""Every diagnostic code, gathered from the modules that declare them.

A code is declared once, beside the check that finds its problem (see
:mod:`gaitgram.language.diagnostics`); this is the list of them all, in code order, that the diagnostics
catalogue of the docs (``gaitgram.cli.docgen``), SARIF's rule metadata and the tests read.
"""

from __future__ import annotations

from gaitgram.analysis.lint import joint_checks, rule_checks, sensor_checks
from gaitgram.language import annotations, look_alikes, meaning, problems, ranges
from gaitgram.language.diagnostics import Code

__all__ = ["CODES", "CODES_BY_NAME"]

_DECLARED: tuple[Code, ...] = (
    *problems.CODES,
    *ranges.CODES,
    *look_alikes.CODES,
    *annotations.CODES,
    *meaning.CODES,
    *rule_checks.CODES,
    *joint_checks.CODES,
    *sensor_checks.CODES,
)

#: Every code by its number (``GG201``), in order.
CODES: dict[str, Code] = {code.code: code for code in sorted(_DECLARED, key=lambda code: code.code)}
#: Every code by its name (``undefined-rule``).
CODES_BY_NAME: dict[str, Code] = {code.name: code for code in CODES.values()}

if len(CODES) != len(_DECLARED) or len(CODES_BY_NAME) != len(
    _DECLARED
):  # pragma: no cover - caught by import
    raise AssertionError("two declarations share a code or a name")
