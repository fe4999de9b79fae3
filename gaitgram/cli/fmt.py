"""``gaitgram fmt``: rewrite grammars in the standard layout, safely."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from gaitgram.analysis.files import rewrite
from gaitgram.analysis.report import human, plural
from gaitgram.cli.common import err, print_error, print_source_error
from gaitgram.cli.stdout import write_bytes
from gaitgram.language.edits import unified_diff
from gaitgram.language.formatter import FormatError, FormatRefused, format_text
from gaitgram.language.source import SourceError, decode_source, encode_as_read, read_bytes


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
    changed = unchanged = refused = failed = 0
    for path in files:
        try:
            data = read_bytes(path)
            source = decode_source(data, str(path))
            formatted = format_text(source)
        except SourceError as error:
            failed += 1
            print_source_error(error)
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
            print_error(str(error))
            continue
        # The formatter reads and writes universal newlines; the file keeps its own line breaks
        # and byte order mark, so a CRLF file stays CRLF and the diff shows only the layout.
        written = encode_as_read(data, formatted)
        if written == data:
            unchanged += 1
            continue
        if diff:
            write_bytes(unified_diff(str(path), data, written))
        elif check:
            err.print(f"would reformat {path}")
        elif (not_written := rewrite(path, written)) is not None:
            failed += 1
            print_error(not_written)
            continue
        else:
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
