"""``gaitgram report``: tables, statistics and figures from study or run directories."""

from __future__ import annotations

import functools
import os
from pathlib import Path
from typing import Annotated

import typer

from gaitgram.cli.common import check_output, err, fail, interrupted, mend_outputs, require_extra
from gaitgram.report.gallery import GalleryError
from gaitgram.report.make import HTML, ReportInterrupted, make_report, watch_report
from gaitgram.report.records import ReportError
from gaitgram.runlayout import ASSESSMENT, in_run

_Directories = Annotated[
    list[Path],
    typer.Argument(
        help="Study directories of `gaitgram study`, or run directories of `gaitgram evolve` (each one arm).",
        show_default=False,
    ),
]
_Out = Annotated[Path, typer.Option("--out", "-o", help="Where to write the report.")]
_Force = Annotated[bool, typer.Option("--force", help="Overwrite an existing report.")]
_Gaits = Annotated[
    int,
    typer.Option(
        min=0,
        help="Animate each arm's best walk, and this many gaits per nsga2 or map-elites arm: "
        "trade-offs spread along the front, repertoire cells spread along the first descriptor "
        "(if the runs' backend draws gaits; slow).",
    ),
]
_Assess = Annotated[
    bool,
    typer.Option(
        "--assess",
        help="First measure each run's best gait beside the real walks and under disturbances "
        "where not yet measured (if the runs' backend measures gaits; simulation, kept in "
        f"{in_run(ASSESSMENT)} of the "
        "run directories; reports read it from there).",
    ),
]
_Watch = Annotated[
    bool,
    typer.Option(
        "--watch",
        help="Follow a study still running: report the runs finished so far, again each time "
        "another finishes, until all have (report.html reloads itself meanwhile); Ctrl-C stops, "
        "leaving the report so far, no longer reloading.",
    ),
]
_Interval = Annotated[
    float | None,
    typer.Option(
        min=1.0,
        help="With --watch: seconds between looks for newly finished runs [default: 30].",
        show_default=False,
    ),
]
_Runs = Annotated[
    int | None,
    typer.Option(
        "--runs",
        min=1,
        help="Read each arm's first N runs alone (runs 0 to N-1): a study grown since a report was "
        "made over fewer is reported as it stood.",
        show_default=False,
    ),
]
_MixedScoring = Annotated[
    bool,
    typer.Option(
        "--mixed-scoring",
        help="Report arms scored under different scoring settings (other bump floors) together: the "
        "report says first that their fitness values do not compare; walks, realism and robustness do.",
    ),
]
_Cell = Annotated[
    list[str] | None,
    typer.Option(
        metavar="I,J", help="Animate the best gait of this repertoire cell (repeatable; see archive-*.png)."
    ),
]


def command(
    directories: _Directories,
    out: _Out = Path("report"),
    force: _Force = False,
    gaits: _Gaits = 0,
    assess: _Assess = False,
    watch: _Watch = False,
    interval: _Interval = None,
    runs: _Runs = None,
    mixed_scoring: _MixedScoring = False,
    cell: _Cell = None,
) -> None:
    """Tables, statistics and figures over runs, like the paper's and more.

    Per arm: mean and SD of the final best and average fitness (the paper's Tables 4 and 5),
    median with a bootstrap interval, viable-only average, unviable share and walk rate; every
    difference tested (Kruskal-Wallis, pairwise Mann-Whitney U with Holm, Vargha-Delaney A12);
    convergence figures with confidence bands. Prints a summary, a screen at most, and writes
    every table in summary.md, summary.csv, summary.json, tables.tex, convergence.png and
    convergence.svg; front-ARM.png (Pareto fronts, objectives pairwise) for nsga2 arms and
    archive-ARM.png (the repertoire as heat maps) for map-elites arms; for mujoco-horse arms, the
    realism and robustness sections, measured by --assess (docs/fitness.md); with --gaits or
    --cell, GIFs of chosen gaits (docs/strategies.md); and report.html, all of it in one page that
    opens from a file (docs/study.md). With --watch, a study still running is reported over its
    finished runs, again as more finish; with --runs N, over each arm's first N runs.
    """
    if interval is not None and not watch:
        raise fail("--interval is how often --watch looks for finished runs; add --watch, or drop --interval")
    require_extra("matplotlib", "reports")
    require_extra("scipy", "reports")
    chosen = [_cell(text) for text in cell or []]
    if gaits or chosen:
        os.environ.setdefault("MUJOCO_GL", "egl")  # before MuJoCo is imported
        require_extra("PIL", "animations")
    check_output(out, force=False, directory=True, parents=True, flag="-o")  # before reading the runs
    mend_outputs(out, directory=True)  # a report cut short there is put back first
    every = {} if interval is None else {"interval": interval}
    report = functools.partial(watch_report, **every) if watch else make_report
    try:
        written = report(
            directories,
            out,
            force=force,
            gaits=gaits,
            chosen=chosen,
            assess=assess,
            runs=runs,
            mixed_scoring=mixed_scoring,
            progress=err.print,
        )
    except (ReportError, GalleryError) as error:
        raise fail(str(error)) from None
    except ReportInterrupted as stop:  # Ctrl-C: what the output directory holds now
        raise interrupted(str(stop)) from None
    except OSError as error:
        raise fail(f"cannot write the report in {out}: {error.strerror or error}") from None
    typer.echo(written.brief, nl=False)
    err.print(f"wrote {len(written.files)} files in {out}; all of it in one page: {out / HTML}")


def _cell(text: str) -> tuple[int, ...]:
    parts = text.replace(" ", "").split(",")
    if not 1 <= len(parts) <= 2 or not all(p.isdigit() for p in parts):
        raise typer.BadParameter(
            f"{text!r}: give a cell as I,J (column, row of archive-*.png)", param_hint="--cell"
        )
    return tuple(int(p) for p in parts)
