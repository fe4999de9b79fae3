"""``gaitgram report``: the paper's fitness figures and tables from run directories."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from gaitgram.cli.common import err
from gaitgram.evolution.report import ReportError, write_report


def command(
    run_dirs: Annotated[
        list[Path], typer.Argument(help="Run directories of `gaitgram evolve`.", show_default=False)
    ],
    out: Annotated[Path, typer.Option("--out", "-o", help="Where to write the report.")] = Path("report"),
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing report.")] = False,
) -> None:
    """Fitness figures and tables over runs, like the paper's.

    Best and average fitness per generation averaged over runs (PNG, SVG), and a table of
    average best and average average with their standard deviations (Markdown, CSV).
    """
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        err.print("error: reports need matplotlib: pip install 'gaitgram[plot]'", style="bold red")
        raise typer.Exit(2) from None
    try:
        written = write_report(run_dirs, out, force=force)
    except ReportError as error:
        err.print(f"error: {error}", style="bold red")
        raise typer.Exit(2) from None
    typer.echo((out / "summary.md").read_text(), nl=False)
    err.print("wrote " + ", ".join(str(p) for p in written))
