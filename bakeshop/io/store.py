"""Arrays kept between processes: a directory of files, one per key, bounded in bytes.

What depends only on shapes (the area filter's matrix of a 4096x2048 latlong to a 6x1024 cube
takes seconds to build and 320 MB to hold) need not be rebuilt by every process: the command
line hands :mod:`bakeshop.sphere` a :class:`ArrayStore` in the user's cache directory
(:func:`user_store`), and a second run at the same sizes reads the matrix instead of building
it.

A file holds the key it was saved under, the arrays (an uncompressed ``.npz``) and the CRC-32 of
each array's bytes, checked when it is read. A file that is truncated, corrupt, or holds another
key is deleted and reported missing, so its entry is rebuilt. Files are written to a temporary
beside their place and renamed over it (atomic on POSIX and Windows), so two processes saving
the same key at once leave one whole file and a reader never sees half of one. The directory is
kept under its budget by deleting the least recently used files (reading a file touches it).

Environment: ``BAKESHOP_CACHE_DIR`` (default: the platform's user cache directory, as
platformdirs names it: ``$XDG_CACHE_HOME/bakeshop`` or ``~/.cache/bakeshop`` on Linux,
``~/Library/Caches/bakeshop`` on macOS, ``%LOCALAPPDATA%\\bakeshop\\Cache`` on Windows) and
``BAKESHOP_CACHE_BYTES`` (default :data:`DEFAULT_BUDGET`; ``0`` keeps nothing on disk).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import secrets
import sys
import time
import zipfile
import zlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from bakeshop.errors import ArgumentError

__all__ = ["DEFAULT_BUDGET", "ArrayStore", "default_cache_dir", "user_store"]

#: default size of the user cache directory: 2 GiB (six area-filter matrices of a 4k latlong
#: to a 6x1024 cube, or hundreds of smaller ones).
DEFAULT_BUDGET = 2 << 30

#: a temporary older than this was left by a process that died while writing it.
STALE_SECONDS = 3600

_SUFFIX = ".npz"


def default_cache_dir() -> Path:
    """The user cache directory of bakeshop (``BAKESHOP_CACHE_DIR`` when set)."""
    override = os.environ.get("BAKESHOP_CACHE_DIR")
    if override:
        return Path(override)
    home = Path.home()
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA") or str(home / "AppData" / "Local")
        return Path(base) / "bakeshop" / "Cache"
    if sys.platform == "darwin":
        return home / "Library" / "Caches" / "bakeshop"
    return Path(os.environ.get("XDG_CACHE_HOME") or home / ".cache") / "bakeshop"


def user_store() -> ArrayStore | None:
    """The store in :func:`default_cache_dir` bounded by ``BAKESHOP_CACHE_BYTES``, or None when
    that is 0 (nothing kept on disk)."""
    text = os.environ.get("BAKESHOP_CACHE_BYTES", "").strip()
    try:
        budget = int(text) if text else DEFAULT_BUDGET
    except ValueError:
        budget = -1
    if budget < 0:
        raise ArgumentError(
            f"BAKESHOP_CACHE_BYTES={text!r}: expected a whole number of bytes (0 keeps nothing)"
        )
    return ArrayStore(default_cache_dir(), budget) if budget else None


def _crc(array: np.ndarray) -> int:
    """CRC-32 of an array's bytes (about 1 s per 2 GB: cheap beside reading them)."""
    return zlib.crc32(np.ascontiguousarray(array).reshape(-1).view(np.uint8).data)


class ArrayStore:
    """Tuples of arrays by string key in ``directory``, at most ``budget`` bytes of files.

    Failures to read or write are never errors (a cache is only a shortcut): :meth:`load`
    returns None and :meth:`put` returns False, and the counters say what happened.
    """

    def __init__(self, directory: str | os.PathLike, budget: int = DEFAULT_BUDGET) -> None:
        self.directory = Path(directory)
        self.budget = int(budget)
        #: files read, files found unusable (and deleted), files written, writes that failed.
        self.loads = self.corrupt = self.saves = self.failures = 0

    def path(self, key: str) -> Path:
        """The file of ``key``."""
        return self.directory / (hashlib.sha256(key.encode()).hexdigest()[:40] + _SUFFIX)

    def load(self, key: str) -> tuple[np.ndarray, ...] | None:
        """The arrays saved under ``key`` (read-only), or None when there are none or the file
        is unusable (then it is deleted)."""
        path = self.path(key)
        try:
            with np.load(path, allow_pickle=False) as z:
                if str(z["key"]) != key:
                    raise ValueError("another key")
                arrays = tuple(z[f"a{i}"] for i in range(int(z["count"])))
                if [_crc(a) for a in arrays] != z["crc"].tolist():
                    raise ValueError("checksum")
        except FileNotFoundError:
            return None
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
            self.corrupt += 1
            with contextlib.suppress(OSError):
                path.unlink()
            return None
        with contextlib.suppress(OSError):
            os.utime(path)  # most recently used
        for a in arrays:
            a.setflags(write=False)
        self.loads += 1
        return arrays

    def put(self, key: str, arrays: Sequence[np.ndarray]) -> bool:
        """Keep ``arrays`` under ``key`` (replacing what was there); False when they exceed the
        budget alone or cannot be written (a read-only or full disk)."""
        if sum(np.asarray(a).nbytes for a in arrays) > self.budget:
            return False
        path = self.path(key)
        tmp = path.with_name(f".{path.stem}.{secrets.token_hex(6)}{_SUFFIX}")
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            with open(tmp, "xb") as f:
                named: dict[str, Any] = {
                    f"a{i}": np.ascontiguousarray(a) for i, a in enumerate(arrays)
                }
                named["crc"] = np.array([_crc(a) for a in named.values()], np.int64)
                np.savez(f, key=np.array(key), count=np.array(len(arrays)), **named)
            os.replace(tmp, path)
        except OSError:
            self.failures += 1
            with contextlib.suppress(OSError):
                tmp.unlink()
            return False
        self.saves += 1
        self.trim()
        return True

    def trim(self) -> None:
        """Delete the least recently used files beyond the budget, and temporaries left by
        processes that died while writing."""
        files = []
        now = time.time()
        with contextlib.suppress(OSError):
            for entry in os.scandir(self.directory):
                if not entry.name.endswith(_SUFFIX):
                    continue
                with contextlib.suppress(OSError):
                    stat = entry.stat()
                    if entry.name.startswith("."):
                        if now - stat.st_mtime > STALE_SECONDS:
                            os.unlink(entry.path)
                    else:
                        files.append((stat.st_mtime, stat.st_size, entry.path))
        total = sum(size for _, size, _ in files)
        for _, size, path in sorted(files):
            if total <= self.budget:
                break
            with contextlib.suppress(OSError):
                os.unlink(path)  # another process may have deleted it first
            total -= size

    def nbytes(self) -> int:
        """Bytes of the files in the store."""
        total = 0
        with contextlib.suppress(OSError):
            for entry in os.scandir(self.directory):
                if entry.name.endswith(_SUFFIX) and not entry.name.startswith("."):
                    with contextlib.suppress(OSError):
                        total += entry.stat().st_size
        return total
