"""``gaitgram check``: parse and lint grammars, report like a compiler."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

from gaitgram import jsonio
from gaitgram.analysis import check
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.cli.output import as_json, effective_severity, human, plural, print_source_error
from gaitgram.diagnostics import Severity
from gaitgram.language import SourceError, parse
from gaitgram.language.source import read_source


class OutputFormat(StrEnum):
    HUMAN = "human"
    JSON = "json"


def command(
    files: Annotated[
        list[Path], typer.Argument(help="Grammar files (.gg, .bnf, .pybnf).", show_default=False)
    ],
    output_format: Annotated[
        OutputFormat, typer.Option("--format", "-f", help="human for people, json for tools.")
    ] = OutputFormat.HUMAN,
    strict: Annotated[bool, typer.Option("--strict", help="Treat warnings as errors.")] = False,
    defines: Defines = None,
) -> None:
    """Check grammars for syntax errors, undefined, unproductive and unreachable rules, bad ranges and joints.

    Exit status: 0 no errors, 1 errors found, 2 a file could not be read or the command line is wrong.
    """
    values = parse_defines(defines)
    out = Console(highlight=False, soft_wrap=True, markup=False)
    err = Console(stderr=True, highlight=False, soft_wrap=True, markup=False)
    counts = dict.fromkeys(Severity, 0)
    records: list[dict[str, object]] = []
    unreadable = 0
    for path in files:
        try:
            source = read_source(path)
        except SourceError as error:
            unreadable += 1
            print_source_error(err, error)
            continue
        result = check(parse(source, defines=values))
        for diagnostic in result.diagnostics:
            counts[effective_severity(diagnostic, strict=strict)] += 1
            if output_format is OutputFormat.JSON:
                records.append(as_json(diagnostic, source, strict=strict))
            else:
                out.print(human(diagnostic, source, strict=strict))

    if output_format is OutputFormat.JSON:
        out.out(jsonio.dumps(records, indent=2))
    else:
        err.print(_summary(counts, len(files) - unreadable, unreadable), style=_style(counts, unreadable))
    if unreadable:
        raise typer.Exit(2)
    if counts[Severity.ERROR]:
        raise typer.Exit(1)


def _summary(counts: dict[Severity, int], checked: int, unreadable: int) -> str:
    """``1 error, 2 warnings in 3 files; 1 file could not be read``, or ``3 files OK``."""
    found = [plural(counts[s], s.value) for s in Severity if counts[s]]
    parts = []
    if found:
        parts.append(f"{', '.join(found)} in {plural(checked, 'file')}")
    elif checked:
        parts.append(f"{plural(checked, 'file')} OK")
    if unreadable:
        parts.append(f"{plural(unreadable, 'file')} could not be read")
    return "; ".join(parts)


def _style(counts: dict[Severity, int], unreadable: int) -> str:
    return "bold red" if counts[Severity.ERROR] or unreadable else "bold green"
