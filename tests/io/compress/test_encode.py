"""The ISPC encoders as bakeshop drives them: surface layouts, padding of small levels, strips on
threads, the explicit choice for values half floats cannot hold, and the quality floors of the
issue on the CC0 probes."""

import numpy as np
import pytest

from bakeshop import sphere
from bakeshop.errors import ArgumentError
from bakeshop.io.compress import decode_image, encode_image
from bakeshop.io.compress.encode import image_jobs, run_jobs
from bakeshop.io.compress.packing import decode_rgbd, encode_rgbd
from bakeshop.io.compress.pipeline import box_mips, compress_levels
from bakeshop.io.compress.quality import mpsnr
from bakeshop.io.compress.texture import check_range, encode_texture
from tests.io.compress.conftest import NORMALS, hdr_chain, ldr_chain
from tests.io.compress.tolerances import (
    BC5_MEAN_ANGLE_FLOOR_DEG,
    BC6H_FAST_MPSNR_FLOOR,
    RGBD_BC7_MPSNR_FLOOR,
    SUNNY_LATLONG_MPSNR_FLOOR,
)


def test_bc1_blocks_are_bc3s_colour_half():
    """ispc-texcomp 1.0.1 returns 16 bytes per BC1 block (the second half uninitialised); the
    8 bytes bakeshop keeps are the colour blocks ISPC's BC3 encoder writes for the same texels."""
    image = ldr_chain(5, 32, cube=False)[0]
    image[..., 3] = 1
    bc1 = np.frombuffer(encode_image(image, "bc1"), np.uint8).reshape(-1, 8)
    bc3 = np.frombuffer(encode_image(image, "bc3"), np.uint8).reshape(-1, 16)
    assert bc1.shape[0] == 64
    np.testing.assert_array_equal(bc1, bc3[:, 8:])
    # and the colour blocks use the four-colour rule, so BC1's punch-through alpha never occurs
    c0 = bc1[:, 0].astype(int) | bc1[:, 1].astype(int) << 8
    c1 = bc1[:, 2].astype(int) | bc1[:, 3].astype(int) << 8
    codes = np.unpackbits(bc1[:, 4:], axis=1, bitorder="little").reshape(-1, 16, 2)
    three = (c0 <= c1) & np.any((codes[..., 0] == 1) & (codes[..., 1] == 1), axis=1)
    assert not three.any()


@pytest.mark.parametrize("name", ["bc4", "bc5"])
def test_rgtc_surfaces_are_one_and_two_channels(name):
    """ISPC's BC4 reads R8 and BC5 RG8 surfaces: a ramp survives within the format's error
    (8 values per block: a 4-texel ramp of 0.1 lands within 3/255)."""
    y, x = np.mgrid[0:32, 0:32] / 31.0
    image = np.stack([x, y], -1).astype(np.float32)[..., : 1 if name == "bc4" else 2]
    got = decode_image(encode_image(image, name), name, 32, 32)
    np.testing.assert_allclose(got, image, atol=3 / 255)


@pytest.mark.parametrize("size", [(1, 1), (2, 2), (3, 5), (7, 2)])
def test_small_levels_are_padded_blocks(size):
    """A level smaller than a block (2x2, 1x1) or with a partial block is padded by repeating
    its texels; the decoder crops the padding away."""
    w, h = size
    y, x = np.mgrid[0:h, 0:w]
    image = np.stack([1 + x, 2 + y, 3 + x * y], -1).astype(np.float32)
    data = encode_image(image, "bc6h")
    assert len(data) == ((w + 3) // 4) * ((h + 3) // 4) * 16
    got = decode_image(data, "bc6h", w, h)
    assert got.shape == (h, w, 3)
    # the same as encoding the image padded by hand (edge texels repeated), then cropping
    padded = np.pad(image, ((0, -h % 4), (0, -w % 4), (0, 0)), mode="edge")
    whole = decode_image(encode_image(padded, "bc6h"), "bc6h", *padded.shape[1::-1])
    np.testing.assert_array_equal(got, whole[:h, :w])


def test_strips_on_threads_equal_one_call():
    image = hdr_chain(4, 1024, cube=False)[0]  # 512 rows: two strips of 256 rows
    jobs = image_jobs(image, "bc6h")
    assert len(jobs) == 2
    assert run_jobs([jobs], workers=2)[0] == run_jobs([image_jobs(image, "bc6h")], workers=1)[0]


def test_bad_input_is_refused():
    with pytest.raises(ArgumentError):
        encode_image(np.full((4, 4, 3), np.nan, np.float32), "bc6h")
    with pytest.raises(ArgumentError):
        encode_image(np.zeros((4, 4, 3), np.float32), "bc5", quality="slow")
    with pytest.raises(ArgumentError):
        encode_image(np.zeros((4, 4, 5), np.float32), "bc7")
    with pytest.raises(ArgumentError):
        encode_image(np.zeros((4, 4, 3), np.float32), "bc8")


def test_values_above_half_range_are_refused_or_clamped_never_infinite():
    level = np.full((8, 8, 3), 2.0, np.float32)
    level[3, 4] = (1.5e6, 70000.0, 9.0)  # a sun
    with pytest.raises(ArgumentError, match="65504"):
        encode_texture([level], "bc6h")
    texture = encode_texture([level], "bc6h", overflow="clamp")
    assert texture.notes["clamped_values"] == 2 and texture.notes["peak"] == 1.5e6
    assert 0 < texture.notes["clamped_energy"] < 1
    decoded = texture.decode()[0]
    assert np.isfinite(decoded).all() and decoded.max() <= 65504
    # negative values cannot go to unsigned BC6H either; signed BC6H takes them
    with pytest.raises(ArgumentError):
        check_range([-level], "bc6h")
    signed = encode_texture([np.clip(-level, -65504, 0)], "bc6h-signed")
    assert np.isfinite(signed.decode()[0]).all()


def test_random_signed_blocks_stay_finite():
    """The spec's signed decoder can return -infinity (0xFC00) for one pattern; bakeshop's
    encoder never writes it, whatever the values (extremes included)."""
    rng = np.random.default_rng(0)
    image = rng.choice([-65504.0, 65504.0, -1.0, 0.0, 1e-5, 3.0], (64, 64, 3)).astype(np.float32)
    got = decode_image(encode_image(image, "bc6h-signed"), "bc6h-signed", 64, 64)
    assert np.isfinite(got).all() and np.abs(got).max() <= 65504


# --- the quality floors on real probes (CC0) -------------------------------------------


@pytest.mark.slow
def test_bc6h_fast_floors_on_the_sunny_and_dawn_probes(sunny, dawn):
    """BC6H "fast": >= 45 dB on the dawn probe (latlong, and the 256 cube a bake makes) and on
    the sunny probe's 512 cube; the sunny latlong itself (busy foliage) reaches 42.4 dB with
    every ISPC profile (42.6 with the slowest), so its floor is 42 dB."""
    latlong = compress_levels([dawn], "bc6h", cube=False, overflow="clamp")
    assert latlong.report["quality"]["mpsnr_db"] >= BC6H_FAST_MPSNR_FLOOR
    for probe, size in ((dawn, 256), (sunny, 512)):
        cube = sphere.remap(probe, "latlong", "cube", size=size, filter="area")
        result = compress_levels([cube], "bc6h", cube=True, overflow="clamp")
        assert result.report["quality"]["mpsnr_db"] >= BC6H_FAST_MPSNR_FLOOR
    sunny_latlong = compress_levels([sunny], "bc6h", cube=False, overflow="clamp")
    assert sunny_latlong.report["quality"]["mpsnr_db"] >= SUNNY_LATLONG_MPSNR_FLOOR
    assert sunny_latlong.report["overflow"]["clamped_values"] > 0  # the sun passes 65504


@pytest.mark.slow
def test_rgbd_in_bc7_floor(sunny, dawn):
    for probe in (sunny, dawn):
        cube = sphere.remap(probe, "latlong", "cube", size=256, filter="area")
        result = compress_levels([cube], "rgbd-bc7", cube=True)
        assert result.report["quality"]["mpsnr_db"] >= RGBD_BC7_MPSNR_FLOOR
        # and the decode formula is the one the packing module states
        stored = result.texture.decode()[0]
        np.testing.assert_allclose(result.decoded[0], decode_rgbd(stored), rtol=1e-6)


def test_bc5_normal_floor():
    from bakeshop.normals.encoding import read_normal_map

    real = read_normal_map(NORMALS)
    y, x = np.mgrid[0:256, 0:256] / 256.0 * 2 * np.pi
    bumps = np.stack([0.4 * np.cos(3 * x), 0.4 * np.cos(5 * y), np.ones_like(x)], -1)
    bumps /= np.linalg.norm(bumps, axis=-1, keepdims=True)
    for normals in (real, bumps.astype(np.float32)):
        result = compress_levels(box_mips(normals, cube=False, normals=True), "bc5",
                                 cube=False, normals=True)  # fmt: skip
        assert result.report["quality"]["angle_mean_deg"] <= BC5_MEAN_ANGLE_FLOOR_DEG


def test_rgbd_png_round_trip_is_close():
    image = hdr_chain(6, 32, cube=False)[0]
    packed = np.rint(encode_rgbd(image) * 255) / 255
    assert mpsnr(image, decode_rgbd(packed)) > 50


def test_half_conversion_is_numpys_rounding_saturated():
    """bakeshop's one-pass half-float surface rounds like numpy (IEEE nearest-even), subnormals
    included, and saturates at +-65504 where numpy would give infinity."""
    from bakeshop.io.compress.encode import to_half_surface

    rng = np.random.default_rng(0)
    values = rng.standard_normal(300000) * 10.0 ** rng.integers(-9, 7, 300000)
    edges = [0, -0.0, 65504, 65519.99, 65520, 1e9, -1e9, np.inf, 6.1035156e-05, 2.98e-08, 1e-8]
    values = np.concatenate([values, edges, edges[:1]]).astype(np.float32).reshape(1, -1, 3)
    got = to_half_surface(values)[0, : values.shape[1], :3]
    want = np.clip(values[0], -65504, 65504).astype(np.float16)
    np.testing.assert_array_equal(got.view(np.uint16), want.view(np.uint16))
    assert np.all(to_half_surface(values)[..., 3] == 1)
