"""Area-filter matrices kept between processes: a second process at the same sizes reads the
matrix instead of building it (counted, not timed), and gets the same result."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from bakeshop.io import ArrayStore
from bakeshop.sphere import cache_info, clear_caches, persist_caches, remap
from bakeshop.sphere._cache import _CACHES, PERSISTED

#: one process: an area-filter remap with the store in DIR; prints the counters and a digest.
CHILD = textwrap.dedent(
    """
    import hashlib, json, sys
    import numpy as np
    from bakeshop.io import ArrayStore
    from bakeshop.sphere import cache_info, persist_caches, remap
    persist_caches(ArrayStore(sys.argv[1], 1 << 30))
    image = np.random.default_rng(0).random((32, 64, 3), np.float32) + 0.1
    out = remap(image, "latlong", "cube", int(sys.argv[2]), filter="area")
    info = cache_info()["area filter matrices"]
    print(json.dumps({"builds": info["builds"], "loads": info["loads"],
                      "digest": hashlib.sha256(out.tobytes()).hexdigest()}))
    """
)


def child(directory, size: int = 8) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(directory), str(size)],
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_every_persisted_cache_exists():
    import bakeshop.sphere.area  # noqa: F401  (defines the area filter's cache)

    assert set(PERSISTED) <= set(_CACHES)


@pytest.mark.slow  # fresh processes
def test_a_second_process_at_the_same_sizes_reads_the_matrix(tmp_path):
    first = child(tmp_path)
    second = child(tmp_path)
    assert (first["builds"], first["loads"]) == (1, 0)
    assert (second["builds"], second["loads"]) == (0, 1)
    assert second["digest"] == first["digest"]
    other = child(tmp_path, size=4)  # another size: another matrix
    assert (other["builds"], other["loads"]) == (1, 0)
    assert len(list(tmp_path.glob("*.npz"))) == 2


@pytest.mark.slow  # fresh processes
def test_a_corrupt_matrix_file_is_rebuilt_with_the_same_result(tmp_path):
    first = child(tmp_path)
    (path,) = tmp_path.glob("*.npz")
    path.write_bytes(path.read_bytes()[:100])
    again = child(tmp_path)
    assert (again["builds"], again["loads"]) == (1, 0)
    assert again["digest"] == first["digest"]
    assert child(tmp_path)["loads"] == 1  # the rebuilt file is whole


@pytest.mark.slow  # fresh processes
def test_two_processes_building_the_same_matrix_at_once_leave_one_valid_file(tmp_path):
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", CHILD, str(tmp_path), "8"], stdout=subprocess.PIPE, text=True
        )
        for _ in range(2)
    ]
    results = [json.loads(p.communicate(timeout=300)[0].strip().splitlines()[-1]) for p in procs]
    assert len({r["digest"] for r in results}) == 1
    assert [p.name for p in tmp_path.iterdir()] == [next(tmp_path.glob("*.npz")).name]
    assert child(tmp_path)["loads"] == 1


#: one process of a library user who chose no store: the user's store is used.
LIBRARY_CHILD = textwrap.dedent(
    """
    import json
    import numpy as np
    from bakeshop.sphere import cache_info, remap
    remap(np.ones((32, 64, 3), np.float32), "latlong", "cube", 8, filter="area")
    info = cache_info()["area filter matrices"]
    print(json.dumps([info["builds"], info["loads"]]))
    """
)


@pytest.mark.slow  # fresh processes
def test_a_library_user_gets_the_user_store_without_asking(tmp_path):
    """Keeping the matrices between processes is the library's behaviour, not the command
    line's: a script that never calls persist_caches reads what an earlier one built."""
    import os

    env = {**os.environ, "BAKESHOP_CACHE_DIR": str(tmp_path), "BAKESHOP_CACHE_BYTES": "1000000000"}
    runs = [
        json.loads(subprocess.run([sys.executable, "-c", LIBRARY_CHILD], check=True, env=env,
                                  capture_output=True, text=True).stdout.splitlines()[-1])
        for _ in range(2)
    ]  # fmt: skip
    assert runs == [[1, 0], [0, 1]]


def test_in_process_the_store_is_read_after_memory_and_only_when_given(tmp_path):
    image = np.random.default_rng(1).random((16, 32, 3), np.float32)
    store = ArrayStore(tmp_path, 1 << 30)
    try:
        persist_caches(store)
        clear_caches()
        before = dict(cache_info()["area filter matrices"])
        a = remap(image, "latlong", "cube", 4, filter="area")
        b = remap(image, "latlong", "cube", 4, filter="area")  # from memory
        clear_caches()
        c = remap(image, "latlong", "cube", 4, filter="area")  # from the store
        info = cache_info()["area filter matrices"]
        assert info["builds"] - before["builds"] == 1 and info["loads"] - before["loads"] == 1
        assert store.saves == 1 and store.loads == 1
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(a, c)
        persist_caches(None)
        clear_caches()
        remap(image, "latlong", "cube", 4, filter="area")
        assert cache_info()["area filter matrices"]["builds"] - info["builds"] == 1
        assert store.loads == 1
    finally:
        persist_caches(None)


@pytest.mark.parametrize("filter", ["nearest", "bilinear"])
def test_point_sampling_plans_are_not_written(tmp_path, filter):
    """Building a nearest or bilinear plan is one pass over the output: not worth a file."""
    image = np.ones((16, 32, 3), np.float32)
    try:
        persist_caches(ArrayStore(tmp_path, 1 << 30))
        clear_caches()
        remap(image, "latlong", "cube", 4, filter=filter)
    finally:
        persist_caches(None)
    assert list(tmp_path.iterdir()) == []
