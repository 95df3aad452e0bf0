"""Window readers and strip writers (bakeshop.io.stream) against the in-memory codecs."""

import pickle

import numpy as np
import pytest

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io import read_image, write_image
from bakeshop.io.stream import open_image, write_strips


def _image(h=300, w=500, c=3, seed=0):
    rng = np.random.default_rng(seed)
    return (rng.random((h, w, c)) ** 4 * 100).astype(np.float32)


@pytest.mark.parametrize("ext", ["pfm", "hdr", "exr", "tif", "zarr"])
def test_windows_equal_the_whole_read(tmp_path, ext):
    a = _image()
    path = tmp_path / f"x.{ext}"
    options = {"pixel_type": "float"} if ext == "exr" else {}
    write_strips(path, a.shape, (a[y : y + 37] for y in range(0, 300, 37)), **options)
    reader = open_image(path)
    assert reader.shape == a.shape and reader.dtype == np.float32
    whole = read_image(path) if ext in ("pfm", "hdr", "exr") else a
    if ext != "hdr":
        assert np.array_equal(whole, a)  # float formats: the strips went in exactly
    for rows, cols in (((13, 290), (7, 433)), ((0, 1), (0, 500)), ((299, 300), (499, 500))):
        window = reader.read(rows, cols)
        assert np.array_equal(window, whole[slice(*rows), slice(*cols)])
    # a reader travels to a dask worker as its header and path
    again = pickle.loads(pickle.dumps(reader))
    assert np.array_equal(again.read((5, 9)), reader.read((5, 9)))


def test_radiance_windows_of_a_file_written_by_the_in_memory_codec(tmp_path):
    a = _image(64, 96)
    write_image(tmp_path / "x.hdr", a)
    reader = open_image(tmp_path / "x.hdr")
    assert np.array_equal(
        reader.read((10, 50), (3, 90)), read_image(tmp_path / "x.hdr")[10:50, 3:90]
    )


def test_headers_are_checked_before_anything_is_read(tmp_path):
    path = tmp_path / "big.pfm"
    path.write_bytes(b"PF\n100000 100000\n-1.0\n" + b"\0" * 1000)
    with pytest.raises(FormatError, match="truncated"):
        open_image(path)
    path = tmp_path / "short.hdr"
    a = _image(32, 64)
    write_image(path, a)
    path.write_bytes(path.read_bytes()[:-100])
    reader = open_image(path)  # the header is whole; the scanlines are walked on the first read
    with pytest.raises(FormatError, match="truncated"):
        reader.read((0, 1))


def test_a_window_outside_the_image_is_refused(tmp_path):
    a = _image(20, 30)
    write_image(tmp_path / "x.pfm", a)
    with pytest.raises(BakeshopError, match="not inside"):
        open_image(tmp_path / "x.pfm").read((10, 21))


def test_a_pickled_radiance_reader_carries_its_scanline_index(tmp_path):
    """Opening reads the header only; pickling (a dask task's copy) indexes the scanlines once,
    so the tasks that unpickle it do not each walk the file."""
    import pickle

    path = tmp_path / "x.hdr"
    a = _image(24, 40)
    write_image(path, a)
    reader = open_image(path)
    assert "starts" not in reader.__dict__
    copy = pickle.loads(pickle.dumps(reader))
    assert len(copy.__dict__["starts"]) == 25
    np.testing.assert_array_equal(copy.read((3, 9)), reader.read((3, 9)))


@pytest.mark.parametrize("ext", ["exr", "tif", "zarr"])
def test_half_strips_refuse_a_value_beyond_65504(tmp_path, ext):
    """A sun in the last strip: half floats would clamp it (EXR) or make it infinite (TIFF,
    zarr); refused, naming the option that keeps it, and nothing is left behind."""
    a = _image(h=64, w=32)
    a[-1, -1] = 1e5
    path = tmp_path / f"x.{ext}"
    with pytest.raises(BakeshopError, match="reach 1e\\+05, beyond .* pixel_type=float keeps"):
        write_strips(path, a.shape, (a[y : y + 16] for y in range(0, 64, 16)), pixel_type="half")
    assert not path.exists() and list(tmp_path.iterdir()) == []
