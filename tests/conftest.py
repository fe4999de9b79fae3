"""Shared fixtures: where the shared test vectors live, and the bundled grammars."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

ROOT = Path(__file__).resolve().parents[1]
#: A copy of ../shared/vectors/ponyge2 (see its README): CI clones only this repository.
VECTORS = ROOT / "tests" / "data" / "ponyge2"
GRAMMARS = ROOT / "grammars"

#: The vectors' GE_RANGE values (vectors/ponyge2/meta.json).
VECTOR_DEFINES = {"dataset_n_vars": 5, "dataset_n_is": 5, "dataset_n_os": 5}

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
