"""``report.html`` in a real browser: Debian's Chromium, headless, opens the page from disk.

Driven through Playwright (:mod:`study.browser`; its own Chromium is not downloaded), which
reports the page's console messages and uncaught errors as events and clicks a header as a user
does (a real mouse event, not a function called from outside). The page must render with no
console error and no request beyond the file itself, its tables must hold their rows, a click on a
column header must sort by it, and every image and animation must have decoded.
"""

from __future__ import annotations

import io
import re
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from PIL import Image
from study.browser import Opened, chromium
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from gaitgram.cli import app
from gaitgram.report.html import html
from gaitgram.report.make import study_report
from gaitgram.report.records import load_arms
from gaitgram.report.sections import Figure, Gait, Section

runner = CliRunner()


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    tmp = tmp_path_factory.mktemp("html")
    study = write_hand_made_study(tmp / "study")
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp / "report")])
    assert result.exit_code == 0, result.stderr
    return tmp / "report"


def test_the_page_is_self_contained(report: Path) -> None:
    page = (report / "report.html").read_text()
    assert page.startswith("<!DOCTYPE html>")
    links = re.findall(r"""(?:src|href)\s*=\s*["']([^"']*)""", page)
    assert links
    assert all(link.startswith("data:") for link in links)
    assert "<script src" not in page
    assert "<link" not in page
    # Every table row of summary.md is in the page once: the summary's, the start's, the first
    # walk's and the spread's.
    assert (report / "summary.md").read_text().count("| alpha |") == page.count("<td>alpha</td>") == 4


def test_the_same_report_gives_the_same_page(report: Path, tmp_path: Path) -> None:
    study = report.parent / "study"
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "again")])
    assert result.exit_code == 0, result.stderr
    assert (tmp_path / "again" / "report.html").read_bytes() == (report / "report.html").read_bytes()


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    with chromium() as launched:
        yield launched


def test_chromium_renders_the_report(browser: Any, report: Path, tmp_path: Path) -> None:
    opened = Opened(browser, report / "report.html")
    page = opened.page
    assert opened.errors == []
    assert opened.requests == [(report / "report.html").as_uri()]  # the file, and nothing else
    shot = page.screenshot(full_page=True)
    (tmp_path / "report.png").write_bytes(shot)
    picture = Image.open(io.BytesIO(shot)).convert("L")
    assert picture.width == 1280
    assert picture.height > 2000
    assert len(picture.getcolors(maxcolors=1 << 16) or range(1 << 16)) > 50  # drawn, not blank
    assert page.title() == "Hand-made: three arms & a title"
    assert opened.column("summary-summary", 0) == ["alpha", "beta_front", "gamma"]
    assert len(opened.column("summary-final-best", 0)) == len(opened.column("summary-final-average", 0)) == 3
    images = opened.images()
    assert [i["kind"] for i in images] == ["image/svg+xml", "image/png", "image/png"]
    assert all(i["complete"] and i["width"] > 0 for i in images), images


def test_a_click_on_a_header_sorts_the_table(browser: Any, report: Path) -> None:
    opened = Opened(browser, report / "report.html")
    header = opened.page.locator("#summary-summary th", has_text="avg. best")
    header.click()
    assert opened.column("summary-summary", 0) == ["gamma", "alpha", "beta_front"]  # 0.3125, 0.625, 0.9375
    assert header.get_attribute("aria-sort") == "ascending"
    header.click()
    assert opened.column("summary-summary", 0) == ["beta_front", "alpha", "gamma"]
    assert header.get_attribute("aria-sort") == "descending"
    arm = opened.page.locator("#summary-summary th", has_text="arm")
    arm.focus()
    opened.page.keyboard.press("Enter")  # the keyboard sorts too
    assert opened.column("summary-summary", 0) == ["alpha", "beta_front", "gamma"]
    assert header.get_attribute("aria-sort") == "none"
    p_values = opened.page.locator("#summary-final-best th", has_text="p (Holm)")
    p_values.click()
    assert opened.column("summary-final-best", 4) == ["1.000", "0.000", "0.000"]  # ties keep their order
    assert opened.errors == []


def test_animations_are_embedded_and_play(browser: Any, report: Path, tmp_path: Path) -> None:
    """The gallery's GIFs (drawn on the horse elsewhere, slowly): two frames made here stand in."""
    frames = [Image.new("RGB", (48, 32), colour) for colour in ("red", "blue")]
    gif = io.BytesIO()
    frames[0].save(gif, format="GIF", save_all=True, append_images=frames[1:], duration=100, loop=0)
    arms, title = load_arms([report.parent / "study"])
    made = study_report(arms, title=title)
    figures = tuple(
        Figure(f"walk-{arm.name}", f"{arm.name}: its best walk", Gait(arm.path, (1, 2)), ("gif",))
        for arm in arms
    )
    gallery = Section("gaits", "Gaits", figures=figures)
    with_gallery = replace(made, sections=(*made.sections, gallery))
    page = html(with_gallery, {f"{f.name}.gif": gif.getvalue() for f in figures})
    (tmp_path / "report.html").write_text(page)
    opened = Opened(browser, tmp_path / "report.html")
    gifs = [i for i in opened.images() if i["kind"] == "image/gif"]
    assert len(gifs) == 3
    assert all(i["complete"] and i["width"] == 48 for i in gifs)
    captions = opened.page.eval_on_selector_all("#gaits figcaption", "cs => cs.map(c => c.textContent)")
    assert captions == ["alpha: its best walk", "beta_front: its best walk", "gamma: its best walk"]
    assert opened.errors == []
