"""Encodings: 8-bit decode formula, conventions, two-channel maps, the check, files."""

import cv2
import imageio
import numpy as np
import pytest

from bakeshop.cli.normals import write_normal_map
from bakeshop.errors import ArgumentError
from bakeshop.normals.encoding import (
    check_normals,
    convert_convention,
    convert_normal_map,
    decode_normals,
    encode_normals,
    normalize,
    read_normal_map,
)
from tests import tolerances as tol
from tests.files import DATA
from tests.normals.test_blend import random_normals


def test_8bit_decode_is_2c_over_255_minus_1_renormalised():
    c = np.random.default_rng(0).integers(0, 256, size=(40, 50, 3))
    c[..., 2] = np.maximum(c[..., 2], 140)
    n = 2.0 * c / 255 - 1  # the house formula, in float64 from the integers
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    got = decode_normals((c / 255).astype(np.float32))
    assert got.dtype == np.float32
    np.testing.assert_allclose(got, n, atol=tol.FLOAT32_UNIT)


def test_gl_dx_round_trip_is_exact():
    n = random_normals(4000, 1).reshape(40, 100, 3).astype(np.float32)
    dx = convert_convention(n, "gl", "dx")
    np.testing.assert_array_equal(dx[..., 1], -n[..., 1])
    np.testing.assert_array_equal(convert_convention(dx, "dx", "gl"), n)
    values = encode_normals(n, convention="dx")
    np.testing.assert_array_equal(
        decode_normals(values, convention="dx")[..., 1],
        -decode_normals(values, convention="gl")[..., 1],
    )


@pytest.mark.parametrize("encoding", ["packed", "signed"])
def test_float_round_trip(encoding):
    n = random_normals(3000, 2, 89).reshape(30, 100, 3)
    back = decode_normals(encode_normals(n, encoding=encoding), encoding=encoding)
    np.testing.assert_allclose(back, n, atol=tol.FLOAT64_UNIT)


def test_two_channel_maps_reconstruct_z():
    n = random_normals(3000, 3, 75).reshape(30, 100, 3)
    values = encode_normals(n, channels="xy")
    np.testing.assert_array_equal(values[..., 2], 0.5)
    np.testing.assert_allclose(decode_normals(values, channels="xy"), n, atol=1e-7)
    # BC5 sources quantised to 8 bits: within a quantisation step (z amplifies near the rim).
    q = np.round(values * 255) / 255
    assert np.abs(decode_normals(q, channels="xy") - n).max() < 0.02
    # read as three channels, the flat blue makes every texel point along the surface: checked.
    report = check_normals(q)
    assert report.off_unit > 0 and not report.ok


def test_normalize_handles_zero_and_nonfinite():
    n = np.array([[0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 0], [3, 0, 4]], np.float32)
    out = normalize(n)
    np.testing.assert_array_equal(out[:3], [[0, 0, 1]] * 3)
    np.testing.assert_allclose(out[3], [0.6, 0, 0.8], atol=tol.FLOAT32_UNIT)


def test_check_counts_what_it_should():
    n = random_normals(100 * 100, 4, 80).reshape(100, 100, 3)
    n[0, 0] *= 0.5  # short
    n[1, 1] *= 1.4  # long
    n[2, 2] = (0.3, 0.0, -np.sqrt(1 - 0.09))  # into the surface
    n[3, 3] = np.nan
    report = check_normals(encode_normals_raw(n), length_tolerance=0.1)
    assert (report.off_unit, report.into_surface, report.invalid) == (2, 1, 1)
    assert report.texels == 10000 and not report.ok
    # the invalid texel first, then farthest from unit length first
    assert [w[:2] for w in report.worst] == [(3, 3), (0, 0), (1, 1), (2, 2)]
    assert check_normals(encode_normals(random_normals(100, 5).reshape(10, 10, 3))).ok


def encode_normals_raw(n):
    """Pack vectors without renormalising them (encode_normals would fix them)."""
    return (n + 1) / 2


def test_bad_arguments():
    with pytest.raises(ArgumentError, match="convention"):
        decode_normals(np.zeros((2, 2, 3)), convention="yup")
    with pytest.raises(ArgumentError, match="at least"):
        decode_normals(np.zeros((2, 2, 1)))
    with pytest.raises(ArgumentError, match="encoding"):
        encode_normals(np.zeros((2, 2, 3)), encoding="snorm")


def test_tga_file_matches_opencv(tmp_path):
    """Writing through bakeshop.io: imageio reads the same 8-bit codes we expect."""
    n = random_normals(64 * 48, 6).reshape(48, 64, 3).astype(np.float32)
    path = tmp_path / "n.tga"
    write_normal_map(path, n, convention="dx")
    rgb = imageio.v3.imread(path)
    dx = n * (1, -1, 1)
    np.testing.assert_array_equal(rgb, np.rint((dx + 1) / 2 * 255).astype(np.uint8))
    back = read_normal_map(path, convention="dx")
    assert np.abs(back - n).max() < 2 / 255


def test_exr_float_round_trip(tmp_path):
    n = random_normals(32 * 32, 7).reshape(32, 32, 3).astype(np.float32)
    path = tmp_path / "n.exr"
    write_normal_map(path, n, encoding="signed", pixel_type="float")
    np.testing.assert_allclose(read_normal_map(path, encoding="signed"), n, atol=tol.FLOAT32_UNIT)


def test_check_on_real_maps():
    """The baked macro map is clean; the scratched-gold detail has short vectors in its scratches
    (about 2.6 % of the texels of our crop, down to length 0.46: it was not renormalised after
    filtering)."""
    macro = cv2.imread(str(DATA / "NormalTangentTest_Normal.png"))[..., ::-1] / 255.0
    assert check_normals(macro).ok
    report = check_normals(
        cv2.imread(str(DATA / "Scratched_gold_01_1K_Normal_crop256.png"))[..., ::-1] / 255.0
    )
    assert report.into_surface == 0 and report.invalid == 0
    assert 0.01 < report.off_unit / report.texels < 0.05 and report.min_length < 0.5


def test_16bit_png_decodes_with_65535(tmp_path):
    unit = random_normals(16 * 24, 8).reshape(16, 24, 3)
    c = np.rint((unit + 1) / 2 * 65535).astype(np.uint16)
    cv2.imwrite(str(tmp_path / "n16.png"), c[..., ::-1])
    n = 2.0 * c / 65535 - 1
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    np.testing.assert_allclose(read_normal_map(tmp_path / "n16.png"), n, atol=tol.FLOAT32_UNIT)


def test_convert_normal_map_flips_stored_green_exactly():
    c = np.random.default_rng(5).integers(0, 256, size=(9, 11, 4))
    packed = (c / 255).astype(np.float32)
    dx = convert_normal_map(packed, source="gl", target="dx")
    np.testing.assert_array_equal(np.rint(dx * 255).astype(int)[..., 1], 255 - c[..., 1])
    np.testing.assert_array_equal(dx[..., [0, 2, 3]], packed[..., [0, 2, 3]])  # alpha too
    back = convert_normal_map(dx, source="dx", target="gl")
    np.testing.assert_array_equal(np.rint(back * 255).astype(int), c)  # the same 8-bit file
    np.testing.assert_array_equal(convert_normal_map(packed, source="gl", target="gl"), packed)
    signed = packed * 2 - 1
    got = convert_normal_map(signed, source="dx", target="gl", encoding="signed")
    np.testing.assert_array_equal(got[..., 1], -signed[..., 1])
    with pytest.raises(ArgumentError, match="three channels"):
        convert_normal_map(packed[..., :2], source="gl", target="dx")


def test_convert_normal_map_rebuilds_z_of_two_channel_maps_and_keeps_alpha():
    rng = np.random.default_rng(6)
    x, y = rng.uniform(-0.6, 0.6, (2, 7, 8))
    alpha = rng.uniform(0, 1, (7, 8))
    bc5 = np.stack([(x + 1) / 2, (y + 1) / 2, np.zeros_like(x), alpha], -1)  # blue unused
    got = convert_normal_map(bc5, source="gl", target="dx", channels="xy")
    z = np.sqrt(1 - x * x - y * y)  # unit length by construction
    expect = np.stack([(x + 1) / 2, (1 - y) / 2, (z + 1) / 2, alpha], -1)
    np.testing.assert_allclose(got, expect, atol=1e-12)
