"""What a run measures of the machine it ran on is no result: the seconds each generation spent
in the backend (a run's ``backend.json``, the ``backend_seconds`` its summary shows). Tests that
find two runs' records equal compare them without those seconds; the steps stay (a resumed run
simulates the uninterrupted run's steps)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any


def summary_results(path: Path) -> dict[str, Any]:
    """A run directory's ``summary.json`` without the seconds its runs spent in the backend (each
    a number >= 0, for every generation of the run)."""
    data = json.loads(path.read_text())
    for run in data["runs"]:
        usage = run["backend_usage"]
        assert usage["backend_seconds"] >= 0
        assert usage["generations_counted"] == run["generations"] + 1
        del usage["backend_seconds"]
    return data


def usage_results(text: str) -> list[dict[str, Any]]:
    """A run's ``backend.json``: per generation, its number and the steps simulated."""
    return [
        {k: v for k, v in entry.items() if k != "backend_seconds"}
        for entry in json.loads(text)["generations"]
    ]


def comparable(path: Path) -> bytes:
    """A file's bytes as two runs' records compare: a run's ``backend.json`` and a run directory's
    ``summary.json`` without their seconds, any other file as it is."""
    data = path.read_bytes()
    if path.name == "backend.json":
        return json.dumps(usage_results(data.decode())).encode()
    if path.name == "summary.json":
        summary = json.loads(data)
        runs = summary.get("runs") if isinstance(summary, dict) else None
        if isinstance(runs, list) and all(isinstance(run, dict) and "backend_usage" in run for run in runs):
            return json.dumps(summary_results(path)).encode()
    return data
