"""The array store of the user cache directory: round trips, corrupt files rebuilt, the byte
budget, concurrent writers, and where it lives."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.io import ArrayStore, user_store
from bakeshop.io.store import STALE_SECONDS, default_cache_dir


def arrays(seed: int = 0, n: int = 1000):
    rng = np.random.default_rng(seed)
    return (rng.integers(0, 1 << 30, n + 1), rng.integers(0, 1 << 20, n, np.int32),
            rng.random(n, np.float32))  # fmt: skip


def test_saved_arrays_load_equal_read_only_and_under_their_key_only(tmp_path):
    store = ArrayStore(tmp_path, 1 << 20)
    saved = arrays()
    assert store.put("plan|a", saved)
    loaded = store.load("plan|a")
    assert len(loaded) == 3
    for a, b in zip(saved, loaded, strict=True):
        np.testing.assert_array_equal(a, b)
        assert a.dtype == b.dtype and not b.flags.writeable
    assert store.load("plan|b") is None
    assert (store.loads, store.saves, store.corrupt) == (1, 1, 0)


@pytest.mark.parametrize(
    "damage",
    ["truncate", "flip", "empty", "another key"],
)
def test_a_damaged_file_is_reported_missing_and_deleted(tmp_path, damage):
    """A truncated, bit-flipped or empty file, or one holding another key (a hash collision),
    loads as missing and is deleted, so the entry is rebuilt and saved anew."""
    store = ArrayStore(tmp_path, 1 << 20)
    store.put("k", arrays())
    path = store.path("k")
    data = bytearray(path.read_bytes())
    if damage == "truncate":
        path.write_bytes(data[: len(data) // 2])
    elif damage == "flip":
        data[len(data) // 2] ^= 0xFF  # inside the arrays: zip's CRC-32 catches it
        path.write_bytes(bytes(data))
    elif damage == "empty":
        path.write_bytes(b"")
    else:
        store.put("other", arrays(1))
        os.replace(store.path("other"), path)
    assert store.load("k") is None
    assert store.corrupt == 1 and not path.exists()
    assert store.put("k", arrays()) and store.load("k") is not None


def test_the_least_recently_used_files_go_beyond_the_budget(tmp_path):
    one = sum(a.nbytes for a in arrays())
    store = ArrayStore(tmp_path, int(3.5 * one))  # three files fit (with their headers), not four
    for i, key in enumerate("abc"):
        store.put(key, arrays(i))
        os.utime(store.path(key), (1000 + i, 1000 + i))  # a, b, c from oldest to newest
    store.load("a")  # now the most recent: b is the oldest
    store.put("d", arrays(3))
    assert [store.load(k) is not None for k in "abcd"] == [True, False, True, True]
    assert store.nbytes() <= store.budget
    assert not store.put("huge", (np.zeros(store.budget + 1, np.uint8),))


def test_stale_temporaries_are_removed_and_fresh_ones_kept(tmp_path):
    store = ArrayStore(tmp_path, 1 << 20)
    stale, fresh = tmp_path / ".dead.0123.npz", tmp_path / ".live.4567.npz"
    for p in (stale, fresh):
        p.write_bytes(b"partial")
    old = time.time() - STALE_SECONDS - 60
    os.utime(stale, (old, old))
    store.put("k", arrays())
    assert not stale.exists() and fresh.exists()


def test_an_unwritable_directory_is_no_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_bytes(b"")
    store = ArrayStore(blocker / "cache", 1 << 20)  # a directory under a file: cannot exist
    assert not store.put("k", arrays()) and store.failures == 1
    assert store.load("k") is None


def test_two_processes_saving_the_same_key_at_once_leave_one_valid_file(tmp_path):
    """Writers race on one key (each writes a temporary and renames it): the directory ends
    with exactly one file, whole, holding one writer's arrays, and no temporary."""
    script = textwrap.dedent(
        f"""
        import sys
        import numpy as np
        from bakeshop.io import ArrayStore
        store = ArrayStore({str(tmp_path)!r}, 1 << 28)
        value = np.full(2_000_000, int(sys.argv[1]), np.int64)
        for _ in range(5):
            assert store.put("same", (value,))
        """
    )
    procs = [subprocess.Popen([sys.executable, "-c", script, str(i)]) for i in (1, 2)]
    assert [p.wait(timeout=120) for p in procs] == [0, 0]
    files = sorted(p.name for p in tmp_path.iterdir())
    assert files == [ArrayStore(tmp_path).path("same").name]
    (value,) = ArrayStore(tmp_path).load("same")
    assert value[0] in (1, 2) and np.all(value == value[0])


def test_the_user_store_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("BAKESHOP_CACHE_DIR", str(tmp_path / "c"))
    monkeypatch.setenv("BAKESHOP_CACHE_BYTES", "12345")
    store = user_store()
    assert store.directory == tmp_path / "c" and store.budget == 12345
    monkeypatch.setenv("BAKESHOP_CACHE_BYTES", "0")
    assert user_store() is None
    monkeypatch.setenv("BAKESHOP_CACHE_BYTES", "lots")
    with pytest.raises(ArgumentError, match="BAKESHOP_CACHE_BYTES"):
        user_store()
    monkeypatch.delenv("BAKESHOP_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    if sys.platform.startswith("linux"):
        assert default_cache_dir() == tmp_path / "xdg" / "bakeshop"
