"""PFM: bit-exact round trips, hand-built files in both byte orders (rows bottom to top), OpenCV
and OpenImageIO as independent readers and writers, bad headers, and fuzzing.

Reference behaviour of the peers (checked here, so an upgrade that changes it shows up):
OpenCV reads and writes PFM rows bottom to top as the format says (BGR channel order);
OpenImageIO 3.2 writes them bottom to top but *reads* them in file order, so its array is the
picture upside down. imageio has no PFM reader of its own (it delegates to OpenCV), so it is not
an independent reference here.
"""

from __future__ import annotations

import subprocess
import sys

import cv2
import numpy as np
import OpenImageIO as oiio
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import pfm, read_image, write_image
from tests.io import fuzzing


def gradient(height=6, width=5, channels=3):
    """An image whose every sample differs, so flips, transposes and channel swaps all show."""
    rows = np.arange(height, dtype=np.float32)[:, None, None] * 100
    cols = np.arange(width, dtype=np.float32)[None, :, None]
    chans = np.arange(channels, dtype=np.float32)[None, None, :] * 0.25
    return (rows + cols + chans).astype(np.float32)


def hand_built(image, byteorder, magic=None, header=None):
    """The bytes of a PFM file built by hand: header, then rows bottom to top."""
    h, w, c = image.shape
    magic = magic or {1: "Pf", 3: "PF", 4: "PF4"}[c]
    scale = "-1.0" if byteorder == "<" else "1.0"
    head = header if header is not None else f"{magic}\n{w} {h}\n{scale}\n".encode()
    return head + image[::-1].astype(byteorder + "f4").tobytes()


def same_bits(a, b):
    """Bitwise equality of two float32 arrays (NaN payloads, signed zeros and all)."""
    a, b = np.asarray(a, np.float32), np.asarray(b, np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


# --- round trips ------------------------------------------------------------------------------


@pytest.mark.parametrize("byteorder", ["<", ">"])
@pytest.mark.parametrize("channels", [1, 3])
def test_round_trip_is_bit_exact(tmp_path, byteorder, channels):
    rng = np.random.default_rng(1)
    image = (rng.standard_normal((17, 23, channels)) * 1e3).astype(np.float32)
    special = [np.nan, np.inf, -np.inf, -0.0, 1e-45, 3.4e38, -1e-40]
    image.flat[: len(special)] = special
    path = tmp_path / "x.pfm"
    write_image(path, image, byteorder=byteorder, scale=2.5)
    back, meta = read_image(path, with_metadata=True)
    assert back.dtype == np.float32 and back.dtype.isnative
    assert same_bits(back, image)
    assert meta["byteorder"] == byteorder and meta["scale"] == 2.5
    assert meta["format"] == "PFM" and meta["stored"] == "float32"


def test_two_dimensional_input_is_written_grey(tmp_path):
    image = gradient(4, 3, 1)[..., 0]
    write_image(tmp_path / "g.pfm", image)
    assert (tmp_path / "g.pfm").read_bytes().startswith(b"Pf\n3 4\n")
    assert same_bits(read_image(tmp_path / "g.pfm"), image[..., None])


def test_other_dtypes_are_written_as_float32(tmp_path):
    image = np.arange(12, dtype=np.float64).reshape(2, 2, 3) / 3
    write_image(tmp_path / "d.pfm", image)
    assert same_bits(read_image(tmp_path / "d.pfm"), image.astype(np.float32))


# --- hand-built files: byte order and row order -------------------------------------------------


@pytest.mark.parametrize("byteorder", ["<", ">"])
@pytest.mark.parametrize("channels", [1, 3, 4])
def test_hand_built_file_reads_top_row_first(tmp_path, byteorder, channels):
    image = gradient(6, 5, channels)
    path = tmp_path / "h.pfm"
    path.write_bytes(hand_built(image, byteorder))
    back, meta = pfm.read(path)
    assert same_bits(back, image), (byteorder, channels)
    assert back.dtype == np.float32 and back.dtype.isnative and back.flags.c_contiguous
    assert meta["byteorder"] == byteorder


def test_blocks_of_rows_land_in_order(tmp_path, monkeypatch):
    """Several read blocks, the last one short: rows still come out top to bottom."""
    image = gradient(7, 5, 3)
    path = tmp_path / "b.pfm"
    path.write_bytes(hand_built(image, "<"))
    monkeypatch.setattr(pfm, "_READ_BLOCK_BYTES", 2 * 5 * 3 * 4)  # two rows per block
    assert same_bits(pfm.read(path)[0], image)


@pytest.mark.parametrize("byteorder", ["<", ">"])
def test_writer_stores_rows_bottom_to_top(tmp_path, byteorder):
    image = gradient(6, 5, 3)
    write_image(tmp_path / "w.pfm", image, byteorder=byteorder)
    assert (tmp_path / "w.pfm").read_bytes() == hand_built(image, byteorder)


def test_the_array_does_not_depend_on_the_file(tmp_path):
    """Truncating the file after reading changes nothing and cannot kill the process (a memory
    map would die of SIGBUS at the first touch of a vanished page: run in a child to see it)."""
    path = tmp_path / "m.pfm"
    image = gradient(64, 256, 3)
    write_image(path, image)
    code = (
        "import sys, numpy as np\n"
        "from bakeshop.io import pfm\n"
        "image, meta = pfm.read(sys.argv[1])\n"
        "open(sys.argv[1], 'r+b').truncate(16)\n"
        "image[0, 0, 0] = -7.0\n"
        "print(float(image[1:].sum()))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(path)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert float(done.stdout) == pytest.approx(float(image[1:].sum(dtype=np.float64)), rel=1e-6)


def test_a_file_that_shrinks_while_being_read_is_a_format_error(tmp_path, monkeypatch):
    path = tmp_path / "s.pfm"
    write_image(path, gradient(8, 8, 3))
    header = pfm._header(path, pfm.MAX_PIXELS)
    with open(path, "r+b") as f:
        f.truncate(header["offset"] + 100)
    monkeypatch.setattr(pfm, "_header", lambda *args: header)  # the size seen before it shrank
    with pytest.raises(FormatError, match="truncated while being read"):
        pfm.read(path)


def test_foreign_byte_order_is_converted_to_native(tmp_path):
    path = tmp_path / "f.pfm"
    write_image(path, gradient(), byteorder=">" if np.little_endian else "<")
    back, meta = pfm.read(path)
    assert back.dtype.isnative and back.flags.c_contiguous
    assert meta["byteorder"] == (">" if np.little_endian else "<")


@pytest.mark.parametrize(
    "header",
    [
        b"PF\n5 6\n-1.0\n",  # canonical
        b"PF\r\n5 6\r\n-1.0\r\n",  # text mode on Windows: CR LF, recognised by the size
        b"PF 5 6 -1.0\n",  # one line
        b"PF\n5\t6\n-1\n",  # tab, integer scale
        b"PF\n  5   6  \n-1.000000 ",  # padding, one space after the scale
        b"PF\n# made by a tool\n5 6\n# scale next\n-1.0\n",  # netpbm-style comments
        b"PF\n5 6\n-0.003921569\n",  # a scale other than 1
    ],
)
def test_header_variants_real_writers_use(tmp_path, header):
    image = gradient(6, 5, 3)
    path = tmp_path / "v.pfm"
    path.write_bytes(hand_built(image, "<", header=header))
    assert same_bits(read_image(path), image)


# --- independent readers and writers ----------------------------------------------------------


@pytest.mark.parametrize("byteorder", ["<", ">"])
@pytest.mark.parametrize("channels", [1, 3])
def test_opencv_reads_what_bakeshop_writes(tmp_path, byteorder, channels):
    image = gradient(7, 9, channels)
    path = tmp_path / "o.pfm"
    write_image(path, image, byteorder=byteorder)
    theirs = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    theirs = theirs[..., None] if theirs.ndim == 2 else theirs[..., ::-1]  # BGR -> RGB
    assert same_bits(theirs, image)


@pytest.mark.parametrize("channels", [1, 3])
def test_bakeshop_reads_what_opencv_writes(tmp_path, channels):
    image = gradient(7, 9, channels)
    path = tmp_path / "c.pfm"
    assert cv2.imwrite(str(path), image[..., 0] if channels == 1 else image[..., ::-1].copy())
    assert same_bits(read_image(path), image)


def oiio_read(path):
    inp = oiio.ImageInput.open(str(path))
    try:
        return inp.read_image("float")
    finally:
        inp.close()


def test_openimageio_reads_what_bakeshop_writes(tmp_path):
    image = gradient(7, 9, 3)
    path = tmp_path / "i.pfm"
    write_image(path, image)
    # OpenImageIO 3.2 returns PFM rows in file order (bottom first): see the module docstring.
    assert same_bits(oiio_read(path)[::-1], image)


@pytest.mark.parametrize("channels", [1, 3])
def test_bakeshop_reads_what_openimageio_writes(tmp_path, channels):
    image = gradient(7, 9, channels)
    path = tmp_path / "j.pfm"
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(9, 7, channels, "float"))
    assert out.write_image(image)
    out.close()
    assert same_bits(read_image(path), image)


# --- bad files and bad arguments ----------------------------------------------------------------


@pytest.mark.parametrize(
    "data, words",
    [
        (b"PF\n5 6\n-1.0\n" + bytes(4 * 3 * 30 - 1), "truncated"),
        (b"PF\n5 6\n-1.0\n", "truncated"),
        (b"PF\n5 6\n", "header"),
        (b"PF\n-5 6\n-1.0\n" + bytes(400), "size"),
        (b"PF\n5 0\n-1.0\n" + bytes(400), "size"),
        (b"PF\n5x 6\n-1.0\n" + bytes(400), "size"),
        (b"PF\n5 6\nnan\n" + bytes(400), "scale"),
        (b"PF\n5 6\n1e999\n" + bytes(400), "scale"),
        (b"PF\n5 6\nabc\n" + bytes(400), "scale"),
        (b"PF\n99999999 99999999\n-1.0\n" + bytes(400), "exceeds"),
        (b"PF\n" + b"9" * 5000 + b" 6\n-1.0\n" + bytes(400), "size"),  # beyond int()'s digits
        (b"PF\n" + b"#" * 70000, "header"),
    ],
)
def test_bad_files_give_a_clear_error(tmp_path, data, words):
    fuzzing.assert_refused(tmp_path / "bad.pfm", data, words)


def test_not_a_pfm_and_unknown_extension(tmp_path):
    (tmp_path / "p.pfm").write_bytes(b"P6\n2 2\n255\n" + bytes(12))
    with pytest.raises(FormatError, match="not a PFM"):
        read_image(tmp_path / "p.pfm")
    write_image(tmp_path / "ok.pfm", gradient())
    (tmp_path / "ok.pfmx").write_bytes((tmp_path / "ok.pfm").read_bytes())
    with pytest.raises(UnsupportedError, match="extension"):
        read_image(tmp_path / "ok.pfmx")


def test_large_file_is_refused_unless_allowed(tmp_path):
    path = tmp_path / "big.pfm"
    write_image(path, np.zeros((64, 64), np.float32))
    with pytest.raises(FormatError, match="max_pixels"):
        read_image(path, max_pixels=1000)
    assert read_image(path, max_pixels=4096).shape == (64, 64, 1)


@pytest.mark.parametrize(
    "image, options, words",
    [
        (np.zeros((2, 2, 4), np.float32), {}, "alpha"),
        (np.zeros((2, 2, 3), np.float32), {"byteorder": "="}, "byte order"),
        (np.zeros((2, 2, 3), np.float32), {"scale": 0.0}, "scale"),
        (np.zeros((2, 2, 3), np.float32), {"scale": np.nan}, "scale"),
        (np.zeros((2, 2, 3), np.complex64), {}, "complex"),
        (np.zeros((2, 2, 2), np.float32), {}, "shape"),
        (np.zeros((2, 2, 3), np.float32), {"quality": 3}, "quality"),
    ],
)
def test_bad_write_arguments(tmp_path, image, options, words):
    with pytest.raises(ArgumentError, match=words):
        write_image(tmp_path / "a.pfm", image, **options)
    assert list(tmp_path.iterdir()) == []  # nothing half-written


# --- fuzzing: only BakeshopError may escape ------------------------------------------------------

SMALL = hand_built(gradient(3, 2, 3), "<")
SMALL_GREY_BE = hand_built(gradient(2, 3, 1), ">")
scratch = fuzzing.scratch_file("f.pfm", seeds=[SMALL, SMALL_GREY_BE])


@pytest.mark.parametrize("data", [SMALL, SMALL_GREY_BE])
def test_truncation_at_every_offset_is_refused(scratch, data):
    fuzzing.assert_truncations_refused(scratch, data)


@fuzzing.FUZZ
@given(st.binary(max_size=200))
def test_random_bytes(scratch, data):
    fuzzing.decode(scratch, data)
    fuzzing.decode(scratch, b"PF\n" + data)


@fuzzing.FUZZ
@given(st.sampled_from([SMALL, SMALL_GREY_BE]), fuzzing.edits(120), st.integers(1, 200))
def test_mutations_of_a_valid_file(scratch, data, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(data, changes, end))
