"""lark's analysed parsers are kept between processes in the user's cache directory
(``gaitgram.language.parser.cache_file``): a damaged or stale file is rebuilt, never trusted, and
a missing or unwritable directory only means no cache."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from conftest import GRAMMARS

_CHECK = [sys.executable, "-m", "gaitgram", "check", str(GRAMMARS / "sine-walk.gg")]


def check_with_cache(cache_home: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "XDG_CACHE_HOME": str(cache_home)}
    return subprocess.run(_CHECK, capture_output=True, text=True, env=env, timeout=120, check=False)


def test_the_parsers_are_cached_and_a_damaged_cache_is_rebuilt(tmp_path: Path) -> None:
    first = check_with_cache(tmp_path)
    assert first.returncode == 0, first.stderr
    cached = sorted((tmp_path / "gaitgram").iterdir())
    assert [p.name.split("-")[0] for p in cached] == ["document", "range"]
    for path in cached:
        path.write_bytes(b"not a parser")  # damaged, or another lark's
    again = check_with_cache(tmp_path)
    assert (again.returncode, again.stdout, again.stderr) == (0, first.stdout, first.stderr)
    assert all(path.read_bytes() != b"not a parser" for path in cached)  # rebuilt and kept


def test_no_writable_cache_directory_means_no_cache(tmp_path: Path) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache directory would go")
    done = check_with_cache(blocked)
    assert done.returncode == 0, done.stderr
    assert "1 file OK" in done.stderr + done.stdout
