"""Standard output that fails like any other output: a one-line error and exit 2, or quietly.

A full disk (``> /dev/full``) or a reader that went away (``| head -1``) shows up as an
OSError at whichever print or flush meets it, deep inside rich or click, or at the
interpreter's last flush, where it can only be "Exception ignored". Click turns a
closed pipe into exit 1 and anything else into a traceback. So standard output is
wrapped to raise :class:`OutputFailed` (no OSError, so nothing on the way catches it
as one), and :func:`run` flushes before exit and turns that into the message.
"""

from __future__ import annotations

import contextlib
import errno
import io
import os
import signal
import sys
from collections.abc import Callable

from gaitgram.language.source import describe_os_error

#: A closed pipe ends the program as SIGPIPE would end a C one (128 + 13 in a shell), so
#: ``set -o pipefail`` treats ``gaitgram sample G | head -1`` exactly like ``yes | head -1``.
BROKEN_PIPE_STATUS = 128 + signal.SIGPIPE


class OutputFailed(Exception):
    """Writing standard output failed; ``error`` is the OSError."""

    def __init__(self, error: OSError) -> None:
        super().__init__(str(error))
        self.error = error


class _GuardedOutput(io.TextIOWrapper):
    def write(self, text: str) -> int:
        try:
            return super().write(text)
        except OSError as error:
            raise OutputFailed(error) from error

    def flush(self) -> None:
        if self.closed:  # closed by whoever owned it (the language server, on exit): nothing to flush
            return
        try:
            super().flush()
        except OSError as error:
            raise OutputFailed(error) from error


def write_text(text: str) -> None:
    """Write machine output (JSON, SARIF) to standard output as it is: a console would measure and
    wrap every line of it, which costs more than making it."""
    sys.stdout.write(text)
    sys.stdout.flush()


def write_bytes(data: bytes) -> None:
    """Write ``data`` to standard output as it is: machine output (a diff) whose tabs, ``\r``
    and encoding a console or a text stream would change. Fails as :class:`OutputFailed`, as
    writes through the guarded text stream do."""
    stream = sys.stdout
    stream.flush()  # what was printed before comes first
    buffer = getattr(stream, "buffer", None)
    if buffer is None:  # a text-only stream (a test runner's): the text, as exactly as it takes it
        stream.write(data.decode("utf-8", "surrogateescape"))
        return
    try:
        view = memoryview(data)
        while view:  # unbuffered (PYTHONUNBUFFERED=1), the buffer is the raw file: writes may be partial
            view = view[buffer.write(view) or 0 :]
        buffer.flush()
    except OSError as error:
        raise OutputFailed(error) from error


def run(main: Callable[[], object]) -> None:
    """Call ``main`` (which ends in SystemExit) with standard output guarded, and flush it
    while a failure can still be reported."""
    _guard()
    try:
        try:
            main()
        finally:
            sys.stdout.flush()
    except OutputFailed as failure:
        _discard_output()
        if failure.error.errno == errno.EPIPE:
            sys.exit(BROKEN_PIPE_STATUS)
        with contextlib.suppress(OSError, ValueError):
            sys.stderr.write(f"error: cannot write <stdout>: {describe_os_error(failure.error)}\n")
            sys.stderr.flush()
        sys.exit(2)


def _guard() -> None:
    stream = sys.stdout
    if type(stream) is not io.TextIOWrapper:  # not the process's own (a test runner's, or None)
        return
    stream.flush()
    sys.stdout = _GuardedOutput(
        stream.buffer,
        encoding=stream.encoding,
        errors=stream.errors,
        line_buffering=stream.line_buffering,
        write_through=stream.write_through,
    )


def _discard_output() -> None:
    """Point file descriptor 1 at /dev/null, so the interpreter's last flush of what is still
    buffered succeeds instead of printing "Exception ignored"."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
