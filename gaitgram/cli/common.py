"""What several commands do first: load a grammar that must be usable, read a genome."""

from __future__ import annotations

import re
import sys
from pathlib import Path
from types import ModuleType

import typer
from rich.console import Console

from gaitgram.analysis import CheckResult, check
from gaitgram.cli.output import human, print_source_error
from gaitgram.extras import MissingExtra, require
from gaitgram.language import SourceError, parse
from gaitgram.language.source import read_source

err = Console(stderr=True, highlight=False, soft_wrap=True, markup=False)


def require_extra(module: str, purpose: str) -> ModuleType:
    """Import an optional dependency, or print how to install it and exit 2."""
    try:
        return require(module, purpose)
    except MissingExtra as error:
        err.print(f"error: {error}", style="bold red")
        raise typer.Exit(2) from None


def load_usable(path: Path, defines: dict[str, int]) -> CheckResult:
    """Parse and check a grammar; on errors print them and exit 1 (2 if unreadable)."""
    try:
        source = read_source(path)
    except SourceError as error:
        print_source_error(err, error)
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
    """From ``--genome 1,2,3`` or ``--genome-file PATH`` (``-`` for standard input)."""
    if (inline is None) == (file is None):
        raise typer.BadParameter("give exactly one of --genome and --genome-file", param_hint="genome")
    if inline is not None:
        return parse_genome(inline, "--genome")
    assert file is not None
    if str(file) == "-":
        return parse_genome(sys.stdin.read(), "<stdin>")
    try:
        return parse_genome(file.read_text(encoding="utf-8"), str(file))
    except (OSError, UnicodeDecodeError) as error:
        raise typer.BadParameter(f"{file}: cannot read: {error}", param_hint="--genome-file") from None
