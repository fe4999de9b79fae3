"""What several commands share: how they report an error, load a grammar that must be usable,
read a genome, and check and write their outputs."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType

import typer

from gaitgram import fileio
from gaitgram.analysis import CheckResult, check
from gaitgram.analysis.report import human, source_error
from gaitgram.backends.api import SettingsError
from gaitgram.cli.options import parse_settings
from gaitgram.cli.terminal import err
from gaitgram.extras import MissingExtra, require
from gaitgram.ge.mapper import MapperError
from gaitgram.ge.registry import (
    DEFAULT_REPRESENTATION,
    Compiled,
    Genome,
    GenomeError,
    RepresentationLoadError,
    RepresentationNotFound,
    compile_representation,
)
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
    path: Path,
    *,
    force: bool,
    directory: bool = False,
    parents: bool = False,
    flag: str = "",
    inputs: Sequence[fileio.Input] = (),
) -> None:
    """Refuse, before any work is done, an output that cannot be written or is one of the command's
    ``inputs`` (:func:`gaitgram.fileio.check_output`): print why, naming the path as given, and
    exit 2."""
    try:
        fileio.check_output(path, force=force, directory=directory, parents=parents, flag=flag, inputs=inputs)
    except fileio.OutputError as error:
        raise fail(str(error)) from None


def read_inputs(*named: tuple[Path | None, str]) -> list[fileio.Input]:
    """The files a command reads, each with what it is ("the grammar"), as inputs no output may be
    (:func:`check_output`); None and ``-`` (standard input) left out."""
    return [fileio.Input(path, what) for path, what in named if path is not None and str(path) != "-"]


def mend_outputs(*paths: Path, directory: bool = False) -> None:
    """Before anything else: put back what an interrupted gaitgram left half-replaced where these
    outputs go (:func:`gaitgram.fileio.recover_swaps`: in the directory of each file, or in each
    ``directory``), saying what was mended."""
    real = [Path(os.path.realpath(path)) for path in paths if not fileio.is_stream(path)]
    places = set(real) if directory else {path.parent for path in real}
    for place in sorted(places):
        try:
            notes = fileio.recover_swaps(place)
        except OSError as error:
            raise fail(f"cannot mend {error.filename or place}: {describe_os_error(error)}") from None
        for note in notes:
            err.print(note)


def write_or_exit(path: Path, data: str | bytes) -> None:
    """Write an output file safely (:func:`gaitgram.fileio.write_output`), or say why not and exit 2."""
    write_all_or_exit([(path, data)])


def write_all_or_exit(files: list[tuple[Path, str | bytes]]) -> None:
    """Write several outputs as one (:func:`gaitgram.fileio.write_outputs`: all new or all as they
    were), or say which could not be written and why, and exit 2; after a Ctrl-C (held until they
    are written), say so and exit 130."""
    try:
        fileio.write_outputs(files, notice=err.print)
    except OSError as error:
        raise fail(f"cannot write {error.filename}: {describe_os_error(error)}") from None
    except KeyboardInterrupt:
        paths = [path for path, _ in files]
        were = "was" if len(paths) == 1 else "were"
        raise interrupted(f"{_listing(paths)} {were} written whole before it took effect") from None


def interrupted(what: str) -> typer.Exit:
    """Say that Ctrl-C stopped the command and what its outputs hold now; the exit to raise (130)."""
    err.print(f"interrupted: {what}", style="bold yellow")
    return typer.Exit(130)


def as_they_were(paths: list[Path]) -> str:
    """What a command stopped before writing left: its outputs, each as it was or not made."""
    kept = [p for p in paths if fileio.is_stream(p) or p.exists() or p.is_symlink()]
    missing = [p for p in paths if p not in kept]
    parts = [f"{_listing(kept)} {'is' if len(kept) == 1 else 'are'} as before"] if kept else []
    parts += [f"{_listing(missing)} {'was' if len(missing) == 1 else 'were'} not made"] if missing else []
    return "nothing was written; " + ", ".join(parts)


def _listing(paths: list[Path]) -> str:
    return " and ".join(map(str, paths))


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


def read_genome_text(inline: str | None, file: Path | None) -> tuple[str, str]:
    """The text of ``--genome TEXT`` or ``--genome-file PATH`` (``-`` for standard input, at most
    8 MB) and where it came from, for messages: a representation decodes it (:func:`decode_genome`)."""
    if (inline is None) == (file is None):
        raise typer.BadParameter("give exactly one of --genome and --genome-file", param_hint="genome")
    if inline is not None:
        return inline, "--genome"
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
    return text, name


def compiled_or_exit(checked: CheckResult, name: str, items: list[str] | None, **flags: object) -> Compiled:
    """The representation ``name`` compiled for a checked grammar with the settings of
    ``--setting KEY=JSON`` (``items``) and of the flags named after a setting (``max_wraps=2``:
    ``--max-wraps``, None when not given, over them), or why not and exit 2."""
    given = {key: value for key, value in flags.items() if value is not None}
    try:
        return compile_representation(
            checked.grammar, checked.facts, name, {**parse_settings(items, "--setting"), **given}
        )
    except (RepresentationNotFound, RepresentationLoadError) as error:
        raise fail(f"--representation: {error}") from None
    except SettingsError as error:
        where = "--" + error.key.replace("_", "-") if error.key in given else f"--setting {error.key}"
        raise fail(f"{where}: {error.message}") from None
    except MapperError as error:
        raise fail(str(error)) from None


def decode_genome(representation: Compiled, text: str, origin: str) -> Genome:
    """A genome in the representation's syntax (GE: ``12,7,301``), or a usage error (exit 2) saying
    where in ``origin`` it is wrong and what to write."""
    try:
        return representation.decode(text)
    except GenomeError as error:
        message = str(error)
        joined = f"{origin}:{message}" if message[:1].isdigit() else f"{origin}: {message}"
        raise typer.BadParameter(
            f"{joined} (a genome of representation {representation.name})"
            if representation.name != DEFAULT_REPRESENTATION
            else joined,
            param_hint="genome",
        ) from None


def read_genome(inline: str | None, file: Path | None, representation: Compiled) -> Genome:
    """From ``--genome TEXT`` or ``--genome-file PATH``, in the representation's syntax."""
    text, origin = read_genome_text(inline, file)
    return decode_genome(representation, text, origin)
