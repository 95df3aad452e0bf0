"""PNG and JPEG: exact PNG round trips at 8 and 16 bits, OpenCV / Pillow / OpenImageIO reading what
bakeshop writes and the other way round, hand-built PNGs for what readers get wrong (16-bit colour,
Adam7 interlacing, low bit depths, colour keys, checksums), a real normal map whose iCCP chunk
has a bad checksum, size limits and decompression bombs, JPEG, and fuzzing.

Peers: Pillow reads 16-bit RGB(A) PNGs as 8-bit and cannot write them, and refuses a PNG whose
ancillary chunk has a bad CRC; OpenCV (libpng) reads everything here, in BGR order; OpenImageIO
premultiplies alpha unless told not to.
"""

from __future__ import annotations

import io
import struct
import zlib

import cv2
import numpy as np
import OpenImageIO as oiio
import pytest
from hypothesis import given
from hypothesis import strategies as st
from PIL import Image

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import ldr, read_image, write_image
from tests.files import DATA
from tests.io import fuzzing
from tests.tolerances import JPEG_DECODER_ATOL, JPEG_Q95_ATOL


def chunk(kind: bytes, payload: bytes) -> bytes:
    return (
        struct.pack(">I", len(payload))
        + kind
        + payload
        + struct.pack(">I", zlib.crc32(kind + payload))
    )


def png_bytes(width, height, depth, colour, scanlines, *, interlace=0, before_idat=(), after=b""):
    """A PNG assembled by hand: ``scanlines`` are the filtered rows, filter bytes included."""
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, interlace)
    body = chunk(b"IHDR", ihdr) + b"".join(before_idat)
    body += chunk(b"IDAT", zlib.compress(scanlines)) + chunk(b"IEND", b"")
    return ldr.PNG_MAGIC + body + after


def unfiltered(samples: np.ndarray, dtype=">u2") -> bytes:
    """Rows of ``samples`` ((h, w, c)) as scanlines with filter type 0."""
    rows = samples.astype(dtype).reshape(samples.shape[0], -1).view(np.uint8)
    return b"".join(b"\x00" + row.tobytes() for row in rows)


def adam7(samples: np.ndarray) -> bytes:
    """The Adam7 sub-images of ``samples``, pass by pass, filter type 0 (PNG spec 8.2)."""
    out = b""
    for x0, y0, dx, dy in ldr.ADAM7:
        sub = samples[y0::dy, x0::dx]
        if sub.size:
            out += unfiltered(sub)
    return out


def write_bytes(tmp_path, data, name="x.png"):
    path = tmp_path / name
    path.write_bytes(data)
    return path


def cv2_rgb(path):
    a = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if a.ndim == 3:
        a = a[..., [2, 1, 0, 3][: a.shape[2]]]
    return a


def oiio_read(path, fmt="uint16"):
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    f = oiio.ImageInput.open(str(path), config)
    try:
        return f.read_image(fmt)
    finally:
        f.close()


def levels(image, bits):
    return np.rint(np.asarray(image) * ((1 << bits) - 1)).astype(
        np.uint8 if bits == 8 else np.uint16
    )


def random_samples(shape, bits, seed=0):
    rng = np.random.default_rng(seed)
    a = rng.integers(0, 1 << bits, shape, dtype=np.uint16 if bits == 16 else np.uint8)
    a[2:6] = a[2:3, :1]  # flat rows, so the encoder's filters and zlib have something to find
    return a


# --- PNG round trips and peers -------------------------------------------------------------------


@pytest.mark.parametrize("channels", [1, 3, 4])
@pytest.mark.parametrize("bits", [8, 16])
def test_png_round_trip_exact_and_peers_agree(tmp_path, channels, bits):
    samples = random_samples((23, 37, channels), bits, seed=channels)
    path = tmp_path / "w.png"
    write_image(path, samples)
    image, meta = read_image(path, with_metadata=True)
    assert image.dtype == np.float32 and image.shape == samples.shape
    np.testing.assert_array_equal(image, samples / np.float32((1 << bits) - 1))
    assert meta["format"] == "PNG" and meta["stored"] == f"uint{bits}" and meta["bits"] == bits
    assert meta["dropped_chunks"] == [] and not meta["srgb"]
    np.testing.assert_array_equal(cv2_rgb(path).reshape(samples.shape), samples)
    np.testing.assert_array_equal(oiio_read(path, f"uint{bits}").reshape(samples.shape), samples)
    if bits == 8 or channels == 1:  # what Pillow can hold
        np.testing.assert_array_equal(np.asarray(Image.open(path)).reshape(samples.shape), samples)


def test_float_input_quantisation(tmp_path):
    values = np.array([[np.nan, -0.5, 0.0, 0.5, 1.0, 7.0, np.inf, 1 / 65535]], np.float32)
    write_image(tmp_path / "q.png", values, bits=16)
    assert levels(read_image(tmp_path / "q.png"), 16)[0, :, 0].tolist() == [
        0, 0, 0, 32768, 65535, 65535, 65535, 1,
    ]  # fmt: skip
    write_image(tmp_path / "u.png", np.array([[0, 255]], np.uint8), bits=16)  # scaled by 257
    assert levels(read_image(tmp_path / "u.png"), 16).ravel().tolist() == [0, 65535]
    every = (np.arange(65536, dtype=np.float32) / 65535).reshape(256, 256)
    write_image(tmp_path / "all.png", every, bits=16)
    np.testing.assert_array_equal(read_image(tmp_path / "all.png")[..., 0], every)


@pytest.mark.parametrize("channels", [1, 3, 4])
@pytest.mark.parametrize("bits", [8, 16])
def test_png_written_by_opencv(tmp_path, channels, bits):
    samples = random_samples((19, 41, channels), bits, seed=10 + channels)
    path = tmp_path / "cv.png"
    bgr = samples[..., 0] if channels == 1 else samples[..., [2, 1, 0, 3][:channels]]
    assert cv2.imwrite(str(path), bgr)
    np.testing.assert_array_equal(levels(read_image(path), bits), samples)


@pytest.mark.parametrize("mode", ["1", "L", "LA", "RGB", "RGBA", "I;16", "P", "P+tRNS"])
def test_png_written_by_pillow(tmp_path, mode):
    rng = np.random.default_rng(4)
    rgba = rng.integers(0, 256, (13, 17, 4), dtype=np.uint8)
    if mode == "I;16":
        picture = Image.fromarray(rng.integers(0, 65536, (13, 17), dtype=np.uint16))
    elif mode.startswith("P"):
        picture = Image.fromarray(rgba[..., :3]).quantize(colors=37)
    else:
        picture = Image.fromarray(rgba).convert(mode)
    options = {"transparency": 5} if mode == "P+tRNS" else {}
    path = tmp_path / "pil.png"
    picture.save(path, **options)
    image, meta = read_image(path, with_metadata=True)
    reference = Image.open(path)
    if mode == "I;16":
        np.testing.assert_array_equal(levels(image, 16)[..., 0], np.asarray(reference))
        return
    expected = {"1": "L", "L": "L", "LA": "RGBA", "RGB": "RGB", "RGBA": "RGBA", "P": "RGB"}
    expected = np.asarray(reference.convert(expected.get(mode, "RGBA")))
    np.testing.assert_array_equal(levels(image, 8), expected.reshape(image.shape))
    assert meta["colour"] == {"1": "grey", "L": "grey", "LA": "grey+alpha", "RGB": "rgb",
                              "RGBA": "rgba"}.get(mode, "palette")  # fmt: skip


# --- hand-built PNGs -----------------------------------------------------------------------------


@pytest.mark.parametrize(("colour", "channels"), [(2, 3), (6, 4), (4, 2)])
def test_16_bit_colour_interlaced(tmp_path, colour, channels):
    samples = random_samples((11, 13, channels), 16, seed=colour)
    path = write_bytes(tmp_path, png_bytes(13, 11, 16, colour, adam7(samples), interlace=1))
    image, meta = read_image(path, with_metadata=True)
    expected = samples[..., [0, 0, 0, 1]] if channels == 2 else samples
    np.testing.assert_array_equal(levels(image, 16), expected)
    assert meta["interlaced"] and meta["stored"] == "uint16"
    reference = oiio_read(path).reshape(samples.shape)  # OpenImageIO keeps grey+alpha as 2
    np.testing.assert_array_equal(reference, samples)
    # the same picture, not interlaced, as libpng writes it with its filters
    if channels != 2:
        cv2.imwrite(str(tmp_path / "cv.png"), samples[..., [2, 1, 0, 3][:channels]])
        np.testing.assert_array_equal(read_image(tmp_path / "cv.png"), image)


def test_tiny_interlaced_image_with_empty_passes(tmp_path):
    samples = random_samples((1, 2, 3), 16)  # passes 2-6 are empty for a 2x1 image
    path = write_bytes(tmp_path, png_bytes(2, 1, 16, 2, adam7(samples), interlace=1))
    np.testing.assert_array_equal(levels(read_image(path), 16), samples)


def test_16_bit_rgb_colour_key(tmp_path):
    samples = random_samples((3, 4, 3), 16)
    samples[1, 2] = (1000, 2000, 3000)
    trns = chunk(b"tRNS", struct.pack(">HHH", 1000, 2000, 3000))
    data = png_bytes(4, 3, 16, 2, unfiltered(samples), before_idat=[trns])
    image = read_image(write_bytes(tmp_path, data))
    assert image.shape == (3, 4, 4)
    alpha = np.ones((3, 4), np.float32)
    alpha[1, 2] = 0
    np.testing.assert_array_equal(image[..., 3], alpha)
    np.testing.assert_array_equal(levels(image[..., :3], 16), samples)


def pack_grey(values: np.ndarray, depth: int) -> bytes:
    """Rows of grey samples of ``depth`` bits as filter-0 scanlines (PNG packs MSB first)."""
    if depth == 16:
        return unfiltered(values[..., None])
    bits = np.unpackbits(values.astype(np.uint8)[..., None], axis=-1)[..., 8 - depth :]
    packed = np.packbits(bits.reshape(values.shape[0], -1), axis=1)
    return b"".join(b"\x00" + r.tobytes() for r in packed)


@pytest.mark.parametrize("depth", [1, 2, 4, 8, 16])
def test_grey_colour_key_at_every_depth(tmp_path, depth):
    top = (1 << depth) - 1
    values = (np.arange(24).reshape(3, 8) * 37) % (top + 1)
    key = int(values[1, 3])
    trns = chunk(b"tRNS", struct.pack(">H", key))
    data = png_bytes(8, 3, depth, 0, pack_grey(values, depth), before_idat=[trns])
    image = read_image(write_bytes(tmp_path, data))
    assert image.shape == (3, 8, 4)
    np.testing.assert_array_equal(image[..., 3], (values != key).astype(np.float32))
    np.testing.assert_array_equal(image[..., 0], (values / top).astype(np.float32))


def test_rgb_colour_key_8_bit(tmp_path):
    samples = random_samples((3, 4, 3), 8)
    samples[2, 1] = (9, 8, 7)
    trns = chunk(b"tRNS", struct.pack(">HHH", 9, 8, 7))
    data = png_bytes(4, 3, 8, 2, unfiltered(samples, "u1"), before_idat=[trns])
    image = read_image(write_bytes(tmp_path, data))
    expected = np.ones((3, 4), np.float32)
    expected[(samples == (9, 8, 7)).all(-1)] = 0
    np.testing.assert_array_equal(image[..., 3], expected)


@pytest.mark.parametrize("depth", [1, 2, 4])
def test_low_bit_depth_grey(tmp_path, depth):
    values = np.arange(24, dtype=np.uint8).reshape(3, 8) % (1 << depth)
    packed = np.packbits(
        np.unpackbits(values[..., None], axis=-1)[..., 8 - depth :].reshape(3, -1), axis=1
    )
    data = png_bytes(8, 3, depth, 0, b"".join(b"\x00" + r.tobytes() for r in packed))
    path = write_bytes(tmp_path, data)
    image, meta = read_image(path, with_metadata=True)
    np.testing.assert_array_equal(image[..., 0], values / np.float32((1 << depth) - 1))
    assert meta["stored"] == f"uint{depth}"
    np.testing.assert_array_equal(
        cv2.imread(str(path), cv2.IMREAD_UNCHANGED), levels(image, 8)[..., 0]
    )


def test_transfer_function_is_reported_not_applied(tmp_path):
    samples = random_samples((2, 3, 3), 8)
    chunks = [chunk(b"sRGB", b"\x00"), chunk(b"gAMA", struct.pack(">I", 45455))]
    data = png_bytes(3, 2, 8, 2, unfiltered(samples, "u1"), before_idat=chunks)
    image, meta = read_image(write_bytes(tmp_path, data), with_metadata=True)
    np.testing.assert_array_equal(image, samples / np.float32(255))  # still the stored values
    assert meta["srgb"] and meta["gamma"] == pytest.approx(0.45455)


def test_a_real_normal_map_with_a_bad_iccp_checksum():
    path = DATA / "Scratched_gold_01_1K_Normal_crop256.png"
    with pytest.raises(Image.UnidentifiedImageError):  # what Pillow alone does with it
        Image.open(path)
    image, meta = read_image(path, with_metadata=True)
    assert image.shape == (256, 256, 3) and meta["dropped_chunks"] == ["iCCP"]
    np.testing.assert_array_equal(levels(image, 8), cv2_rgb(path))  # libpng warns and reads


def test_peer_behaviours_the_docs_describe(tmp_path):
    """Pin what docs/formats.md says of the peers, so an upgrade that changes it shows up."""
    write_image(tmp_path / "a.png", np.array([[[200, 100, 50, 128]]], np.uint8))
    f = oiio.ImageInput.open(str(tmp_path / "a.png"))
    assert f.read_image("uint8").ravel().tolist() == [100, 50, 25, 128]  # premultiplied
    f.close()
    write_image(tmp_path / "w.png", random_samples((4, 5, 3), 16))
    with Image.open(tmp_path / "w.png") as im:
        assert im.mode == "RGB" and np.asarray(im).dtype == np.uint8  # 16 -> 8 bits
    with pytest.raises(TypeError):
        Image.fromarray(random_samples((4, 5, 3), 16)).save(tmp_path / "p.png")
    normal = DATA / "Scratched_gold_01_1K_Normal_crop256.png"
    f = oiio.ImageInput.open(str(normal))
    assert f.read_image("uint8").shape == (256, 256, 3)  # read silently
    f.close()


def test_bad_checksums(tmp_path):
    samples = random_samples((2, 3, 3), 8)
    good = png_bytes(3, 2, 8, 2, unfiltered(samples, "u1"), before_idat=[chunk(b"tEXt", b"a\0b")])
    text = good.index(b"tEXt")
    broken = bytearray(good)
    broken[text + 4] ^= 1  # text payload: the chunk is dropped, the pixels still read
    image, meta = read_image(write_bytes(tmp_path, bytes(broken)), with_metadata=True)
    assert meta["dropped_chunks"] == ["tEXt"]
    np.testing.assert_array_equal(levels(image, 8), samples)
    for kind in (b"IHDR", b"IDAT", b"IEND"):
        broken = bytearray(good)
        broken[good.index(kind) + 4] ^= 1
        with pytest.raises(FormatError, match=f"bad checksum in the {kind.decode()} chunk"):
            read_image(write_bytes(tmp_path, bytes(broken)))


@pytest.mark.parametrize(
    ("data", "reason"),
    [
        (png_bytes(3, 2, 8, 2, b"\x00" * 5), "truncated"),
        (png_bytes(3, 2, 8, 2, b"\x00" * 10)[:-12], "ends before its IEND"),
        (png_bytes(3, 2, 8, 2, b"\x07" + b"\x00" * 19), "invalid filter type|corrupt"),
        (
            png_bytes(3, 2, 16, 2, b"\x00" * 19 + b"\x09" + b"\x00" * 18),
            "filter type in scanline 2",
        ),
        (png_bytes(3, 2, 16, 2, b"\x00" * 10), "inflates to 10"),
        (png_bytes(3, 2, 3, 2, b"\x00" * 10), "bit depth 3"),
        (png_bytes(0, 2, 8, 0, b"\x00" * 10), "size"),
        (png_bytes(20000, 20000, 8, 0, b""), "exceeds the limit"),
        (png_bytes(10000, 10000, 8, 0, b"\x00" * 1000), "cannot come from"),
        (ldr.PNG_MAGIC + chunk(b"IDAT", b"") + chunk(b"IEND", b""), "first chunk is not IHDR"),
        (ldr.PNG_MAGIC + b"\x00\x00\x00\x05I@AT", "bad chunk header|ends"),
    ],
)
def test_bad_pngs_are_format_errors(tmp_path, data, reason):
    fuzzing.assert_refused(tmp_path / "x.png", data, reason)


def test_pillow_decompression_bomb_limit(tmp_path):
    # 182 M one-bit pixels: inside bakeshop's limit, beyond twice Pillow's MAX_IMAGE_PIXELS
    width, height = 14000, 13000
    rows = (b"\x00" + b"\x55" * (width // 8)) * height
    data = ldr.PNG_MAGIC + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 1, 0, 0, 0, 0))
    data += chunk(b"IDAT", zlib.compress(rows, 1)) + chunk(b"IEND", b"")
    with pytest.raises(FormatError, match="decompression-bomb limit"):
        read_image(write_bytes(tmp_path, data))


# --- JPEG ----------------------------------------------------------------------------------------


def smooth_rgb(height=48, width=64):
    y, x = np.mgrid[0:height, 0:width]
    return np.stack([x * 4, y * 5, (x + y) * 2], -1).clip(0, 255).astype(np.uint8)


@pytest.mark.parametrize("channels", [1, 3])
def test_jpeg_written_by_bakeshop(tmp_path, channels):
    picture = smooth_rgb()[..., :channels]
    path = tmp_path / "b.jpg"
    write_image(path, picture)
    image, meta = read_image(path, with_metadata=True)
    assert image.shape == picture.shape and meta["format"] == "JPEG" and meta["stored"] == "uint8"
    assert np.abs(levels(image, 8).astype(int) - picture).max() <= JPEG_Q95_ATOL
    reference = cv2_rgb(path).reshape(picture.shape)
    assert np.abs(levels(image, 8).astype(int) - reference).max() <= JPEG_DECODER_ATOL
    with Image.open(path) as f:
        assert f.info.get("progressive") is None and f.layer[0][1:3] == (1, 1)  # 4:4:4


def test_jpeg_written_by_opencv_and_quality(tmp_path):
    picture = smooth_rgb()
    cv2.imwrite(str(tmp_path / "cv.jpg"), picture[..., ::-1], [cv2.IMWRITE_JPEG_QUALITY, 90])
    image = read_image(tmp_path / "cv.jpg")
    reference = cv2_rgb(tmp_path / "cv.jpg")
    assert np.abs(levels(image, 8).astype(int) - reference).max() <= JPEG_DECODER_ATOL
    write_image(tmp_path / "low.jpeg", picture, quality=5)
    write_image(tmp_path / "high.jpeg", picture, quality=100)
    assert (tmp_path / "low.jpeg").stat().st_size < (tmp_path / "high.jpeg").stat().st_size


def test_jpeg_orientation_reported_and_cmyk_refused(tmp_path):
    exif = Image.Exif()
    exif[0x0112] = 6
    Image.fromarray(smooth_rgb()).save(tmp_path / "o.jpg", exif=exif)
    image, meta = read_image(tmp_path / "o.jpg", with_metadata=True)
    assert meta["exif_orientation"] == 6 and image.shape == (48, 64, 3)  # not rotated
    Image.fromarray(smooth_rgb()).convert("CMYK").save(tmp_path / "c.jpg")
    with pytest.raises(UnsupportedError, match="CMYK"):
        read_image(tmp_path / "c.jpg")


def test_bad_jpegs(tmp_path):
    buf = io.BytesIO()
    Image.fromarray(smooth_rgb()).save(buf, format="JPEG")
    data = buf.getvalue()
    with pytest.raises(FormatError, match="truncated|corrupt"):
        read_image(write_bytes(tmp_path, data[: len(data) // 2], "t.jpg"))
    sof = data.index(b"\xff\xc0")
    huge = bytearray(data)
    huge[sof + 5 : sof + 9] = struct.pack(">HH", 14000, 14000)  # 196 M pixels, no data for them
    with pytest.raises(FormatError, match="decompression-bomb limit"):
        read_image(write_bytes(tmp_path, bytes(huge), "h.jpg"))
    huge[sof + 5 : sof + 9] = struct.pack(">HH", 9000, 9000)  # 81 M: within Pillow's limit
    with pytest.raises(FormatError, match="^image size 9000x9000 exceeds the limit of 100 "):
        ldr.read(write_bytes(tmp_path, bytes(huge), "m.jpg"), max_pixels=100)


def test_bad_write_arguments(tmp_path):
    rgb = np.zeros((2, 2, 3), np.float32)
    cases = [
        ("a.png", rgb, {"bits": 12}, "8 or 16"),
        ("a.png", rgb, {"quality": 90}, "quality= applies to JPEG"),
        ("a.png", rgb, {"compression": 11}, "0-9"),
        ("a.jpg", rgb, {"quality": 0}, "1-100"),
        ("a.jpg", rgb, {"bits": 16}, "JPEG stores 8 bits"),
        ("a.jpg", np.zeros((2, 2, 4)), {}, "no alpha"),
        ("a.png", np.zeros((2, 2, 3), np.int32), {}, "int32"),
    ]
    for name, image, options, reason in cases:
        with pytest.raises(ArgumentError, match=reason):
            write_image(tmp_path / name, image, **options)
    assert not list(tmp_path.iterdir())


def test_content_decides_the_codec(tmp_path):
    write_image(tmp_path / "p.png", smooth_rgb())
    (tmp_path / "p.jpg").write_bytes((tmp_path / "p.png").read_bytes())
    assert read_image(tmp_path / "p.jpg", with_metadata=True)[1]["format"] == "PNG"
    assert ldr.sniff(b"\xff\xd8\xff\xe0") and not ldr.sniff(b"v/1\x01")


# --- fuzzing -------------------------------------------------------------------------------------


def seeds():
    out = []
    for bits, channels in ((8, 3), (16, 4), (8, 1), (16, 3)):
        buf = io.BytesIO()
        samples = random_samples((3, 4, channels), bits)
        rows = samples.astype(">u2" if bits == 16 else "u1").reshape(3, -1).view(np.uint8)
        filtered = b"".join(bytes([y % 5]) + r.tobytes() for y, r in enumerate(rows))
        colour = {1: 0, 3: 2, 4: 6}[channels]
        out.append(png_bytes(4, 3, bits, colour, filtered))
    out.append(png_bytes(5, 3, 16, 2, adam7(random_samples((3, 5, 3), 16)), interlace=1))
    buf = io.BytesIO()
    Image.fromarray(smooth_rgb(8, 8)).quantize(colors=4).save(buf, format="PNG", transparency=1)
    out.append(buf.getvalue())
    buf = io.BytesIO()
    Image.fromarray(smooth_rgb(8, 8)).save(buf, format="JPEG", quality=50)
    out.append(buf.getvalue())
    return out


SEEDS = seeds()
scratch = fuzzing.scratch_file("f.png", seeds=SEEDS)  # the content, not the name, picks the codec


@pytest.mark.parametrize("seed", range(len(SEEDS)))
def test_truncation_at_every_offset(tmp_path, seed):
    data = SEEDS[seed]
    path = tmp_path / ("f.jpg" if data.startswith(ldr.JPEG_MAGIC) else "f.png")
    fuzzing.assert_truncations_refused(path, data, tail=2)  # a JPEG without its last marker decodes


@fuzzing.FUZZ
@given(st.binary(max_size=300), st.sampled_from([ldr.PNG_MAGIC, ldr.JPEG_MAGIC, b""]))
def test_random_bytes(scratch, data, magic):
    fuzzing.decode(scratch, magic + data)


@fuzzing.FUZZ
@given(st.sampled_from(SEEDS), fuzzing.edits(600, min_size=1), st.integers(1, 2000))
def test_mutations_of_valid_files(scratch, data, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(data, changes, end))
