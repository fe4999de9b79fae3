"""``gaitgram check`` as a library: check grammar files, or fix them, and count what was found.

:func:`check_files` reads each file, checks it (or, fixing, applies its fixes with
:func:`~gaitgram.analysis.fixes.fix_source` and writes the file back, or makes the diff that
would), and yields what happened to it; :class:`Tally` adds those up into the summary line and
the exit status. The command line only prints them.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from gaitgram.analysis import CheckResult, check
from gaitgram.analysis.fixes import AppliedFix, FixOutcome, fix_source
from gaitgram.analysis.report import CheckedFile, effective_severity, plural
from gaitgram.fileio import OutputError, check_rewritable, write_output
from gaitgram.language import parse
from gaitgram.language.diagnostics import Severity
from gaitgram.language.edits import unified_diff
from gaitgram.language.source import SourceError, decode_source, describe_os_error, encode_as_read, read_bytes

__all__ = ["CheckOptions", "FileCheck", "Tally", "check_files", "rewrite"]


@dataclass(frozen=True)
class CheckOptions:
    defines: Mapping[str, int] = field(default_factory=dict)
    #: Warnings count as errors.
    strict: bool = False
    #: Apply the safe fixes and write the files.
    fix: bool = False
    #: Also apply the preferred fix of problems that have no safe one (with ``fix`` or ``diff``).
    unsafe: bool = False
    #: Change nothing; make the diff that ``fix`` would write.
    diff: bool = False

    @property
    def fixing(self) -> bool:
        return self.fix or self.diff


@dataclass(frozen=True, eq=False)
class FileCheck:
    """What checking (or fixing) one file did."""

    path: Path
    #: Why the file could not be read (then nothing else is set).
    unreadable: SourceError | None = None
    #: The problems in the file as it now is; None if unreadable, or with ``diff`` (which reports
    #: no problems, only the changes).
    result: CheckResult | None = None
    #: What fixing did, when fixing.
    outcome: FixOutcome | None = None
    #: With ``diff``: the unified diff of the fixes, if they change the file.
    diff: bytes | None = None
    #: Why the fixed file was not written (then ``result`` is the file as it was).
    not_written: str | None = None

    @property
    def applied(self) -> tuple[AppliedFix, ...]:
        """The fixes made (or, with ``diff``, that would be): none if the file was not written."""
        if self.outcome is None or self.not_written is not None:
            return ()
        return self.outcome.applied

    @property
    def checked(self) -> CheckedFile | None:
        if self.result is None:
            return None
        source = self.result.grammar.source
        return CheckedFile(source.name, source, self.result.diagnostics)


def check_files(paths: Iterable[Path], options: CheckOptions) -> Iterator[FileCheck]:
    """Check (or fix) each file in turn, yielding what happened to it as soon as it is done."""
    for path in paths:
        yield _check_file(path, options)


def _check_file(path: Path, options: CheckOptions) -> FileCheck:
    try:
        data = read_bytes(path)
        source = decode_source(data, str(path))
    except SourceError as error:
        return FileCheck(path, unreadable=error)
    if not options.fixing:
        return FileCheck(path, result=check(parse(source, defines=options.defines)))
    outcome = fix_source(source, defines=options.defines, unsafe=options.unsafe)
    fixed = encode_as_read(data, outcome.text) if outcome.changed else None
    if options.diff:
        diff = None if fixed is None else unified_diff(str(path), data, fixed)
        return FileCheck(path, outcome=outcome, diff=diff)
    not_written = None if fixed is None else rewrite(path, fixed, read=data)
    if not_written is not None:  # report what is in the file
        result = check(parse(source, defines=options.defines))
        return FileCheck(path, result=result, outcome=outcome, not_written=not_written)
    return FileCheck(path, result=outcome.result, outcome=outcome)


def rewrite(path: Path, data: bytes, *, read: bytes | None = None) -> str | None:
    """Write ``data`` over the file ``path`` (whole, never half); with ``read``, only if the file
    still holds what was read (it is being fixed). Why it was not written, or None."""
    try:
        check_rewritable(path)  # a regular file, not read-only
        if read is not None and read_bytes(path) != read:
            return f"{path} changed while it was being fixed; not written (run the command again)"
        write_output(path, data)
    except SourceError as error:
        return f"cannot write {path}: {error.message}"
    except OutputError as error:
        return str(error)
    except OSError as error:
        return f"cannot write {path}: {describe_os_error(error)}"
    return None


@dataclass
class Tally:
    """What a run of :func:`check_files` found, added up."""

    options: CheckOptions
    counts: dict[Severity, int] = field(default_factory=lambda: dict.fromkeys(Severity, 0))
    files: int = 0
    unreadable: int = 0
    #: Files whose fixes could not be written.
    failed: int = 0
    fixed_files: int = 0
    fixed_problems: int = 0
    #: Fixes ``--unsafe-fixes`` would also make.
    unsafe_left: int = 0

    def add(self, found: FileCheck) -> None:
        self.files += 1
        if found.unreadable is not None:
            self.unreadable += 1
            return
        self.failed += found.not_written is not None
        if found.outcome is not None:
            self.unsafe_left += found.outcome.unsafe_available
        if found.applied:
            self.fixed_files += 1
            self.fixed_problems += len(found.applied)
        if found.result is not None:
            for diagnostic in found.result.diagnostics:
                self.counts[effective_severity(diagnostic, strict=self.options.strict)] += 1

    @property
    def failing(self) -> bool:
        """Whether the summary reports a failure (an error, or a file not read or written)."""
        return bool(self.counts[Severity.ERROR] or self.unreadable or self.failed)

    @property
    def status(self) -> int:
        """The exit status: 2 a file could not be read or written; with ``diff``, 1 if a file would
        change; else 1 if there are errors; else 0."""
        if self.unreadable or self.failed:
            return 2
        if self.options.diff:
            return 1 if self.fixed_problems else 0
        return 1 if self.counts[Severity.ERROR] else 0

    def summary(self) -> str:
        """``1 error, 2 warnings in 3 files; 1 file could not be read``, or ``3 files OK``; when
        fixing, what was fixed first."""
        found = self._found()
        if not self.options.fixing:
            return found
        return self._fixed() + ("" if self.options.diff else f"; {found or 'nothing checked'}")

    def _found(self) -> str:
        nouns = {Severity.INFO: "info message"}  # "2 infos" is not English
        found = [plural(self.counts[s], nouns.get(s, s.value)) for s in Severity if self.counts[s]]
        checked = self.files - self.unreadable
        parts = []
        if found:
            parts.append(f"{', '.join(found)} in {plural(checked, 'file')}")
        elif checked:
            parts.append(f"{plural(checked, 'file')} OK")
        if self.unreadable:
            parts.append(f"{plural(self.unreadable, 'file')} could not be read")
        return "; ".join(parts)

    def _fixed(self) -> str:
        """``fixed 3 problems in 2 files (2 more fixes with --unsafe-fixes); 1 file could not be written``."""
        verb = "would fix" if self.options.diff else "fixed"
        text = f"{verb} {plural(self.fixed_problems, 'problem')} in {plural(self.fixed_files, 'file')}"
        if not self.fixed_problems:
            text = "fixed nothing" if self.failed else "nothing to fix"
        if self.unsafe_left:
            fixes = "fix" if self.unsafe_left == 1 else "fixes"
            text += f" ({self.unsafe_left} more {fixes} with --unsafe-fixes)"
        if self.failed:
            text += f"; {plural(self.failed, 'file')} could not be written"
        return text
