"""lark's analysed parsers kept between processes (about 25 ms of ``gaitgram check``'s start-up),
in a cache no one but the user can write.

Not lark's own ``Lark(cache=...)``: its file is a pickle, unpickled before the grammar's digest is
compared, so whoever can write the file runs code as the user who parses; and it follows a
symbolic link at the file's path when it writes. Here the file holds lark's own serialisation of
an analysed parser (``Lark.memo_serialize``, read back by ``Lark._load_from_dict``, as
``lark.tools.standalone``'s generated modules do) as JSON, a format that builds data and nothing
else: the only classes it names are lark's grammar classes, and the lexer class the caller passed.
A file is also read only from a directory the user owns and no group or other user can write
(opened once, without following a symbolic link, and checked through that descriptor, so nothing
renamed into its place afterwards is read), without following a symbolic link at the file, and is
written through a temporary file in that directory renamed over it. A digest of the grammar, the
options, lark's version and Python's, on the file's first line, is compared before the rest is
parsed; a stale or damaged file is rebuilt. Where no such directory can be had, there is no cache,
and one line on stderr says why (docs/cli.md, "Files gaitgram writes outside a run directory").
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import stat
import sys
from typing import Any

import lark
from lark import Lark
from lark.grammar import Rule
from lark.lark import _LOAD_ALLOWED_OPTIONS  # the options lark's own cache gives at load time
from lark.lexer import TerminalDef

#: Set (to anything but "" or "0") to keep no cache at all, and say nothing about it.
NO_CACHE_VARIABLE = "GAITGRAM_NO_CACHE"
#: Changes whenever the file's layout does, so that an older gaitgram's file is rebuilt.
_FORMAT = "gaitgram-lark-json-1"
#: The JSON objects that stand for what JSON has no form of; any other one-key object whose key is
#: one of these is written as a list of pairs, so decoding is exact.
_TUPLE, _PAIRS, _CLASS = "(", "{", "<"
_RESERVED = (_TUPLE, _PAIRS, _CLASS)
_warned = False


class NoCache(Exception):
    """Why no cache directory can be used, and what to do about it (the message)."""


def cached_lark(name: str, grammar: str, **options: Any) -> Lark:
    """``Lark(grammar, **options)``, read from the cache file ``name`` when it holds this parser,
    else built and written there."""
    allowed = {option: value for option, value in options.items() if option in _LOAD_ALLOWED_OPTIONS}
    classes = {_class_name(value): value for value in options.values() if isinstance(value, type)}
    python = "".join(map(str, sys.version_info[:2]))
    filename = f"{name}-lark{lark.__version__}-py{python}.json"
    key = _digest(grammar, options).encode("ascii") + b"\n"
    directory = _open_directory()
    try:
        if directory is not None:
            found = _read(directory, filename, key)
            if found is not None:
                try:
                    data = json.loads(found, object_hook=lambda obj: _decode(obj, classes))
                    return Lark._load_from_dict(data["data"], data["memo"], **allowed)
                except Exception:  # any damage to the file only means a rebuild
                    pass
        parser = Lark(grammar, **options)
        if directory is not None:
            data, memo = parser.memo_serialize([TerminalDef, Rule])
            data["options"] = {k: v for k, v in data["options"].items() if k not in _LOAD_ALLOWED_OPTIONS}
            try:
                text = json.dumps(_encode({"data": data, "memo": memo}, classes), separators=(",", ":"))
            except TypeError:  # something in the parser JSON cannot hold: no cache for it
                return parser
            _write(directory, filename, key + text.encode("utf-8"))
        return parser
    finally:
        if directory is not None:
            os.close(directory)


def cache_directory() -> str:
    """``$XDG_CACHE_HOME/gaitgram``, or ``~/.cache/gaitgram`` where that is unset or relative (the
    XDG base-directory specification says to ignore a relative path); :class:`NoCache` where there
    is no home directory to put it in."""
    configured = os.environ.get("XDG_CACHE_HOME", "")
    if os.path.isabs(configured):
        return os.path.join(configured, "gaitgram")
    home = os.environ.get("HOME")
    if home is None:
        import pwd

        try:
            home = pwd.getpwuid(os.geteuid()).pw_dir
        except KeyError:
            home = ""
    if not os.path.isabs(home):
        raise NoCache("HOME is not an absolute path; set XDG_CACHE_HOME to a directory of your own")
    return os.path.join(home, ".cache", "gaitgram")


def private_directory(path: str) -> int:
    """A descriptor of the directory ``path``, made (mode 0700) if missing, along with the cache
    root above it, but never a directory above that (a home directory that does not exist is not
    made). :class:`NoCache` unless it is a real directory, not a symbolic link, of this process's
    user, that neither group nor others can write. Checked through the descriptor, so that the
    directories above it (a shared one, say) cannot swap another in after the check."""
    root = os.path.dirname(path)
    for made in (root, path):
        above = os.path.dirname(made)
        if not os.path.isdir(above):
            why = "is not a directory" if os.path.lexists(above) else "does not exist"
            raise NoCache(f"{above} {why}; set XDG_CACHE_HOME to a directory of your own")
        try:
            os.mkdir(made, 0o700)
        except FileExistsError:
            pass
        except OSError as error:
            raise NoCache(f"cannot make {made}: {error.strerror}; set XDG_CACHE_HOME elsewhere") from None
    try:
        fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError as error:
        if os.path.islink(path):
            raise NoCache(f"{path} is a symbolic link; remove it (gaitgram makes a directory)") from None
        raise NoCache(f"cannot open {path}: {error.strerror}; remove it or set XDG_CACHE_HOME") from None
    found = os.fstat(fd)
    problem = None
    if found.st_uid != os.geteuid():
        problem = f"{path} belongs to {_user(found.st_uid)}, not to you; remove it or set XDG_CACHE_HOME"
    elif found.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        problem = (
            f"{path} can be written by others (mode {stat.S_IMODE(found.st_mode):04o}); remove it, since "
            "anyone may have put files in it, and gaitgram makes a private one"
        )
    if problem is not None:
        os.close(fd)
        raise NoCache(problem)
    return fd


def _open_directory() -> int | None:
    """The cache directory's descriptor, or ``None``: the cache turned off, a system without the
    calls that make it safe (``O_NOFOLLOW``, ``openat``), or one line on stderr saying why not
    (once a process)."""
    global _warned
    if os.environ.get(NO_CACHE_VARIABLE, "") not in ("", "0"):
        return None
    if not hasattr(os, "O_NOFOLLOW") or os.open not in os.supports_dir_fd:
        return None
    try:
        return private_directory(cache_directory())
    except NoCache as why:
        if not _warned:
            _warned = True
            quiet = f"{NO_CACHE_VARIABLE}=1 keeps no cache and says nothing"
            print(f"warning: gaitgram keeps no parser cache: {why} ({quiet})", file=sys.stderr)
        return None


def _read(directory: int, filename: str, key: bytes) -> bytes | None:
    """The file's contents after ``key``, if it is a regular file of this user's that starts with
    ``key``; ``None`` for anything else, a symbolic link included."""
    flags = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC
    try:
        fd = os.open(filename, flags, dir_fd=directory)
    except OSError:  # missing, or a symbolic link (ELOOP)
        return None
    with os.fdopen(fd, "rb") as handle:
        found = os.fstat(fd)
        if not stat.S_ISREG(found.st_mode) or found.st_uid != os.geteuid():
            return None
        if handle.readline() != key:
            return None
        return handle.read()


def _write(directory: int, filename: str, payload: bytes) -> None:
    """``payload`` into a new 0600 file beside ``filename``, renamed over it: a symbolic link there
    is replaced, never followed. A failure (a full disk, a read-only directory) only means no cache."""
    temporary = f".{filename}.{os.getpid()}.{os.urandom(4).hex()}.tmp"
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC
    try:
        fd = os.open(temporary, flags, 0o600, dir_fd=directory)
    except OSError:
        return
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
        os.replace(temporary, filename, src_dir_fd=directory, dst_dir_fd=directory)
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(temporary, dir_fd=directory)


def _digest(grammar: str, options: dict[str, Any]) -> str:
    """What the analysed parser depends on. A post-lexer's ``always_accept`` decides which
    terminals lark keeps, so it counts; lark's own cache leaves the post-lexer out."""
    described = []
    for option, value in sorted(options.items()):
        if isinstance(value, type):
            value = _class_name(value)
        elif not isinstance(value, (str, int, float, bool, list, tuple, type(None))):
            value = [_class_name(type(value)), sorted(getattr(value, "always_accept", ()))]
        described.append(f"{option}={value!r}")
    text = "\0".join([_FORMAT, lark.__version__, repr(sys.version_info[:2]), grammar, *described])
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _encode(value: Any, classes: dict[str, type]) -> Any:
    """``value`` as JSON can hold it: tuples, dictionaries with keys other than strings, and the
    caller's classes as one-key objects; anything else raises :class:`TypeError`."""
    if isinstance(value, dict):
        if all(type(k) is str for k in value) and not (len(value) == 1 and next(iter(value)) in _RESERVED):
            return {k: _encode(v, classes) for k, v in value.items()}
        return {_PAIRS: [[_encode(k, classes), _encode(v, classes)] for k, v in value.items()]}
    if isinstance(value, list):
        return [_encode(v, classes) for v in value]
    if isinstance(value, tuple):
        return {_TUPLE: [_encode(v, classes) for v in value]}
    if isinstance(value, type) and classes.get(_class_name(value)) is value:
        return {_CLASS: _class_name(value)}
    if value is None or isinstance(value, (str, int, float, bool)):
        return value
    raise TypeError(f"cannot cache a {type(value).__name__}")


def _decode(obj: dict[str, Any], classes: dict[str, type]) -> Any:
    """The inverse of :func:`_encode`, one object at a time (``json.loads``'s ``object_hook``); a
    class the caller did not pass raises :class:`KeyError`."""
    if len(obj) == 1:
        [(tag, value)] = obj.items()
        if tag == _TUPLE:
            return tuple(value)
        if tag == _PAIRS:
            return dict(value)
        if tag == _CLASS:
            return classes[value]
    return obj


def _class_name(cls: type) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def _user(uid: int) -> str:
    import pwd

    try:
        return f"{pwd.getpwuid(uid).pw_name} (uid {uid})"
    except KeyError:
        return f"uid {uid}"
