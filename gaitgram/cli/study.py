"""``gaitgram study``: every arm and run of a study file, in parallel, resumable."""

from __future__ import annotations

import os
import shlex
import time
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn
from rich.table import Table

from gaitgram.cli.common import check_output, err, fail
from gaitgram.evolution.distributed import ClusterError, DaskCluster, connect
from gaitgram.evolution.session import stop_on_interrupt
from gaitgram.extras import MissingExtra
from gaitgram.study.runner import (
    TASK_ERRORS,
    ArmStatus,
    RunProgress,
    StudyCheck,
    StudyDirectory,
    StudyRun,
    TaskResult,
    check_study,
    open_study,
    run_study,
)
from gaitgram.study.spec import ScaleDown, Study, load_study

_StudyFile = Annotated[Path, typer.Argument(help="The study file (docs/study.md).", show_default=False)]
_Out = Annotated[
    Path | None,
    typer.Option("--out", "-o", help="The study directory; giving it again continues the study."),
]
_Runs = Annotated[int | None, typer.Option(min=1, help="Runs per arm, instead of the file's.")]
_Generations = Annotated[
    int | None,
    typer.Option(
        min=1,
        help="Generations of every run, instead of the file's; weight stages and @joint free= "
        "generations move with it (the same design, shorter).",
    ),
]
_Population = Annotated[
    int | None, typer.Option(min=2, help="Population of every run; the elite keeps its share of it.")
]
_Representation = Annotated[
    str | None,
    typer.Option(
        help="Every arm's representation (what a genome is: ge, pige, sge, dsge, cfg-gp; docs/ge.md), "
        "instead of the file's."
    ),
]
_Jobs = Annotated[
    int | None, typer.Option(min=1, help="Runs at once in local processes (default: one per core).")
]
_Threads = Annotated[
    int | None, typer.Option(min=1, help="Simulation threads per run (default: cores / jobs).")
]
_Scheduler = Annotated[
    str | None,
    typer.Option(
        help="Run on the Dask scheduler at this address (tcp://HOST:PORT), one run per task; its "
        "workers must see the study directory (docs/study.md)."
    ),
]
_DaskLocal = Annotated[
    int | None, typer.Option(min=1, help="Run on a local Dask cluster of this many workers.")
]
_Quiet = Annotated[bool, typer.Option("--quiet", "-q", help="Print only the summary.")]
_Check = Annotated[
    bool,
    typer.Option(
        "--check",
        help="Check the study file (and the -o directory, if given) and print its plan and progress; "
        "run nothing, write nothing.",
    ),
]


def command(
    study_file: _StudyFile,
    out: _Out = None,
    runs: _Runs = None,
    generations: _Generations = None,
    population: _Population = None,
    representation: _Representation = None,
    jobs: _Jobs = None,
    threads: _Threads = None,
    scheduler: _Scheduler = None,
    dask_local: _DaskLocal = None,
    quiet: _Quiet = False,
    check: _Check = False,
) -> None:
    """Run a study: every arm (grammar, configuration, strategy) for its number of runs.

    Runs go in parallel, one per core by default. Every generation of every run is checkpointed:
    run the same command again after a stop, a crash or kill -9 and the study continues to exactly
    the results of an uninterrupted one. A different study file or flags for an existing directory
    are refused. Report it with `gaitgram report DIR`. `--check` says whether the command would
    run, and how far the directory has got, before hours are spent.
    """
    if check:
        _check(study_file, out, ScaleDown(runs, generations, population, representation))
        return
    if out is None:
        raise typer.BadParameter(
            "give the study directory to run the study in (only --check runs without one)",
            param_hint="'-o' / '--out'",
        )
    cores = os.cpu_count() or 1
    jobs = jobs or (dask_local or cores)
    threads = threads or max(1, cores // jobs)
    check_output(out, force=False, directory=True, parents=True, flag="-o")  # an existing study continues
    try:
        study = load_study(study_file, ScaleDown(runs, generations, population, representation))
        # The cluster answers before any directory is made; the directory is whole before any run.
        cluster = connect(scheduler, dask_local)
        try:
            with open_study(study, out) as directory:
                done = _run(directory, jobs, threads, cluster, quiet)
        finally:
            if cluster is not None:
                cluster.close()
    except (*TASK_ERRORS, ClusterError, MissingExtra) as error:
        raise fail(str(error)) from None
    except OSError as error:
        raise fail(
            f"cannot write {error.filename or out}: {error.strerror or error}; run the same command "
            "again to continue the study"
        ) from None
    _say_how_it_ended(directory, done)


def _say_how_it_ended(directory: StudyDirectory, done: StudyRun) -> None:
    """Records rewritten, then complete (exit 0) or stopped with runs unfinished (exit 130)."""
    if done.restored:
        err.print(
            f"rewrote {len(done.restored)} record file(s) that disagreed with their runs' checkpoints: "
            + ", ".join(str(p) for p in done.restored),
        )
    unfinished = [t for t in directory.tasks if not directory.finished(t)]
    if unfinished:
        err.print(f"stopped with {len(unfinished)} run(s) unfinished; continue with the same command")
        raise typer.Exit(130)
    study = directory.study
    err.print(
        f"study complete: {len(study.arms)} arms x {study.runs} runs in {directory.path} "
        f"({len(done.results)} run(s) this time); "
        f"report with: gaitgram report {directory.path}",
    )


def _run(
    directory: StudyDirectory, jobs: int, threads: int, cluster: DaskCluster | None, quiet: bool
) -> StudyRun:
    tasks = directory.tasks
    config = {name: arm.config for name, arm in directory.arms.items()}
    per_run = {name: c.generations + 1 for name, c in config.items()}
    total = sum(per_run[t.arm] for t in tasks)
    progress = Progress(
        TextColumn("{task.fields[runs]}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("generations  {task.fields[rate]} evals/s"),
        TimeRemainingColumn(),
        console=err.console(),
        disable=quiet,
    )
    started = time.perf_counter()
    first: dict[tuple[str, int], int] = {}
    last_poll = 0.0

    def on_progress(active: list[RunProgress], done: list[TaskResult]) -> None:
        nonlocal last_poll
        now = time.perf_counter()
        if now - last_poll < 1.0:
            return
        last_poll = now
        states = [directory.progress(t) for t in tasks]
        generations = sum(min(p.generation + 1, per_run[p.arm]) for p in states)
        evaluations = 0
        for p in states:
            first.setdefault((p.arm, p.run), p.evaluations)
            evaluations += p.evaluations - first[(p.arm, p.run)]
        finished = sum(p.generation + 1 >= per_run[p.arm] for p in states)
        rate = evaluations / max(now - started, 1e-9)
        progress.update(bar, completed=generations, runs=f"{finished}/{len(tasks)} runs", rate=f"{rate:.1f}")

    with progress, stop_on_interrupt() as should_stop:
        bar = progress.add_task("study", total=total, runs=f"0/{len(tasks)} runs", rate="-")
        on_progress([], [])
        done = run_study(
            directory,
            jobs=jobs,
            threads=threads,
            cluster=cluster,
            on_progress=on_progress,
            should_stop=should_stop,
        )
        last_poll = 0.0
        on_progress([], done.results)
    return done


def _check(study_file: Path, out: Path | None, scale: ScaleDown) -> None:
    """The plan of a study, and what of it ``out`` holds: exit 2 with the error a run would give."""
    try:
        study = load_study(study_file, scale)
        found = check_study(study, out)
    except TASK_ERRORS as error:
        raise fail(str(error)) from None
    console = Console(highlight=False, soft_wrap=True)
    console.print(_plan_table(study, found.arms))
    console.print(_what_running_it_does(study, study_file, out, scale, found))


def _what_running_it_does(
    study: Study, study_file: Path, out: Path | None, scale: ScaleDown, found: StudyCheck
) -> str:
    where = shlex.quote(str(out)) if out is not None else "DIR"
    flags = [f"--runs {scale.runs}" if scale.runs is not None else "", scale.flags]
    run = " ".join(filter(None, ["gaitgram study", shlex.quote(str(study_file)), "-o", where, *flags]))
    planned = study.runs * len(study.arms)
    if out is None or not found.held:
        return f"ready: {planned} runs, nothing written; run with: {run}"
    finished = sum(arm.finished for arm in found.arms)
    said = [f"{out} holds this study: {finished} of {planned} runs finished"]
    if found.running:
        said.append("another gaitgram is running it now (a second is refused until it stops)")
    if finished == planned:
        return f"{said[0]}, complete; report with: gaitgram report {where}"
    fewer = [arm.held for arm in found.arms if 0 < arm.held < study.runs]
    if fewer:
        said.append(f"running it grows arms from {min(fewer)} to {study.runs} runs")
    missing = [arm.name for arm in found.arms if arm.held == 0]
    if missing:
        said.append(f"{', '.join(missing)} start from scratch (no directory)")
    return "; ".join(said) + f"; continue with: {run}"


def _plan_table(study: Study, statuses: tuple[ArmStatus, ...]) -> Table:
    table = Table(
        title=f"{study.title}: {len(study.arms)} arms x {study.runs} runs",
        caption="budget: new gaits per run, population + generations x (population - elite)",
    )
    for column in ("arm", "strategy", "grammar", "generations", "population", "budget", "finished"):
        table.add_column(column, justify="left" if column in ("arm", "strategy", "grammar") else "right")
    for arm, status in zip(study.arms, statuses, strict=True):
        config = arm.config
        table.add_row(
            arm.name,
            arm.strategy,
            os.path.normpath(arm.grammar),
            str(config.generations),
            str(config.population),
            str(config.budget),
            f"{status.finished}/{study.runs}",
        )
    return table
