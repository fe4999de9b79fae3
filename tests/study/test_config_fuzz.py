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
from gaitgram.configuration import ConfigError, load_config
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


NAMES = st.text(alphabet="abcdefghij_-#.= \"'[]", min_size=1, max_size=6).filter(lambda k: k.strip() == k)
SCALARS = st.one_of(
    st.integers(-5, 5),
    st.booleans(),
    st.text(alphabet='ab=#[]"\n', max_size=6),  # strings holding what looks like TOML
)


@st.composite
def documents(draw: st.DrawFn) -> tuple[str, dict[tuple[str, ...], int]]:
    """A TOML document written as a run.toml is (top-level keys, then [tables], values of every
    kind including strings that look like keys and headers, and multi-line arrays), and the line
    each key path is written on."""
    from gaitgram.configuration import _key, _toml_value

    lines: list[str] = []
    where: dict[tuple[str, ...], int] = {}

    def write(path: tuple[str, ...], value: object) -> None:
        if draw(st.booleans()) and isinstance(value, list):  # an array over several lines
            lines.append(f"{_key(path[-1])} = [")
            lines.extend(f"  {_toml_value(v)}," for v in value)
            lines.append("]")
            where[path] = len(lines) - len(value) - 1
        else:
            lines.append(f"{_key(path[-1])} = {_toml_value(value)}")
            where[path] = len(lines)

    values = st.one_of(SCALARS, st.lists(SCALARS, max_size=3))
    for name, value in draw(st.dictionaries(NAMES, values, max_size=3)).items():
        write((name,), value)
    for table, keys in draw(
        st.dictionaries(NAMES, st.dictionaries(NAMES, values, max_size=3), max_size=3)
    ).items():
        if (table,) in where:
            continue
        lines.append(f"[{_key(table)}]")
        where[(table,)] = len(lines)
        for name, value in keys.items():
            write((table, name), value)
    return "\n".join(lines) + "\n", where


@FUZZ
@given(documents())
def test_every_key_is_placed_on_the_line_that_writes_it(
    document: tuple[str, dict[tuple[str, ...], int]],
) -> None:
    """key_location on documents gaitgram's own TOML writer makes: whatever the keys and values
    hold (quotes, '#', '=', brackets, new lines in strings), each key is found on its line."""
    import tomllib

    from gaitgram.tomlplaces import key_location

    text, where = document
    parsed = tomllib.loads(text)  # the document is TOML, and says what was written
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "run.toml"
        path.write_text(text)
        for keys, line in where.items():
            if any("." in key for key in keys):
                continue  # dotted names are how a place is asked for; a key holding a dot is not asked
            table = parsed
            for key in keys:
                table = table[key]
            assert key_location(path, "", ".".join(keys)) == f"{path}:{line}:1", (keys, text)
