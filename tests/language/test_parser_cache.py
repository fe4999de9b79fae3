"""lark's analysed parsers are kept between processes in the user's cache directory
(``gaitgram.language.parser_cache``): a damaged or stale file is rebuilt, never trusted; a file is
read only from a directory of the user's that no one else can write, never through a symbolic
link, and written only through a new file renamed into place; where that cannot be had there is no
cache and one line on stderr says why.

Every test runs ``gaitgram check`` as a user does, in a process of its own, with the environment
the case needs. "Another user" is a real one where the tests run as root (the planted directory is
given to another uid); elsewhere the command runs as if its user were another (``os.geteuid``
answers another uid), which is the same to the cache: a directory that is not the user's.
"""

from __future__ import annotations

import json
import os
import pickle
import stat
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from conftest import GRAMMARS, vector_grammars
from gaitgram.language.parser_cache import _decode, _encode

#: Small, with a range, so that both of gaitgram's parsers (the document's and the ranges') are built.
SMALL = "@start <gait>\n<gait> ::= float[0..1 step 0.5]*sin(2*PI*t)\n"
OTHER_UID = OTHER_GID = 4242
#: ``gaitgram ARGS`` as if run by another user: the cache's directories are then not this user's.
_AS_ANOTHER_USER = (
    "import os, sys\n"
    "uid = os.geteuid() + 1\n"
    "os.geteuid = lambda: uid\n"
    "from gaitgram.cli import main\n"
    "sys.argv = ['gaitgram', *sys.argv[1:]]\n"
    "main()\n"
)
WARNING = "warning: gaitgram keeps no parser cache"


class _Planted:
    """A pickle whose unpickling makes the directory ``marker``: proof that it ran."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self) -> tuple[Any, ...]:
        return os.mkdir, (str(self.marker),)


@pytest.fixture
def grammar(tmp_path: Path) -> Path:
    path = tmp_path / "small.gg"
    path.write_text(SMALL)
    return path


def check(
    *arguments: str | Path,
    as_another_user: bool = False,
    cwd: Path | None = None,
    umask: int = -1,
    **env: str | None,
) -> subprocess.CompletedProcess[str]:
    """``gaitgram check ARGUMENTS`` with ``env`` over this process's environment (``None`` unsets)."""
    environment = {k: v for k, v in os.environ.items() if k != "GAITGRAM_NO_CACHE"}
    for name, value in env.items():
        environment.pop(name, None)
        if value is not None:
            environment[name] = value
    command = ["-c", _AS_ANOTHER_USER] if as_another_user else ["-m", "gaitgram"]
    return subprocess.run(
        [sys.executable, *command, "check", *map(str, arguments)],
        capture_output=True,
        text=True,
        env=environment,
        cwd=cwd,
        umask=umask,
        timeout=120,
        check=False,
    )


def private(path: Path) -> Path:
    path.mkdir(mode=0o700, parents=True)
    return path


@pytest.fixture
def clean(grammar: Path, tmp_path: Path) -> tuple[subprocess.CompletedProcess[str], dict[str, bytes]]:
    """What ``check`` prints with a cache of the user's own, and the cache files it writes."""
    cache_home = private(tmp_path / "clean-cache")
    done = check(grammar, XDG_CACHE_HOME=str(cache_home))
    assert done.returncode == 0, done.stderr
    assert WARNING not in done.stderr
    files = {p.name: p.read_bytes() for p in (cache_home / "gaitgram").iterdir()}
    assert sorted(name.split("-")[0] for name in files) == ["document", "range"]
    return done, files


def tampered(cache: bytes) -> bytes:
    """A cache file as gaitgram writes it, first line and all, whose parser finds no rule heads: a
    file that changes what ``check`` says when it is loaded."""
    key, body = cache.split(b"\n", 1)
    data = json.loads(body)
    found = []

    def walk(value: Any) -> None:
        if isinstance(value, dict):
            if value.get("name") == "RULE_HEAD" and "pattern" in value:
                found.append(value)
            for item in value.values():
                walk(item)
        elif isinstance(value, list):
            for item in value:
                walk(item)

    walk(data)
    assert found, "no RULE_HEAD terminal in the document parser's cache"
    for terminal in found:
        terminal["pattern"]["value"] = "(?!)"
    return key + b"\n" + json.dumps(data).encode()


def planted_pickle(marker: Path) -> bytes:
    """A digest-like first line and a pickle, as lark's own cache file is laid out."""
    return b"0" * 64 + b"\n" + pickle.dumps(_Planted(marker))


def same_as_clean(done: subprocess.CompletedProcess[str], clean: subprocess.CompletedProcess[str]) -> None:
    """``done`` printed what the clean run did, but for exactly one warning line."""
    assert done.returncode == 0, done.stderr
    assert done.stdout == clean.stdout
    lines = done.stderr.splitlines()
    assert [line for line in lines if not line.startswith(WARNING)] == clean.stderr.splitlines()
    assert len(lines) - len(clean.stderr.splitlines()) == 1, done.stderr


def test_the_parsers_are_cached_and_a_damaged_cache_is_rebuilt(tmp_path: Path, grammar: Path) -> None:
    first = check(grammar, XDG_CACHE_HOME=str(tmp_path))
    assert first.returncode == 0, first.stderr
    cached = sorted((tmp_path / "gaitgram").iterdir())
    assert [p.name.split("-")[0] for p in cached] == ["document", "range"]
    for path in cached:
        path.write_bytes(b"not a parser")  # damaged, or another lark's
    again = check(grammar, XDG_CACHE_HOME=str(tmp_path))
    assert (again.returncode, again.stdout, again.stderr) == (0, first.stdout, first.stderr)
    assert all(path.read_bytes() != b"not a parser" for path in cached)  # rebuilt and kept


def test_a_parser_read_from_the_cache_checks_as_a_built_one_does(tmp_path: Path) -> None:
    broken = tmp_path / "broken.gg"
    broken.write_text('@start <a>\n<a> ::= <b> | float[1..0 step 0] | "unclosed\n<a> ::=\n@joint\n')
    files = [*sorted(map(str, GRAMMARS.glob("*.gg"))), *map(str, vector_grammars()), str(broken)]
    cache_home = private(tmp_path / "cache")
    cache = cache_home / "gaitgram"
    built = check("--format", "json", *files, GAITGRAM_NO_CACHE="1")
    check("--format", "json", *files, XDG_CACHE_HOME=str(cache_home))  # writes the cache
    written = {p.name: p.stat().st_ino for p in cache.iterdir()}
    loaded = check("--format", "json", *files, XDG_CACHE_HOME=str(cache_home))
    assert {p.name: p.stat().st_ino for p in cache.iterdir()} == written  # read, not rebuilt
    assert len(written) == 2
    assert (loaded.returncode, loaded.stdout, loaded.stderr) == (built.returncode, built.stdout, built.stderr)
    assert '"GG' in built.stdout  # the broken grammar's diagnostics are among what is compared


def test_the_cache_is_loaded_from_the_users_own_directory(
    tmp_path: Path, grammar: Path, clean: tuple[subprocess.CompletedProcess[str], dict[str, bytes]]
) -> None:
    # The control for the refusals below: the tampered file they plant changes what check says
    # once it is trusted, so their unchanged output is the refusal's doing.
    done, files = clean
    cache_home = private(tmp_path / "own")
    private(cache_home / "gaitgram")
    for name, data in files.items():
        (cache_home / "gaitgram" / name).write_bytes(tampered(data) if name.startswith("document") else data)
    fooled = check(grammar, XDG_CACHE_HOME=str(cache_home))
    assert fooled.stdout + fooled.stderr != done.stdout + done.stderr
    assert "GG201" in fooled.stdout + fooled.stderr  # `@start <gait>`: no rule <gait> was found


def test_no_writable_cache_directory_means_no_cache(tmp_path: Path, grammar: Path) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache directory would go")
    done = check(grammar, XDG_CACHE_HOME=str(blocked))
    assert done.returncode == 0, done.stderr
    assert "1 file OK" in done.stderr + done.stdout
    assert [line for line in done.stderr.splitlines() if line.startswith(WARNING)] == [
        f"{WARNING}: {blocked} is not a directory; set XDG_CACHE_HOME to a directory of your own "
        "(GAITGRAM_NO_CACHE=1 keeps no cache and says nothing)"
    ]


def test_the_files_are_the_users_alone_whatever_the_umask(tmp_path: Path, grammar: Path) -> None:
    done = check(grammar, umask=0, XDG_CACHE_HOME=str(tmp_path / "cache"))
    assert done.returncode == 0, done.stderr
    directory = tmp_path / "cache" / "gaitgram"
    assert stat.S_IMODE(directory.stat().st_mode) == 0o700
    assert stat.S_IMODE((tmp_path / "cache").stat().st_mode) == 0o700  # made by gaitgram too
    files = list(directory.iterdir())
    assert len(files) == 2
    assert {stat.S_IMODE(p.stat().st_mode) for p in files} == {0o600}


def plant(files: dict[str, bytes], marker: Path) -> Iterator[dict[str, bytes]]:
    """What to put at the cache's file names in turn: a pickle that would make ``marker`` (lark's
    own cache unpickles before it compares the digest), then a genuine cache file that fools check
    (in the cache's own format: its refusal is no matter of format)."""
    yield {name: planted_pickle(marker) for name in files}
    yield {name: tampered(data) if name.startswith("document") else data for name, data in files.items()}


def test_a_cache_planted_in_another_users_directory_is_never_loaded(
    tmp_path: Path, grammar: Path, clean: tuple[subprocess.CompletedProcess[str], dict[str, bytes]]
) -> None:
    done, files = clean
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)  # a directory everyone may write in, as /tmp is
    hostile = shared / "gaitgram"
    hostile.mkdir()
    hostile.chmod(0o755)
    marker = tmp_path / "the planted pickle ran"
    another = os.geteuid() != 0  # as root, the directory really is another user's
    for planted in plant(files, marker):
        for name, data in planted.items():
            (hostile / name).write_bytes(data)
        if not another:
            for path in [hostile, *hostile.iterdir()]:
                os.chown(path, OTHER_UID, OTHER_GID)
        refused = check(grammar, as_another_user=another, XDG_CACHE_HOME=str(shared))
        assert not marker.exists()
        same_as_clean(refused, done)
        assert f"{hostile} belongs to " in refused.stderr
        assert {p.name: p.read_bytes() for p in hostile.iterdir()} == planted  # nothing written


@pytest.mark.parametrize("mode", [0o770, 0o707, 0o777], ids=["group", "others", "both"])
def test_a_directory_others_can_write_is_never_loaded_though_it_is_the_users(
    tmp_path: Path, grammar: Path, clean: tuple[subprocess.CompletedProcess[str], dict[str, bytes]], mode: int
) -> None:
    done, files = clean
    cache_home = private(tmp_path / "cache")
    directory = cache_home / "gaitgram"
    directory.mkdir()
    directory.chmod(mode)
    marker = tmp_path / "the planted pickle ran"
    for planted in plant(files, marker):
        for name, data in planted.items():
            (directory / name).write_bytes(data)
        refused = check(grammar, XDG_CACHE_HOME=str(cache_home))
        assert not marker.exists()
        same_as_clean(refused, done)
        assert f"{directory} can be written by others (mode {mode:04o})" in refused.stderr
        assert {p.name: p.read_bytes() for p in directory.iterdir()} == planted


def test_a_symbolic_link_at_a_cache_file_is_neither_read_nor_written_through(
    tmp_path: Path, grammar: Path, clean: tuple[subprocess.CompletedProcess[str], dict[str, bytes]]
) -> None:
    done, files = clean
    cache_home = private(tmp_path / "cache")
    directory = private(cache_home / "gaitgram")
    elsewhere = private(tmp_path / "elsewhere")
    marker = tmp_path / "the planted pickle ran"
    for planted in plant(files, marker):
        for name, data in planted.items():
            target = elsewhere / name  # a file of the user's, 0600
            target.write_bytes(data)
            target.chmod(0o600)
            (directory / name).unlink(missing_ok=True)
            (directory / name).symlink_to(target)
        again = check(grammar, XDG_CACHE_HOME=str(cache_home))
        assert not marker.exists()
        assert (again.returncode, again.stdout, again.stderr) == (0, done.stdout, done.stderr)
        assert {p.name: p.read_bytes() for p in elsewhere.iterdir()} == planted  # not written through
        for name in files:  # the links were replaced by the cache's own files
            assert (directory / name).is_file()
            assert not (directory / name).is_symlink()


def test_a_symbolic_link_for_the_cache_directory_is_refused(
    tmp_path: Path, grammar: Path, clean: tuple[subprocess.CompletedProcess[str], dict[str, bytes]]
) -> None:
    done, files = clean
    cache_home = private(tmp_path / "cache")
    elsewhere = private(tmp_path / "elsewhere")
    (cache_home / "gaitgram").symlink_to(elsewhere)
    marker = tmp_path / "the planted pickle ran"
    for planted in plant(files, marker):
        for name, data in planted.items():
            (elsewhere / name).write_bytes(data)
        refused = check(grammar, XDG_CACHE_HOME=str(cache_home))
        assert not marker.exists()
        same_as_clean(refused, done)
        assert f"{cache_home / 'gaitgram'} is a symbolic link" in refused.stderr
        assert {p.name: p.read_bytes() for p in elsewhere.iterdir()} == planted


def test_a_relative_xdg_cache_home_is_ignored(tmp_path: Path, grammar: Path) -> None:
    home = private(tmp_path / "home")
    work = private(tmp_path / "work")
    done = check(grammar, cwd=work, HOME=str(home), XDG_CACHE_HOME="relative/cache")
    assert done.returncode == 0, done.stderr
    assert WARNING not in done.stderr
    assert list(work.iterdir()) == []  # the XDG specification: a relative path is to be ignored
    assert len(list((home / ".cache" / "gaitgram").iterdir())) == 2  # the default, ~/.cache, instead


def test_a_home_that_does_not_exist_is_not_made_and_said_once(tmp_path: Path, grammar: Path) -> None:
    missing = tmp_path / "no-such-home"
    done = check(grammar, HOME=str(missing), XDG_CACHE_HOME=None)
    assert done.returncode == 0, done.stderr
    assert not missing.exists()
    warnings = [line for line in done.stderr.splitlines() if line.startswith(WARNING)]
    assert warnings == [  # once, though two parsers were built
        f"{WARNING}: {missing} does not exist; set XDG_CACHE_HOME to a directory of your own "
        "(GAITGRAM_NO_CACHE=1 keeps no cache and says nothing)"
    ]


def test_gaitgram_no_cache_keeps_none_and_says_nothing(tmp_path: Path, grammar: Path) -> None:
    cache_home = private(tmp_path / "cache")
    done = check(grammar, XDG_CACHE_HOME=str(cache_home), GAITGRAM_NO_CACHE="1")
    assert done.returncode == 0, done.stderr
    assert list(cache_home.iterdir()) == []
    missing = tmp_path / "no-such-home"
    done = check(grammar, HOME=str(missing), XDG_CACHE_HOME=None, GAITGRAM_NO_CACHE="1")
    assert (done.returncode, WARNING in done.stderr, missing.exists()) == (0, False, False)


def test_the_test_suite_keeps_its_cache_and_home_apart_from_the_users(grammar: Path) -> None:
    import pwd

    cache_home, home = Path(os.environ["XDG_CACHE_HOME"]), Path(os.environ["HOME"])
    real_home = Path(pwd.getpwuid(os.geteuid()).pw_dir)
    assert home != real_home
    assert cache_home.is_relative_to(home)
    assert stat.S_IMODE(home.stat().st_mode) == 0o700
    assert check(grammar).returncode == 0  # as every test's subprocess runs, with the session's environment
    assert len(list((cache_home / "gaitgram").iterdir())) == 2


_KEYS = st.one_of(st.text(max_size=3), st.integers(), st.sampled_from(["(", "{", "<"]))
_VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.text(max_size=5)),
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.lists(inner, max_size=4).map(tuple),
        st.dictionaries(_KEYS, inner, max_size=4),
    ),
    max_leaves=20,
)


def _exactly(value: Any) -> Any:
    """``value`` with each container's type spelt out, so that a tuple never equals a list."""
    if isinstance(value, dict):
        return ("dict", [(_exactly(k), _exactly(v)) for k, v in value.items()])
    if isinstance(value, (list, tuple)):
        return (type(value).__name__, [_exactly(v) for v in value])
    return (type(value).__name__, value)


@given(_VALUES)
def test_the_cache_format_reads_back_exactly_what_was_written(value: Any) -> None:
    # JSON has no tuples and only string keys; lark's parse tables hold both.
    text = json.dumps(_encode(value, {}))
    assert _exactly(json.loads(text, object_hook=lambda obj: _decode(obj, {}))) == _exactly(value)
