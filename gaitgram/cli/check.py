"""``gaitgram check``: parse and lint grammars, report like a compiler, and apply fixes."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

from gaitgram import jsonio
from gaitgram.analysis import CheckResult, check
from gaitgram.analysis.fixes import fix_source
from gaitgram.cli.options import Defines, parse_defines
from gaitgram.cli.output import as_json, effective_severity, human, plural, print_source_error, unified_diff
from gaitgram.cli.sarif import CheckedFile, sarif_log
from gaitgram.cli.stdout import write_bytes
from gaitgram.diagnostics import Severity
from gaitgram.fileio import OutputError, check_rewritable, write_output
from gaitgram.language import SourceError, parse
from gaitgram.language.source import decode_source, describe_os_error, encode_as_read, read_bytes


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
    values = parse_defines(defines)
    out = Console(highlight=False, soft_wrap=True, markup=False)
    err = Console(stderr=True, highlight=False, soft_wrap=True, markup=False)
    if unsafe_fixes and not (fix or diff):
        raise typer.BadParameter("--unsafe-fixes needs --fix or --diff", param_hint="--unsafe-fixes")
    if diff and output_format is not OutputFormat.HUMAN:
        raise typer.BadParameter(f"--diff prints a diff, not {output_format.value}", param_hint="--format")
    fixing = fix or diff
    counts = dict.fromkeys(Severity, 0)
    records: list[dict[str, object]] = []
    checked: list[CheckedFile] = []
    unreadable: list[SourceError] = []
    failed = fixed_files = fixed_problems = unsafe_left = 0
    for path in files:
        try:
            data = read_bytes(path)
            source = decode_source(data, str(path))
        except SourceError as error:
            unreadable.append(error)
            print_source_error(err, error)
            continue
        if fixing:
            outcome = fix_source(source, defines=values, unsafe=unsafe_fixes)
            result = outcome.result
            unsafe_left += outcome.unsafe_available
            written = True
            if not outcome.converged:
                err.print(
                    f"warning: {path}: the fixes did not settle after {plural(outcome.passes, 'round')}, "
                    "each making more to fix; run the command again for the rest",
                    style="bold yellow",
                )
            if outcome.changed:
                fixed = encode_as_read(data, outcome.text)
                if diff:
                    write_bytes(unified_diff(str(path), data, fixed))
                elif not _write(err, path, data, fixed):
                    failed += 1
                    written = False
                    result = check(parse(source, defines=values))  # what is in the file
            if written and outcome.applied:
                fixed_files += 1
                fixed_problems += len(outcome.applied)
                if not diff:
                    for applied in outcome.applied:
                        where = f"{path}:{applied.location.line}:{applied.location.column}"
                        err.print(f"fixed {where}: {applied.code.code} {applied.title}")
            if diff:
                continue
        else:
            result = check(parse(source, defines=values))
        _report(out, result, output_format, strict, counts, records, checked)

    if output_format is OutputFormat.JSON:
        out.out(jsonio.dumps(records, indent=2))
    elif output_format is OutputFormat.SARIF:
        out.out(jsonio.dumps(sarif_log(checked, unreadable, strict=strict), indent=2))
    summary = _summary(counts, len(files) - len(unreadable), len(unreadable))
    if fixing:
        summary = _fix_summary(fixed_problems, fixed_files, unsafe_left, failed, dry_run=diff) + (
            "" if diff else f"; {summary or 'nothing checked'}"
        )
    if output_format is OutputFormat.HUMAN or fixing:
        err.print(summary, style=_style(counts, len(unreadable) + failed))
    if unreadable or failed:
        raise typer.Exit(2)
    if diff:
        raise typer.Exit(1 if fixed_problems else 0)
    if counts[Severity.ERROR]:
        raise typer.Exit(1)


def _report(
    out: Console,
    result: CheckResult,
    output_format: OutputFormat,
    strict: bool,
    counts: dict[Severity, int],
    records: list[dict[str, object]],
    checked: list[CheckedFile],
) -> None:
    source = result.grammar.source
    for diagnostic in result.diagnostics:
        counts[effective_severity(diagnostic, strict=strict)] += 1
        if output_format is OutputFormat.JSON:
            records.append(as_json(diagnostic, source, strict=strict))
        elif output_format is OutputFormat.HUMAN:
            out.print(human(diagnostic, source, strict=strict))
    if output_format is OutputFormat.SARIF:
        checked.append(CheckedFile(source.name, source, result.diagnostics))


def _write(err: Console, path: Path, read: bytes, fixed: bytes) -> bool:
    """Write ``fixed`` over ``path``; refused if the file changed since it was read. False if
    not written."""
    try:
        check_rewritable(path)  # a regular file, not read-only
        if read_bytes(path) != read:
            err.print(
                f"error: {path} changed while it was being fixed; not written (run the command again)",
                style="bold red",
            )
            return False
        write_output(path, fixed)
    except SourceError as error:
        err.print(f"error: cannot write {path}: {error.message}", style="bold red")
        return False
    except OutputError as error:
        err.print(f"error: {error}", style="bold red")
        return False
    except OSError as error:
        err.print(f"error: cannot write {path}: {describe_os_error(error)}", style="bold red")
        return False
    return True


def _summary(counts: dict[Severity, int], checked: int, unreadable: int) -> str:
    """``1 error, 2 warnings in 3 files; 1 file could not be read``, or ``3 files OK``."""
    nouns = {Severity.INFO: "info message"}  # "2 infos" is not English
    found = [plural(counts[s], nouns.get(s, s.value)) for s in Severity if counts[s]]
    parts = []
    if found:
        parts.append(f"{', '.join(found)} in {plural(checked, 'file')}")
    elif checked:
        parts.append(f"{plural(checked, 'file')} OK")
    if unreadable:
        parts.append(f"{plural(unreadable, 'file')} could not be read")
    return "; ".join(parts)


def _fix_summary(problems: int, files: int, unsafe_left: int, failed: int, *, dry_run: bool) -> str:
    """``fixed 3 problems in 2 files (2 more fixes with --unsafe-fixes); 1 file could not be written``."""
    verb = "would fix" if dry_run else "fixed"
    text = f"{verb} {plural(problems, 'problem')} in {plural(files, 'file')}"
    if not problems:
        text = "fixed nothing" if failed else "nothing to fix"
    if unsafe_left:
        text += f" ({unsafe_left} more {'fix' if unsafe_left == 1 else 'fixes'} with --unsafe-fixes)"
    if failed:
        text += f"; {plural(failed, 'file')} could not be written"
    return text


def _style(counts: dict[Severity, int], unreadable: int) -> str:
    return "bold red" if counts[Severity.ERROR] or unreadable else "bold green"
