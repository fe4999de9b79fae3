"""The grammar files of a workspace, read once each and again only when they change on disk:
for workspace-wide searches such as workspace symbols."""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from pathlib import Path

from gaitgram.analysis import CheckResult, check
from gaitgram.language import parse
from gaitgram.language.source import SourceError, read_source

__all__ = ["GRAMMAR_SUFFIXES", "MAX_WORKSPACE_FILES", "WorkspaceGrammars", "grammar_files"]

GRAMMAR_SUFFIXES = (".gg", ".bnf", ".pybnf")
_SKIP_DIRECTORIES = {".git", ".hg", ".venv", "venv", "node_modules", "__pycache__", ".tox", "build", "dist"}
#: A workspace is searched for at most this many grammar files.
MAX_WORKSPACE_FILES = 2_000


def grammar_files(roots: Iterable[str | Path], limit: int = MAX_WORKSPACE_FILES) -> Iterator[Path]:
    """Grammar files under ``roots`` (at most ``limit``), skipping version control, virtual
    environments and build output."""
    seen = 0
    for root in roots:
        for directory, subdirectories, files in os.walk(root):
            subdirectories[:] = sorted(d for d in subdirectories if d not in _SKIP_DIRECTORIES)
            for name in sorted(files):
                if name.endswith(GRAMMAR_SUFFIXES):
                    seen += 1
                    if seen > limit:
                        return
                    yield Path(directory, name)


class WorkspaceGrammars:
    """Checked grammars of files, cached by modification time and size."""

    def __init__(self) -> None:
        self._cache: dict[Path, tuple[tuple[float, int], CheckResult]] = {}

    def get(self, path: Path) -> CheckResult | None:
        """The file's checked grammar; None if it cannot be read."""
        try:
            stat = path.stat()
        except OSError:
            return None
        key = (stat.st_mtime, stat.st_size)
        cached = self._cache.get(path)
        if cached is not None and cached[0] == key:
            return cached[1]
        try:
            result = check(parse(read_source(path)))
        except SourceError:
            return None
        self._cache[path] = (key, result)
        return result
