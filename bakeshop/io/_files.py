"""File plumbing shared by the codecs: what may be opened, atomic writes, the files a run wrote,
and header-versus-size checks."""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import stat
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import BinaryIO

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io._intent import check_written

#: Largest accepted image side, in pixels.
MAX_SIDE = 1 << 20
#: Largest accepted pixel count (about 268 megapixels: 3.2 GB as float32 RGB). Codecs that can
#: read larger images take a ``max_pixels`` option.
MAX_PIXELS = 1 << 28

_KINDS = (
    (stat.S_ISDIR, "is a directory, not a file"),
    (stat.S_ISFIFO, "is a named pipe (FIFO), not a file: bakeshop reads regular files only"),
    (stat.S_ISCHR, "is a character device, not a file: bakeshop reads regular files only"),
    (stat.S_ISBLK, "is a block device, not a file: bakeshop reads regular files only"),
    (stat.S_ISSOCK, "is a socket, not a file: bakeshop reads regular files only"),
)


def check_input(path: str | os.PathLike) -> os.stat_result:
    """Refuse anything but a readable regular file, before it is opened; return its status.

    Opening a named pipe blocks until something writes to it (forever, for a pipe nobody
    feeds), a device can be endless, and a directory or a symbolic link loop fails deep inside
    a codec with a message about something else. Every reader of :mod:`bakeshop.io` calls this
    first, and so does the command line for each input it is given, so each of these cases
    fails at once with one plain reason.

    Raises
    ------
    bakeshop.errors.BakeshopError
        With ``path`` and the reason: no such file (or a symbolic link to a missing one), a
        symbolic link loop, permission denied, a directory, a named pipe, a device, a socket.
    """
    try:
        status = os.stat(path)
    except OSError as e:
        raise BakeshopError(_input_problem(path, e), path) from None
    for test, reason in _KINDS:
        if test(status.st_mode):
            raise BakeshopError(reason, path)
    if not stat.S_ISREG(status.st_mode):
        raise BakeshopError("is not a regular file", path)
    if not os.access(path, os.R_OK):
        raise BakeshopError("cannot read the file: permission denied", path)
    return status


def _input_problem(path: str | os.PathLike, error: OSError) -> str:
    if error.errno == errno.ELOOP:
        return "a symbolic link loop (too many levels of symbolic links)"
    if error.errno == errno.ENOENT:
        if os.path.islink(path):
            return "a symbolic link to a file that does not exist"
        return "no such file"
    return f"cannot read the file: {describe_os_error(error)}"


def open_input(path: str | os.PathLike) -> BinaryIO:
    """:func:`check_input`, then open ``path`` for reading in binary mode, without blocking.

    The file is opened with ``O_NONBLOCK`` and checked again through its descriptor, so a
    regular file swapped for a named pipe between the check and the open is refused too
    instead of blocking. Returns a buffered binary file object (the flag is cleared).
    """
    check_input(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as e:
        raise BakeshopError(_input_problem(path, e), path) from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise BakeshopError("is not a regular file (it changed while being opened)", path)
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


#: errno -> plain words, for errors that name the file themselves.
_WORDS = {
    errno.ENOSPC: "no space left on the device (the disk is full)",
    errno.EDQUOT: "disk quota exceeded",
    errno.EROFS: "read-only file system",
    errno.EACCES: "permission denied",
    errno.EPERM: "operation not permitted",
    errno.ENOENT: "no such file or directory",
    errno.EISDIR: "it is a directory",
    errno.EFBIG: "the file is too large for the file system",
    errno.EIO: "input/output error",
}


def describe_os_error(error: OSError) -> str:
    """The reason of an :class:`OSError` in plain words, without the file name it carries."""
    if error.errno in _WORDS:
        return _WORDS[error.errno]
    text = error.strerror or str(error)
    return text[:1].lower() + text[1:]


#: flags of a new temporary file: created here or not at all, closed on exec.
_CREATE = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)

_journal_lock = threading.Lock()
#: open journals: (the list, the thread it is limited to or None for every thread).
_journals: list[tuple[list[Path], int | None]] = []


@contextlib.contextmanager
def record_writes(*, this_thread: bool = False) -> Iterator[list[Path]]:
    """Within the block, collect every file that :func:`atomic_path` completes (in order);
    with ``this_thread``, only those written by the calling thread (a bake running steps at
    once keeps one per step).

    Yields the list, which grows as files are written. The command line keeps one open for
    each run, so that a run that fails or is interrupted after writing some of its outputs can
    say which ones exist.
    """
    written: list[Path] = []
    owner = threading.get_ident() if this_thread else None
    with _journal_lock:
        _journals.append((written, owner))
    try:
        yield written
    finally:
        with _journal_lock:  # by identity: two journals may hold the same paths
            _journals[:] = [j for j in _journals if j[0] is not written]


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``target`` (same extension); rename it over ``target`` on
    success, delete it on failure. A failed write leaves no partial file and the old one intact.

    The temporary is deleted on every way out of the block: an exception, and also a signal,
    once the command line has turned SIGINT and SIGTERM into exceptions (see
    :mod:`bakeshop.cli.main`); only SIGKILL or a power cut can leave one behind. Errors name
    ``target``, never the temporary: an :class:`OSError` (a full disk, a read-only mount, a
    directory where no file may be created) becomes a :class:`BakeshopError` about ``target``,
    and a codec's own message that mentions the temporary is rewritten to mention ``target``.
    """
    target = Path(target)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise BakeshopError(f"directory {str(directory)!r} does not exist", target)
    tmp = None
    try:
        # The name is chosen before the file exists, inside the block that removes it: a signal
        # that lands just after the file is created (where tempfile.mkstemp would still be
        # returning its name) finds it already known. 48 random bits: a name taken by someone
        # else is skipped (O_EXCL), and is never ours to remove.
        while tmp is None:
            tmp = directory / f".{target.stem}.{secrets.token_hex(6)}{target.suffix}"
            try:
                os.close(os.open(tmp, _CREATE, 0o600))
            except FileExistsError:
                tmp = None
            except OSError as e:
                tmp = None  # nothing was created
                reason = f"cannot create a file in {str(directory)!r}: {describe_os_error(e)}"
                raise BakeshopError(reason, target) from None
        yield tmp
        check_written(tmp, target)  # within verify_writes(): reloads or fails
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException as e:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        if isinstance(e, OSError):
            raise BakeshopError(f"cannot write the file: {describe_os_error(e)}", target) from None
        if isinstance(e, BakeshopError) and tmp is not None:
            _name_target(e, str(tmp), target)
        raise
    with _journal_lock:
        me = threading.get_ident()
        for journal, owner in _journals:
            if owner is not None and owner != me:
                continue
            journal.append(target)


def _name_target(error: BakeshopError, tmp: str, target: Path) -> None:
    """Make ``error`` speak of ``target`` wherever it speaks of the temporary ``tmp``."""
    if error.path is None or os.path.abspath(error.path) == os.path.abspath(tmp):
        error.path = os.fspath(target)
    for name, replacement in ((tmp, os.fspath(target)), (Path(tmp).name, target.name)):
        error.reason = error.reason.replace(name, replacement)
    error.args = (error.reason, *error.args[1:])


def check_dimensions(
    width: int, height: int, channels: int = 1, *, max_pixels: int = MAX_PIXELS
) -> None:
    """Refuse absurd sizes before anything is allocated."""
    if width < 1 or height < 1:
        raise FormatError(f"invalid image size {width}x{height}")
    if width > MAX_SIDE or height > MAX_SIDE or width * height > max_pixels:
        raise FormatError(
            f"image size {width}x{height} exceeds the limit of {max_pixels} pixels "
            f"({MAX_SIDE} per side); pass max_pixels= to read larger images"
        )


def check_payload(needed: int, available: int, what: str = "pixel data") -> None:
    """Refuse a header that promises more bytes than the file holds."""
    if needed > available:
        raise FormatError(
            f"truncated file: the header promises {needed} bytes of {what}, "
            f"the file holds {available}"
        )


def read_payload(f: BinaryIO, size: int, what: str) -> bytes:
    """The next ``size`` bytes of the file ``f``, refused (:func:`check_payload`) before they
    are read when fewer are left."""
    check_payload(size, os.fstat(f.fileno()).st_size - f.tell(), what)
    data = f.read(size)
    check_payload(size, len(data), what)  # the file shrank while it was read
    return data
