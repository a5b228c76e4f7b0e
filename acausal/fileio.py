"""Files written whole or not at all, and files read only when they are what they claim.

Two helpers for the files acausal writes and reads on a user's behalf
(result CSV and MAT files, the teaching page of ``acausal explain --html``):

* :func:`atomic_write` writes a new version of a file beside it and renames
  it into place: a write that fails half-way (a full disk, a value that
  cannot be written, Ctrl-C or SIGTERM) leaves the earlier file exactly as it
  was and no temporary file behind.  Readers see the old file or the new one,
  never a truncated mix.
* :func:`open_regular` opens a file for reading only if it is a regular file
  below a size cap, checked without blocking: a FIFO, a device
  (``/dev/zero``), a socket or a directory is refused with an error naming
  it, instead of hanging the reader or filling the memory.

Both raise :class:`OSError` (and its subclasses), the errors any file
operation raises, with messages that name the file.  This module is part of
the language layer and imports only the standard library.
"""

from __future__ import annotations

import errno
import io
import os
import secrets
import stat
from pathlib import Path
from typing import IO, Any, Callable

__all__ = ["atomic_write", "open_regular"]

#: Longest file name (in characters) kept in the name of the temporary file written beside it:
#: the temporary name adds about 20 characters, and file systems allow 255 bytes.
_MAX_NAME_KEPT = 200


# ---------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------


def atomic_write(path: str | os.PathLike, write: Callable[[IO[Any]], object], mode: str = "w", *,
                 encoding: str | None = None, newline: str | None = None) -> Path:
    """Write a file through ``write(handle)``, replacing the earlier file only when all went well.

    ``write`` writes into a temporary file in the same folder (hidden, named
    after the file); the temporary file is flushed to disk (``fsync``) and
    renamed over ``path`` (:func:`os.replace`, atomic on POSIX and Windows).
    If anything fails on the way (``write`` raises, the disk is full, the
    process is interrupted), the temporary file is removed and the earlier
    file at ``path``, if there was one, is left untouched; the exception
    propagates.

    A file that is replaced keeps its permission bits; a new one gets the
    permissions ``open()`` would give it (the umask applies).  A symbolic
    link keeps pointing to the file written.  Two cases are written in place,
    without the guarantee:

    * ``path`` exists and is not a regular file: a device or a pipe such as
      ``/dev/null``, ``/dev/stdout`` or a shell's ``>(gzip > r.gz)`` cannot
      be replaced, only written to;
    * ``path`` exists and may be written, but its folder takes no new file
      (no permission to create the temporary file there).

    Parameters
    ----------
    path : str or path-like
    write : callable
        ``write(handle)`` writes the content into the open file ``handle``;
        what it returns is ignored.
    mode : {'w', 'wb'}
        Text or binary.
    encoding, newline : str, optional
        As for :func:`open` (text mode only).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    IsADirectoryError
        If ``path`` is a directory (before ``write`` is called).
    OSError
        Whatever creating, writing or renaming the file raised (with
        ``filename`` set to ``path`` if it named no file); the earlier file
        is then unchanged.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"mode must be 'w' or 'wb', not {mode!r}")
    path = Path(path)
    target = Path(os.path.realpath(path))  # through symbolic links: the link itself stays
    try:
        info = os.stat(target)
    except FileNotFoundError:
        info = None
    if info is not None and stat.S_ISDIR(info.st_mode):
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(path))
    if info is not None and not stat.S_ISREG(info.st_mode):
        # a device or a pipe: replacing it would put a regular file in its place
        with open(path, mode, encoding=encoding, newline=newline) as handle:
            write(handle)
        return path
    try:
        fd, temporary = _create_beside(target)
    except PermissionError:
        if info is None:
            raise
        # a writable file in a folder that takes no new file: written in place, as open() would
        with open(path, mode, encoding=encoding, newline=newline) as handle:
            write(handle)
        return path
    try:
        if info is not None:
            _set_mode(fd, temporary, stat.S_IMODE(info.st_mode))
        with os.fdopen(fd, mode, encoding=encoding, newline=newline) as handle:
            fd = -1  # the handle owns (and closes) it now
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, target)
    except BaseException as exc:
        # KeyboardInterrupt and SIGTERM included: no half-written file is left behind
        if fd >= 0:
            os.close(fd)
        _remove_quietly(temporary)
        if isinstance(exc, OSError) and exc.filename is None:
            exc.filename = str(path)  # a full disk says so when writing: name the file it was for
        raise
    _sync_folder(target.parent)
    return path


def _create_beside(target: Path) -> tuple[int, Path]:
    """A new, empty, hidden file in ``target``'s folder, opened for writing: (descriptor, path).

    Created with ``O_EXCL`` under a random name (never someone else's file)
    and mode 0o666, so that the umask gives it the permissions of a file
    ``open()`` creates (:func:`tempfile.mkstemp` would make it 0o600).
    """
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):
        name = f".{target.name[:_MAX_NAME_KEPT]}.{secrets.token_hex(4)}.tmp"
        candidate = target.parent / name
        try:
            return os.open(candidate, flags, 0o666), candidate
        except FileExistsError:
            continue
    raise FileExistsError(errno.EEXIST, f"cannot create a temporary file beside {target}")


def _set_mode(fd: int, path: Path, mode: int) -> None:
    """Give the new file the earlier file's permission bits (best effort)."""
    try:
        if hasattr(os, "fchmod"):
            os.fchmod(fd, mode)
        else:  # pragma: no cover - Windows before Python 3.13
            os.chmod(path, mode)
    except OSError:
        pass  # e.g. a file system without POSIX permissions: the umask's bits then


def _remove_quietly(path: Path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass  # already renamed, or removed by someone else


def _sync_folder(folder: Path) -> None:
    """Flush the folder's entry of the renamed file to disk (POSIX; best effort)."""
    if not hasattr(os, "O_DIRECTORY"):
        return  # pragma: no cover - Windows has no directory descriptors
    try:
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass  # some file systems refuse fsync on a directory: the rename is done all the same
    finally:
        os.close(fd)


# ---------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------


def open_regular(path: str | os.PathLike, limit: int | None, *, hint: str | None = None) -> io.BufferedReader:
    """``path`` opened for reading bytes, if it is a regular file of at most ``limit`` bytes.

    Symbolic links are followed.  The file is examined before it is opened
    and again once open (it may have been swapped in between), and it is
    opened with ``O_NONBLOCK``: a FIFO is refused at once instead of waiting
    for a writer, and a device is refused before it is read.  A file that
    grows past ``limit`` while it is read (or a file that reports no size) is
    refused when the reading gets there.

    Parameters
    ----------
    path : str or path-like
    limit : int or None
        Largest size in bytes; None for no cap.
    hint : str, optional
        Appended to the message of a file that is too large (how to allow a
        larger one).

    Returns
    -------
    io.BufferedReader
        Seekable, to be closed by the caller (a context manager).

    Raises
    ------
    FileNotFoundError, PermissionError
        As :func:`open` raises them.
    IsADirectoryError
        For a directory.
    OSError
        ``errno.EINVAL`` for a FIFO, a device or a socket; ``errno.EFBIG``
        for a file larger than ``limit``.  The message names the file, what
        it is, and for a large file its size and the cap.
    """
    path = Path(path)
    info = os.stat(path)
    if not stat.S_ISREG(info.st_mode):
        raise _not_regular(path, info.st_mode)  # not even opened: opening a device can do things
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    try:
        info = os.fstat(fd)  # the file opened may not be the one examined
        if not stat.S_ISREG(info.st_mode):
            raise _not_regular(path, info.st_mode)
        if limit is not None and info.st_size > limit:
            raise _too_large(path, info.st_size, limit, hint)
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)  # a regular file: read it as any other
        raw = io.FileIO(fd, "rb", closefd=True)
    except BaseException:
        os.close(fd)
        raise
    return io.BufferedReader(_Capped(raw, path, limit, hint))


class _Capped(io.RawIOBase):
    """A file read only up to ``limit`` bytes: reading past them raises ``errno.EFBIG``."""

    def __init__(self, raw: io.FileIO, path: Path, limit: int | None, hint: str | None) -> None:
        super().__init__()
        self._raw, self._path, self._limit, self._hint = raw, path, limit, hint

    @property
    def name(self) -> str:
        return str(self._path)

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return self._raw.seekable()

    def seek(self, offset: int, whence: int = os.SEEK_SET) -> int:
        return self._raw.seek(offset, whence)

    def tell(self) -> int:
        return self._raw.tell()

    def fileno(self) -> int:
        return self._raw.fileno()

    def readinto(self, buffer) -> int | None:
        count = self._raw.readinto(buffer)
        if count and self._limit is not None and self._raw.tell() > self._limit:
            raise _too_large(self._path, None, self._limit, self._hint)
        return count

    def close(self) -> None:
        self._raw.close()
        super().close()


def _not_regular(path: Path, mode: int) -> OSError:
    if stat.S_ISDIR(mode):
        return IsADirectoryError(errno.EISDIR, f"{path} is a directory, not a regular file")
    kinds = ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
             (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))
    kind = next((text for test, text in kinds if test(mode)), "not a regular file")
    link = f" (a symbolic link to {os.path.realpath(path)})" if os.path.islink(path) else ""
    return OSError(errno.EINVAL, f"{path}{link} is {kind}, not a regular file; only a regular "
                                 f"file is read")


def _too_large(path: Path, size: int | None, limit: int, hint: str | None) -> OSError:
    if size is None:  # found while reading: the file grew, or did not say its size
        what = f"holds more than {_describe_size(limit)}"
    else:
        what = f"is {_describe_size(size)}" + (f" ({size} bytes)" if size >= 1024 else "")
    return OSError(errno.EFBIG, f"{path} {what}, more than the {_describe_size(limit)} this reader "
                                f"accepts" + (f"; {hint}" if hint else ""))


def _describe_size(size: int) -> str:
    """``512 MiB``, ``1.5 GiB``, ``800 bytes``: a size in bytes for a message."""
    for unit, factor in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if size >= factor:
            return f"{size / factor:.4g} {unit}"
    return f"{size} bytes"
