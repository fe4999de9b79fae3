"""Debian's Chromium, headless, driven through Playwright (which launches the system's Chromium: its
own is never downloaded), for the tests that open ``report.html`` from disk as a reader does."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest

CHROMIUM = shutil.which("chromium")
#: As the probe that set up the machine ran it: without the background-networking flags its
#: connections are refused by the closed network and logged as errors.
FLAGS = [
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


@contextmanager
def chromium() -> Iterator[Any]:
    """The browser; skips, saying why, where Chromium or Playwright is missing."""
    if CHROMIUM is None:
        pytest.skip("chromium is not installed (Debian: apt-get install chromium; .ci/run installs it)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed ('.[dev]')")
    with sync_api.sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        try:
            yield launched
        finally:
            launched.close()


class Opened:
    """A page loaded from a file, with everything it said and asked for."""

    def __init__(self, browser: Any, path: Path) -> None:
        self.page = browser.new_page(viewport={"width": 1280, "height": 900})
        self.errors: list[str] = []
        self.requests: list[str] = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda error: self.errors.append(str(error)))
        self.page.on("request", lambda request: self.requests.append(request.url))
        self.page.goto(path.as_uri(), wait_until="load")

    def column(self, table: str, index: int) -> list[str]:
        return self.page.eval_on_selector_all(
            f"#{table} tbody tr", f"rows => rows.map(r => r.cells[{index}].textContent)"
        )

    def images(self, within: str = "") -> list[dict[str, Any]]:
        return self.page.eval_on_selector_all(
            f"{within} img".strip(),
            "images => images.map(i => ({complete: i.complete, width: i.naturalWidth, "
            "kind: i.src.slice(5, i.src.indexOf(';')), id: i.parentElement.id}))",
        )
