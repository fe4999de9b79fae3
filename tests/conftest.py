"""Shared fixtures: where the shared test vectors live, the bundled grammars, and the tiny
curve-match problem the evolution, strategy and study tests run."""

from __future__ import annotations

import os
import resource
import shutil
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, settings

ROOT = Path(__file__).resolve().parents[1]
#: A copy of ../shared/vectors/ponyge2 (see its README): CI clones only this repository.
VECTORS = ROOT / "tests" / "data" / "ponyge2"
GRAMMARS = ROOT / "grammars"

#: The vectors' GE_RANGE values (vectors/ponyge2/meta.json).
VECTOR_DEFINES = {"dataset_n_vars": 5, "dataset_n_is": 5, "dataset_n_os": 5}

#: The tiny curve-match problem: two joints, a structural choice (sin or cos) over ranges. The
#: targets are reachable: their amplitudes, multipliers and phases are on the grammar's grids.
CURVE_GRAMMAR = """\
@start <gait>
<gait> ::= <hip>;<elbow>
@joint hip_hind
<hip> ::= <amp>*sin(<k>*2*PI*t+<phase>) | <amp>*cos(<k>*2*PI*t+<phase>)
@joint elbow_fore
<elbow> ::= <amp>*sin(<k>*2*PI*t+<phase>)+<amp>
<amp> ::= int[0..20]
<k> ::= int[1..3]
<phase> ::= float[0..3 step 0.5]
"""
#: The same curves with no structural choice: one expression of ranges, a parameter vector of 7
#: coordinates (what CMA-ES searches).
CURVE_NUMERICAL = """\
@start <gait>
<gait> ::= <hip>;<elbow>
@joint hip_hind
<hip> ::= int[0..20]*sin(int[1..3]*2*PI*t+float[0..3 step 0.5])
@joint elbow_fore
<elbow> ::= int[0..20]*sin(int[1..3]*2*PI*t+float[0..3 step 0.5])+int[0..20]
"""
#: The curves the curve-match backend scores against (``backend_settings.targets``).
CURVE_TARGETS = {"hip_hind": "7*sin(1*2*PI*t+1.5)", "elbow_fore": "3*sin(2*2*PI*t+0.5)+4"}
#: The targets as the body of a TOML table (``[backend_settings.targets]`` in a run file,
#: ``[settings.backend_settings.targets]`` in a study file).
CURVE_TARGETS_TOML = "".join(f'{joint} = "{curve}"\n' for joint, curve in CURVE_TARGETS.items())
#: A study of the problem (``g.gg``: CURVE_GRAMMAR): three runs of two arms; ``{generations}``
#: to fill in with ``str.format``.
CURVE_STUDY = (
    """\
title = "tiny"
runs = 3
seed = 7

[settings]
generations = {generations}
population = 12
elite = 1
init_max_depth = 6
backend = "curve-match"

[settings.backend_settings.targets]
"""
    + CURVE_TARGETS_TOML
    + """
[[arm]]
name = "plain"
grammar = "g.gg"

[[arm]]
name = "mutant"
grammar = "g.gg"
[arm.settings]
mutation = 0.2
"""
)


settings.register_profile("ci", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("ci")

#: What the session's private home keeps of the real one, as links: the tools' settings (where
#: their registries and mirrors are, who commits) and the package managers' download caches, so
#: that git, pip, npm and pre-commit in the tests work as they do for the user. Nothing of gaitgram's.
CARRIED_FROM_HOME = (
    *(".gitconfig", ".config/git", ".netrc"),
    *(".config/pip", ".pip", ".pypirc"),
    *(".npmrc", ".npm"),
)
CARRIED_FROM_CACHE = ("pip",)
_PRIVATE_HOME = pytest.StashKey[tuple[Path, dict[str, str | None]]]()


def pytest_configure(config: pytest.Config) -> None:
    """HOME and XDG_CACHE_HOME are a directory of this session's own (mode 0700) from before the
    tests are collected, for this process and every subprocess: the suite never writes into the
    user's cache (``~/.cache/gaitgram``, the parser cache) or home."""
    real_home = Path(os.path.expanduser("~"))
    real_cache = Path(os.environ.get("XDG_CACHE_HOME") or real_home / ".cache")
    home = Path(tempfile.mkdtemp(prefix="gaitgram-tests-home-"))  # 0700
    cache = home / ".cache"
    cache.mkdir(mode=0o700)
    carried = [(real_home, home, name) for name in CARRIED_FROM_HOME]
    for real, private, name in [*carried, *((real_cache, cache, name) for name in CARRIED_FROM_CACHE)]:
        if (real / name).exists():
            (private / name).parent.mkdir(mode=0o700, parents=True, exist_ok=True)
            (private / name).symlink_to(real / name)
    config.stash[_PRIVATE_HOME] = home, {name: os.environ.get(name) for name in ("HOME", "XDG_CACHE_HOME")}
    os.environ.update(HOME=str(home), XDG_CACHE_HOME=str(cache))


def pytest_unconfigure(config: pytest.Config) -> None:
    home, saved = config.stash[_PRIVATE_HOME]
    for name, value in saved.items():
        if value is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = value
    shutil.rmtree(home, ignore_errors=True)


#: What a test not marked slow may take, in seconds (its setup and call): on the CI machine, idle,
#: and what it takes here measured as that machine would see it (below). ``-o max_test_seconds=0``
#: turns the check off.
MAX_TEST_SECONDS = 20.0
_STARTED = pytest.StashKey[tuple[float, float]]()


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addini(
        "max_test_seconds",
        "a test not marked slow that takes longer (setup and call) fails; 0: no limit",
        default=str(MAX_TEST_SECONDS),
    )


def _clocks() -> tuple[float, float]:
    """Wall seconds, and the processor seconds of this process and of the subprocesses it has
    waited for."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.perf_counter(), time.process_time() + children.ru_utime + children.ru_stime


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item: pytest.Item) -> Iterator[None]:
    item.stash[_STARTED] = _clocks()
    yield


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Iterator[None]:
    """A test not marked slow that passed but took over ``max_test_seconds`` fails, saying so: the
    default run stays quick, and a slow test is marked (``.ci/run`` still runs it). What it took
    is the lesser of its wall time and its processor time (its own and that of the subprocesses
    it waited for): on an idle machine, the wall time of a test that computes; on a machine
    loaded by others, about what it would take on an idle one. A test that mostly waits (on a
    timer, or on a process it does not wait for) is charged only the processor time it spends.
    """
    outcome = yield
    report = outcome.get_result()
    limit = float(item.config.getini("max_test_seconds"))
    if call.when != "call" or not report.passed or not limit or item.get_closest_marker("slow"):
        return
    wall, processor = (now - then for now, then in zip(_clocks(), item.stash[_STARTED], strict=True))
    took = min(wall, processor)
    if took > limit:
        report.outcome = "failed"
        report.longrepr = (
            f"{item.nodeid} took {took:.1f} s (wall {wall:.1f} s, processors {processor:.1f} s), over the "
            f"{limit:g} s a test not marked slow may take: make it faster, or mark it "
            "@pytest.mark.slow (.ci/run still runs it)"
        )


def vector_grammars() -> list[Path]:
    found = sorted([*VECTORS.glob("*.bnf"), *VECTORS.glob("*.pybnf")])
    if not found:  # a missing oracle must fail loudly, never pass vacuously
        raise FileNotFoundError(f"no vector grammars in {VECTORS}")
    return found


@pytest.fixture(params=vector_grammars(), ids=lambda p: p.name)
def vector_grammar(request: pytest.FixtureRequest) -> Path:
    return request.param


@pytest.fixture
def sigint_guard() -> Iterator[None]:
    """While a test sends itself SIGINTs: one that no handler of gaitgram's catches fails the test
    where it lands (an AssertionError) instead of ending the test session."""

    def unhandled(signum: int, frame: object) -> None:
        raise AssertionError("a SIGINT reached no handler of gaitgram's")

    previous = signal.signal(signal.SIGINT, unhandled)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@pytest.fixture
def ctrl_c(monkeypatch: pytest.MonkeyPatch, sigint_guard: None) -> Callable[[int], None]:
    """``ctrl_c(n)``: a real SIGINT, as Ctrl-C sends, reaches this process once, while a curve-match
    run in it (an in-process ``gaitgram evolve``) scores generation ``n``."""
    from gaitgram.backends.curve_match import CurveMatch

    def arm(generation: int) -> None:
        real = CurveMatch.evaluate
        sent = False

        def evaluate(self: CurveMatch, batch: Any, **kwargs: Any) -> Any:
            nonlocal sent
            if not sent and kwargs.get("generation") == generation:
                sent = True
                signal.raise_signal(signal.SIGINT)
            return real(self, batch, **kwargs)

        monkeypatch.setattr(CurveMatch, "evaluate", evaluate)

    return arm


@pytest.fixture
def ctrl_c_when(sigint_guard: None) -> Iterator[Callable[[Callable[[], bool]], None]]:
    """``ctrl_c_when(condition)``: a real SIGINT reaches this process once ``condition()`` holds,
    polled from a thread until the test ends (for work done in other processes: a study's runs)."""
    done = threading.Event()
    watchers: list[threading.Thread] = []

    def watch(condition: Callable[[], bool]) -> None:
        while not done.wait(0.02):
            if condition():
                os.kill(os.getpid(), signal.SIGINT)
                return

    def arm(condition: Callable[[], bool]) -> None:
        watchers.append(threading.Thread(target=watch, args=(condition,), daemon=True))
        watchers[-1].start()

    try:
        yield arm
    finally:
        done.set()
        for watcher in watchers:
            watcher.join()
