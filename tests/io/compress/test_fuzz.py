"""Broken compressed files: truncation at every offset is refused, and no mutation of a valid
file (header, level index, descriptor, Zstandard frames, blocks) makes a reader raise anything
but a BakeshopError."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from bakeshop.io.compress.texture import encode_texture
from bakeshop.io.dds import read_dds, write_dds_blocks
from bakeshop.io.ktx import read_ktx, write_ktx_blocks
from bakeshop.io.ktx2 import read_ktx2, write_ktx2_blocks
from tests.io import fuzzing
from tests.io.compress.conftest import hdr_chain, ldr_chain

READERS = {
    ".dds": lambda p: read_dds(p)[0],
    ".ktx2": lambda p: read_ktx2(p)[0],
    ".ktx": lambda p: read_ktx(p)[0],
}


@pytest.fixture(scope="module")
def seeds(tmp_path_factory):
    folder = tmp_path_factory.mktemp("compressed_seeds")
    cube = encode_texture(hdr_chain(21, 8), "bc6h")  # 8, 4, 2, 1
    flat = encode_texture(ldr_chain(22, 8, cube=False), "bc7")
    out = []
    for texture, tag in ((cube, "cube"), (flat, "flat")):
        for suffix, write in ((".dds", write_dds_blocks), (".ktx", write_ktx_blocks),
                              (".ktx2", write_ktx2_blocks)):  # fmt: skip
            path = folder / f"{tag}{suffix}"
            write(path, texture)
            out.append((suffix, path.read_bytes()))
        path = folder / f"{tag}_z.ktx2"
        write_ktx2_blocks(path, texture, supercompression="zstd", zstd_level=1)
        out.append((".ktx2", path.read_bytes()))
    return out


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    return tmp_path_factory.mktemp("compressed_fuzz")


@pytest.mark.slow
def test_truncation_at_every_offset_is_refused(scratch, seeds):
    for i, (suffix, data) in enumerate(seeds):
        path = scratch / f"t{i}{suffix}"
        fuzzing.assert_truncations_refused(path, data, read=READERS[suffix])


@fuzzing.FUZZ
@given(st.integers(0, 7), fuzzing.edits(400), st.integers(1, 2000))
def test_mutations_of_valid_files(scratch, seeds, which, changes, end):
    suffix, data = seeds[which]
    fuzzing.decode(scratch / f"m{suffix}", fuzzing.mutate(data, changes, end), READERS[suffix])
