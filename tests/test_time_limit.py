"""The default run's time limit (``tests/conftest.py``): a test not marked slow that takes longer
than ``max_test_seconds`` fails, naming the limit and the marker; one marked slow, or quick, passes."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from conftest import ROOT

#: A limit of 0.3 s; the slow marker declared, as pyproject.toml declares it for the suite.
LIMITED = ("-p", "no:cacheprovider", "-rA", "-o", "max_test_seconds=0.3", "-o", "markers=slow")
TESTS = """
import time

import pytest


def spin(seconds):
    started = time.process_time()
    while time.process_time() - started < seconds:
        pass


def test_quick():
    pass


def test_long():
    spin(0.6)


@pytest.mark.slow
def test_long_and_marked():
    spin(0.6)
"""


def test_a_long_test_not_marked_slow_fails_and_says_why(tmp_path: Path) -> None:
    """The suite's conftest loaded as a plug-in, on tests of its own, with a limit of 0.3 s."""
    (tmp_path / "test_timed.py").write_text(TESTS, encoding="utf-8")
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-p",
            "conftest",
            "-p",
            "no:cacheprovider",
            *LIMITED,
            "test_timed.py",
        ],
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": str(ROOT / "tests")},
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 1, result.stdout
    assert "PASSED test_timed.py::test_quick" in result.stdout
    assert "PASSED test_timed.py::test_long_and_marked" in result.stdout
    assert "FAILED test_timed.py::test_long" in result.stdout
    assert "over the 0.3 s a test not marked slow may take" in result.stdout
    assert "mark it @pytest.mark.slow" in result.stdout
    assert "1 failed, 2 passed" in result.stdout
