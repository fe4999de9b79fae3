"""Shared fixtures: where the shared test vectors live, the bundled grammars, and the tiny
curve-match problem the evolution, strategy and study tests run."""

from __future__ import annotations

import signal
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


settings.register_profile("ci", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("ci")


def vector_grammars() -> list[Path]:
    found = sorted([*VECTORS.glob("*.bnf"), *VECTORS.glob("*.pybnf")])
    if not found:  # a missing oracle must fail loudly, never pass vacuously
        raise FileNotFoundError(f"no vector grammars in {VECTORS}")
    return found


@pytest.fixture(params=vector_grammars(), ids=lambda p: p.name)
def vector_grammar(request: pytest.FixtureRequest) -> Path:
    return request.param


@pytest.fixture
def ctrl_c(monkeypatch: pytest.MonkeyPatch) -> Iterator[Callable[[int], None]]:
    """``ctrl_c(n)``: a real SIGINT, as Ctrl-C sends, reaches this process once, while a curve-match
    run in it (an in-process ``gaitgram evolve``) scores generation ``n``. Meanwhile a SIGINT that
    no handler of gaitgram's catches fails the test where it lands instead of ending the session."""
    from gaitgram.backends.curve_match import CurveMatch

    def unhandled(signum: int, frame: object) -> None:
        raise AssertionError("a SIGINT reached no handler of gaitgram's")

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

    previous = signal.signal(signal.SIGINT, unhandled)
    try:
        yield arm
    finally:
        signal.signal(signal.SIGINT, previous)
