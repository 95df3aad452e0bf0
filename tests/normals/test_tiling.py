"""Placing detail: exact tiling, prefiltered minification, rotation = rotated height field."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.normals.blend import blend
from bakeshop.normals.encoding import normalize
from bakeshop.normals.tiling import (
    DetailLayer,
    apply_layers,
    mask_weights,
    mip_chain,
    place_detail,
    sample_wrapped,
)
from tests import tolerances as tol
from tests.normals.test_blend import random_normals


def detail_map(size=64, seed=0):
    return random_normals(size * size, seed, 60).reshape(size, size, 3).astype(np.float32)


def test_integer_tiles_at_texel_scale_are_the_tiled_map():
    d = detail_map()
    out = place_detail(d, (128, 192), tile=(3, 2))
    np.testing.assert_allclose(out, np.tile(d, (2, 3, 1)), atol=tol.FLOAT32_UNIT)


def test_minified_tiles_are_box_filtered_without_seams():
    d = detail_map()
    out = place_detail(d, (64, 64), tile=4)  # 4 detail texels per output texel
    box = d.reshape(16, 4, 16, 4, 3).mean(axis=(1, 3))
    np.testing.assert_allclose(out, np.tile(normalize(box), (4, 4, 1)), atol=tol.FLOAT32_UNIT)


def test_rotation_by_90_degrees_turns_the_picture_and_the_vectors():
    d = detail_map()
    out = place_detail(d, (64, 64), rotation=90)
    turned = np.rot90(d).copy()  # counter-clockwise as displayed
    turned[..., 0], turned[..., 1] = -np.rot90(d)[..., 1], np.rot90(d)[..., 0]
    np.testing.assert_allclose(out, turned, atol=tol.FLOAT32_UNIT)


def test_mirrored_tile_mirrors_the_normals():
    d = detail_map()
    out = place_detail(d, (64, 64), tile=(-1, 1))
    expected = d[:, ::-1] * (-1, 1, 1)
    np.testing.assert_allclose(out, expected, atol=tol.FLOAT32_UNIT)


def wave_height(s, t):
    """A tileable height on the unit tile and its gradient (d/ds, d/dt), t up."""
    a = 2 * np.pi * (s + 2 * t)
    b = 2 * np.pi * (3 * s - t)
    h = 0.05 * np.sin(a) + 0.02 * np.cos(b)
    return (
        h,
        0.1 * np.pi * np.cos(a) - 0.12 * np.pi * np.sin(b),
        (0.2 * np.pi * np.cos(a) + 0.04 * np.pi * np.sin(b)),
    )


def normals_from_gradient(gs, gt):
    n = np.stack([-gs, -gt, np.ones_like(gs)], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


@pytest.mark.parametrize("rotation", [30.0, -117.0])
def test_rotating_a_tiled_map_is_the_normal_map_of_the_rotated_height_field(rotation):
    size, out_size, tiles = 256, 384, 1.5  # one detail texel per output texel: no mip blur
    c = (np.arange(size) + 0.5) / size
    s, t = np.meshgrid(c, c[::-1])
    _, gs, gt = wave_height(s, t)
    placed = place_detail(
        normals_from_gradient(gs, gt),
        (out_size, out_size),
        tile=tiles,
        rotation=rotation,
        offset=(0.25, 0.1),
    )
    # the rotated height field h'(p) = h(R(-theta) p + o), p = tiles (u, v): its gradient is
    # R(theta) grad h(q), evaluated analytically at each output texel
    c = (np.arange(out_size) + 0.5) / out_size
    u, v = np.meshgrid(c, c[::-1])
    th = np.radians(rotation)
    pu, pv = tiles * u, tiles * v
    qs = np.cos(th) * pu + np.sin(th) * pv + 0.25
    qt = -np.sin(th) * pu + np.cos(th) * pv + 0.1
    _, gs, gt = wave_height(qs, qt)
    expected = normals_from_gradient(
        np.cos(th) * gs - np.sin(th) * gt, np.sin(th) * gs + np.cos(th) * gt
    )
    angle = np.degrees(np.arccos(np.clip(np.sum(placed * expected, axis=-1), -1, 1)))
    assert angle.max() < 0.03  # bilinear interpolation: (2 pi / 80 texels)^2 / 8 of a slope


def test_sample_wrapped_wraps_and_clamps():
    img = np.arange(12, dtype=np.float32).reshape(3, 4, 1)
    chain = img
    # halfway between the last and the first column, on a row centre
    got = sample_wrapped(chain, np.array([4.0, 4.0]), np.array([0.5, 0.5]))
    np.testing.assert_allclose(got[:, 0], [(3 + 0) / 2] * 2)
    got = sample_wrapped(chain, np.array([4.0]), np.array([0.5]), wrap=False)
    np.testing.assert_allclose(got[:, 0], [3.0])
    assert len(mip_chain(np.zeros((8, 2, 3)))) == 4
    assert mip_chain(np.zeros((8, 2, 3))).level(2).shape == (2, 1, 3)


def test_mask_weights_grey_and_ids():
    grey = np.linspace(0, 1, 16, dtype=np.float32).reshape(4, 4)
    np.testing.assert_array_equal(mask_weights(grey, (4, 4)), grey)
    assert mask_weights(grey, (8, 8)).shape == (8, 8)
    ids = np.zeros((4, 4, 3), np.float32)
    ids[:2] = np.array([255, 0, 0]) / 255
    ids[2:, :2] = 128 / 255
    np.testing.assert_array_equal(mask_weights(ids, (4, 4), ids=[(255, 0, 0)])[:, 0], [1, 1, 0, 0])
    np.testing.assert_array_equal(mask_weights(ids, (4, 4), ids=[128])[:, 0], [0, 0, 1, 1])
    big = mask_weights(ids, (8, 8), ids=[(255, 0, 0), 128])  # nearest texel: IDs never blend
    assert set(np.unique(big)) == {0.0, 1.0} and big[:, :4].all()
    with pytest.raises(ArgumentError, match="material ID"):
        mask_weights(grey, (4, 4), ids=[(1, 2)])


def test_layers_apply_in_order_with_masks():
    macro = detail_map(32, 5)
    a, b = detail_map(16, 6), detail_map(8, 7)
    mask = np.zeros((32, 32), np.float32)
    mask[:, 16:] = 1
    out = apply_layers(
        macro,
        [DetailLayer(a, tile=2, strength=0.5), DetailLayer(b, tile=4, rotation=90, mask=mask)],
        method="rnm",
    )
    step = blend(macro, place_detail(a, (32, 32), tile=2), method="rnm", strength=0.5)
    np.testing.assert_allclose(out[:, :16], step[:, :16], atol=tol.FLOAT32_UNIT)
    expected = blend(step, place_detail(b, (32, 32), tile=4, rotation=90), method="rnm")
    np.testing.assert_allclose(out[:, 16:], expected[:, 16:], atol=tol.FLOAT32_UNIT)


def test_bad_placement():
    d = detail_map(8)
    with pytest.raises(ArgumentError, match="non-zero"):
        place_detail(d, (8, 8), tile=0)
    with pytest.raises(ArgumentError, match="pair"):
        place_detail(d, (8, 8), offset=(1, 2, 3))
    with pytest.raises(ArgumentError, match=r"\(h, w, 3\)"):
        place_detail(d[..., :2], (8, 8))
    with pytest.raises(ArgumentError, match="mask"):
        apply_layers(d, [DetailLayer(d, mask=np.ones((3, 3)))])
