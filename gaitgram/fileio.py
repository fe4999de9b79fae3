"""Writing files that must never be half-written, with the permissions a user expects.

Every file gaitgram writes into a run directory goes through
:func:`write_atomically`: written beside its target, flushed to disk and renamed
over it, so a kill at any instant leaves the old file or the new one. The new
file gets the mode a plain ``open()`` would give it (``0o666`` less the umask),
not ``mkstemp``'s private ``0o600``.

Files named on the command line (``-o``, and the grammars ``fmt`` rewrites) go
through :func:`write_output`, which writes what ``open(path, "w")`` would write
to, but safely; see its docstring for symlinks, hard links and devices. Every
command checks its outputs with :func:`check_output` before doing any work, so
that an hour of rendering never ends in "no such directory".

Directories that must appear whole (a run directory, a study directory) are built
under a temporary name beside their target and renamed into place
(:func:`created_directory`); one process at a time works in such a directory
(:class:`DirectoryLock`).
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import shutil
import stat
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from types import TracebackType
from typing import BinaryIO

#: The lock file of a directory gaitgram works in: created once, never deleted.
LOCK_FILE = ".lock"
#: The suffix of a directory being built under a temporary name (see :func:`created_directory`).
CREATING_SUFFIX = ".creating"


def current_umask() -> int:
    """The process's umask (read by setting it and putting it back: there is no getter)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_atomically(
    path: Path,
    text: str | bytes,
    *,
    mode: int | None = None,
    owner: tuple[int, int] | None = None,
    parents: bool = True,
) -> None:
    """Write ``text`` (str as UTF-8, or bytes) to ``path`` through a temporary file and a rename.

    ``mode`` defaults to ``0o666`` less the umask, as for any new file; ``owner`` is a
    ``(uid, gid)`` to give the new file where permitted (the group alone if only that is);
    ``parents=False`` leaves a missing directory an error, as ``open()`` does. An
    :class:`OSError` names ``path``, never the temporary file, which is gone.
    """
    if parents:
        path.parent.mkdir(parents=True, exist_ok=True)
    try:
        temporary = _temporary_copy(path, text.encode("utf-8") if isinstance(text, str) else text)
    except OSError as error:
        raise _naming(error, path) from error
    try:
        if owner is not None:  # before the chmod: a chown clears set-id bits
            _give_owner(temporary, *owner)
        os.chmod(temporary, (0o666 & ~current_umask()) if mode is None else mode)
        os.replace(temporary, path)
    except BaseException as error:
        Path(temporary).unlink(missing_ok=True)
        if isinstance(error, OSError):
            raise _naming(error, path) from error
        raise


def _naming(error: OSError, path: Path) -> OSError:
    """The same error (its subclass too: ``OSError(errno, ...)`` picks it), about ``path``."""
    return OSError(error.errno, error.strerror or str(error), str(path))


class OutputError(ValueError):
    """An output that cannot be written; the message names the path as the user wrote it."""


def check_output(
    path: Path, *, force: bool = False, directory: bool = False, parents: bool = False, flag: str = ""
) -> None:
    """Raise :class:`OutputError` if :func:`write_output` (or, with ``directory``, making a
    directory there and files in it) would fail or overwrite a file without ``force``.

    Checked: an existing directory where a file is meant (or a file where a directory is), an
    existing regular file without ``force``, a missing directory above the path (unless
    ``parents``: the command makes it), a file above it, and write permission where the file or
    directory would be made. A device, a FIFO or a path under ``/dev`` or ``/proc``
    (``/dev/null``, ``/dev/stdout``) is an output to write to, never to replace: ``force`` is not
    needed. Nothing is created; as for any check before the fact, a later write can still fail
    (a full disk), and says so then. ``flag`` (``--out``) names the option, for the remedy.
    """
    elsewhere, or_elsewhere = (
        (f"; choose another {flag}", f", or choose another {flag}") if flag else ("", "")
    )
    if not directory and is_stream(path) and os.path.exists(path):  # /dev/stdout: a link into /proc
        if os.path.isdir(path):
            raise OutputError(f"cannot write {path}: is a directory{elsewhere}")
        if not os.access(path, os.W_OK):
            raise OutputError(f"cannot write {path}: permission denied{elsewhere}")
        return
    target = Path(os.path.realpath(path)) if os.path.islink(path) else path  # a dangling link: its target
    if os.path.exists(target):
        if os.path.isdir(target) != directory:
            if directory:
                raise OutputError(f"cannot make the directory {path}: a file of that name exists{elsewhere}")
            raise OutputError(f"cannot write {path}: is a directory{elsewhere}")
        if directory:
            if not os.access(target, os.W_OK | os.X_OK):
                raise OutputError(f"cannot write in {path}: permission denied{elsewhere}")
            return
        if os.path.isfile(target) and not force:
            raise OutputError(f"{path} exists; pass --force to overwrite it{or_elsewhere}")
        if not os.access(target, os.W_OK):
            raise OutputError(f"cannot write {path}: permission denied (the file is read-only){elsewhere}")
        return
    missing = []
    above = target.parent
    while not os.path.exists(above) and above != above.parent:
        missing.append(above)
        above = above.parent
    if not os.path.isdir(above):
        raise OutputError(f"cannot write {path}: {above} is not a directory{elsewhere}")
    if not os.access(above, os.X_OK):
        raise OutputError(f"cannot write {path}: permission denied (cannot look in {above}){elsewhere}")
    if missing and not parents:
        raise OutputError(
            f"cannot write {path}: no such directory {missing[0]}; create it first{or_elsewhere}"
        )
    if not os.access(above, os.W_OK | os.X_OK):
        raise OutputError(
            f"cannot write {path}: permission denied (cannot create files in {above}){elsewhere}"
        )


def check_rewritable(path: Path) -> None:
    """Raise :class:`OutputError` unless ``path`` is a regular file this process may rewrite in
    place (``fmt``, ``check --fix``): not a FIFO or ``/dev/fd/N`` (read fine, but no file to
    rewrite), not a read-only file."""
    if not path.is_file():
        raise OutputError(f"cannot write {path}: not a regular file")
    check_output(path, force=True)


def write_output(path: Path, data: str | bytes) -> None:
    """Write a file the user named, where and as ``open(path, "w")`` would, but never half-written.

    - A symlink is followed: its target is rewritten and the link stays a link.
    - A new file is created atomically with ``0o666`` less the umask; a missing parent
      directory is an error (a typo should not create directories).
    - An existing file with one link is replaced atomically, keeping its mode and, where
      permitted, its owner and group (ACLs and extended attributes are not copied).
    - An existing file with several hard links is rewritten in its own inode, which a rename
      would split from its other names: see :func:`_write_in_place` for how that stays safe.
    - A device, a FIFO, or anything under ``/dev`` or ``/proc`` (``/dev/stdout``) is opened
      and written: a rename would replace the device node, not write to it.
    - A directory raises :class:`IsADirectoryError`.
    """
    payload = data.encode("utf-8") if isinstance(data, str) else data
    if is_stream(path):
        with open(path, "wb") as handle:
            handle.write(payload)
        return
    target = Path(os.path.realpath(path))  # a dangling link names the file to create, as for open()
    try:
        info = target.stat()
    except FileNotFoundError:
        write_atomically(target, payload, parents=False)
        return
    if stat.S_ISDIR(info.st_mode):
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(path))
    if not stat.S_ISREG(info.st_mode):
        with open(target, "wb") as handle:
            handle.write(payload)
    elif info.st_nlink > 1:
        _write_in_place(target, payload, copy=True)
    else:
        try:
            write_atomically(
                target,
                payload,
                mode=stat.S_IMODE(info.st_mode),
                owner=(info.st_uid, info.st_gid),
                parents=False,
            )
        except PermissionError:
            # A writable file in a directory we may not create files in: write it as an editor would.
            if not os.access(target, os.W_OK) or os.access(target.parent, os.W_OK):
                raise
            _write_in_place(target, payload, copy=False)


def write_outputs(files: Sequence[tuple[Path, str | bytes]]) -> None:
    """Write several outputs (:func:`write_output`), in order, as one: if one fails, the files this
    call created are removed again, and the error names that output's path as given (never a
    temporary file beside it). Files it replaced keep their new content."""
    made: list[Path] = []
    for path, data in files:
        new = not os.path.lexists(path)
        try:
            write_output(path, data)
        except OSError as error:
            for done in made:
                done.unlink(missing_ok=True)
            raise _naming(error, path) from error
        if new:
            made.append(path)


def is_stream(path: Path) -> bool:
    """``/dev/stdout``, ``/dev/fd/3``, ``/proc/self/fd/1``: names of open streams, not files to replace."""
    parts = Path(os.path.abspath(path)).parts
    return os.name == "posix" and len(parts) > 2 and parts[1] in ("dev", "proc")


def _temporary_copy(path: Path, payload: bytes) -> str:
    """``payload`` in a new temporary file beside ``path``, flushed to disk; its name."""
    fd, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
            handle.flush()
            os.fsync(handle.fileno())
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return temporary


def _give_owner(path: str, uid: int, gid: int) -> None:
    """chown where permitted: root gives both, an owner can give one of its own groups, else nothing."""
    for wanted in ((uid, gid), (-1, gid)):
        try:
            os.chown(path, *wanted)
            return
        except OSError:
            continue


def _write_in_place(path: Path, payload: bytes, *, copy: bool) -> None:
    """Overwrite ``path``'s own inode, so hard links keep sharing it, as safely as that can be.

    With ``copy``, the new content is first written and flushed to a temporary file beside
    it: a full disk or quota fails there, before the file is touched, and if the process
    dies mid-write that copy survives. If writing the file itself fails, its old content
    (read just before) is written back; the copy is kept, and named in the error, only if
    that fails too.
    """
    temporary = _temporary_copy(path, payload) if copy else None
    keep = temporary is not None
    try:
        with open(path, "r+b") as handle:
            original = handle.read()
            try:
                _overwrite(handle, payload)
            except OSError:
                _overwrite(handle, original)  # it fitted before, so it fits again
                keep = False
                raise
        keep = False
    except OSError as error:
        if not keep:
            raise
        raise OSError(
            error.errno, f"{error.strerror}; the new content is kept in {temporary}", str(path)
        ) from error
    finally:
        if temporary is not None and not keep:
            Path(temporary).unlink(missing_ok=True)


def _overwrite(handle: BinaryIO, payload: bytes) -> None:
    handle.seek(0)
    handle.write(payload)
    handle.truncate()
    handle.flush()
    os.fsync(handle.fileno())


# ---- directories that appear whole, worked in by one process at a time ----------------------


class DirectoryInUse(OSError):
    """Another process holds the directory's lock."""

    def __init__(self, directory: Path) -> None:
        super().__init__(errno.EBUSY, "in use by another gaitgram", str(directory))


class DirectoryLock:
    """An exclusive lock on a directory: ``flock`` on its ``.lock`` file, until :meth:`release`.

    The lock file is created once and never deleted, by anyone: deleting a lock file while
    another process holds or waits on it is how two processes come to hold "the" lock at once.
    The kernel drops the lock when the process dies, so a kill -9 leaves no stale lock.
    Raises :class:`DirectoryInUse` if another process holds it.
    """

    def __init__(self, directory: Path) -> None:
        self.directory = directory
        path = directory / LOCK_FILE
        while True:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666 & ~current_umask())
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                raise DirectoryInUse(directory) from None
            except BaseException:
                os.close(fd)
                raise
            try:  # the file locked is still the one the directory holds (it is never replaced)
                same = os.fstat(fd).st_ino == os.stat(path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                self._fd: int | None = fd
                return
            os.close(fd)

    @staticmethod
    def held(directory: Path) -> bool:
        """Whether another process holds the lock now: a shared ``flock`` for an instant, on the
        lock file if there is one (none is made: a directory never locked has none)."""
        try:
            fd = os.open(directory / LOCK_FILE, os.O_RDONLY | os.O_CLOEXEC)
        except OSError:
            return False
        try:
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        finally:
            os.close(fd)
        return False

    def release(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def __enter__(self) -> DirectoryLock:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.release()


def is_empty_directory(path: Path) -> bool:
    return path.is_dir() and not path.is_symlink() and not any(path.iterdir())


@contextlib.contextmanager
def created_directory(path: Path) -> Iterator[Path]:
    """A new directory at ``path`` that appears whole or not at all.

    Yields a temporary directory beside ``path`` (``.NAME.XXXX.creating``) to fill; when the
    block ends without error it is renamed to ``path``, else removed. A kill at any instant
    leaves either no ``path`` or all of it; the temporary directory a killed attempt leaves is
    removed by the next one (it is locked while in use, so a live one is never touched).
    ``path`` may be missing or an empty directory; anything else raises
    :class:`FileExistsError`, before or (if another process made it meanwhile) at the rename.
    """
    if (path.exists() or path.is_symlink()) and not is_empty_directory(path):
        raise FileExistsError(errno.EEXIST, "exists and is not an empty directory", str(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_abandoned(path)
    while True:
        temporary = Path(tempfile.mkdtemp(dir=path.parent, prefix=f".{path.name}.", suffix=CREATING_SUFFIX))
        try:
            lock = DirectoryLock(temporary)
        except (DirectoryInUse, FileNotFoundError):  # another attempt took it for abandoned
            continue
        break
    with lock:
        try:
            os.chmod(temporary, 0o777 & ~current_umask())  # as mkdir would make it, not mkdtemp's 0o700
            yield temporary
            try:
                os.rename(temporary, path)  # onto nothing, or onto an empty directory
            except OSError as error:
                if error.errno in (errno.EEXIST, errno.ENOTEMPTY, errno.EISDIR, errno.ENOTDIR):
                    raise FileExistsError(
                        errno.EEXIST, "exists and is not an empty directory", str(path)
                    ) from None
                raise
        except BaseException:
            shutil.rmtree(temporary, ignore_errors=True)
            raise


def remove_abandoned(path: Path) -> None:
    """Remove the temporary directories that attempts to create ``path`` left when killed."""
    prefix = f".{path.name}."
    with contextlib.suppress(OSError):
        for sibling in path.parent.iterdir():
            name = sibling.name
            if not (name.startswith(prefix) and name.endswith(CREATING_SUFFIX)) or sibling.is_symlink():
                continue
            try:
                with DirectoryLock(sibling):
                    shutil.rmtree(sibling, ignore_errors=True)
            except OSError:  # in use (a live attempt), or gone already
                continue
