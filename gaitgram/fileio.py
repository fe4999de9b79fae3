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
(:class:`DirectoryLock`). Several files that must change together (a report's
tables, figures and page; an animation and its strip) are made in a staging
directory and swapped in at once (:func:`swapped_files`): an interruption leaves
all of them old or all new, and what a kill -9 cut short is put back by the next
swap (:func:`recover_swaps`).
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import json
import os
import shutil
import signal
import stat
import tempfile
import threading
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
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


@dataclass(frozen=True)
class Input:
    """Something a command reads, which none of its outputs may be: a file, or a directory and,
    given a path below it as parts, whether that path is the directory's own (``holds``; None:
    all of it is). ``what`` names it in messages: "the grammar", "the run directory"."""

    path: Path
    what: str
    holds: Callable[[tuple[str, ...]], bool] | None = None


def input_written(path: Path, inputs: Sequence[Input]) -> tuple[Input, tuple[str, ...]] | None:
    """The input that writing ``path`` would write over or into, and where below it (``()``: it is
    that input); None if none. Every spelling is the same path: a symlink, ``..``, a trailing
    slash, relative or absolute, and for a file another hard link to it."""
    for found in inputs:
        parts = _below(path, found.path)
        if parts is None or (parts and not os.path.isdir(found.path)):  # nothing is inside a file
            continue
        if not parts or found.holds is None or found.holds(parts):
            return found, parts
    return None


def _below(path: Path, root: Path) -> tuple[str, ...] | None:
    """``path`` below ``root``, as parts (``()``: the same file or directory); None if outside it."""
    with contextlib.suppress(OSError):
        if os.path.samefile(path, root):
            return ()
    real, base = os.path.realpath(path), os.path.realpath(root)
    inside = os.path.relpath(real, base)
    if inside == os.curdir:
        return ()
    if inside == os.pardir or inside.startswith(os.pardir + os.sep):
        return None
    return tuple(Path(inside).parts)


def check_output(
    path: Path,
    *,
    force: bool = False,
    directory: bool = False,
    parents: bool = False,
    flag: str = "",
    inputs: Sequence[Input] = (),
) -> None:
    """Raise :class:`OutputError` if :func:`write_output` (or, with ``directory``, making a
    directory there and files in it) would fail or overwrite a file without ``force``, or would
    write over or into one of the command's ``inputs`` (with or without ``force``).

    Checked: an input (:func:`input_written`), an existing directory where a file is meant (or a
    file where a directory is), an existing regular file without ``force``, a missing directory
    above the path (unless ``parents``: the command makes it), a file above it, and write
    permission where the file or directory would be made. A device, a FIFO or a path under
    ``/dev`` or ``/proc`` (``/dev/null``, ``/dev/stdout``) is an output to write to, never to
    replace: ``force`` is not needed. Nothing is created; as for any check before the fact, a
    later write can still fail (a full disk), and says so then. ``flag`` (``--out``) names the
    option, for the remedy.
    """
    elsewhere, or_elsewhere = (
        (f"; choose another {flag}", f", or choose another {flag}") if flag else ("", "")
    )
    touched = None if is_stream(path) else input_written(path, inputs)
    if touched is not None:
        found, parts = touched
        where = "is" if not parts else f"is {parts[0]} of" if len(parts) == 1 else f"is inside {parts[0]} of"
        named = f"{flag} {path}" if flag else str(path)
        raise OutputError(
            f"{named} {where} {found.what} {found.path}, which this command reads: an output never "
            f"replaces an input{elsewhere}"
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


def write_outputs(
    files: Sequence[tuple[Path, str | bytes]], notice: Callable[[str], None] | None = None
) -> None:
    """Write several outputs (:func:`write_output`) as one: every one of them is replaced, or none.

    The regular files (new ones, and existing ones with one link in a directory this process may
    create files in) are made in a staging directory beside their targets (past symlinks),
    keeping an existing file's mode and owner, and swapped in together (:func:`swapped_files`, one
    swap a directory, done last): a failure (a full disk), Ctrl-C or a kill -9 leaves all of them
    old or all new. Only for outputs in two directories can a kill -9 between the two swaps leave
    one directory's files new. Devices, streams (``/dev/stdout``) and files with several hard
    links cannot be swapped: they are written in place, as :func:`write_output` writes them,
    before the swaps. An error names the output's path as given; ``notice`` hears what an
    interrupted earlier swap into the same directory left and how it was mended. Ctrl-C waits
    until all are written (their content is made already: this is only writing it), then raises
    :class:`KeyboardInterrupt`.
    """
    with interrupts_deferred():
        if len(files) == 1:
            path, data = files[0]
            try:
                write_output(path, data)
            except OSError as error:
                raise _naming(error, path) from error
        else:
            _write_together(files, notice)


def _write_together(files: Sequence[tuple[Path, str | bytes]], notice: Callable[[str], None] | None) -> None:
    swapped: dict[Path, list[tuple[Path, Path, bytes]]] = {}
    in_place: list[tuple[Path, bytes]] = []
    for path, data in files:
        payload = data.encode("utf-8") if isinstance(data, str) else data
        target = Path(os.path.realpath(path))
        try:
            plain = not is_stream(path) and _swappable(target)
        except OSError as error:
            raise _naming(error, path) from error
        if not plain:
            in_place.append((path, payload))
        else:
            swapped.setdefault(target.parent, []).append((path, target, payload))
    with contextlib.ExitStack() as stack:
        for directory, outputs in swapped.items():
            if not directory.is_dir():  # as open() would: a typo creates no directories
                path = outputs[0][0]
                raise OSError(errno.ENOENT, os.strerror(errno.ENOENT), str(path))
            staging = stack.enter_context(swapped_files(directory, notice))
            for path, target, payload in outputs:
                try:
                    _stage(staging.path / target.name, target, payload)
                except OSError as error:
                    raise _naming(error, path) from error
        for path, payload in in_place:
            try:
                write_output(path, payload)
            except OSError as error:
                raise _naming(error, path) from error


def _stage(new: Path, target: Path, payload: bytes) -> None:
    """The new file for ``target``, with the mode and owner of the file it replaces, if any."""
    try:
        info = target.stat()
    except FileNotFoundError:
        write_atomically(new, payload, parents=False)
        return
    owner = (info.st_uid, info.st_gid)
    write_atomically(new, payload, mode=stat.S_IMODE(info.st_mode), owner=owner, parents=False)


def _swappable(target: Path) -> bool:
    """A new file, or a regular one with one link, in a directory this process may create files in
    (else it is written in place); a directory raises :class:`IsADirectoryError`."""
    try:
        info = target.stat()
    except FileNotFoundError:
        return True
    if stat.S_ISDIR(info.st_mode):
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(target))
    return stat.S_ISREG(info.st_mode) and info.st_nlink == 1 and os.access(target.parent, os.W_OK | os.X_OK)


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


def _locked_temporary(parent: Path, prefix: str) -> tuple[Path, DirectoryLock]:
    """A new directory in ``parent`` (``PREFIX``XXXX``.creating``, mode 0o700), locked while in use,
    so that :func:`remove_abandoned` and :func:`recover_swaps` never take it for a dead one's."""
    while True:
        temporary = Path(tempfile.mkdtemp(dir=parent, prefix=prefix, suffix=CREATING_SUFFIX))
        try:
            return temporary, DirectoryLock(temporary)
        except (DirectoryInUse, FileNotFoundError):  # another process took it for abandoned
            continue


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
    temporary, lock = _locked_temporary(path.parent, f".{path.name}.")
    with lock:
        try:
            os.chmod(temporary, 0o777 & ~current_umask())  # as mkdir would make it, not mkdtemp's 0o700
            yield temporary
            try:
                with interrupts_deferred():  # a Ctrl-C here is raised once the directory is in place
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


def remove_abandoned(path: Path) -> list[Path]:
    """Remove the temporary directories that attempts to create ``path`` left when killed; those
    removed."""
    prefix = f".{path.name}."
    removed = []
    with contextlib.suppress(OSError):
        for sibling in sorted(path.parent.iterdir()):
            name = sibling.name
            if not (name.startswith(prefix) and name.endswith(CREATING_SUFFIX)) or sibling.is_symlink():
                continue
            try:
                with DirectoryLock(sibling):
                    shutil.rmtree(sibling, ignore_errors=True)
            except OSError:  # in use (a live attempt), or gone already
                continue
            removed.append(sibling)
    return removed


@contextlib.contextmanager
def interrupts_deferred() -> Iterator[None]:
    """Ctrl-C (SIGINT) during the block takes effect when it ends: steps that must all be taken,
    or none, are not cut in two by it (if the block fails, its error is raised, not the Ctrl-C).
    A kill -9 still can cut them: :func:`recover_swaps` mends that."""
    if threading.current_thread() is not threading.main_thread():
        yield  # signals reach the main thread only
        return
    caught: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:  # a block that failed says so; a Ctrl-C held then would only hide its error
        signal.signal(signal.SIGINT, signal.default_int_handler if previous is None else previous)
    if caught:
        signal.raise_signal(signal.SIGINT)  # to whatever handled it before: KeyboardInterrupt


# ---- files replaced together --------------------------------------------------------------------

#: The prefix of a staging directory, made inside the directory its files will replace files in.
STAGING_PREFIX = ".staging."
#: In a staging directory: the names of its files, written before they are moved in and removed
#: once all are in place (that removal is the moment the swap is done).
MOVING_IN = ".moving-in.json"
#: In a staging directory: the files a swap set aside, to put back if it is cut short.
SET_ASIDE = ".set-aside"


@dataclass
class Staging:
    """Where :func:`swapped_files` has the new files made (``path``), and whether they are in
    place (``swapped``: a Ctrl-C during the swap is raised after it)."""

    path: Path
    swapped: bool = False


@contextlib.contextmanager
def swapped_files(directory: Path, notice: Callable[[str], None] | None = None) -> Iterator[Staging]:
    """Files that appear in ``directory`` all at once, replacing the files of the same names.

    Yields a :class:`Staging` whose ``path`` is an empty directory to make the new files in (files
    only). When the block ends without error they go into ``directory``: if it does not exist, it
    is made of them whole (:func:`created_directory`); else each file ``directory`` holds under a
    new file's name is set aside (a hard link, or a rename where links fail) and the new file is
    renamed over it, one swap at a time in a directory (``flock`` on it) and with Ctrl-C held
    until the last is in place (:func:`interrupts_deferred`). Files of other names are left
    alone. If the block fails (a full disk, Ctrl-C), the staging directory goes and
    ``directory`` is as it was.

    A kill -9 halfway through the renames leaves some files new: the next swap into
    ``directory`` (or :func:`recover_swaps`, which it calls first and whose lines ``notice``
    hears) puts back those set aside, so that what stays is all old or all new.
    """
    for note in recover_swaps(directory):
        if notice is not None:
            notice(note)
    if not os.path.exists(directory):
        staging = Staging(directory)
        try:
            with created_directory(directory) as building:
                staging.path = building
                yield staging
            staging.swapped = True
        except KeyboardInterrupt:  # before the rename (the block), or held until after it
            staging.swapped = os.path.isdir(directory) and not os.path.exists(staging.path)
            raise
        finally:  # the lock it was built under: no one locks these files' directory by it
            if staging.swapped:
                with contextlib.suppress(OSError):
                    os.unlink(directory / LOCK_FILE)
        return
    temporary, lock = _locked_temporary(directory, STAGING_PREFIX)
    staging = Staging(temporary)
    with lock:
        try:
            yield staging
            _swap_in(staging, directory, notice)
        finally:
            with interrupts_deferred():  # removed whole: a Ctrl-C here leaves nothing to mend
                shutil.rmtree(temporary, ignore_errors=True)


def recover_swaps(directory: Path) -> list[str]:
    """Mend what interrupted swaps into ``directory`` (:func:`swapped_files`) left: the files a
    swap cut short by a kill -9 had replaced are put back (and its new files removed), staging
    directories never swapped in are removed, and so is what an attempt to create ``directory``
    whole left beside it. A line for each thing mended, to tell the user. Staging directories in
    use (locked), or not this user's own, are left alone."""
    notes = [f"removed {p}, left unfinished by an interrupted gaitgram" for p in remove_abandoned(directory)]
    if not os.path.isdir(directory) or not os.access(directory, os.R_OK | os.X_OK):
        return notes  # nothing of ours can be in it (a write there says why it cannot be made)
    with _directory_locked(directory), interrupts_deferred():
        return notes + _recover_staging(directory)


def _recover_staging(directory: Path) -> list[str]:
    """:func:`recover_swaps` inside ``directory``, whose ``flock`` is held."""
    notes = []
    for entry in sorted(os.scandir(directory), key=lambda e: e.name):
        if not (entry.name.startswith(STAGING_PREFIX) and entry.name.endswith(CREATING_SUFFIX)):
            continue
        info = entry.stat(follow_symlinks=False)
        if not stat.S_ISDIR(info.st_mode) or info.st_uid != os.geteuid() or info.st_mode & 0o022:
            continue  # only a staging directory this user made (mkdtemp's 0o700) is mended
        staging = Path(entry.path)
        try:
            lock = DirectoryLock(staging)
        except OSError:  # a live swap's, or gone already
            continue
        with lock:
            if os.path.lexists(staging / MOVING_IN):
                put, removed = _put_back(staging, directory)
                notes.append(
                    f"an interrupted gaitgram left {directory} half-replaced: put back the {put} "
                    f"file(s) it had replaced and removed the {removed} it had added"
                )
            elif os.path.lexists(staging / SET_ASIDE):
                notes.append(
                    f"removed {staging}, the files an interrupted gaitgram had replaced in {directory} "
                    "(its new ones are in place)"
                )
            else:
                notes.append(
                    f"removed {staging}, the unfinished files of an interrupted gaitgram "
                    f"({directory} was left as it was)"
                )
            shutil.rmtree(staging, ignore_errors=True)
    return notes


def _swap_in(staging: Staging, directory: Path, notice: Callable[[str], None] | None) -> None:
    """Move the staging directory's files into ``directory`` (see :func:`swapped_files`), after
    mending what a swap killed since the block began left."""
    names = sorted(name for name in os.listdir(staging.path) if name != LOCK_FILE)
    for name in names:
        if not stat.S_ISREG(os.lstat(staging.path / name).st_mode):
            raise IsADirectoryError(errno.EISDIR, "only files are swapped in", str(staging.path / name))
        target = directory / name
        if os.path.isdir(target) and not os.path.islink(target):
            raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(target))
    with _directory_locked(directory) as descriptor, interrupts_deferred():
        for note in _recover_staging(directory):  # its files put back after ours would undo ours
            if notice is not None:
                notice(note)
        write_atomically(staging.path / MOVING_IN, json.dumps(names), parents=False)
        aside = staging.path / SET_ASIDE
        os.mkdir(aside)
        try:
            for name in names:
                target = directory / name
                if os.path.lexists(target):
                    try:  # a link keeps the old file where readers look for it until it is replaced
                        os.link(target, aside / name, follow_symlinks=False)
                    except OSError:
                        os.rename(target, aside / name)
                os.replace(staging.path / name, target)
        except BaseException:
            _put_back(staging.path, directory)
            raise
        os.unlink(staging.path / MOVING_IN)  # done: from here a kill leaves the new files
        staging.swapped = True
        os.fsync(descriptor)


def _put_back(staging: Path, directory: Path) -> tuple[int, int]:
    """Undo a swap cut short: each file set aside goes back, each new file that replaced none is
    removed; how many of each."""
    try:
        names = json.loads((staging / MOVING_IN).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        names = None
    if not isinstance(names, list) or not all(
        isinstance(n, str) and n not in ("", ".", "..") and "/" not in n and "\0" not in n for n in names
    ):
        raise OSError(errno.EINVAL, "an unreadable list of files; put them back by hand", str(staging))
    put = removed = 0
    for name in names:
        kept, target = staging / SET_ASIDE / name, directory / name
        if os.path.lexists(kept):
            os.replace(kept, target)
            put += 1
        elif not os.path.lexists(staging / name) and os.path.lexists(target):
            os.unlink(target)
            removed += 1
    os.unlink(staging / MOVING_IN)
    return put, removed


@contextlib.contextmanager
def _directory_locked(directory: Path) -> Iterator[int]:
    """An exclusive ``flock`` on ``directory`` itself (no lock file is added to it: it may be the
    user's), held while files are swapped in or put back; its descriptor, to sync the renames."""
    descriptor = os.open(directory, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX)
        yield descriptor
    finally:
        os.close(descriptor)
