"""``gaitgram evolve``: run GE on a grammar, with progress, checkpoints and resume."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

from gaitgram.cli.common import err, load_usable
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.evolution.config import ConfigError, load_config
from gaitgram.evolution.engine import CheckpointError, GenerationStats
from gaitgram.evolution.session import (
    SessionError,
    load_evaluator,
    resume_session,
    run_session,
    start_session,
    stop_on_interrupt,
)


def command(
    grammar: Annotated[
        Path | None, typer.Argument(help="The grammar to evolve (not needed with --resume).")
    ] = None,
    config: Annotated[
        Path | None, typer.Option("--config", "-c", help="A run.toml; see docs/evolve.md.")
    ] = None,
    generations: Annotated[
        int | None, typer.Option(min=1, help="Generations after the initial one [50].")
    ] = None,
    population: Annotated[int | None, typer.Option(min=2, help="Population size [75].")] = None,
    runs: Annotated[int | None, typer.Option(min=1, help="Independent runs with derived seeds [1].")] = None,
    seed: Annotated[int | None, typer.Option(min=0, help="Random seed [0].")] = None,
    backend: Annotated[str | None, typer.Option(help="Fitness backend [the grammar's @backend].")] = None,
    threads: Annotated[int | None, typer.Option(min=1, help="Backend threads [all cores].")] = None,
    out: Annotated[
        Path | None, typer.Option("--out", "-o", help="Run directory [runs/GRAMMAR-seedS].")
    ] = None,
    resume: Annotated[Path | None, typer.Option(help="Continue the stopped run in this directory.")] = None,
    scheduler: Annotated[str | None, typer.Option(help="Dask scheduler address, tcp://HOST:PORT.")] = None,
    dask_local: Annotated[
        int | None, typer.Option(min=1, help="Start a local Dask cluster of N workers.")
    ] = None,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print only the summary.")] = False,
    jsonl: Annotated[
        bool, typer.Option("--jsonl", help="One JSON line of statistics per generation.")
    ] = False,
    defines: Defines = None,
) -> None:
    """Evolve gaits with GE (the paper's Table 1 parameters by default).

    Every generation is checkpointed: Ctrl-C stops cleanly after the current one, and --resume
    continues to exactly the result of an uninterrupted run.
    """
    values = parse_defines(defines)
    try:
        if resume is not None:
            session = resume_session(resume, values)
        else:
            if grammar is None:
                raise typer.BadParameter("give a grammar to evolve, or --resume DIR", param_hint="GRAMMAR")
            checked = load_usable(grammar, values)
            run_config = load_config(
                config,
                {
                    "generations": generations,
                    "population": population,
                    "runs": runs,
                    "seed": seed,
                    "backend": backend,
                    "backend_settings": {"threads": threads} if threads else None,
                },
            )
            directory = out or Path("runs") / f"{grammar.stem}-seed{run_config.seed}"
            session = start_session(directory, checked.grammar.source.text, str(grammar), run_config, values)
        evaluator = load_evaluator(session.backend, session.config.backend_settings)
    except (ConfigError, SessionError, CheckpointError) as error:
        err.print(f"error: {error}", style="bold red")
        raise typer.Exit(2) from None

    if scheduler or dask_local:
        from gaitgram.evolution.distributed import DaskEvaluator, DaskMissing

        try:
            evaluator = DaskEvaluator.connect(
                session.backend, session.config.backend_settings, address=scheduler, local_workers=dask_local
            )
        except DaskMissing as error:
            err.print(f"error: {error}", style="bold red")
            raise typer.Exit(2) from None

    total = session.config.runs * (session.config.generations + 1)
    out_console = Console(highlight=False, soft_wrap=True)
    progress = Progress(
        TextColumn("run {task.fields[run]}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("best {task.fields[best]}  avg {task.fields[average]}  {task.fields[rate]} evals/s"),
        TimeRemainingColumn(),
        console=err,
        disable=quiet or jsonl,
        transient=False,
    )
    started = time.perf_counter()
    evaluations = 0

    def on_generation(run: int, stats: GenerationStats) -> None:
        nonlocal evaluations
        evaluations += stats.evaluations
        rate = evaluations / max(time.perf_counter() - started, 1e-9)
        if jsonl:
            out_console.out(json.dumps({"run": run, **stats.as_record()}))
        progress.update(
            task,
            advance=1,
            run=run,
            best=f"{stats.best:.4g}",
            average=f"{stats.average:.4g}",
            rate=f"{rate:.1f}",
        )

    try:
        with progress, stop_on_interrupt() as should_stop:
            task = progress.add_task("evolve", total=total, run=0, best="-", average="-", rate="-")
            states = run_session(
                session,
                evaluator,
                resume=resume is not None,
                on_generation=on_generation,
                should_stop=should_stop,
            )
    except CheckpointError as error:
        err.print(f"error: {error}", style="bold red")
        raise typer.Exit(2) from None
    finally:
        evaluator.close()

    done = len(states) == session.config.runs and all(
        s.generation == session.config.generations for s in states
    )
    if not done:
        err.print(
            f"stopped; continue with: gaitgram evolve --resume {session.directory}", style="bold yellow"
        )
        raise typer.Exit(130)
    best = min((min(s.population, key=lambda i: i.fitness) for s in states), key=lambda i: i.fitness)
    err.print(
        f"best fitness {best.fitness:.6g} ({best.evaluation.status}); run directory {session.directory}"
    )
