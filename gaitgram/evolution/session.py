"""An invocation of ``gaitgram evolve``: a run directory holding one or more independent runs.

Layout of a run directory::

    config.toml        the resolved configuration (defaults, file, flags)
    grammar.gg         the grammar text the runs used, so a resume cannot pick up an edited file
    run-000/           one directory per run: checkpoint.json, stats.csv, stats.jsonl, best.json
    summary.json       written when every run has finished
"""

from __future__ import annotations

import json
import signal
import threading
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gaitgram.analysis import CheckResult, check
from gaitgram.backends.api import Evaluator
from gaitgram.backends.registry import BackendLoadError, BackendNotFound, backend_names, get_backend
from gaitgram.evolution.config import RunConfig, load_config
from gaitgram.evolution.engine import GenerationStats, Problem, RunState, run_evolution
from gaitgram.fileio import write_atomically
from gaitgram.language import parse

DEFAULT_BACKEND = "mujoco-horse"


class SessionError(ValueError):
    """A run directory or backend that cannot be used; the message says what to do."""


@dataclass(frozen=True)
class Session:
    directory: Path
    config: RunConfig
    checked: CheckResult
    backend: str

    @property
    def grammar_path(self) -> Path:
        return self.directory / "grammar.gg"

    def run_dir(self, run: int) -> Path:
        return self.directory / f"run-{run:03d}"


def choose_backend(config: RunConfig, checked: CheckResult) -> str:
    return config.backend or checked.grammar.backend or DEFAULT_BACKEND


def start_session(
    directory: Path,
    grammar_text: str,
    grammar_name: str,
    config: RunConfig,
    defines: Mapping[str, int] | None = None,
) -> Session:
    """Create a new run directory; refuses to touch one that already holds anything."""
    if directory.exists() and any(directory.iterdir()):
        raise SessionError(
            f"{directory} already exists and is not empty; pass --resume {directory} to continue it, "
            "or choose another --out"
        )
    checked = check(parse(grammar_text, name=grammar_name, defines=defines))
    directory.mkdir(parents=True, exist_ok=True)
    write_atomically(directory / "grammar.gg", checked.grammar.source.text)
    write_atomically(directory / "config.toml", config.to_toml())
    return Session(directory, config, checked, choose_backend(config, checked))


def resume_session(directory: Path, defines: Mapping[str, int] | None = None) -> Session:
    config_path, grammar_path = directory / "config.toml", directory / "grammar.gg"
    if not config_path.exists() or not grammar_path.exists():
        raise SessionError(f"{directory} is not a gaitgram run directory (no config.toml and grammar.gg)")
    config = load_config(config_path)
    checked = check(parse(grammar_path.read_text(encoding="utf-8"), name=str(grammar_path), defines=defines))
    return Session(directory, config, checked, choose_backend(config, checked))


def load_evaluator(name: str, settings: Mapping[str, Any]) -> Evaluator:
    try:
        spec = get_backend(name)
    except BackendNotFound:
        raise SessionError(f"no backend named {name!r}; installed: {', '.join(backend_names())}") from None
    except BackendLoadError as error:
        raise SessionError(str(error)) from None
    if spec.load is None:
        raise SessionError(f"backend {name!r} declares joints but cannot evaluate gaits")
    try:
        return spec.load(dict(settings))
    except (ValueError, TypeError, ImportError) as error:
        raise SessionError(f"backend {name!r}: {error}") from None


def joint_order(backend: str, checked: CheckResult) -> tuple[str, ...]:
    """The backend's joints when it has a catalogue (undriven ones hold neutral), else the grammar's."""
    spec = get_backend(backend)
    if spec.catalogue is not None:
        return tuple(spec.catalogue.names)
    return tuple(j.joint for j in checked.grammar.joints)


def run_session(
    session: Session,
    evaluator: Evaluator,
    *,
    resume: bool,
    on_generation: Callable[[int, GenerationStats], None] | None = None,
    should_stop: Callable[[], bool] = lambda: False,
) -> list[RunState]:
    problem = Problem(session.checked, session.config, joint_order(session.backend, session.checked))
    states = []
    for run in range(session.config.runs):
        if should_stop():
            break
        states.append(
            run_evolution(
                problem,
                evaluator,
                session.config,
                run,
                session.run_dir(run),
                resume=resume,
                on_generation=on_generation,
                should_stop=should_stop,
            )
        )
    finished = len(states) == session.config.runs and all(
        s.generation == session.config.generations for s in states
    )
    if finished:
        write_atomically(
            session.directory / "summary.json", json.dumps(summary(session, states), indent=1) + "\n"
        )
    return states


def summary(session: Session, states: list[RunState]) -> dict[str, Any]:
    bests = [min(s.population, key=lambda i: i.fitness) for s in states]
    return {
        "grammar": session.grammar_path.name,  # the copy in the run directory: the text the runs used
        "backend": session.backend,
        "runs": [
            {
                "run": r,
                "best_fitness": b.fitness,
                "status": b.evaluation.status.value,
                "phenotype": b.phenotype,
                "generations": s.generation,
            }
            for r, (s, b) in enumerate(zip(states, bests, strict=True))
        ],
        "best_fitness": min(b.fitness for b in bests),
    }


@contextmanager
def stop_on_interrupt() -> Iterator[Callable[[], bool]]:
    """First Ctrl-C: finish the current generation, then stop. Second: stop now."""
    requested = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield requested.is_set
        return
    previous = signal.getsignal(signal.SIGINT)

    def handler(signum: int, frame: object) -> None:
        if requested.is_set():
            signal.signal(signal.SIGINT, previous)
            raise KeyboardInterrupt
        requested.set()

    signal.signal(signal.SIGINT, handler)
    try:
        yield requested.is_set
    finally:
        signal.signal(signal.SIGINT, previous)
