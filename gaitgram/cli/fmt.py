"""``gaitgram fmt``: rewrite grammars in the standard layout, safely."""

from __future__ import annotations

import difflib
import os
import tempfile
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

from gaitgram.cli.output import human, plural, print_source_error
from gaitgram.language.formatter import FormatError, FormatRefused, format_text
from gaitgram.language.source import SourceError, read_source


def command(
    files: Annotated[
        list[Path], typer.Argument(help="Grammar files to format in place.", show_default=False)
    ],
    check: Annotated[
        bool, typer.Option("--check", help="Change nothing; exit 1 if a file would change.")
    ] = False,
    diff: Annotated[bool, typer.Option("--diff", help="Change nothing; print a unified diff.")] = False,
) -> None:
    """Format grammars in place. Only layout changes; a file with syntax errors is left alone.

    Exit status: 0 done (or nothing to change), 1 with --check/--diff when a file would change or
    a file has syntax errors, 2 when a file cannot be read or written.
    """
    out = Console(highlight=False, soft_wrap=True, markup=False)
    err = Console(stderr=True, highlight=False, soft_wrap=True, markup=False)
    changed = refused = failed = 0
    for path in files:
        try:
            source = read_source(path)
            formatted = format_text(source)
        except SourceError as error:
            failed += 1
            print_source_error(err, error)
            continue
        except FormatRefused as refusal:
            refused += 1
            err.print(
                f"{path}: not formatted: {plural(len(refusal.diagnostics), 'syntax error')}", style="bold red"
            )
            for diagnostic in refusal.diagnostics:
                err.print(human(diagnostic, source))
            continue
        except FormatError as error:
            failed += 1
            err.print(f"error: {error}", style="bold red")
            continue
        original = path.read_text(encoding="utf-8-sig")
        if formatted == original:
            continue
        changed += 1
        if diff:
            lines = difflib.unified_diff(
                original.splitlines(keepends=True), formatted.splitlines(keepends=True), f"{path}", f"{path}"
            )
            out.out("".join(lines), end="")
        elif check:
            err.print(f"would reformat {path}")
        else:
            try:
                _write_atomically(path, formatted)
            except OSError as error:
                failed += 1
                err.print(f"error: {path}: cannot write: {error.strerror or error}", style="bold red")
                continue
            err.print(f"reformatted {path}")

    verb = "would be reformatted" if check or diff else "reformatted"
    err.print(
        f"{plural(changed, 'file')} {verb}, "
        f"{plural(len(files) - changed - refused - failed, 'file')} unchanged"
    )
    if failed:
        raise typer.Exit(2)
    if refused or ((check or diff) and changed):
        raise typer.Exit(1)


def _write_atomically(path: Path, text: str) -> None:
    """Write beside the file and rename over it, so a crash never leaves half a grammar."""
    mode = path.stat().st_mode
    fd, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
        os.chmod(temporary, mode)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
