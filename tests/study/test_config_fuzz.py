"""Fuzzing the configuration formats: a study file or a run.toml mangled any way either loads
or is refused with a :class:`StudyError`/:class:`ConfigError` (never another exception), and
where the message names a line and column, they are in the file."""

from __future__ import annotations

import re
import tempfile
from collections.abc import Callable
from pathlib import Path

from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from conftest import CURVE_GRAMMAR, CURVE_STUDY
from gaitgram.evolution.config import ConfigError, load_config
from gaitgram.study.spec import StudyError, load_study

BASE = CURVE_STUDY.format(generations=2)
RUN_TOML = """\
generations = 3
population = 12
elite = 1
mutation = 0.05
backend = "curve-match"

[backend_settings.targets]
hip_hind = "7*sin(1*2*PI*t+1.5)"

[[weight_schedule]]
start = 0
weights = { rms_hip_hind = 1.0 }
"""

KEYS = st.sampled_from(
    ["runs", "seed", "title", "name", "grammar", "config", "population", "elite", "generations",
     "mutation", "strategy", "backend", "settings", "arm", "weights", "start", "tournament",
     "backend_settings", "strategy_settings", "defines", "start_from", "hip_hind", "zzz"]
)  # fmt: skip
VALUES = st.recursive(
    st.one_of(
        st.integers(-(2**70), 2**70).map(str),
        st.floats(allow_nan=True).map(lambda x: {float("inf"): "inf", float("-inf"): "-inf"}.get(x, repr(x))),
        st.sampled_from(["nan", "true", "false", '""', '"g.gg"', '"ge"', '"../x"', '"\\u0000"']),
        st.sampled_from(["1979-05-27", "0.5", "1", "2", "12", '"nsga2"', '"curve-match"']),
        st.text(max_size=8).map(lambda s: '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'),
    ),
    lambda inner: st.one_of(
        st.lists(inner, max_size=3).map(lambda xs: "[" + ", ".join(xs) + "]"),
        st.lists(st.tuples(KEYS, inner), max_size=3).map(
            lambda kv: "{ " + ", ".join(f"{k} = {v}" for k, v in dict(kv).items()) + " }"
        ),
    ),
    max_leaves=6,
)


@st.composite
def mangled(draw: st.DrawFn, text: str) -> str:
    """``text`` with lines deleted, duplicated, re-valued, or new ``key = value`` lines and
    table headers inserted."""
    lines = text.splitlines()
    for _ in range(draw(st.integers(1, 4))):
        where = draw(st.integers(0, len(lines)))
        kind = draw(st.sampled_from(["delete", "duplicate", "revalue", "insert", "header"]))
        if kind == "delete" and where < len(lines):
            del lines[where]
        elif kind == "duplicate" and where < len(lines):
            lines.insert(where, lines[where])
        elif kind == "revalue" and where < len(lines) and "=" in lines[where]:
            lines[where] = lines[where].split("=", 1)[0] + "= " + draw(VALUES)
        elif kind == "insert":
            lines.insert(where, f"{draw(KEYS)} = {draw(VALUES)}")
        elif kind == "header":
            header = ".".join(draw(st.lists(KEYS, min_size=1, max_size=3)))
            lines.insert(where, f"[[{header}]]" if draw(st.booleans()) else f"[{header}]")
    return "\n".join(lines) + "\n"


def located_in(message: str, path: Path, text: str) -> None:
    """Every ``path:line:column`` the message names is a place in ``text``."""
    lines = text.splitlines()
    for line, column in re.findall(re.escape(str(path)) + r":(\d+):(\d+)", message):
        assert 1 <= int(line) <= len(lines), message
        assert 1 <= int(column) <= len(lines[int(line) - 1]) + 1, message


def refusal(load: Callable[[Path], object], path: Path) -> str | None:
    """The message ``load`` refuses ``path`` with (None: loaded); any other exception fails."""
    try:
        load(path)
    except (StudyError, ConfigError) as error:
        event("refused: " + ("not TOML" if "not valid TOML" in str(error) else "checked"))
        return str(error)
    event("loaded")
    return None


FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FUZZ
@given(mangled(BASE))
def test_a_mangled_study_file_loads_or_is_refused_with_its_place(text: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "s.toml"
        (Path(folder) / "g.gg").write_text(CURVE_GRAMMAR)
        path.write_text(text)
        message = refusal(load_study, path)
    if message is not None:
        assert message.strip()
        located_in(message, path, text)


@FUZZ
@given(mangled(RUN_TOML))
def test_a_mangled_run_toml_loads_or_is_refused_with_its_place(text: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "run.toml"
        path.write_text(text)
        message = refusal(load_config, path)
    if message is not None:
        assert message.strip()
        located_in(message, path, text)
