"""Radiance .hdr: hand-built files for every orientation and scanline form, the representational
error of the encoder, OpenCV and OpenImageIO as independent readers and writers, the real probes,
corrupt and lying files, and fuzzing.

The peers decode RGBE as ``m * 2**(e - 136)`` (Walter's rgbe.c, which both OpenCV and
OpenImageIO carry), while bakeshop uses Radiance's ``(m + 0.5) * 2**(e - 136)``: on the same
bytes the two differ by exactly half a step of the pixel's exponent, and the comparisons below
check exactly that. imageio reads .hdr through its OpenCV plugin, so it is not an independent
reference.
"""

from __future__ import annotations

import tracemalloc

import cv2
import numpy as np
import OpenImageIO as oiio
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bakeshop import threads
from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import read_image, rgbe, write_image
from tests.files import PROBES, probe_path
from tests.io import fuzzing
from tests.tolerances import FLOAT32_VALUE, XYZ_MATRIX_ATOL

HEADER = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n"


# --- independent helpers: Radiance's definitions written out directly -----------------------------


def reference_decode(pixels):
    """(m + 0.5) * 2**(e - 136), 0 where e == 0, in float64 (then float32)."""
    pixels = np.asarray(pixels, np.uint8)
    e = pixels[..., 3:].astype(np.float64)
    values = (pixels[..., :3] + 0.5) * np.exp2(e - 136)
    return np.where(e == 0, 0.0, values).astype(np.float32)


def peer_to_radiance(peer):
    """Values decoded by OpenCV/OpenImageIO (m * 2**(e-136)) -> bakeshop's (m + 0.5) * 2**(e-136).

    Every writer involved normalises the largest mantissa into [128, 255], so the step of a pixel
    is 2**(floor(log2(max)) - 7) and the two readings differ by half of it."""
    peer = np.asarray(peer, np.float64)
    top = peer.max(axis=-1, keepdims=True)
    step = np.exp2(np.floor(np.log2(np.where(top > 0, top, 1.0))) - 7)
    return np.where(top > 0, peer + 0.5 * step, 0.0).astype(np.float32)


def random_rgbe(shape, seed=0):
    """Random normalised RGBE pixels (largest mantissa >= 128, as every encoder writes them)."""
    rng = np.random.default_rng(seed)
    pixels = rng.integers(0, 256, shape + (4,), dtype=np.uint8)
    top = pixels[..., :3].argmax(axis=-1)
    np.put_along_axis(pixels[..., :3], top[..., None], 128 + pixels[..., :1] % 128, axis=-1)
    pixels[..., 3] = rng.integers(100, 160, shape)
    return pixels


def rle_scanline(row):
    """New-style RLE of one scanline (W, 4), written independently of bakeshop's encoder: runs
    for every stretch of >= 3 equal bytes, literals (<= 128) otherwise."""
    width = len(row)
    out = bytearray([2, 2, width >> 8, width & 255])
    for c in range(4):
        plane = row[:, c].tolist()
        i = 0
        while i < width:
            j = i
            while j < width and plane[j] == plane[i] and j - i < 127:
                j += 1
            if j - i >= 3:
                out += bytes([128 + j - i, plane[i]])
                i = j
                continue
            k = i
            while k < width and k - i < 128:
                if k + 2 < width and plane[k] == plane[k + 1] == plane[k + 2]:
                    break
                k += 1
            out += bytes([k - i]) + bytes(plane[i:k])
            i = k
    return bytes(out)


def file_order(picture, orientation):
    """Scanlines of ``picture`` (H, W, 4, row 0 on top) in the file order of ``orientation``,
    following Radiance's pix2loc: scanline i, pixel j -> (x, y) with y pointing up."""
    height, width = picture.shape[:2]
    first, second = orientation.split()
    ymajor = first[1] == "Y"
    xdecr = "-X" in orientation
    ydecr = "-Y" in orientation
    nscan, scanlen = (height, width) if ymajor else (width, height)
    out = np.empty((nscan, scanlen, 4), np.uint8)
    for i in range(nscan):
        for j in range(scanlen):
            x, y = (j, i) if ymajor else (i, j)
            if xdecr:
                x = width - 1 - x
            if ydecr:
                y = height - 1 - y
            out[i, j] = picture[height - 1 - y, x]
    return out


def resolution(picture, orientation):
    height, width = picture.shape[:2]
    size = {"X": width, "Y": height}
    return " ".join(f"{axis} {size[axis[1]]}" for axis in orientation.split()).encode() + b"\n"


def hand_built(picture, orientation="-Y +X", form="flat", header=HEADER):
    scans = file_order(picture, orientation)
    if form == "rle":
        body = b"".join(rle_scanline(s) for s in scans)
    else:
        body = scans.tobytes()
    return header + resolution(picture, orientation) + body


ORIENTATIONS = ["-Y +X", "-Y -X", "+Y +X", "+Y -X", "+X -Y", "+X +Y", "-X -Y", "-X +Y"]


# --- hand-built files -----------------------------------------------------------------------------


@pytest.mark.parametrize("form", ["flat", "rle"])
@pytest.mark.parametrize("orientation", ORIENTATIONS)
def test_all_eight_orientations(tmp_path, orientation, form):
    picture = random_rgbe((9, 11), seed=3)  # 9 and 11 >= 8: both axes can be RLE scanlines
    picture[2:5, 3:10] = picture[2, 3]  # runs, so the RLE really uses run packets
    path = tmp_path / "o.hdr"
    path.write_bytes(hand_built(picture, orientation, form))
    image, meta = read_image(path, with_metadata=True)
    np.testing.assert_array_equal(image, reference_decode(picture))
    assert meta["orientation"] == orientation


def test_old_style_rle_with_shifting_counts(tmp_path):
    a, b, c = random_rgbe((3,), seed=5)
    width = 300
    line1 = bytes(a) + bytes([1, 1, 1, 43, 1, 1, 1, 1])  # a, then 43 + (1 << 8) = 299 repeats
    line2 = bytes([1, 1, 1, 5]) + bytes(b) + bytes([1, 1, 1, 2])  # starts by repeating a
    line2 += bytes(c) * (width - 9) + bytes([1, 1, 1, 0]) + bytes(a)  # zero count: no-op
    line3 = rle_scanline(np.tile(b, (width, 1)))  # a new-style scanline in the same file
    path = tmp_path / "old.hdr"
    path.write_bytes(HEADER + f"-Y 3 +X {width}\n".encode() + line1 + line2 + line3)
    expected = np.empty((3, width, 4), np.uint8)
    expected[0] = a
    expected[1, :5] = a
    expected[1, 5:8] = b
    expected[1, 8:-1] = c
    expected[1, -1] = a
    expected[2] = b
    np.testing.assert_array_equal(read_image(path), reference_decode(expected))


def test_peers_read_no_old_style_rle(tmp_path):
    a, b = random_rgbe((2,), seed=17)
    path = tmp_path / "old.hdr"
    path.write_bytes(
        HEADER + b"-Y 2 +X 300\n" + bytes(a) + bytes([1, 1, 1, 43, 1, 1, 1, 1]) + bytes(b) * 300
    )
    expected = reference_decode(np.stack([np.tile(a, (300, 1)), np.tile(b, (300, 1))]))
    np.testing.assert_array_equal(read_image(path), expected)
    assert cv2.imread(str(path), cv2.IMREAD_UNCHANGED) is None
    inp = oiio.ImageInput.open(str(path))
    assert inp is None or inp.read_image("float") is None
    oiio.geterror()


def test_scanline_starting_like_rle_but_not_rle_is_a_flat_pixel(tmp_path):
    # Radiance's rule: 2, 2, b, e with b >= 128 is an ordinary pixel, not an RLE header.
    picture = random_rgbe((2, 9), seed=6)
    picture[:, 0] = (2, 2, 200, 130)
    path = tmp_path / "f.hdr"
    path.write_bytes(hand_built(picture))
    np.testing.assert_array_equal(read_image(path), reference_decode(picture))


def test_xyze_is_converted_with_radiance_primaries(tmp_path):
    picture = random_rgbe((4, 10), seed=7)
    path = tmp_path / "xyz.hdr"
    path.write_bytes(hand_built(picture, header=b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n"))
    image, meta = read_image(path, with_metadata=True)
    xyz = reference_decode(picture).astype(np.float64)
    np.testing.assert_allclose(image, xyz @ rgbe.XYZ_TO_RGB.T, rtol=FLOAT32_VALUE)
    assert meta["stored"] == "xyze" and "XYZ to RGB" in meta["converted"]


def test_xyz_to_rgb_matrix_from_the_primaries_chromaticities():
    # Independent checks of the matrix: equal-energy white (X = Y = Z) is RGB (1, 1, 1), and the
    # XYZ of each primary's chromaticity maps onto its own axis only.
    np.testing.assert_allclose(rgbe.XYZ_TO_RGB @ np.ones(3), np.ones(3), atol=XYZ_MATRIX_ATOL)
    for axis, (x, y) in enumerate([(0.64, 0.33), (0.29, 0.60), (0.15, 0.06)]):
        rgb = rgbe.XYZ_TO_RGB @ np.array([x / y, 1.0, (1 - x - y) / y])
        others = np.delete(rgb, axis)
        np.testing.assert_allclose(others, 0.0, atol=XYZ_MATRIX_ATOL)
        assert rgb[axis] > 0


def test_exposure_and_colorcorr_divide_unless_raw(tmp_path):
    picture = random_rgbe((3, 9), seed=8)
    header = (
        b"#?RADIANCE\nEXPOSURE=2.0\nFORMAT=32-bit_rle_rgbe\nEXPOSURE= 1.5\n"
        b"COLORCORR=1 2 4\nPRIMARIES=0.64 0.33 0.3 0.6 0.15 0.06 0.3127 0.329\n\n"
    )
    path = tmp_path / "e.hdr"
    path.write_bytes(hand_built(picture, header=header))
    stored = reference_decode(picture).astype(np.float64)
    image, meta = read_image(path, with_metadata=True)
    np.testing.assert_allclose(image, stored / 3.0 / np.array([1, 2, 4]), rtol=FLOAT32_VALUE)
    assert meta["exposure"] == 3.0 and meta["colorcorr"] == (1.0, 2.0, 4.0)
    assert meta["primaries"] == (0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329)
    raw, meta = read_image(path, with_metadata=True, raw=True)
    np.testing.assert_array_equal(raw, stored.astype(np.float32))
    assert meta["raw"] and meta["exposure"] == 3.0


@pytest.mark.parametrize(
    "header",
    [
        b"#?RGBE\nFORMAT=32-bit_rle_rgbe\n\n",
        b"#?RADIANCE\n#?RADIANCE\nGAMMA=1\nPRIMARIES=0 0 0 0 0 0 0 0\nFORMAT=32-bit_rle_rgbe\n\n",
        b"#?RADIANCE\n# Made with Adobe Photoshop\nFORMAT=32-bit_rle_rgbe\n\n",
        b"#?pfilt\npfilt -x /2 -y /2\nVIEW= -vtv -vp 0 0 0\n\n",  # no FORMAT line: RGBE
        b"#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\nSOFTWARE=x\r\n\r\n",
    ],
)
def test_header_variants_of_real_writers(tmp_path, header):
    picture = random_rgbe((3, 9), seed=9)
    data = hand_built(picture, header=header)
    if b"\r\n" in header:
        data = data.replace(b"+X 9\n", b"+X 9\r\n")
    path = tmp_path / "v.hdr"
    path.write_bytes(data)
    np.testing.assert_array_equal(read_image(path), reference_decode(picture))


# --- the decoder against one written out in Python; its parallel parts against its serial pass ---


def python_decode(data, pos, nscan, scanlen, out, factors, dry):
    """New-style run-length scanlines decoded in Python, a packet at a time, and converted to
    float in numpy (``(m + 0.5) * 2**(e - 136) * factor`` in float64, rounded once to float32):
    the decoder's (status, scanline, position), or None when a scanline is not new-style."""
    raw = data.tobytes()
    n = len(raw)
    lines = None if dry else np.empty((nscan, 4, scanlen), np.uint8)
    for s in range(nscan):
        if not (pos + 4 <= n and raw[pos] == 2 and raw[pos + 1] == 2 and raw[pos + 2] < 128):
            return None
        if (raw[pos + 2] << 8) + raw[pos + 3] != scanlen:
            return rgbe._LENGTH, s, pos
        pos += 4
        for c in range(4):
            plane = bytearray()
            j = 0
            while j < scanlen:
                if pos >= n:
                    return rgbe._TRUNCATED, s, pos
                code = raw[pos]
                pos += 1
                if code > 128:
                    count = code - 128
                    if j + count > scanlen:
                        return rgbe._OVERRUN, s, pos
                    if pos >= n:
                        return rgbe._TRUNCATED, s, pos
                    plane += raw[pos : pos + 1] * count
                    pos += 1
                else:
                    count = code
                    if count == 0:
                        return rgbe._EMPTY_RUN, s, pos
                    if j + count > scanlen:
                        return rgbe._OVERRUN, s, pos
                    if pos + count > n:
                        return rgbe._TRUNCATED, s, pos
                    plane += raw[pos : pos + count]
                    pos += count
                j += count
            if lines is not None:
                lines[s, c] = np.frombuffer(plane, np.uint8)
    if lines is not None:
        e = lines[:, 3]
        scale = np.where(e == 0, 0.0, np.ldexp(1.0, e.astype(np.int64) - 136))
        for c in range(3):
            out[:, :, c] = (lines[:, c] + 0.5) * scale * factors[c]
    return rgbe._OK, nscan, pos


def both_decoders(data, nscan, scanlen, dry=False):
    """(status, scanline, position) and the pixels of the Python decoder above and of the
    compiled one on the same bytes."""
    _, offset = rgbe._header(data)
    factors = np.array([1.0, 0.5, 3.0])
    results = []
    for decode in (python_decode, rgbe._decode):
        out = np.zeros((nscan, scanlen, 3), np.float32)
        result = decode(data, offset, nscan, scanlen, out, factors, dry)
        results.append((None if result is None else tuple(result), out))
    return results


@pytest.mark.parametrize("name", PROBES)
def test_decoder_gives_the_python_decoders_bits_on_real_probes(name):
    data = np.fromfile(probe_path(name), np.uint8)
    facts, _ = rgbe._header(data)
    (status, out), (kernel_status, kernel_out) = both_decoders(
        data, facts["height"], facts["width"]
    )
    assert status == kernel_status and status[0] == 0
    assert np.array_equal(out.view(np.uint32), kernel_out.view(np.uint32))


@pytest.mark.parametrize("seed", range(6))
def test_decoder_finds_the_python_decoders_problems(tmp_path, seed):
    rng = np.random.default_rng(seed)
    image = np.exp(rng.normal(0, 3, (9, 40, 3))).astype(np.float32)
    image[:, :20] = image[:, :1]  # runs
    write_image(tmp_path / "c.hdr", image)
    data = np.fromfile(tmp_path / "c.hdr", np.uint8)
    _, offset = rgbe._header(data)
    for k in rng.integers(offset, data.size, 40):
        mutated = data.copy()
        mutated[k] = rng.integers(0, 256)
        for candidate in (mutated, data[:k]):
            for dry in (True, False):
                (status, out), (kernel_status, kernel_out) = both_decoders(candidate, 9, 40, dry)
                # None: a scanline not in the new form, which the Python decoder leaves
                assert status is None or status == kernel_status
                if status is not None and status[0] == 0 and not dry:
                    assert np.array_equal(out.view(np.uint32), kernel_out.view(np.uint32))


@pytest.mark.parametrize("seed", range(3))
def test_the_parallel_decoder_gives_the_serial_kernels_bits_and_problems(tmp_path, seed):
    """A large image is decoded in parts on every thread: the same float32 bits as the serial
    pass (one thread), and the same (status, scanline, position) for files mutated or cut
    anywhere."""

    def parallel(*args):
        with threads.limited(4):
            return rgbe._decode(*args)

    def serial(*args):
        with threads.limited(1):
            return rgbe._decode(*args)

    rng = np.random.default_rng(seed)
    image = np.exp(rng.normal(0, 3, (1040, 1024, 3))).astype(np.float32)
    image[:, 100:400] = image[:, 99:100]  # runs
    write_image(tmp_path / "big.hdr", image)
    data = np.fromfile(tmp_path / "big.hdr", np.uint8)
    _, offset = rgbe._header(data)
    factors = np.array([1.0, 0.5, 2.0])
    candidates = [data]
    for k in rng.integers(offset, data.size, 6):
        mutated = data.copy()
        mutated[k] = rng.integers(0, 256)
        candidates += [mutated, data[:k]]
    for candidate in candidates:
        got, want = np.zeros((2, 1040, 1024, 3), np.float32)
        status = parallel(candidate, offset, 1040, 1024, got, factors, False)
        assert status == serial(candidate, offset, 1040, 1024, want, factors, False)
        if status[0] == 0:
            assert np.array_equal(got.view(np.uint32), want.view(np.uint32))
    # into the flipped and transposed views that read() passes for other orientations
    for base, view in (((1040, 1024), lambda a: a[::-1, ::-1]),
                       ((1024, 1040), lambda a: a.transpose(1, 0, 2)[::-1])):  # fmt: skip
        got, want = np.zeros((2, *base, 3), np.float32)
        status = parallel(data, offset, 1040, 1024, view(got), factors, False)
        assert status == serial(data, offset, 1040, 1024, view(want), factors, False)
        assert status[0] == 0
        assert np.array_equal(got.view(np.uint32), want.view(np.uint32))


# --- the encoder ----------------------------------------------------------------------------------


def test_encode_error_is_within_half_a_step():
    rng = np.random.default_rng(10)
    image = np.exp(rng.uniform(-80, 80, (64, 50, 3))).astype(np.float32)
    image[::3, ::2, 1] = 0.0
    back = roundtrip(image)
    top = image.astype(np.float64).max(axis=-1, keepdims=True)
    half_step = np.exp2(np.frexp(top)[1] - 9.0)  # 0.5 * 2**(e - 136), e = frexp exponent + 128
    assert np.all(np.abs(back - image.astype(np.float64)) <= half_step)


def reference_encode(image):
    """RGBE bytes (H, W, 4) written out from the definition in float64: the largest component's
    frexp exponent (capped at 255), each mantissa the floor of value * 2**(136 - e) capped at 255;
    NaN and negatives 0, infinities float32's largest, a pixel below 2**-128 black."""
    biggest = float(np.finfo(np.float32).max)
    a = np.clip(np.nan_to_num(image.astype(np.float64), nan=0.0, posinf=biggest), 0, biggest)
    top = a.max(axis=-1)
    e = np.minimum(np.frexp(top)[1] + 128, 255)
    m = np.minimum(np.floor(a * np.exp2(136.0 - e)[..., None]), 255)
    pixels = np.concatenate([m, e[..., None]], axis=-1).astype(np.uint8)
    pixels[top < 2.0**-128] = 0
    return pixels


def walter_rle(plane) -> bytes:
    """RLE_WriteBytes of Walter's rgbe.c (the packing Radiance's fwritecolrs also makes), written
    out in Python: runs of at least 4 equal bytes (at most 127), literals of at most 128, a
    2- or 3-byte run just before a long one written as a run."""
    plane, out, cur, n = bytes(plane), bytearray(), 0, len(plane)
    while cur < n:
        beg, run, old = cur, 0, 0
        while run < 4 and beg < n:
            beg, old, run = beg + run, run, 1
            while beg + run < n and run < 127 and plane[beg] == plane[beg + run]:
                run += 1
        if old > 1 and old == beg - cur:
            out += bytes([128 + old, plane[cur]])
            cur = beg
        while cur < beg:
            count = min(128, beg - cur)
            out += bytes([count]) + plane[cur : cur + count]
            cur += count
        if run >= 4:
            out += bytes([128 + run, plane[beg]])
            cur += run
    return bytes(out)


def encoder_input(seed):
    """Pixels of every kind: noise over 60 octaves, special values, and rows of runs of every
    length (1 to 300 equal pixels) that exercise the packing's cases."""
    rng = np.random.default_rng(seed)
    noise = np.exp(rng.uniform(-85, 85, (6, 300, 3))).astype(np.float32)
    special = [np.nan, np.inf, -np.inf, -1.0, 3.4e38, 1e-39, 1.2e-38, 3e-39, 0.0, 1.0]
    noise[0, :40] = rng.permutation(np.tile(special, 12)).reshape(40, 3)
    lengths = rng.integers(1, 9, 400)
    lengths[::37] = rng.integers(100, 300, len(lengths[::37]))
    runs = np.repeat(rng.integers(0, 3, len(lengths)), lengths)[:1800].reshape(6, 300)
    levels = np.float32([0.25, 0.5, 3.0])[runs][..., None] * np.float32([1.0, 0.75, 0.1])
    return np.concatenate([noise, levels.astype(np.float32)])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_flat_pixels_are_the_definition(tmp_path, seed):
    image = encoder_input(seed)
    write_image(tmp_path / "f.hdr", image, rle=False)
    data = (tmp_path / "f.hdr").read_bytes()
    assert data.endswith(reference_encode(image).tobytes())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_run_length_scanlines_are_walters_packing(tmp_path, seed):
    image = encoder_input(seed)
    height, width = image.shape[:2]
    pixels = reference_encode(image)
    expected = b"".join(
        bytes([2, 2, width >> 8, width & 255])
        + b"".join(walter_rle(pixels[y, :, c]) for c in range(4))
        for y in range(height)
    )
    write_image(tmp_path / "r.hdr", image)
    assert (tmp_path / "r.hdr").read_bytes().endswith(expected)


def roundtrip(image, **options):
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        write_image(Path(d) / "r.hdr", image, **options)
        return read_image(Path(d) / "r.hdr")


def test_special_values():
    biggest = np.float32(255.5 * 2.0**119)
    image = np.array(
        [[[np.nan, 1, -1], [np.inf, 1, 0], [-np.inf, 0, 2], [3.4e38, 3e38, 0], [1e-39, 0, 0]]],
        np.float32,
    )
    back = roundtrip(image)
    # NaN and negatives are stored as mantissa 0, which Radiance reconstructs as half a step.
    np.testing.assert_array_equal(back[0, 0], reference_decode([0, 128, 0, 129]))
    assert back[0, 1, 0] == biggest and back[0, 1, 1] == reference_decode([0, 0, 0, 255])[0]
    np.testing.assert_array_equal(back[0, 2], reference_decode([0, 0, 128, 130]))
    assert back[0, 3, 0] == biggest  # float32's largest values saturate
    assert np.all(back[0, 4] == 0.0)  # below 2**-128: black


@pytest.mark.parametrize("rle", [True, False])
def test_decode_encode_decode_is_exact(tmp_path, rle):
    picture = random_rgbe((12, 40), seed=11)
    picture[3, :] = (0, 0, 0, 0)
    (tmp_path / "a.hdr").write_bytes(hand_built(picture))
    first = read_image(tmp_path / "a.hdr")
    write_image(tmp_path / "b.hdr", first, rle=rle)
    np.testing.assert_array_equal(read_image(tmp_path / "b.hdr"), first)
    if not rle:  # flat: the very bytes come back
        assert (tmp_path / "b.hdr").read_bytes().endswith(picture.tobytes())


@pytest.mark.parametrize("width", [1, 7, 8, 127, 128, 129, 300])
def test_widths_around_the_rle_limits(tmp_path, width):
    rng = np.random.default_rng(width)
    image = rng.random((3, width, 3)).astype(np.float32)
    image[1] = 0.5  # long runs
    path = tmp_path / "w.hdr"
    write_image(path, image)
    data = path.read_bytes()
    body = data[data.index(f"+X {width}\n".encode()) + len(f"+X {width}\n") :]
    assert (body[:2] == b"\x02\x02") == (8 <= width <= 32767)
    back = read_image(path)
    theirs = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1]
    np.testing.assert_array_equal(back, peer_to_radiance(theirs))
    assert np.all(np.abs(back - image) <= 2.0**-8 * image.max(axis=-1, keepdims=True))


def test_very_wide_image_is_written_flat(tmp_path):
    image = np.linspace(0.1, 5, 40000 * 3, dtype=np.float32).reshape(1, 40000, 3)
    path = tmp_path / "wide.hdr"
    write_image(path, image)
    assert path.stat().st_size == len(b"#?RADIANCE\nSOFTWARE=bakeshop\n") + 4 * 40000 + len(
        b"FORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 40000\n"
    )
    np.testing.assert_array_equal(read_image(path), roundtrip(image))


def test_grey_is_written_as_equal_rgb(tmp_path):
    grey = np.linspace(0, 4, 30, dtype=np.float32).reshape(3, 10)
    back = roundtrip(grey)
    np.testing.assert_array_equal(back[..., 0], back[..., 2])
    np.testing.assert_array_equal(back, roundtrip(np.repeat(grey[..., None], 3, axis=2)))


# --- independent readers and writers --------------------------------------------------------------


def oiio_read(path):
    inp = oiio.ImageInput.open(str(path))
    try:
        return inp.read_image("float")
    finally:
        inp.close()


def smooth_and_noisy(height=40, width=70):
    rng = np.random.default_rng(12)
    y, x = np.mgrid[0:height, 0:width]
    smooth = np.stack([np.sin(x / 9) + 1.1, np.cos(y / 7) + 1.2, (x + y) / 50], -1)
    noisy = np.exp(rng.normal(0, 4, (height, width, 3)))
    return np.concatenate([smooth, noisy]).astype(np.float32)


def test_opencv_and_openimageio_read_what_bakeshop_writes(tmp_path):
    image = smooth_and_noisy()
    path = tmp_path / "b.hdr"
    write_image(path, image)
    ours = read_image(path)
    np.testing.assert_array_equal(peer_to_radiance(cv2.imread(str(path), -1)[..., ::-1]), ours)
    np.testing.assert_array_equal(peer_to_radiance(oiio_read(path)), ours)


def test_bakeshop_reads_what_opencv_and_openimageio_write(tmp_path):
    image = smooth_and_noisy()
    cv2.imwrite(str(tmp_path / "c.hdr"), image[..., ::-1].copy())
    theirs = cv2.imread(str(tmp_path / "c.hdr"), -1)[..., ::-1]
    np.testing.assert_array_equal(read_image(tmp_path / "c.hdr"), peer_to_radiance(theirs))
    out = oiio.ImageOutput.create(str(tmp_path / "o.hdr"))
    assert out.open(str(tmp_path / "o.hdr"), oiio.ImageSpec(70, 80, 3, "float"))
    assert out.write_image(image)
    out.close()
    theirs = oiio_read(tmp_path / "o.hdr")
    np.testing.assert_array_equal(read_image(tmp_path / "o.hdr"), peer_to_radiance(theirs))


@pytest.mark.parametrize("orientation", ORIENTATIONS)
def test_peers_on_other_orientations(tmp_path, orientation):
    # What docs/formats.md says of the peers. OpenCV reads the standard orientation only;
    # OpenImageIO returns file order with an EXIF Orientation, and after reorient() agrees with
    # Radiance's pix2loc except for +X +Y and -X -Y, which it swaps (the picture turned 180).
    picture = random_rgbe((9, 11), seed=16)
    path = tmp_path / "p.hdr"
    path.write_bytes(hand_built(picture, orientation, "rle"))
    expected = reference_decode(picture)
    np.testing.assert_array_equal(read_image(path), expected)
    theirs = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    assert (theirs is not None) == (orientation == "-Y +X")
    upright = oiio.ImageBufAlgo.reorient(oiio.ImageBuf(str(path))).get_pixels(oiio.FLOAT)
    if orientation in ("+X +Y", "-X -Y"):
        expected = expected[::-1, ::-1]
    np.testing.assert_array_equal(peer_to_radiance(upright), expected)


@pytest.mark.parametrize("name", PROBES)
def test_real_probes_read_as_opencv_and_openimageio_read_them(name):
    path = probe_path(name)
    ours, meta = read_image(path, with_metadata=True)
    assert ours.shape == (512, 1024, 3) and meta["orientation"] == "-Y +X"
    np.testing.assert_array_equal(ours, peer_to_radiance(cv2.imread(str(path), -1)[..., ::-1]))
    np.testing.assert_array_equal(ours, peer_to_radiance(oiio_read(path)))


# --- bad files, bad arguments and the public entry points -----------------------------------------


def corrupt(body: bytes, res: bytes = b"-Y 2 +X 8\n") -> bytes:
    return HEADER + res + body


GOOD = random_rgbe((2, 8), seed=13)


@pytest.mark.parametrize(
    "data, words",
    [
        (
            corrupt(bytes([2, 2, 0, 8, 130, 1, 0]) + bytes(16)),
            "scanline 1 of 2: a run of length 0",
        ),
        (corrupt(bytes([2, 2, 0, 8, 137, 1]) + bytes(16)), "scanline 1 of 2: a run overruns"),
        (corrupt(bytes([2, 2, 0, 8, 9]) + bytes(9)), "scanline 1 of 2: a run overruns"),
        (corrupt(rle_scanline(GOOD[0]) + bytes([2, 2, 0, 9]) + bytes(40)), "scanline 2 of 2"),
        (corrupt(rle_scanline(GOOD[0]) + rle_scanline(GOOD[1])[:-1]), "scanline 2 of 2: the file"),
        (corrupt(bytes([1, 1, 1, 3]) + bytes(60)), "no previous pixel"),
        (corrupt(GOOD[0, 0].tobytes() + bytes([1, 1, 1, 8]) + bytes(60)), "overruns"),
        (corrupt(bytes(32)), "scanline 2 of 2: the file ends"),
        (corrupt(bytes(7)), "truncated file"),
        (corrupt(bytes(64), b"-Y 2 +Z 8\n"), "resolution"),
        (corrupt(bytes(64), b"-Y 2 +Y 8\n"), "resolution"),
        (corrupt(bytes(64), b"-Y 0 +X 8\n"), "size"),
        (corrupt(bytes(64), b"-Y 100000000 +X 100000000\n"), "exceeds"),
        (corrupt(bytes(64), b"-Y " + b"9" * 5000 + b" +X 8\n"), "resolution"),
        (corrupt(bytes(64), b""), "resolution"),
        (b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", "header is truncated"),
        (b"#?RADIANCE\nEXPOSURE=0\n\n-Y 2 +X 8\n" + bytes(64), "EXPOSURE"),
        (b"#?RADIANCE\nEXPOSURE=abc\n\n-Y 2 +X 8\n" + bytes(64), "EXPOSURE"),
        (b"#?RADIANCE\nCOLORCORR=1 2\n\n-Y 2 +X 8\n" + bytes(64), "COLORCORR"),
    ],
)
def test_corrupt_files_name_the_problem(tmp_path, data, words):
    fuzzing.assert_refused(tmp_path / "bad.hdr", data, words)


def test_unsupported_pixel_format(tmp_path):
    (tmp_path / "s.hdr").write_bytes(
        b"#?RADIANCE\nFORMAT=Radiance_spectra\n\n-Y 1 +X 1\n" + bytes(4)
    )
    with pytest.raises(UnsupportedError, match="Radiance_spectra"):
        read_image(tmp_path / "s.hdr")


def test_lying_size_allocates_nothing_large(tmp_path):
    # 16000 x 16000 pixels (3 GB as float32) promised by 16000 four-byte scanlines of old-style
    # repeats of a pixel that never came: refused before the image is allocated, by the decode
    # budget, and with a budget that allows it, by the pass that checks the runs first.
    data = corrupt(bytes([1, 1, 1, 255]) * 16000, b"-Y 16000 +X 16000\n")
    (tmp_path / "lie.hdr").write_bytes(data)
    with pytest.raises(FormatError, match="decompression bomb"):
        read_image(tmp_path / "lie.hdr")
    tracemalloc.start()
    try:
        with pytest.raises(FormatError, match="scanline 1 of 16000"):
            read_image(tmp_path / "lie.hdr", max_decoded=1 << 40)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 4 * len(data) + (1 << 20)


def test_wrong_extension_says_what_the_file_is(tmp_path):
    write_image(tmp_path / "a.pfm", np.ones((2, 2, 3), np.float32))
    (tmp_path / "a.hdr").write_bytes((tmp_path / "a.pfm").read_bytes())
    with pytest.raises(FormatError, match="the file is PFM, not Radiance HDR"):
        read_image(tmp_path / "a.hdr")
    write_image(tmp_path / "b.hdr", np.ones((2, 2, 3), np.float32))
    (tmp_path / "b.pfm").write_bytes((tmp_path / "b.hdr").read_bytes())
    with pytest.raises(FormatError, match="the file is Radiance HDR, not PFM"):
        read_image(tmp_path / "b.pfm")


@pytest.mark.parametrize(
    "image, options, words",
    [
        (np.zeros((2, 2, 4), np.float32), {}, "alpha"),
        (np.zeros((2, 2, 3), np.complex64), {}, "complex"),
        (np.zeros((2, 2, 3), np.float32), {"byteorder": "<"}, "byteorder"),
    ],
)
def test_bad_write_arguments(tmp_path, image, options, words):
    with pytest.raises(ArgumentError, match=words):
        write_image(tmp_path / "a.hdr", image, **options)
    assert list(tmp_path.iterdir()) == []


# --- fuzzing: only BakeshopError may escape -------------------------------------------------------

SMALL_RLE = hand_built(random_rgbe((3, 9), seed=14), form="rle")
SMALL_OLD = corrupt(GOOD[0, 0].tobytes() + bytes([1, 1, 1, 7]) + GOOD[1].tobytes())
SMALL_TRANSPOSED = hand_built(random_rgbe((8, 3), seed=15), "+X -Y", form="rle")
SEEDS = [SMALL_RLE, SMALL_OLD, SMALL_TRANSPOSED]


scratch = fuzzing.scratch_file("f.hdr", seeds=SEEDS)


@pytest.mark.parametrize("seed", range(len(SEEDS)))
def test_truncation_at_every_offset_is_refused(scratch, seed):
    fuzzing.assert_truncations_refused(scratch, SEEDS[seed])


@fuzzing.FUZZ
@given(st.binary(max_size=300), st.sampled_from([b"-Y 3 +X 9\n", b"+X 5 +Y 20\n", b"-Y 2 +X 3\n"]))
def test_random_bytes(scratch, data, res):
    fuzzing.decode(scratch, data)
    fuzzing.decode(scratch, HEADER + res + data)


@fuzzing.FUZZ
@given(st.sampled_from(SEEDS), fuzzing.edits(200), st.integers(1, 400))
def test_mutations_of_valid_files(scratch, data, changes, end):
    fuzzing.decode(scratch, fuzzing.mutate(data, changes, end))
