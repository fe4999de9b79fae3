"""``gaitgram fmt``: rewrite grammars in the standard layout, safely."""

from __future__ import annotations

import difflib
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

from gaitgram.cli.output import human, plural, print_source_error
from gaitgram.fileio import OutputError, check_rewritable, write_output
from gaitgram.language.formatter import FormatError, FormatRefused, format_text
from gaitgram.language.source import SourceError, describe_os_error, read_source


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
    changed = unchanged = refused = failed = 0
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
        original = source.text  # as read: BOM dropped, newlines universal, like the formatter's input
        if formatted == original:
            unchanged += 1
            continue
        if diff:
            lines = difflib.unified_diff(
                original.splitlines(keepends=True), formatted.splitlines(keepends=True), f"{path}", f"{path}"
            )
            out.out("".join(lines), end="")
        elif check:
            err.print(f"would reformat {path}")
        else:
            try:
                check_rewritable(path)  # a regular file, not read-only
                write_output(path, formatted)
            except OutputError as error:
                failed += 1
                err.print(f"error: {error}", style="bold red")
                continue
            except OSError as error:
                failed += 1
                err.print(f"error: cannot write {path}: {describe_os_error(error)}", style="bold red")
                continue
            err.print(f"reformatted {path}")
        changed += 1

    err.print(_summary(changed, unchanged, refused, failed, dry_run=check or diff))
    if failed:
        raise typer.Exit(2)
    if refused or ((check or diff) and changed):
        raise typer.Exit(1)


def _summary(changed: int, unchanged: int, refused: int, failed: int, *, dry_run: bool) -> str:
    """``2 files reformatted, 1 file unchanged, 1 file with syntax errors, 1 file failed``: every
    file counted once, in the one group it ended in."""
    parts = [
        f"{plural(changed, 'file')} {'would be reformatted' if dry_run else 'reformatted'}",
        f"{plural(unchanged, 'file')} unchanged",
    ]
    if refused:
        parts.append(f"{plural(refused, 'file')} with syntax errors")
    if failed:
        parts.append(f"{plural(failed, 'file')} failed")
    return ", ".join(parts)
