"""What ``gaitgram report`` writes, pinned to the byte on a small hand-made study: each text format
is a published layout (committed studies' reports must not churn), so any change to it shows here."""

from __future__ import annotations

from pathlib import Path

import pytest
from study.report_fixtures import write_hand_made_study
from typer.testing import CliRunner

from gaitgram.cli import app

runner = CliRunner()
EXPECTED = Path(__file__).parent / "data" / "hand-made-report"
TEXT_FORMATS = ("summary.md", "summary.csv", "tables.tex", "summary.json")


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The hand-made study's report directory and what the command printed."""
    tmp = tmp_path_factory.mktemp("hand-made")
    study = write_hand_made_study(tmp / "study")
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp / "report")])
    assert result.exit_code == 0, result.stderr
    return tmp / "report", result.stdout


@pytest.mark.parametrize("name", TEXT_FORMATS)
def test_each_text_format_is_the_published_layout(report: tuple[Path, str], name: str) -> None:
    out, _ = report
    assert (out / name).read_bytes() == (EXPECTED / name).read_bytes()


def test_the_printed_summary_is_a_screen_of_what_summary_md_holds(report: tuple[Path, str]) -> None:
    """What the terminal shows of the report (tests/study/test_report_brief.py): its lines of the
    summary's table are summary.md's, cut to the main columns."""
    out, printed = report
    summary = (out / "summary.md").read_text()
    assert len(printed.splitlines()) <= 40 < len(summary.splitlines())
    assert "| gamma | 3 | 0.3125 | 0.3125 [0.25, 0.375] | 8% | 67% [21%, 94%] |" in printed
    assert "| gamma | 3 | 0.3125 | 0.0625 | 1.25 | 0.25 | 0.3125 [0.25, 0.375] |" in summary


def test_figures_are_drawn_for_the_arms_that_keep_fronts_and_repertoires(report: tuple[Path, str]) -> None:
    out, _ = report
    for name in ("convergence.png", "front-beta_front.png", "archive-gamma.png"):
        assert (out / name).read_bytes().startswith(b"\x89PNG\r\n\x1a\n"), name
    svg = (out / "convergence.svg").read_text()
    assert all(f"{arm} (3 runs)" in svg for arm in ("alpha", "beta_front", "gamma"))  # the legend


def test_assess_measures_nothing_off_the_horse_and_changes_no_file(
    report: tuple[Path, str], tmp_path: Path
) -> None:
    """The hand-made arms are not recorded as scored on mujoco-horse: --assess, which would measure
    nothing, is refused (not a report the same as without it), and nothing is written."""
    out, _ = report
    study = out.parent / "study"
    result = runner.invoke(app, ["report", str(study), "-o", str(tmp_path / "assessed"), "--assess"])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: --assess measures the best gaits of mujoco-horse runs")
    assert "(alpha: backend not recorded; beta_front: backend not recorded" in result.stderr
    assert not list(study.rglob("*assessment.json"))
    assert not (tmp_path / "assessed").exists()
