"""What several commands share: how they report an error, load a grammar that must be usable,
read a genome, and check and write their outputs."""

from __future__ import annotations

import re
import sys
from pathlib import Path
from types import ModuleType

import typer

from gaitgram import fileio
from gaitgram.analysis import CheckResult, check
from gaitgram.analysis.report import human, source_error
from gaitgram.cli.terminal import err
from gaitgram.extras import MissingExtra, require
from gaitgram.language import SourceError, parse
from gaitgram.language.source import (
    MAX_SOURCE_BYTES,
    describe_os_error,
    read_bytes,
    read_limited,
    read_source,
)


def print_error(message: str) -> None:
    """``error: message`` on standard error, in bold red: how every command says what failed."""
    err.print(f"error: {message}", style="bold red")


def fail(message: str, code: int = 2) -> typer.Exit:
    """Print the error and give the exit to raise: ``raise fail(str(error)) from None``."""
    print_error(message)
    return typer.Exit(code)


def print_source_error(error: SourceError) -> None:
    """``error: cannot read PATH: why``, and the hint."""
    err.print(source_error(error), end="")


def require_extra(module: str, purpose: str) -> ModuleType:
    """Import an optional dependency, or print how to install it and exit 2."""
    try:
        return require(module, purpose)
    except MissingExtra as error:
        raise fail(str(error)) from None


def check_output(
    path: Path, *, force: bool, directory: bool = False, parents: bool = False, flag: str = ""
) -> None:
    """Refuse, before any work is done, an output that cannot be written
    (:func:`gaitgram.fileio.check_output`): print why, naming the path as given, and exit 2."""
    try:
        fileio.check_output(path, force=force, directory=directory, parents=parents, flag=flag)
    except fileio.OutputError as error:
        raise fail(str(error)) from None


def write_or_exit(path: Path, data: str | bytes) -> None:
    """Write an output file safely (:func:`gaitgram.fileio.write_output`), or say why not and exit 2."""
    write_all_or_exit([(path, data)])


def write_all_or_exit(files: list[tuple[Path, str | bytes]]) -> None:
    """Write several outputs as one (:func:`gaitgram.fileio.write_outputs`: none left half-made),
    or say which could not be written and why, and exit 2."""
    try:
        fileio.write_outputs(files)
    except OSError as error:
        raise fail(f"cannot write {error.filename}: {describe_os_error(error)}") from None


def load_usable(path: Path, defines: dict[str, int]) -> CheckResult:
    """Parse and check a grammar; on errors print them and exit 1 (2 if unreadable)."""
    try:
        source = read_source(path)
    except SourceError as error:
        print_source_error(error)
        raise typer.Exit(2) from None
    result = check(parse(source, defines=defines))
    if result.errors:
        for diagnostic in result.diagnostics:
            if diagnostic.is_error:
                err.print(human(diagnostic, source))
        err.print(
            f"{path}: {result.errors} error(s); run `gaitgram check {path}` for details", style="bold red"
        )
        raise typer.Exit(1)
    return result


_CODON = re.compile(r"[^\s,\[\]]+")


def parse_genome(text: str, origin: str) -> tuple[int, ...]:
    """Codons separated by commas and/or whitespace, optionally in [brackets] (JSON works)."""
    codons = []
    for match in _CODON.finditer(text):
        token = match.group()
        if not token.isdigit():
            line = text.count("\n", 0, match.start()) + 1
            column = match.start() - (text.rfind("\n", 0, match.start()) + 1) + 1
            raise typer.BadParameter(
                f"{origin}:{line}:{column}: {token!r} is not a codon; codons are non-negative integers "
                "separated by commas or spaces, e.g. 12,7,301",
                param_hint="genome",
            )
        codons.append(int(token))
    if not codons:
        raise typer.BadParameter(f"{origin}: the genome is empty", param_hint="genome")
    return tuple(codons)


def read_genome(inline: str | None, file: Path | None) -> tuple[int, ...]:
    """From ``--genome 1,2,3`` or ``--genome-file PATH`` (``-`` for standard input), at most 8 MB."""
    if (inline is None) == (file is None):
        raise typer.BadParameter("give exactly one of --genome and --genome-file", param_hint="genome")
    if inline is not None:
        return parse_genome(inline, "--genome")
    assert file is not None
    name = "<stdin>" if str(file) == "-" else str(file)
    try:
        if str(file) == "-":
            data = read_limited(sys.stdin.buffer, name, max_bytes=MAX_SOURCE_BYTES, what="genome")
        else:
            data = read_bytes(file, max_bytes=MAX_SOURCE_BYTES, what="genome")
        text = data.decode("utf-8-sig")
    except SourceError as error:
        print_source_error(error)
        raise typer.Exit(2) from None
    except (OSError, UnicodeDecodeError) as error:
        reason = describe_os_error(error) if isinstance(error, OSError) else "not UTF-8 text"
        raise fail(f"cannot read {name}: {reason}") from None
    return parse_genome(text, name)
