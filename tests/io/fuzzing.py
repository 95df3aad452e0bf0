"""The bad-input harness every codec test shares: a broken file is refused with a clear
BakeshopError naming the problem and the file, and no bytes at all (truncated, mutated or random)
make a reader crash, hang or raise anything else.

A codec's tests keep their own seed files and expectations; the mechanics live here:

    from tests.io import fuzzing

    scratch = fuzzing.scratch_file("f.pfm", seeds=SEEDS)  # a module-scoped fixture

    @fuzzing.FUZZ
    @given(st.sampled_from(SEEDS), fuzzing.edits(120), st.integers(1, 200))
    def test_mutations_of_valid_files(scratch, data, changes, end):
        fuzzing.decode(scratch, fuzzing.mutate(data, changes, end))
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io import read_image

#: One profile for every codec's fuzz tests. The deadline only guards against hangs on this
#: shared, loaded machine (no timing is asserted); ``tmp_path`` is reused across examples on
#: purpose, since every example rewrites the whole file.
FUZZ = settings(
    max_examples=200, deadline=3000, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


def decode(path: Path, data: bytes, read: Callable = read_image):
    """Write ``data`` to ``path`` and read it back with ``read``.

    Returns what ``read`` returns (an image, or a list of mip levels), or None when bakeshop
    refused the file with a BakeshopError; any other exception escapes and fails the test. Every
    pixel is touched, so a lazily mapped file is read to its end.
    """
    path.write_bytes(data)
    try:
        image = read(path)
    except BakeshopError:
        return None
    for array in image if isinstance(image, list) else [image]:
        float(np.sum(array, dtype=np.float64))
    return image


def scratch_file(name: str, seeds: Sequence[bytes] = ()):
    """A module-scoped fixture: the path ``name`` in a fresh folder, rewritten by each decode.

    Every seed must decode, which also loads (or compiles) the codec's kernels before any timed
    Hypothesis example runs.
    """

    @pytest.fixture(scope="module", name="scratch")
    def fixture(tmp_path_factory):
        path = tmp_path_factory.mktemp("fuzz") / name
        for i, data in enumerate(seeds):
            assert decode(path, data) is not None, i
        return path

    return fixture


def assert_truncations_refused(path: Path, data: bytes, *, tail: int = 0, read=read_image):
    """``data`` decodes; every shorter prefix is decoded and, except for the last ``tail``
    lengths (bytes a format lets go missing, such as a trailing footer), refused."""
    assert decode(path, data, read) is not None
    for end in range(len(data)):
        image = decode(path, data[:end], read)
        if end < len(data) - tail:
            assert image is None, end


def edits(last_position: int, *, min_size: int = 0):
    """Up to six byte overwrites ``(position, value)`` with positions in ``0..last_position``."""
    pair = st.tuples(st.integers(0, last_position), st.integers(0, 255))
    return st.lists(pair, min_size=min_size, max_size=6)


def mutate(data: bytes, changes, end: int | None = None) -> bytes:
    """``data`` with each ``(position, value)`` in ``changes`` written (positions past the end
    ignored), then cut to its first ``end`` bytes."""
    out = bytearray(data)
    for position, value in changes:
        if position < len(out):
            out[position] = value
    return bytes(out[:end])


def assert_refused(path: Path, data: bytes, words: str | None, error=FormatError, read=read_image):
    """Reading ``data`` from ``path`` raises ``error`` whose message matches ``words`` (None: any
    message) and whose ``path`` names the file."""
    path.write_bytes(data)
    with pytest.raises(error, match=words) as info:
        read(path)
    assert info.value.path == str(path)
    return info.value
