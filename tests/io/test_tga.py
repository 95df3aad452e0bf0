"""TGA: hand-built files for every image type, depth, origin and colour-map form (bytes packed with
struct here, so the expected picture is known independently of any decoder), RLE packets that
cross scanlines, bad files, Pillow / imageio / OpenImageIO as independent readers and writers,
exact round trips, and fuzzing.

Reference behaviour of the peers: OpenCV has no TGA codec (cv2.imread returns None), so it is not
a reference here. OpenImageIO premultiplies a TGA's alpha unless asked not to
(``oiio:UnassociatedAlpha``), and its float conversion of 8-bit samples is v * (1/255), one ulp
away from v / 255 for some v: comparisons with it are done on the 8-bit samples.
"""

from __future__ import annotations

import struct
import tracemalloc

import imageio.v3 as iio
import numpy as np
import OpenImageIO as oiio
import pytest
from hypothesis import given
from hypothesis import strategies as st
from PIL import Image

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import read_image, tga, write_image
from tests.io import fuzzing

FOOTER = struct.pack("<II", 0, 0) + b"TRUEVISION-XFILE.\0"


def tga_bytes(
    image_type,
    width,
    height,
    depth,
    data,
    *,
    descriptor=0x20,
    cmap=b"",
    cmap_first=0,
    cmap_len=0,
    cmap_bits=0,
    image_id=b"",
    trailer=b"",
):
    """A TGA file assembled field by field (Truevision TGA 2.0 specification, table 1)."""
    header = struct.pack(
        "<BBBHHBHHHHBB",
        len(image_id),
        1 if cmap_len else 0,
        image_type,
        cmap_first,
        cmap_len,
        cmap_bits,
        0,
        0,
        width,
        height,
        depth,
        descriptor,
    )
    return header + image_id + cmap + bytes(data) + trailer


def bgr(rgb):
    """Pack RGB(A) 8-bit tuples into the file's B, G, R(, A) byte order."""
    out = bytearray()
    for p in rgb:
        out += bytes([p[2], p[1], p[0], *p[3:]])
    return bytes(out)


#: a 3 x 2 picture (top row first), each pixel different: (R, G, B, A)
PICTURE = np.array(
    [
        [(255, 0, 0, 255), (0, 255, 0, 128), (0, 0, 255, 0)],
        [(10, 20, 30, 40), (50, 60, 70, 80), (90, 100, 110, 120)],
    ],
    np.uint8,
)


def stored_rows(picture, origin):
    """The picture's pixels in the order a file with ``origin`` stores them."""
    p = picture
    if origin.startswith("bottom"):
        p = p[::-1]
    if origin.endswith("right"):
        p = p[:, ::-1]
    return p.reshape(-1, p.shape[-1])


DESCRIPTOR = {"bottom-left": 0x00, "bottom-right": 0x10, "top-left": 0x20, "top-right": 0x30}


def write_bytes(tmp_path, data, name="x.tga"):
    path = tmp_path / name
    path.write_bytes(data)
    return path


def as_u8(image):
    return np.rint(np.asarray(image) * 255).astype(np.uint8)


def oiio_u8(path):
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    f = oiio.ImageInput.open(str(path), config)
    try:
        return f.read_image("uint8")
    finally:
        f.close()


# --- hand-built files -------------------------------------------------------------------------


@pytest.mark.parametrize("origin", list(DESCRIPTOR))
@pytest.mark.parametrize("depth", [24, 32])
def test_true_colour_every_origin(tmp_path, origin, depth):
    channels = depth // 8
    rows = stored_rows(PICTURE[..., :channels], origin)
    alpha_bits = 8 if depth == 32 else 0
    data = tga_bytes(2, 3, 2, depth, bgr(rows), descriptor=DESCRIPTOR[origin] | alpha_bits)
    path = write_bytes(tmp_path, data)
    image, meta = read_image(path, with_metadata=True)
    assert image.dtype == np.float32 and image.shape == (2, 3, channels)
    np.testing.assert_array_equal(image, PICTURE[..., :channels] / np.float32(255))
    assert meta == {
        "format": "TGA",
        "stored": "uint8",
        "bits": depth,
        "type": 2,
        "kind": "true-colour",
        "origin": origin,
        "rle": False,
        "alpha_bits": alpha_bits,
    }
    # the independent readers agree on the picture
    np.testing.assert_array_equal(np.asarray(Image.open(path)), PICTURE[..., :channels])
    np.testing.assert_array_equal(oiio_u8(path), PICTURE[..., :channels])


def test_32_bit_without_alpha_bits_keeps_the_fourth_byte(tmp_path):
    data = tga_bytes(2, 3, 2, 32, bgr(stored_rows(PICTURE, "top-left")), descriptor=0x20)
    image, meta = read_image(write_bytes(tmp_path, data), with_metadata=True)
    assert meta["alpha_bits"] == 0
    np.testing.assert_array_equal(as_u8(image), PICTURE)


def pack_555(r, g, b, a=0):
    return struct.pack("<H", (a << 15) | (r << 10) | (g << 5) | b)


FIVE = [(31, 0, 0, 1), (0, 31, 0, 0), (0, 0, 31, 1), (1, 2, 3, 0), (16, 8, 4, 1), (30, 29, 28, 0)]


@pytest.mark.parametrize(("depth", "alpha_bits", "channels"), [(15, 0, 3), (16, 0, 3), (16, 1, 4)])
def test_five_bit_colour(tmp_path, depth, alpha_bits, channels):
    data = b"".join(pack_555(*p) for p in FIVE)  # bottom row first (origin bottom-left)
    path = write_bytes(tmp_path, tga_bytes(2, 3, 2, depth, data, descriptor=alpha_bits))
    image, meta = read_image(path, with_metadata=True)
    expected = np.array(FIVE, np.float32).reshape(2, 3, 4)[::-1]
    expected[..., :3] /= 31
    np.testing.assert_array_equal(image, expected[..., :channels])
    assert meta["stored"] == "uint5" and meta["bits"] == depth
    # OpenImageIO expands 5 bits to 8 by bit replication (v << 3 | v >> 2), within one level of
    # v * 255 / 31. It reads no alpha from 16-bit files; Pillow cannot open 15-bit ones and
    # reads the 16-bit attribute bit inverted (set = transparent), against GIMP and TGA 2.0.
    five = np.rint(image[..., :3] * 31).astype(np.uint8)
    np.testing.assert_array_equal(oiio_u8(path), (five << 3) | (five >> 2))


def test_grey_and_grey_alpha(tmp_path):
    grey = np.array([[0, 7, 255], [128, 1, 254]], np.uint8)
    path = write_bytes(tmp_path, tga_bytes(3, 3, 2, 8, grey.tobytes()))
    image, meta = read_image(path, with_metadata=True)
    assert image.shape == (2, 3, 1) and meta["kind"] == "grey"
    np.testing.assert_array_equal(image[..., 0], grey / np.float32(255))
    np.testing.assert_array_equal(np.asarray(Image.open(path)), grey)

    alpha = np.array([[255, 0, 9], [10, 11, 12]], np.uint8)
    ga = np.stack([grey, alpha], -1)
    path = write_bytes(tmp_path, tga_bytes(3, 3, 2, 16, ga.tobytes(), descriptor=0x28), "ga.tga")
    image = read_image(path)
    assert image.shape == (2, 3, 4)
    np.testing.assert_array_equal(as_u8(image), np.stack([grey, grey, grey, alpha], -1))
    np.testing.assert_array_equal(np.asarray(Image.open(path).convert("RGBA")), as_u8(image))


@pytest.mark.parametrize("cmap_bits", [15, 16, 24, 32])
@pytest.mark.parametrize("index_bits", [8, 16])
def test_colour_mapped(tmp_path, cmap_bits, index_bits):
    first = 5
    if cmap_bits in (15, 16):
        entries = [(31, 0, 0, 1), (0, 31, 0, 0), (3, 7, 11, 1), (30, 20, 10, 0)]
        cmap = b"".join(pack_555(*e) for e in entries)
        colours = np.array(entries, np.float32)
        colours[:, :3] /= 31
        channels = 4 if cmap_bits == 16 else 3
    else:
        entries = [(255, 0, 0, 255), (0, 255, 0, 0), (1, 2, 3, 4), (200, 100, 50, 25)]
        cmap = bgr([e[: cmap_bits // 8] for e in entries])
        colours = np.array(entries, np.float32) / 255
        channels = cmap_bits // 8
    picture = np.array([[3, 0, 1], [2, 2, 3]])  # entry numbers, top row first
    indices = (picture[::-1] + first).astype("<u1" if index_bits == 8 else "<u2")
    data = tga_bytes(
        1,
        3,
        2,
        index_bits,
        indices.tobytes(),
        descriptor=1 if cmap_bits == 16 else 0,
        cmap=cmap,
        cmap_first=first,
        cmap_len=4,
        cmap_bits=cmap_bits,
    )
    image, meta = read_image(write_bytes(tmp_path, data), with_metadata=True)
    np.testing.assert_array_equal(image, colours[picture][..., :channels])
    assert meta["colormap"] == {"first": first, "length": 4, "bits": cmap_bits}
    assert meta["type"] == 1


def test_colour_mapped_matches_pillow(tmp_path):
    rng = np.random.default_rng(3)
    palette = rng.integers(0, 256, (256, 3), dtype=np.uint8)
    picture = rng.integers(0, 256, (9, 11), dtype=np.uint8)
    data = tga_bytes(1, 11, 9, 8, picture.tobytes(), cmap=bgr(palette), cmap_len=256, cmap_bits=24)
    path = write_bytes(tmp_path, data)
    np.testing.assert_array_equal(as_u8(read_image(path)), palette[picture])
    np.testing.assert_array_equal(np.asarray(Image.open(path).convert("RGB")), palette[picture])


def test_image_id_unused_colour_map_and_footer_are_skipped(tmp_path):
    rows = stored_rows(PICTURE[..., :3], "top-left")
    data = tga_bytes(
        2,
        3,
        2,
        24,
        bgr(rows),
        image_id=b"made by hand",
        cmap=b"\x01\x02\x03" * 2,
        cmap_len=2,
        cmap_bits=24,
        trailer=b"\x00" * 40 + FOOTER,
    )
    image, meta = read_image(write_bytes(tmp_path, data), with_metadata=True)
    np.testing.assert_array_equal(as_u8(image), PICTURE[..., :3])
    assert meta["image_id"] == "made by hand"


def run(count, pixel):
    return bytes([0x80 | (count - 1)]) + pixel


def raw(*pixels):
    return bytes([len(pixels) - 1]) + b"".join(pixels)


def test_rle_packets_crossing_scanlines(tmp_path):
    # a 3 x 3 picture, bottom row first; packets straddle rows 0/1 and 1/2
    a, b, c, d = (bytes([i, 2 * i, 3 * i]) for i in (10, 20, 30, 40))
    packets = run(4, a) + raw(b, c, d, b) + run(1, c)
    path = write_bytes(tmp_path, tga_bytes(10, 3, 3, 24, packets, descriptor=0))
    image, meta = read_image(path, with_metadata=True)
    file_order = [a, a, a, a, b, c, d, b, c]
    expected = np.array([[p[2], p[1], p[0]] for p in file_order], np.uint8).reshape(3, 3, 3)
    np.testing.assert_array_equal(as_u8(image), expected[::-1])
    assert meta["rle"] and meta["type"] == 10 and meta["origin"] == "bottom-left"
    np.testing.assert_array_equal(oiio_u8(path), expected[::-1])
    with pytest.raises(OSError, match="buffer overrun"):  # Pillow refuses packets across rows
        Image.open(path).load()


@pytest.mark.parametrize("origin", list(DESCRIPTOR))
def test_rle_grey_and_colour_mapped(tmp_path, origin):
    grey = np.arange(12, dtype=np.uint8).reshape(3, 4) * 20
    grey[1] = 99  # the middle row, stored as pixels 4..7 whatever the origin
    stored = [bytes([v]) for v in stored_rows(grey[..., None], origin)[:, 0]]
    packets = raw(*stored[:6]) + run(2, stored[6]) + raw(*stored[8:])  # the first crosses rows
    image = read_image(
        write_bytes(tmp_path, tga_bytes(11, 4, 3, 8, packets, descriptor=DESCRIPTOR[origin]))
    )
    np.testing.assert_array_equal(as_u8(image)[..., 0], grey)

    palette = bgr([(255, 0, 0), (0, 255, 0), (0, 0, 255)])
    packets = run(5, b"\x02") + raw(b"\x03", b"\x04") + run(5, b"\x03")  # first entry is 2
    data = tga_bytes(
        9, 4, 3, 8, packets, descriptor=0x20, cmap=palette, cmap_first=2, cmap_len=3, cmap_bits=24
    )
    image = read_image(write_bytes(tmp_path, data, "cm.tga"))
    expected = np.array([0] * 5 + [1, 2] + [1] * 5).reshape(3, 4)
    np.testing.assert_array_equal(
        as_u8(image), np.array([(255, 0, 0), (0, 255, 0), (0, 0, 255)], np.uint8)[expected]
    )


@pytest.mark.parametrize(
    ("image_type", "depth", "descriptor", "cmap_bits"),
    [(2, 15, 0, 0), (2, 16, 1, 0), (2, 24, 0, 0), (2, 32, 8, 0), (3, 8, 0, 0), (3, 16, 8, 0),
     (1, 8, 0, 24), (1, 16, 0, 32)],
)  # fmt: skip
def test_every_rle_form_equals_its_uncompressed_form(tmp_path, image_type, depth, descriptor,
                                                      cmap_bits):  # fmt: skip
    """The same pixel stream, plain and as RLE packets (runs and literals crossing rows)."""
    size = (depth + 7) // 8
    rng = np.random.default_rng(depth)
    if image_type == 1:  # indices 3..10 into an 8-entry map starting at 3
        cmap = rng.integers(0, 256, 8 * cmap_bits // 8, dtype=np.uint8).tobytes()
        unique = [int(i).to_bytes(size, "little") for i in rng.integers(3, 11, 40)]
        extra = {"cmap": cmap, "cmap_first": 3, "cmap_len": 8, "cmap_bits": cmap_bits}
    else:
        unique = [rng.integers(0, 256, size, dtype=np.uint8).tobytes() for _ in range(40)]
        extra = {}
    stream, packets = [], b""
    for k in range(0, 40, 4):  # 2 literal pixels, then a run of 3, or of 129 sent as 128 + 1
        literal, repeated = unique[k : k + 2], unique[k + 2]
        stream += literal + [repeated] * (129 if k % 8 == 0 else 3)
        packets += raw(*literal)
        packets += run(128, repeated) + run(1, repeated) if k % 8 == 0 else run(3, repeated)
    width, height = 17, 40  # 680 pixels: packets cross rows everywhere
    assert len(stream) == width * height
    plain = tga_bytes(image_type, width, height, depth, b"".join(stream), descriptor=descriptor,
                      **extra)  # fmt: skip
    rle = tga_bytes(image_type + 8, width, height, depth, packets, descriptor=descriptor, **extra)
    expected, meta = read_image(write_bytes(tmp_path, plain, "p.tga"), with_metadata=True)
    image, rle_meta = read_image(write_bytes(tmp_path, rle, "r.tga"), with_metadata=True)
    np.testing.assert_array_equal(image, expected)
    assert rle_meta["rle"] and not meta["rle"] and rle_meta["bits"] == depth
    # one pixel fewer in the header: the last packet now runs past the end
    short = tga_bytes(image_type + 8, width, height - 1, depth, packets, descriptor=descriptor,
                      **extra)  # fmt: skip
    with pytest.raises(FormatError, match="past the last pixel"):
        read_image(write_bytes(tmp_path, short, "s.tga"))


# --- bad files ----------------------------------------------------------------------------------


def small_rle():
    return tga_bytes(10, 3, 3, 24, run(4, b"\x01\x02\x03") + run(5, b"\x04\x05\x06"))


@pytest.mark.parametrize(
    ("data", "reason"),
    [
        (tga_bytes(2, 3, 2, 24, b"\x00" * 17), "truncated"),
        (tga_bytes(10, 3, 3, 24, run(4, b"\x01\x02\x03") + run(6, b"\x04\x05\x06")), "past"),
        (tga_bytes(10, 3, 3, 24, run(4, b"\x01\x02\x03") + run(5, b"\x04")), "truncated"),
        (tga_bytes(10, 3, 3, 24, run(4, b"\x01\x02\x03") + raw(b"\x04\x05\x06")), "truncated"),
        (tga_bytes(11, 200, 200, 8, run(128, b"\x01") * 3), "truncated"),
        (tga_bytes(2, 0, 2, 24, b""), "size"),
        (tga_bytes(0, 3, 2, 24, b""), "no image data"),
        (tga_bytes(7, 3, 2, 24, b"\x00" * 18), "not a TGA"),
        (tga_bytes(2, 3, 2, 12, b"\x00" * 18), "12-bit"),
        (tga_bytes(3, 3, 2, 24, b"\x00" * 18), "24-bit"),
        (tga_bytes(1, 3, 2, 8, b"\x00" * 6), "without a colour map"),
        (b"\x00\x00\x02\x00", "truncated"),
        (
            tga_bytes(1, 2, 1, 8, b"\x01\x04", cmap=b"\x00" * 9, cmap_first=1, cmap_len=3,
                      cmap_bits=24),
            "index 4 is outside",
        ),
        (
            tga_bytes(1, 2, 1, 8, b"\x00\x01", cmap=b"\x00" * 9, cmap_first=1, cmap_len=3,
                      cmap_bits=24),
            "index 0 is outside",
        ),
        (tga_bytes(1, 2, 1, 8, b"\x00\x01", cmap=b"\x00" * 8, cmap_len=3, cmap_bits=24),
         "truncated"),
        (tga_bytes(2, 2, 1, 24, b"\x00" * 6, cmap=b"\x00" * 3, cmap_len=1, cmap_bits=12),
         "entry size"),
    ],
)  # fmt: skip
def test_bad_files_are_format_errors(tmp_path, data, reason):
    fuzzing.assert_refused(tmp_path / "x.tga", data, reason)


@pytest.mark.parametrize(("image_type", "descriptor"), [(32, 0x20), (2, 0x60)])
def test_unsupported_variants(tmp_path, image_type, descriptor):
    data = tga_bytes(image_type, 1, 1, 24, b"\x00" * 3, descriptor=descriptor)
    with pytest.raises(UnsupportedError):
        read_image(write_bytes(tmp_path, data))


@pytest.mark.parametrize(("image_type", "width", "height"), [(2, 60000, 60000), (10, 4000, 4000)])
def test_lying_size_is_refused_before_allocating(tmp_path, image_type, width, height):
    path = write_bytes(tmp_path, tga_bytes(image_type, width, height, 32, b"\x00" * 100))
    tracemalloc.start()
    try:
        with pytest.raises(FormatError, match="truncated|exceeds"):
            read_image(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1 << 20


# --- writing --------------------------------------------------------------------------------------


@pytest.mark.parametrize("channels", [1, 3, 4])
@pytest.mark.parametrize("rle", [False, True])
@pytest.mark.parametrize("origin", ["top-left", "bottom-left"])
def test_round_trip_exact_and_peers_agree(tmp_path, channels, rle, origin):
    rng = np.random.default_rng(channels)
    image = rng.integers(0, 256, (19, 300, channels), dtype=np.uint8)
    image[3:9, 20:290] = 77  # long runs, also across the 128-pixel packet limit
    image[10, ::2] = 5
    path = tmp_path / "w.tga"
    write_image(path, image, rle=rle, origin=origin)
    back, meta = read_image(path, with_metadata=True)
    np.testing.assert_array_equal(back, image / np.float32(255))
    assert meta["rle"] == rle and meta["origin"] == origin
    assert meta["bits"] == 8 * channels and meta["alpha_bits"] == (8 if channels == 4 else 0)
    expected = image[..., 0] if channels == 1 else image
    np.testing.assert_array_equal(np.asarray(Image.open(path)), expected)
    np.testing.assert_array_equal(iio.imread(path), expected)
    np.testing.assert_array_equal(oiio_u8(path).reshape(image.shape), image)
    assert path.read_bytes().endswith(b"TRUEVISION-XFILE.\0")


def test_float_input_is_quantised_to_nearest(tmp_path):
    values = np.array([[np.nan, -1.0, 0.0, 0.5, 127.4 / 255, 127.6 / 255, 1.0, 2.0, np.inf]])
    write_image(tmp_path / "q.tga", values.astype(np.float32))
    back = read_image(tmp_path / "q.tga")
    assert as_u8(back)[0, :, 0].tolist() == [0, 0, 0, 128, 127, 128, 255, 255, 255]
    # every stored value comes back to itself through float
    levels = (np.arange(256, dtype=np.float32) / 255).reshape(16, 16)
    write_image(tmp_path / "l.tga", levels)
    np.testing.assert_array_equal(read_image(tmp_path / "l.tga")[..., 0], levels)


def test_rle_packets_are_the_textbook_ones(tmp_path):
    a, b, c, d = (bytes([i]) for i in (1, 2, 3, 4))
    row = np.frombuffer(a * 3 + b + c + d * 2 + a * 300, np.uint8)[None, :]
    write_image(tmp_path / "p.tga", row, rle=True)
    body = (tmp_path / "p.tga").read_bytes()[18:-26]
    assert body == (run(3, a) + raw(b, c) + run(2, d) + run(128, a) + run(128, a) + run(44, a))


def test_files_written_by_pillow_and_openimageio(tmp_path):
    rng = np.random.default_rng(7)
    image = rng.integers(0, 256, (21, 33, 4), dtype=np.uint8)
    image[5:15, 4:30] = (9, 8, 7, 6)
    for rle in (False, True):
        path = tmp_path / f"pil{rle}.tga"
        Image.fromarray(image).save(path, compression="tga_rle" if rle else None)
        np.testing.assert_array_equal(as_u8(read_image(path)), image)
        Image.fromarray(image[..., 0]).save(path, compression="tga_rle" if rle else None)
        np.testing.assert_array_equal(as_u8(read_image(path))[..., 0], image[..., 0])

        path = tmp_path / f"oiio{rle}.tga"
        out = oiio.ImageOutput.create(str(path))
        spec = oiio.ImageSpec(33, 21, 3, "uint8")
        spec.attribute("compression", "rle" if rle else "none")
        out.open(str(path), spec)
        out.write_image(image[..., :3])
        out.close()
        np.testing.assert_array_equal(as_u8(read_image(path)), image[..., :3])


def test_bad_arguments(tmp_path):
    with pytest.raises(ArgumentError, match="origin"):
        write_image(tmp_path / "a.tga", np.zeros((2, 2, 3)), origin="middle")
    with pytest.raises(ArgumentError, match="uint16"):
        write_image(tmp_path / "a.tga", np.zeros((2, 2, 3), np.uint16))
    with pytest.raises(ArgumentError, match="65535"):
        write_image(tmp_path / "a.tga", np.zeros((1, 65536), np.uint8))
    assert not list(tmp_path.iterdir())


def test_sniff_accepts_plausible_headers_only():
    assert tga.sniff(small_rle()[:64])
    assert not tga.sniff(b"\x89PNG\r\n\x1a\n" + b"\x00" * 20)
    assert not tga.sniff(b"#?RADIANCE\n")
    assert not tga.sniff(b"\x00\x00\x02")


# --- fuzzing -----------------------------------------------------------------------------

VALID = [
    small_rle(),
    tga_bytes(2, 3, 2, 32, bgr(stored_rows(PICTURE, "top-right")), descriptor=0x38),
    tga_bytes(11, 4, 2, 8, run(3, b"\x05") + raw(b"\x01", b"\x02") + run(3, b"\x07")),
    tga_bytes(
        9, 3, 2, 8, run(6, b"\x01"), cmap=bgr([(1, 2, 3, 4)] * 2), cmap_len=2, cmap_bits=32
    ),
    tga_bytes(1, 2, 2, 8, b"\x01\x00\x01\x00", cmap=pack_555(1, 2, 3) * 2, cmap_len=2,
              cmap_bits=16, descriptor=1),
    tga_bytes(2, 2, 2, 16, pack_555(1, 2, 3, 1) * 4, image_id=b"id", trailer=FOOTER),
]  # fmt: skip


scratch = fuzzing.scratch_file("fuzz.tga", seeds=VALID)


def test_valid_fuzz_seeds_decode(scratch):
    for data in VALID:
        assert fuzzing.decode(scratch, data) is not None


def test_truncation_at_every_offset(scratch):
    for data in VALID:
        # the footer and image ID aside, a shortened file never decodes
        fuzzing.assert_truncations_refused(scratch, data, tail=len(FOOTER))


@fuzzing.FUZZ
@given(st.binary(max_size=300))
def test_random_bytes(scratch, data):
    fuzzing.decode(scratch, data)
    fuzzing.decode(scratch, b"\x00\x00\x0a" + data)


@fuzzing.FUZZ
@given(st.sampled_from(VALID), fuzzing.edits(80), st.integers(1, 120))
def test_mutations_of_valid_files(scratch, data, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(data, changes, end))
