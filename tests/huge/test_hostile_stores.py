"""Chunked inputs that are damaged or too coarse for the memory bound: corrupt zarr chunks,
empty chunk shapes and truncated BigTIFF tiles fail in one line naming the file, and a chunk
that cannot fit the bound is refused, from its shape, before it is read."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
import tifffile
import zarr

from bakeshop.cli.main import main
from bakeshop.errors import FormatError
from bakeshop.huge import Engine, resize
from bakeshop.huge.memory import MemoryBoundError
from bakeshop.io.stream import open_image, write_strips
from tests.cli.test_process import one_error_line


def _panorama(h: int = 64, w: int = 128) -> np.ndarray:
    rng = np.random.default_rng(3)
    return rng.uniform(0.1, 2.0, (h, w, 3)).astype(np.float32)


@pytest.fixture
def store(tmp_path):
    path = tmp_path / "pano.zarr"
    write_strips(path, (64, 128, 3), [_panorama()], chunks=(32, 32))
    return path


def _chunk_files(store):
    return sorted(p for p in (store / "c").rglob("*") if p.is_file())


def test_a_corrupt_zarr_chunk_is_one_line_naming_the_store(store, tmp_path, capfd):
    chunk = _chunk_files(store)[0]
    chunk.write_bytes(b"not zstd" + chunk.read_bytes()[8:])
    with pytest.raises(FormatError, match="corrupt or truncated data in rows 0..") as error:
        open_image(store).read((0, 8), (0, 8))
    assert error.value.path == str(store)
    status = main(["-q", "resize", str(store), str(tmp_path / "o.zarr"), "--size", "64x32"])
    assert status == 2
    line = one_error_line(capfd)
    assert line.startswith(f"bakeshop: error: {store}: corrupt or truncated")
    assert not re.search(r"\(\w+: ", line)  # the reason, not Python's class name


def test_an_empty_chunk_shape_is_refused_when_opened(store):
    meta = json.loads((store / "zarr.json").read_text())
    meta["chunk_grid"]["configuration"]["chunk_shape"] = [0, 32, 3]
    (store / "zarr.json").write_text(json.dumps(meta))
    with pytest.raises(FormatError) as error:
        open_image(store)
    assert error.value.path == str(store)


@pytest.mark.parametrize("damage", ["corrupt", "truncated"])
def test_a_damaged_bigtiff_tile_is_one_line(tmp_path, capfd, damage):
    path = tmp_path / "pano.tif"
    write_strips(path, (64, 128, 3), [_panorama()], tile=32, compression="zlib")
    with tifffile.TiffFile(path) as tif:
        offsets = tif.pages.first.dataoffsets
    data = bytearray(path.read_bytes())
    if damage == "corrupt":
        data[offsets[0] : offsets[0] + 16] = bytes(16)  # not a zlib stream
    else:
        del data[max(offsets) + 8 :]  # the last tile cut short
    path.write_bytes(bytes(data))
    with pytest.raises(FormatError, match="corrupt or truncated data") as error:
        open_image(path).read()
    assert error.value.path == str(path)
    status = main(["-q", "resize", str(path), str(tmp_path / "o.zarr"), "--size", "64x32"])
    assert status == 2
    line = one_error_line(capfd)
    assert line.startswith(f"bakeshop: error: {path}: ") and not re.search(r"\(\w+: ", line)


def test_a_chunk_larger_than_the_bound_is_refused_from_its_shape(tmp_path, capfd):
    # one 2048 x 2048 x 3 float32 chunk (48 MiB, inflated whole by any read) under 16 MiB
    path = tmp_path / "one_chunk.zarr"
    a = zarr.create_array(
        store=str(path), shape=(2048, 2048, 3), chunks=(2048, 2048, 3), dtype="f4",
        fill_value=0.0,
    )  # fmt: skip
    a[:8, :8] = 1.0
    reader = open_image(path)
    assert reader.read_floor == 2 * 48 << 20
    with pytest.raises(MemoryBoundError, match="--memory") as error:
        resize(reader, (256, 128), engine=Engine("synchronous", 16 << 20))
    assert error.value.path == str(path) and error.value.needed >= 96 << 20
    status = main(["-q", "resize", str(path), str(tmp_path / "o.zarr"), "--size", "256x128",
                   "--memory", "16MiB"])  # fmt: skip
    assert status == 2
    line = one_error_line(capfd)
    assert line.startswith(f"bakeshop: error: {path}: ") and "--memory" in line


@pytest.mark.parametrize("command", ["dims", "remap"])
def test_dims_and_remap_read_a_zarr_store(store, tmp_path, capfd, command):
    if command == "dims":
        argv = ["dims", str(store), "-o", str(tmp_path / "d"), "--size", "16x8"]
        written = tmp_path / "d" / "sun.json"
    else:
        argv = ["remap", str(store), str(tmp_path / "r.exr"), "--to", "latlong", "--size", "32x16"]
        written = tmp_path / "r.exr"
    assert main(["-q", *argv]) == 0, capfd.readouterr().err
    assert written.is_file()


def test_a_tasks_share_of_the_bound_leaves_room_for_its_chunk(store):
    reader = open_image(store)  # 32 x 32 x 3 float32 chunks: 12 KiB, 24 KiB with their bytes
    assert reader.read_floor == 2 * 32 * 32 * 3 * 4
    engine = Engine("synchronous", 8 << 20)
    assert engine.per_task(1 << 20, reader) == (7 << 20) - reader.read_floor
    assert engine.per_task(1 << 20) == 7 << 20
