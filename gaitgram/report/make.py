"""Study reports: the paper's tables and figures, with the statistics the paper did not compute.

Per arm, the final generation of every run gives one final best and one final
average; the report shows them in the layout of the paper's Tables 4 and 5
(mean ± SD), with medians, bootstrap intervals, the share of unviable gaits,
the walk rate and the share of runs that hand back a walk at all, and tests
every difference (:mod:`gaitgram.report.stats`). Arms run at different budgets,
or scored by different backends, are refused: their numbers do not compare.

The report is made in stages, each its own module:

- :mod:`~gaitgram.report.records` reads the run directories (untrusted input);
- :mod:`~gaitgram.report.sections` makes the report as data: summaries, rank tests and
  sections of tables and figures;
- :mod:`~gaitgram.report.formats` (Markdown, CSV, LaTeX, JSON),
  :mod:`~gaitgram.report.html`, :mod:`~gaitgram.report.figures` and
  :mod:`~gaitgram.report.gallery` (GIFs) draw it;
- this module writes it, whole or not at all: made in a staging directory and swapped
  into the output directory at once (:func:`gaitgram.fileio.swapped_files`), so that an
  interrupted report (Ctrl-C, a full disk, kill -9) leaves the old report or the new one,
  never some files of each.

Written files: ``summary.md``, ``summary.csv``, ``tables.tex``,
``summary.json``, ``convergence.png`` and ``convergence.svg``; for an arm whose
runs keep a Pareto front (``nsga2``) ``front-ARM.png``, the fronts' objectives
pairwise, and for one whose runs keep a repertoire (``map-elites``)
``archive-ARM.png``, its cells as heat maps; for arms whose backend measures its
gaits (``BackendSpec.assess``) the realism and robustness sections
(``realism-*.csv``, ``robustness-*.csv``, ``realism.png`` and ``realism.svg``), read
from the assessments ``make_report(..., assess=True)`` (``gaitgram report
--assess``) keeps in the run directories; on request, GIFs, drawn by the backend
(``BackendSpec.render``), of each arm's best walk (beside it ``curves-ARM.png``, its
gaits on the real walks' band), of trade-off gaits and of repertoire cells; last,
``report.html``, all of it in one page.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from gaitgram.backends.registry import backends_that
from gaitgram.evolution.rundir import run_input
from gaitgram.fileio import (
    Input,
    OutputError,
    check_output,
    interrupts_deferred,
    recover_swaps,
    swapped_files,
    write_atomically,
)
from gaitgram.report import escape
from gaitgram.report.assess import assess_arms, assesses, assessing
from gaitgram.report.figures import draw, rendered
from gaitgram.report.formats import brief, text_files
from gaitgram.report.gallery import check_cells, draws, gaits_section, render_gaits, spread_cells
from gaitgram.report.graded import graded_section
from gaitgram.report.html import html
from gaitgram.report.realism_robustness import (
    arm_curves_figure,
    load_assessed,
    measured_nothing,
    realism_section,
    robustness_section,
    unmeasured_section,
)
from gaitgram.report.records import ArmRecord, ReportError, check_comparable, load_arms, scoring_listing
from gaitgram.report.sections import (
    Gait,
    Section,
    StudyReport,
    build_report,
    figure_name,
    first_walk_section,
    fronts_section,
    spread_section,
    start_section,
    walk_rates_section,
)
from gaitgram.report.usage import usage_section
from gaitgram.runlayout import ARMS, STUDY_MANIFEST
from gaitgram.strategies.kept import Front, RecordError, Repertoire, load_fronts, load_repertoire
from gaitgram.study.manifest import study_holds

HTML = "report.html"


@dataclass(frozen=True)
class Written:
    """A report as written: every file, in order, and what a terminal shows of it
    (:func:`gaitgram.report.formats.brief`: a screen at most; the files hold every table)."""

    files: list[Path]
    brief: str


class ReportInterrupted(KeyboardInterrupt):
    """Ctrl-C while a report was made; the message says what the output directory holds now,
    ``written`` whether the new report is in it."""

    def __init__(self, message: str, *, written: bool = False) -> None:
        super().__init__(message)
        self.written = written


def study_report(
    arms: Sequence[ArmRecord],
    *,
    title: str = "",
    gaits: int = 0,
    chosen: Sequence[tuple[int, ...]] = (),
    mixed_scoring: bool = False,
) -> StudyReport:
    """The report of ``arms``, with the sections their strategies call for; ``chosen`` cells (or
    ``gaits`` cells spread over each repertoire) are animated and outlined on its heat map, and
    with ``gaits`` each arm's best walk and ``gaits`` trade-offs of each front are animated. With
    ``mixed_scoring``, arms scored under other scoring settings are reported together."""
    fronts, repertoires = kept_sets(arms)
    cells = {
        name: list(chosen) or spread_cells(repertoire, gaits)
        for name, repertoire in repertoires.items()
        if repertoire is not None
    }
    assessed = [found for found in map(load_assessed, arms) if found is not None]
    gallery = gaits_section(arms, fronts, repertoires, cells, gaits=gaits)
    measured = (
        (unmeasured_section(assessed),)
        if measured_nothing(assessed)
        else (
            realism_section(arms, assessed),
            robustness_section(arms, assessed),
            graded_section(arms, assessed),
        )
    )
    sections = (
        start_section(arms),
        first_walk_section(arms),
        walk_rates_section(arms),
        spread_section(arms),
        fronts_section(arms, fronts, repertoires, cells),
        *measured,
        gallery and _beside_the_real_walks(gallery, arms, assessed),
        usage_section(arms),
    )
    return build_report(
        arms, title=title, sections=[s for s in sections if s is not None], mixed_scoring=mixed_scoring
    )


def check_requests(
    arms: Sequence[ArmRecord], *, gaits: int, chosen: Sequence[tuple[int, ...]], assess: bool
) -> None:
    """Refuse, before anything is measured or drawn, options the arms give nothing to, rather than
    make a report the same as without them: ``chosen`` cells where no arm keeps a repertoire (or
    of another shape than its cells), ``assess`` and gaits to animate (``gaits``, ``chosen``)
    where no arm was scored on the backend that measures and draws them."""
    if chosen:
        repertoires = {name: r for name, r in kept_sets(arms)[1].items() if r is not None}
        if not repertoires:
            kept = ", ".join(f"{a.name}: {a.strategy}" for a in arms)
            raise ReportError(
                f"--cell picks a cell of a map-elites arm's repertoire; no arm here keeps one ({kept}): "
                "drop --cell"
            )
        for name, repertoire in repertoires.items():
            check_cells(name, repertoire, chosen)
    scored = scoring_listing(arms)
    if assess and not any(assessing(a.backend) for a in arms):
        measured = " or ".join(backends_that(assesses)) or "no installed"
        raise ReportError(
            f"--assess measures the best gaits of {measured} runs beside real gaits and under "
            f"disturbances; these arms were scored otherwise ({scored}): drop --assess"
        )
    if (gaits or chosen) and not any(draws(a.backend) for a in arms):
        flag = f"--gaits {gaits}" if gaits else f"--cell {','.join(map(str, chosen[0]))}"
        drawn = " or ".join(backends_that(lambda spec: spec.render is not None)) or "no installed"
        raise ReportError(
            f"{flag}: gaits are drawn on the {drawn} backend; these arms were scored otherwise "
            f"({scored}): drop {flag.split()[0]}"
        )


def _say_unanimated(report: StudyReport, gaits: int, progress: Callable[[str], None] | None) -> None:
    """Say that ``--gaits`` found nothing to animate (no arm hands back a walk, a front or a
    repertoire), rather than leave the report silently the same as without it."""
    if gaits and progress and not any(isinstance(f.data, Gait) for f in report.figures):
        progress(
            f"--gaits {gaits}: no arm hands back a walk, a Pareto front or a repertoire; nothing to animate"
        )


def _beside_the_real_walks(gallery: Section, arms: Sequence[ArmRecord], assessed: Sequence) -> Section:
    """The gallery with each arm's curves (its runs' best gaits on the real walks' band) after its
    animated best walk, where its gaits were measured."""
    walks = {figure_name("walk", a.arm, ""): a for a in assessed}
    figures = []
    for figure in gallery.figures:
        figures.append(figure)
        if figure.name in walks and isinstance(figure.data, Gait):
            beside = arm_curves_figure(arms, walks[figure.name], figure.data.genome)
            if beside is not None:
                figures.append(beside)
    return replace(gallery, figures=tuple(figures))


def kept_sets(arms: Sequence[ArmRecord]) -> tuple[dict[str, list[Front]], dict[str, Repertoire | None]]:
    """Each arm's fronts and merged repertoire (empty, None: its runs keep none)."""
    try:
        return (
            {a.name: load_fronts(a.path, a.numbers) for a in arms},
            {a.name: load_repertoire(a.path, a.numbers) for a in arms},
        )
    except RecordError as error:
        raise ReportError(str(error)) from None


def report_files(report: StudyReport, out: Path) -> list[Path]:
    """Every file :func:`write_report` writes, in order."""
    figures = [name for figure in report.figures for name in figure.files]
    return [out / name for name in [*text_files(report), *figures, HTML]]


def write_report(
    report: StudyReport,
    out: Path,
    *,
    force: bool = False,
    refresh: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> list[Path]:
    """The whole report, tables, figures, GIFs and page (reloading itself every ``refresh``
    seconds, for a study still running), or none of it. Every file is checked first (an existing
    one needs ``force``); all are made in a staging directory and swapped into ``out`` at once
    (:func:`gaitgram.fileio.swapped_files`), so that whatever stops it (a GIF that cannot be
    rendered, a full disk, Ctrl-C, kill -9) ``out`` holds the old report or the new one, never
    files of each; directories made for it go again. What an interrupted report left is mended
    first, and ``progress`` hears how. Ctrl-C raises :class:`ReportInterrupted`, a full disk a
    :class:`ReportError`, each saying what ``out`` holds."""
    return _write(report, out, force=force, refresh=refresh, progress=progress, images={})


def _write(
    report: StudyReport,
    out: Path,
    *,
    force: bool,
    refresh: float | None,
    progress: Callable[[str], None] | None,
    images: dict[str, bytes],
    redraw: bool = True,
) -> list[Path]:
    """:func:`write_report`, filling ``images`` with the figures' files by name, for the page;
    without ``redraw``, ``images`` holds them already, as ``out`` does: only the tables and the
    page are made again (a watched report that stops reloading)."""
    for note in recover_swaps(out):  # before the checks: a half-replaced report is put back first
        if progress:
            progress(note)
    names = [*text_files(report), *(n for f in report.figures for n in f.files if redraw), HTML]
    try:
        for name in names:
            check_output(out / name, force=force, parents=True, flag="-o")
    except OutputError as error:
        raise ReportError(str(error)) from None
    made = [d for d in out.parents if not d.exists()]  # out itself appears whole, or not at all
    staging = None
    try:
        with swapped_files(out, progress) as staging:
            for name, text in text_files(report).items():
                write_atomically(staging.path / name, text)
            if redraw:
                images.update(_draw_figures(report, staging.path))
            write_atomically(staging.path / HTML, html(report, images, refresh=refresh))
    except BaseException as error:
        if staging is not None and staging.swapped:
            if isinstance(error, KeyboardInterrupt):
                raise ReportInterrupted(f"the report was written whole in {out}", written=True) from None
            raise
        for directory in made:  # innermost first
            with contextlib.suppress(OSError):
                directory.rmdir()
        if isinstance(error, KeyboardInterrupt):
            raise ReportInterrupted(f"the report was not written; {as_it_was(out)}") from None
        if isinstance(error, OSError):
            reason = error.strerror or str(error)
            raise ReportError(f"cannot write the report in {out}: {reason}; {as_it_was(out)}") from None
        raise
    return report_files(report, out)


def report_inputs(directories: Sequence[Path]) -> list[Input]:
    """The study and run directories a report reads, as inputs no output may write over or into."""
    return [
        Input(d, "the study directory", study_holds) if (d / STUDY_MANIFEST).is_file() else run_input(d)
        for d in directories
    ]


def check_out(out: Path, directories: Sequence[Path]) -> None:
    """Refuse, before anything is read, an output directory that is one of the ``directories``
    reported or lies among what one holds (its runs, its arms), however it is spelt; a directory
    of its own inside one (``runs/table5/report``) is fine, and so is one that holds them (the
    reports of record share ``docs/results/NAME`` with their runs)."""
    try:
        check_output(out, directory=True, parents=True, flag="-o", inputs=report_inputs(directories))
    except OutputError as error:
        raise ReportError(str(error)) from None


def as_it_was(out: Path) -> str:
    """What a report that was not written left: ``out`` untouched, or not made."""
    return f"{out} is as it was" if os.path.lexists(out) else f"{out} was not made"


def _draw_figures(report: StudyReport, out: Path) -> dict[str, bytes]:
    """Each figure's files written (plots first, then the GIFs, one evaluator per run directory);
    returns them by name, for the page."""
    images: dict[str, bytes] = {}
    animated: dict[Path, list[tuple[Gait, Path]]] = {}
    for figure in report.figures:
        if isinstance(figure.data, Gait):
            (name,) = figure.files
            animated.setdefault(figure.data.run_directory, []).append((figure.data, out / name))
            continue
        drawn = draw(figure.data)
        for suffix, name in zip(figure.formats, figure.files, strict=True):
            images[name] = rendered(drawn, suffix)
            write_atomically(out / name, images[name])
    for run_directory, gifs in animated.items():
        render_gaits(run_directory, [gait.genome for gait, _ in gifs], [path for _, path in gifs])
        images.update((path.name, path.read_bytes()) for _, path in gifs)
    return images


def make_report(
    directories: Sequence[Path],
    out: Path,
    *,
    force: bool = False,
    gaits: int = 0,
    chosen: Sequence[tuple[int, ...]] = (),
    assess: bool = False,
    runs: int | None = None,
    mixed_scoring: bool = False,
    progress: Callable[[str], None] | None = None,
) -> Written:
    """``gaitgram report``: the report of study or run directories whose runs have all finished
    (each arm's first ``runs``, if given), written to ``out``; what was written. With ``assess``,
    each run's best gait is first measured where its kept assessment is missing or stale
    (simulation; :mod:`gaitgram.report.assess`). Ctrl-C raises :class:`ReportInterrupted`."""
    check_out(out, directories)
    try:
        arms, title = load_arms(directories, runs=runs)
        check_comparable(arms, mixed_scoring=mixed_scoring)  # before anything is made
        check_requests(arms, gaits=gaits, chosen=chosen, assess=assess)
        if assess:
            assess_arms(arms, progress=progress)
        report = study_report(arms, title=title, gaits=gaits, chosen=chosen, mixed_scoring=mixed_scoring)
        _say_unanimated(report, gaits, progress)
        report = _with_window(report, arms)
        return Written(write_report(report, out, force=force, progress=progress), brief(report))
    except ReportInterrupted:
        raise
    except KeyboardInterrupt:
        raise ReportInterrupted(f"the report was not written; {as_it_was(out)}") from None


def window_section(arms: Sequence[ArmRecord]) -> Section | None:
    """What a report over each arm's first runs alone (``--runs``) says first; None when it reads
    every run the arms plan."""
    grown = [a for a in arms if a.window is not None]
    if not grown:
        return None
    first = min(a.planned_runs for a in arms)
    names = ", ".join(escape.markdown(a.name) for a in grown)
    return Section(
        "window",
        "First runs only",
        f"runs 0-{first - 1} of each arm",
        text=(
            f"This report reads each arm's first {first} runs alone (`gaitgram report --runs {first}`). "
            f"Of these arms, {names} hold more runs, grown since a report was made over the first ones; "
            "the same command without --runs reports them all."
        ),
    )


def _with_window(report: StudyReport, arms: Sequence[ArmRecord]) -> StudyReport:
    window = window_section(arms)
    return report if window is None else replace(report, sections=(window, *report.sections))


def progress_section(arms: Sequence[ArmRecord], planned: int, interval: float | None) -> Section | None:
    """What a page of a study still running says first: how many of the ``planned`` runs have
    finished, and that it reloads itself every ``interval`` seconds (None: the watch was
    stopped); None when all have finished."""
    finished = sum(len(a.runs) for a in arms)
    if finished >= planned:
        return None
    per_arm = ", ".join(
        f"{escape.markdown(a.name)} {len(a.runs)} of {max(a.planned_runs, len(a.runs))}" for a in arms
    )
    return Section(
        "progress",
        "Study in progress",
        f"{finished} of {planned} runs finished",
        text=(
            f"Everything below is over the runs finished so far ({per_arm}); arms with none yet are left "
            + (
                f"out. `gaitgram report --watch` makes it again as runs finish, and this page reloads "
                f"itself every {interval:g} s."
                if interval is not None
                else "out. `gaitgram report --watch` was stopped here and this page no longer reloads "
                "itself; the same command again follows the study."
            )
        ),
    )


def watch_report(
    directories: Sequence[Path],
    out: Path,
    *,
    interval: float = 30.0,
    force: bool = False,
    gaits: int = 0,
    chosen: Sequence[tuple[int, ...]] = (),
    assess: bool = False,
    runs: int | None = None,
    mixed_scoring: bool = False,
    progress: Callable[[str], None] | None = None,
    sleep: Callable[[float], None] = time.sleep,
) -> Written:
    """``gaitgram report --watch``: the report of the runs finished so far, made again each time
    another finishes (looked for every ``interval`` seconds), its page reloading itself, until every
    run has finished: then the report is the one :func:`make_report` writes. What was written
    last."""
    check_out(out, directories)
    seen: tuple[tuple[str, tuple[int, ...]], ...] | None = None
    written = Written([], "")
    shown: _Shown | None = None  # the page out holds, while it reloads itself
    try:
        while True:
            arms, title = load_arms(directories, finished_only=True, runs=runs)
            state = tuple((a.name, a.numbers) for a in arms)
            planned = _planned(directories, runs)
            done = sum(len(a.runs) for a in arms) >= planned
            if arms and state != seen:
                check_comparable(arms, mixed_scoring=mixed_scoring)
                check_requests(arms, gaits=gaits, chosen=chosen, assess=assess)
                if assess:
                    assess_arms(arms, progress=progress)
                report = study_report(
                    arms, title=title, gaits=gaits, chosen=chosen, mixed_scoring=mixed_scoring
                )
                _say_unanimated(report, gaits, progress)
                report = _with_window(report, arms)
                ongoing = None if done else progress_section(arms, planned, interval)
                drawn = None if ongoing is None else _Shown(arms, planned, report, {})
                try:
                    shown_now = (
                        report if ongoing is None else replace(report, sections=(ongoing, *report.sections))
                    )
                    files = _write(
                        shown_now,
                        out,
                        force=force or seen is not None,
                        refresh=None if ongoing is None else interval,
                        progress=progress,
                        images={} if drawn is None else drawn.images,
                    )
                    written = Written(files, brief(shown_now))
                except ReportInterrupted as stop:
                    shown = drawn if stop.written else shown
                    raise
                shown = drawn
                seen = state
                if progress:
                    finished = sum(len(a.runs) for a in arms)
                    progress(f"{finished} of {planned} runs finished: wrote {out / HTML}")
            if done:
                return written
            sleep(interval)
    except KeyboardInterrupt as stop:
        if shown is None:
            if isinstance(stop, ReportInterrupted):
                raise
            raise ReportInterrupted(f"the report was not written; {as_it_was(out)}") from None
        raise ReportInterrupted(_stop_reloading(shown, out, progress), written=True) from None


@dataclass(frozen=True)
class _Shown:
    """A report ``--watch`` wrote: over ``arms``, of ``planned`` runs; the report (without its
    progress section) and its figures' files."""

    arms: Sequence[ArmRecord]
    planned: int
    report: StudyReport
    images: dict[str, bytes]


def _stop_reloading(shown: _Shown, out: Path, progress: Callable[[str], None] | None) -> str:
    """The watched report made again, with its figures as they are, saying it was stopped, its
    page no longer reloading itself (a second Ctrl-C waits for it); what ``out`` holds then."""
    stopped = progress_section(shown.arms, shown.planned, None)
    report = (
        shown.report if stopped is None else replace(shown.report, sections=(stopped, *shown.report.sections))
    )
    finished = sum(len(a.runs) for a in shown.arms)
    failed: Exception | None = None
    try:
        with interrupts_deferred():
            try:
                _write(
                    report,
                    out,
                    force=True,
                    refresh=None,
                    progress=progress,
                    images=shown.images,
                    redraw=False,
                )
            except (ReportError, OSError) as error:
                failed = error
    except KeyboardInterrupt:
        pass  # a second Ctrl-C, held until the page was written
    if failed is not None:
        return (
            f"{out / HTML} is the report of the {finished} of {shown.planned} runs finished so far, but it "
            f"could not be rewritten ({failed}): it still reloads itself"
        )
    return (
        f"{out / HTML} is the report of the {finished} of {shown.planned} runs finished so far, and no "
        "longer reloads itself; `gaitgram report --watch` again follows the study"
    )


def _planned(directories: Sequence[Path], runs: int | None = None) -> int:
    """How many runs the study or run directories will have when finished (at most ``runs`` an
    arm)."""
    from gaitgram.evolution.rundir import RunDirectoryError, read_manifest, saved_config
    from gaitgram.study.manifest import read_study_manifest
    from gaitgram.study.spec import StudyError

    paths: list[Path] = []
    for directory in directories:
        if (directory / STUDY_MANIFEST).is_file():
            try:
                manifest = read_study_manifest(directory)
            except StudyError as error:
                raise ReportError(str(error)) from None
            paths += [directory / ARMS / a.name for a in manifest.arms]
        else:
            paths.append(directory)
    try:
        planned = [saved_config(p, read_manifest(p)).runs for p in paths]
    except RunDirectoryError as error:
        raise ReportError(str(error)) from None
    return sum(planned if runs is None else [min(runs, n) for n in planned])
