"""``gaitgram evolve``: search a grammar's gaits (GE, or another strategy), with progress, checkpoints
and a verified resume."""

from __future__ import annotations

import contextlib
import os
import time
from dataclasses import replace
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

from gaitgram.backends.api import Evaluator
from gaitgram.cli.common import check_output, err, fail, load_usable
from gaitgram.cli.options import REPRESENTATIONS, Defines, listed, parse_defines
from gaitgram.configuration import (
    NESTED,
    ConfigError,
    RunConfig,
    load_config,
    setting_location,
    with_overrides,
)
from gaitgram.evolution.checkpoint import CheckpointError, load_checkpoint
from gaitgram.evolution.distributed import ClusterError, DaskEvaluator, connect
from gaitgram.evolution.rundir import RunDirectory, RunDirectoryError
from gaitgram.evolution.session import run_session, stop_on_interrupt
from gaitgram.evolution.transfer import TransferError, start_genomes
from gaitgram.extras import MissingExtra
from gaitgram.fileio import DirectoryInUse, DirectoryLock
from gaitgram.language.source import SourceError, read_source
from gaitgram.pipeline import DEFAULT_BACKEND, Pipeline, PipelineError
from gaitgram.strategies.api import GenerationStats, StrategyError
from gaitgram.strategies.registry import BUILTIN as STRATEGIES
from gaitgram.strategies.registry import load_strategy, run_pipeline

#: What makes a run refused before it starts (exit 2).
_INPUT_ERRORS = (ConfigError, PipelineError, RunDirectoryError, CheckpointError, TransferError)
#: What a run is without a config file or flags: the defaults help shows.
_DEFAULT = RunConfig()


_Grammar = Annotated[
    Path | None,
    typer.Argument(help="The grammar to evolve; with --resume, only checked against the run's copy."),
]
_Config = Annotated[
    Path | None, typer.Option("--config", "-c", help="A run.toml with any of the keys in docs/evolve.md.")
]
_Generations = Annotated[
    int | None,
    typer.Option(min=1, help=f"Generations after the initial one (default {_DEFAULT.generations})."),
]
_Population = Annotated[
    int | None, typer.Option(min=2, help=f"Population size (default {_DEFAULT.population}).")
]
_Runs = Annotated[
    int | None, typer.Option(min=1, help=f"Independent runs with derived seeds (default {_DEFAULT.runs}).")
]
_Seed = Annotated[int | None, typer.Option(min=0, help=f"Random seed (default {_DEFAULT.seed}).")]
_Backend = Annotated[
    str | None,
    typer.Option(help=f"Fitness backend (default: the grammar's @backend, else {DEFAULT_BACKEND})."),
]
_Strategy = Annotated[
    str | None,
    typer.Option(
        help=f"Search strategy: {listed(STRATEGIES, _DEFAULT.strategy)}, or a plug-in's (docs/strategies.md)."
    ),
]
_Representation = Annotated[
    str | None,
    typer.Option(
        help=f"What a genome is: {listed(REPRESENTATIONS, _DEFAULT.representation)}, or a plug-in's; "
        "its settings in the --config file's [representation_settings] (docs/ge.md)."
    ),
]
_Threads = Annotated[
    int | None,
    typer.Option(min=1, help="Simulation threads, for backends that use them (default: all cores)."),
]
_StartFrom = Annotated[
    Path | None,
    typer.Option(
        help="Start from this finished run's final population (the same grammar; run i from its "
        "run i): a horse's run, for example, with body = \"draft\" in the --config file's "
        "[backend_settings]."
    ),
]
_Out = Annotated[
    Path | None,
    typer.Option("--out", "-o", help="A new run directory (default runs/GRAMMAR-seedSEED)."),
]
_Resume = Annotated[
    Path | None,
    typer.Option(help="Continue the run in this directory; any flag given must agree with it."),
]
_Scheduler = Annotated[
    str | None, typer.Option(help="Evaluate on the Dask scheduler at this address, tcp://HOST:PORT.")
]
_DaskLocal = Annotated[
    int | None, typer.Option(min=1, help="Evaluate on a local Dask cluster of this many workers.")
]
_Quiet = Annotated[bool, typer.Option("--quiet", "-q", help="Print only the summary.")]
_Jsonl = Annotated[bool, typer.Option("--jsonl", help="Print one JSON line of statistics per generation.")]


def command(
    grammar: _Grammar = None,
    config: _Config = None,
    generations: _Generations = None,
    population: _Population = None,
    runs: _Runs = None,
    seed: _Seed = None,
    backend: _Backend = None,
    strategy: _Strategy = None,
    representation: _Representation = None,
    threads: _Threads = None,
    start_from: _StartFrom = None,
    out: _Out = None,
    resume: _Resume = None,
    scheduler: _Scheduler = None,
    dask_local: _DaskLocal = None,
    quiet: _Quiet = False,
    jsonl: _Jsonl = False,
    defines: Defines = None,
) -> None:
    """Evolve gaits with GE (the paper's Table 1 parameters by default), or search them with another
    strategy at the same budget (--strategy).

    Every generation is checkpointed: Ctrl-C stops cleanly after the current one, and --resume
    continues to exactly the result of an uninterrupted run. A resume refuses any grammar, --define,
    config or flag that would change the run's meaning.
    """
    flags = {"generations": generations, "population": population, "runs": runs, "seed": seed}
    flags["backend"] = backend
    flags["strategy"] = strategy
    flags["representation"] = representation
    flags["start_from"] = None if start_from is None else os.path.abspath(start_from)  # as a file's is
    given = {k: v for k, v in flags.items() if v is not None}
    with contextlib.ExitStack() as held:  # the run directory's lock and the evaluator, until the end
        try:
            if resume is not None:
                directory = _resume(resume, grammar, config, given, defines, out, held)
                pipeline = directory.pipeline
            else:
                pipeline, out = _new_run(grammar, config, given, defines, out)
            # Everything is checked and the backend loaded before a new run directory is made.
            evaluator = _evaluator(pipeline, _runtime(pipeline, threads), scheduler, dask_local)
            held.callback(evaluator.close)
            if resume is None:
                values = parse_defines(defines)
                directory = RunDirectory.create(out, pipeline, defines=values, origin=str(grammar))
                held.enter_context(_lock(directory.path))
        except (*_INPUT_ERRORS, MissingExtra, ClusterError) as error:
            raise fail(str(error)) from None
        _evolve(directory, evaluator, resumed=resume is not None, quiet=quiet, jsonl=jsonl)


def _new_run(
    grammar: Path | None,
    config: Path | None,
    given: dict[str, Any],
    defines: list[str] | None,
    out: Path | None,
) -> tuple[Pipeline, Path]:
    """A new run's pipeline and directory, all checked (the strategy installed, every run's start
    there and finished, the directory new) before anything is written."""
    if grammar is None:
        raise typer.BadParameter("give a grammar to evolve, or --resume DIR", param_hint="GRAMMAR")
    if out is not None:
        RunDirectory.check_new(out)  # before any work
    try:
        pipeline = run_pipeline(load_usable(grammar, parse_defines(defines)), load_config(config, given))
    except PipelineError as error:
        top = (error.key or "").split(".")[0]
        if error.key is None or config is None or (top in given and top not in NESTED):
            raise  # nowhere in the file: a grammar's fault, or a flag's (whose name the message has)
        raise PipelineError(f"{setting_location(config, error.key)}: {error}", key=error.key) from None
    if out is None:
        out = Path("runs") / f"{grammar.stem}-seed{pipeline.config.seed}"
        RunDirectory.check_new(out)
    load_strategy(pipeline)  # its library is installed, before anything is written
    for run in range(pipeline.config.runs):  # every run's start is there and finished
        start_genomes(pipeline, run)
    return pipeline, out


def _evolve(
    directory: RunDirectory, evaluator: Evaluator, *, resumed: bool, quiet: bool, jsonl: bool
) -> None:
    """Run the directory's runs with a progress display, and say how it ended."""
    run_config = directory.config
    total = run_config.runs * (run_config.generations + 1)
    out_console = Console(highlight=False, soft_wrap=True, markup=False)
    progress = Progress(
        TextColumn("run {task.fields[run]}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("best {task.fields[best]}  avg {task.fields[average]}  {task.fields[rate]} evals/s"),
        TimeRemainingColumn(),
        console=err.console(),
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
            from gaitgram import jsonio

            out_console.out(jsonio.dumps({"run": run, **stats.as_record()}), highlight=False)
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
                directory,
                evaluator,
                resume=resumed,
                on_generation=on_generation,
                on_restored=lambda path: err.print(
                    f"rewrote {path} from its run's checkpoint (it was missing or disagreed with it)",
                ),
                should_stop=should_stop,
            )
    except (CheckpointError, PipelineError, StrategyError) as error:
        raise fail(str(error)) from None
    except OSError as error:  # a full disk, a directory gone: the last checkpoint is intact
        where = error.filename or directory.path
        raise fail(
            f"cannot write {where}: {error.strerror or error}; the run can continue from its last "
            f"checkpoint with: gaitgram evolve --resume {directory.path}"
        ) from None

    done = len(states) == run_config.runs and all(s.generation == run_config.generations for s in states)
    if not done:
        err.print(
            f"stopped; continue with: gaitgram evolve --resume {directory.path}",
            style="bold yellow",
        )
        raise typer.Exit(130)
    best = min((s.best for s in states), key=lambda i: i.fitness)
    err.print(
        f"best fitness {best.fitness:.6g} ({best.evaluation.status}); run directory {directory.path}",
    )
    verdict = directory.pipeline.spec.verdict
    if verdict is not None:
        err.print(f"the best gait is {verdict.sentence(best.evaluation)}")


def _lock(path: Path) -> DirectoryLock:
    """One gaitgram at a time in a run directory: two would write the same checkpoints."""
    try:
        return DirectoryLock(path)
    except DirectoryInUse:
        raise RunDirectoryError(
            f"{path} is in use by another gaitgram (an evolve, or the study it is an arm of); wait for "
            "it to finish, or stop it"
        ) from None
    except FileNotFoundError:
        raise RunDirectoryError(f"{path} is not a run directory (no such directory)") from None
    except NotADirectoryError:
        raise RunDirectoryError(f"{path} is not a run directory (not a directory)") from None
    except OSError as error:  # a read-only directory, say: a run there cannot continue
        raise RunDirectoryError(f"cannot write {path}: {error.strerror or error}") from None


def _resume(
    path: Path,
    grammar: Path | None,
    config: Path | None,
    flags: dict[str, Any],
    defines: list[str] | None,
    out: Path | None,
    held: contextlib.ExitStack,
) -> RunDirectory:
    """Open the run, lock it (into ``held``) and refuse anything on the command line that
    disagrees with it."""
    directory = RunDirectory.open(path)
    for place in (path, *(directory.run_dir(run) for run in range(directory.config.runs))):
        if place.exists():  # checkpoints are written there: before a generation is computed
            check_output(place, force=False, directory=True)
    held.enter_context(_lock(path))
    found: list[str] = []
    if out is not None and os.path.realpath(out) != os.path.realpath(path):  # a link loop raises no error
        found.append(f"--out {out}: a resumed run stays in {path}")
    source = None
    if grammar is not None:
        try:
            source = read_source(grammar)
        except SourceError as error:
            raise fail(f"cannot read {error.path}: {error.message}") from None
    given: RunConfig | None = None
    if config is not None:
        given = load_config(config, flags)
    elif flags:
        given = with_overrides(directory.config, **flags)
        if given.strategy != directory.config.strategy:  # another strategy: its own default settings
            given = replace(given, strategy_settings={})
        if given.representation != directory.config.representation:  # likewise its representation
            given = replace(given, representation_settings={})
    grow_to = None
    if given is not None and given.runs > directory.config.runs:  # more runs: added, the rest kept
        grow_to, given = given.runs, replace(given, runs=directory.config.runs)
    found += directory.differences(
        grammar=source, defines=parse_defines(defines) if defines else None, config=given
    )
    if found:
        raise RunDirectoryError(
            f"cannot resume {path}: what was given differs from the run:\n  - "
            + "\n  - ".join(found)
            + "\nresume with no grammar or flags (the run keeps its own), or start a new run with --out"
        )
    if grow_to is not None:
        directory = directory.grow(grow_to)
    load_strategy(directory.pipeline)  # its library is installed, to read the strategy's state
    accepted, finish = directory.fingerprints, directory.config.generations
    for run, checkpoint in enumerate(directory.checkpoints):  # all of them, before anything runs
        if checkpoint.exists():
            state = load_checkpoint(
                checkpoint, directory.pipeline, fingerprint=accepted, run=run, with_memory=False
            )
            if state.generation < finish:  # it goes on: its strategy's memory must be there
                load_checkpoint(checkpoint, directory.pipeline, fingerprint=accepted, run=run)
    return directory


def _runtime(pipeline: Pipeline, threads: int | None) -> dict[str, Any]:
    if threads is not None and "threads" in pipeline.spec.runtime_settings:
        return {"threads": threads}
    return {}


def _evaluator(
    pipeline: Pipeline, runtime: dict[str, Any], scheduler: str | None, dask_local: int | None
) -> Evaluator:
    cluster = connect(scheduler, dask_local)
    if cluster is None:
        return pipeline.load_evaluator(runtime)
    return DaskEvaluator(cluster, pipeline.backend, {**pipeline.config.backend_settings, **runtime})
