"""``gaitgram check``: parse and lint grammars, report like a compiler, and apply fixes."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from gaitgram.analysis.files import CheckOptions, FileCheck, Tally, check_files
from gaitgram.analysis.report import CheckedFile, human, json_report, plural
from gaitgram.cli.common import err, print_error, print_source_error
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.cli.stdout import write_bytes, write_text
from gaitgram.cli.terminal import Terminal
from gaitgram.language.source import SourceError


class OutputFormat(StrEnum):
    HUMAN = "human"
    JSON = "json"
    SARIF = "sarif"


def command(
    files: Annotated[
        list[Path], typer.Argument(help="Grammar files (.gg, .bnf, .pybnf).", show_default=False)
    ],
    output_format: Annotated[
        OutputFormat,
        typer.Option("--format", "-f", help="human for people, json for tools, sarif for code scanning."),
    ] = OutputFormat.HUMAN,
    strict: Annotated[bool, typer.Option("--strict", help="Treat warnings as errors.")] = False,
    fix: Annotated[
        bool, typer.Option("--fix", help="Apply the safe fixes to the files, then report what remains.")
    ] = False,
    unsafe_fixes: Annotated[
        bool,
        typer.Option(
            "--unsafe-fixes",
            help="With --fix or --diff, also apply the preferred fix of problems that have no safe one.",
        ),
    ] = False,
    diff: Annotated[
        bool, typer.Option("--diff", help="Change nothing; print the fixes --fix would make as a diff.")
    ] = False,
    defines: Defines = None,
) -> None:
    """Check grammars for syntax errors, undefined, unproductive and unreachable rules, bad ranges and joints.

    Exit status: 0 no errors, 1 errors found, 2 a file could not be read or written, or the command
    line is wrong. With --diff: 0 nothing to fix, 1 a file would change, 2 as above.
    """
    options = CheckOptions(parse_defines(defines), strict, fix, unsafe_fixes, diff)
    if unsafe_fixes and not options.fixing:
        raise typer.BadParameter("--unsafe-fixes needs --fix or --diff", param_hint="--unsafe-fixes")
    if diff and output_format is not OutputFormat.HUMAN:
        raise typer.BadParameter(f"--diff prints a diff, not {output_format.value}", param_hint="--format")
    out = Terminal()
    tally = Tally(options)
    checked: list[CheckedFile] = []
    unreadable: list[SourceError] = []
    in_order: list[CheckedFile | SourceError] = []  # what JSON lists, the files as given
    for found in check_files(files, options):
        tally.add(found)
        _show(found, out, output_format, strict)
        if found.unreadable is not None:
            unreadable.append(found.unreadable)
            in_order.append(found.unreadable)
        elif found.checked is not None and output_format is not OutputFormat.HUMAN:
            checked.append(found.checked)
            in_order.append(found.checked)
    if output_format is OutputFormat.JSON:
        write_text(json_report(in_order, strict=strict) + "\n")
    elif output_format is OutputFormat.SARIF:
        from gaitgram.analysis.sarif import sarif_report  # urllib and the code catalogue: only here

        write_text(sarif_report(checked, unreadable, strict=strict) + "\n")
    if output_format is OutputFormat.HUMAN or options.fixing:
        err.print(tally.summary(), style="bold red" if tally.failing else "bold green")
    raise typer.Exit(tally.status)


def _show(found: FileCheck, out: Terminal, output_format: OutputFormat, strict: bool) -> None:
    """What happened to one file: why it could not be read or written, its fixes or their diff,
    and, for people, its problems."""
    if found.unreadable is not None:
        print_source_error(found.unreadable)
        return
    outcome = found.outcome
    if outcome is not None and not outcome.converged:
        err.print(
            f"warning: {found.path}: the fixes did not settle after {plural(outcome.passes, 'round')}, "
            "each making more to fix; run the command again for the rest",
            style="bold yellow",
        )
    if found.diff is not None:
        write_bytes(found.diff)
    if found.not_written is not None:
        print_error(found.not_written)
    if found.result is not None:  # fixed, not diffed
        for applied in found.applied:
            where = f"{found.path}:{applied.location.line}:{applied.location.column}"
            err.print(f"fixed {where}: {applied.code.code} {applied.title}")
    if found.result is not None and output_format is OutputFormat.HUMAN:
        for diagnostic in found.result.diagnostics:
            out.print(human(diagnostic, found.result.grammar.source, strict=strict))
