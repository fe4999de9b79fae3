"""Regression datasets: two built from their published definitions, any other read from files in
PonyGE2's format.

PonyGE2 ships Pagie-1 (as ``datasets/Paige1``), Keijzer-6 and Vladislavleva-4, under GPL-3.0, which
this MIT package does not bundle. Pagie-1 and Keijzer-6 are functions on fixed grids, so they are
built here from their definitions, printed as PonyGE2's files print them (12 significant digits)
and read back: equal to PonyGE2's files value for value (``tests/backends/test_symbolic_regression.py``
checks them against digests of PonyGE2's files). Vladislavleva-4's inputs are random draws, which
no definition reproduces: read it from PonyGE2's files (``train`` and ``test`` settings).

No numpy here: :func:`read_table` parses in plain Python, so that checking a run's settings stays
cheap; the evaluator turns rows into arrays.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

Rows = tuple[tuple[float, ...], ...]


@dataclass(frozen=True)
class Table:
    """A dataset split as PonyGE2 reads it: input columns, then the response, one row per case."""

    rows: Rows

    @property
    def n_inputs(self) -> int:
        return len(self.rows[0]) - 1


@dataclass(frozen=True)
class Dataset:
    name: str
    train: Table
    test: Table | None
    summary: str = ""


class DatasetError(ValueError):
    """A data file that cannot be read as PonyGE2 reads it; says the file, the line and why."""


def _printed(value: float) -> float:
    """``value`` as PonyGE2's files hold it: Python 2's ``str(float)``, 12 significant digits."""
    return float(format(value, ".12g"))


def _pagie_grid(step_tenths: int) -> list[float]:
    """-5..5 in steps of ``step_tenths`` / 10, without 0 (where x^-4 is undefined)."""
    points = [_printed(-5 + step_tenths * k / 10) for k in range(100 // step_tenths + 1)]
    return [x for x in points if x != 0]


def _pagie(step_tenths: int) -> Table:
    grid = _pagie_grid(step_tenths)
    return Table(tuple((a, b, _printed(1 / (1 + a**-4) + 1 / (1 + b**-4))) for a in grid for b in grid))


def _keijzer(cases: int) -> Table:
    return Table(
        tuple((float(n), _printed(sum(1 / i for i in range(1, n + 1)))) for n in range(1, cases + 1))
    )


def pagie_1() -> Dataset:
    return Dataset(
        "pagie-1",
        _pagie(4),
        _pagie(1),
        "Pagie and Hogeweg 1997: 1/(1+x^-4) + 1/(1+y^-4); train on the 26x26 grid -5:0.4:5, "
        "test on the 100x100 grid -5:0.1:5 without 0",
    )


def keijzer_6() -> Dataset:
    return Dataset(
        "keijzer-6",
        _keijzer(50),
        _keijzer(120),
        "Keijzer 2003: sum of 1/i for i = 1..x; train on x = 1..50, test on x = 1..120",
    )


#: The datasets built from their definitions, by the name a run's settings give.
BUILT: dict[str, Callable[[], Dataset]] = {"pagie-1": pagie_1, "keijzer-6": keijzer_6}


def digest(table: Table) -> str:
    """SHA-256 of the table's values as little-endian float64, row by row: equal digests, equal data."""
    import struct

    hasher = hashlib.sha256()
    for row in table.rows:
        hasher.update(struct.pack(f"<{len(row)}d", *row))
    return hasher.hexdigest()


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes, which a run records so that it never resumes on other data."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


_DELIMITERS = ("\t", ",", ";", ":")


def read_table(path: Path, delimiter: str | None = None) -> Table:
    """A data file read as PonyGE2's ``get_data`` reads it: a header line skipped, the delimiter that
    of the first line that is not a comment (tab, comma, semicolon, colon, else whitespace), the
    last column the response. Stricter than numpy's reader: a field that is not a number, or a row
    of another width, is refused with its line rather than read as NaN."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise DatasetError(f"{path}: cannot read it ({error})") from None
    lines = text.splitlines()
    if delimiter is None:
        delimiter = _sniff(lines)
    rows: list[tuple[float, ...]] = []
    for number, line in enumerate(lines[1:], start=2):
        content = line.split("#", 1)[0]
        if not content.strip():
            continue
        fields = content.split(delimiter) if delimiter != " " else content.split()
        try:
            row = tuple(float(field) for field in fields)
        except ValueError:
            bad = next(f for f in fields if not _is_number(f))
            raise DatasetError(f"{path}:{number}: {bad.strip()!r} is not a number") from None
        if len(row) < 2:
            raise DatasetError(f"{path}:{number}: a row needs inputs and a response, found {len(row)} field")
        if rows and len(row) != len(rows[0]):
            raise DatasetError(f"{path}:{number}: {len(row)} fields where the rows above have {len(rows[0])}")
        rows.append(row)
    if not rows:
        raise DatasetError(f"{path}: no rows after the header line")
    return Table(tuple(rows))


def _sniff(lines: list[str]) -> str:
    for line in lines:
        if line.startswith("#") or not line:  # PonyGE2 skips lines shorter than 2 with their newline
            continue
        return next((d for d in _DELIMITERS if d in line), " ")
    return " "


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
