"""Blend methods: identities, independent formulations, and the ground-truth study."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.normals.blend import DEFAULT_METHOD, METHODS, blend, blend_pd, blend_rnm
from tests import tolerances as tol
from tests.normals import groundtruth as gt


def random_normals(n, seed, max_angle=70.0):
    """``n`` unit normals spread over the cap within ``max_angle`` degrees of +Z."""
    rng = np.random.default_rng(seed)
    theta = np.radians(max_angle) * np.sqrt(rng.random(n))
    phi = 2 * np.pi * rng.random(n)
    return np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1
    )


FLAT = np.array([0.0, 0.0, 1.0])


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_flat_detail_returns_macro(method, dtype):
    macro = random_normals(5000, 1, 89.0).astype(dtype)
    flat = np.broadcast_to(FLAT, macro.shape).astype(dtype)
    out = blend(macro, flat, method=method)
    assert out.dtype == dtype
    limit = tol.FLOAT64_UNIT if dtype == np.float64 else tol.FLOAT32_UNIT
    np.testing.assert_allclose(out, macro, rtol=0, atol=limit)


@pytest.mark.parametrize("method", [m for m in METHODS if m != "udn"])
def test_flat_macro_returns_detail(method):
    detail = random_normals(5000, 2, 89.0)
    out = blend(np.broadcast_to(FLAT, detail.shape), detail, method=method)
    np.testing.assert_allclose(out, detail, rtol=0, atol=tol.FLOAT64_UNIT)


def test_udn_flattens_detail_on_flat_macro():
    """UDN keeps the macro's z, so even on a flat macro it weakens the detail (documented)."""
    detail = random_normals(1000, 3, 60.0)
    out = blend(np.broadcast_to(FLAT, detail.shape), detail, method="udn")
    assert np.all(out[:, 2] >= detail[:, 2] - 1e-12)
    assert np.abs(out - detail).max() > 0.1


def rotation_z_to(n):
    """Rotation matrices taking +Z to each unit vector n (Rodrigues), built independently."""
    axis = np.cross(FLAT, n)
    s = np.linalg.norm(axis, axis=-1)
    c = n[..., 2]
    k = axis / np.where(s > 0, s, 1)[..., None]
    kx = np.zeros(n.shape[:-1] + (3, 3))
    kx[..., 0, 1], kx[..., 0, 2], kx[..., 1, 2] = -k[..., 2], k[..., 1], -k[..., 0]
    kx = kx - np.swapaxes(kx, -1, -2)
    eye = np.eye(3)
    return eye + s[..., None, None] * kx + (1 - c)[..., None, None] * (kx @ kx)


def test_rnm_is_the_rotation_of_the_detail():
    macro, detail = random_normals(3000, 4, 85.0), random_normals(3000, 5, 80.0)
    expected = np.einsum("nij,nj->ni", rotation_z_to(macro), detail)
    np.testing.assert_allclose(blend_rnm(macro, detail), expected, atol=tol.FLOAT64_UNIT)


def test_pd_adds_slopes():
    macro, detail = random_normals(3000, 6), random_normals(3000, 7)
    slopes = macro[:, :2] / macro[:, 2:] + detail[:, :2] / detail[:, 2:]
    expected = np.concatenate([slopes, np.ones((3000, 1))], axis=1)
    expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    np.testing.assert_allclose(blend_pd(macro, detail), expected, atol=tol.FLOAT64_UNIT)


def test_sg_equals_pd_in_a_shared_tangent_frame():
    macro, detail = random_normals(3000, 8), random_normals(3000, 9)
    np.testing.assert_allclose(
        blend(macro, detail, method="sg"), blend_pd(macro, detail), atol=tol.FLOAT64_UNIT
    )


def test_exact_is_the_displaced_surface_normal_without_curvature():
    """(S_u + d_u N) x (S_v + d_v N) for S = (u, v, H): the first-order displaced normal."""
    macro, detail = random_normals(3000, 10, 75.0), random_normals(3000, 11, 60.0)
    hu, hv = -macro[:, 0] / macro[:, 2], -macro[:, 1] / macro[:, 2]
    du, dv = -detail[:, 0] / detail[:, 2], -detail[:, 1] / detail[:, 2]
    su = np.stack([np.ones_like(hu), np.zeros_like(hu), hu], axis=1)
    sv = np.stack([np.zeros_like(hu), np.ones_like(hu), hv], axis=1)
    n = np.cross(su + du[:, None] * macro, sv + dv[:, None] * macro)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    np.testing.assert_allclose(blend(macro, detail, method="exact"), n, atol=tol.FLOAT64_UNIT)


@pytest.mark.parametrize("method", METHODS)
def test_strength_scales_the_detail_height(method):
    """strength s on a detail from slopes g equals the detail made from slopes s g."""
    macro = random_normals(2000, 12)
    g = np.random.default_rng(13).normal(scale=0.4, size=(2000, 2))

    def from_slopes(slopes):
        n = np.concatenate([-slopes, np.ones((len(slopes), 1))], axis=1)
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    s = np.linspace(-1.5, 2.0, 2000)
    np.testing.assert_allclose(
        blend(macro, from_slopes(g), method=method, strength=s),
        blend(macro, from_slopes(g * s[:, None]), method=method),
        atol=1e-12,
    )
    np.testing.assert_allclose(
        blend(macro, from_slopes(g), method=method, strength=0.0), macro, atol=tol.FLOAT64_UNIT
    )


def test_image_shapes_blocks_and_dtype():
    macro = random_normals(700 * 500, 14).reshape(700, 500, 3).astype(np.float32)
    detail = random_normals(700 * 500, 15).reshape(700, 500, 3).astype(np.float32)
    out = blend(macro, detail)  # > one block of texels
    assert out.shape == (700, 500, 3) and out.dtype == np.float32
    ref = blend(macro.astype(np.float64), detail.astype(np.float64))
    np.testing.assert_allclose(out, ref, atol=tol.FLOAT32_UNIT)


def test_bad_input():
    n = random_normals(10, 0)
    with pytest.raises(ArgumentError, match="blend method"):
        blend(n, n, method="add")
    with pytest.raises(ArgumentError, match="same shape"):
        blend(n, n[:5])
    with pytest.raises(ArgumentError, match="3-vectors"):
        blend(n[:, :2], n[:, :2])
    with pytest.raises(ArgumentError, match="strength"):
        blend(n, n, strength=np.ones(3))
    bad = n.copy()
    bad[0] = np.nan
    out = blend(n, bad)
    assert np.isfinite(out).all()
    np.testing.assert_array_equal(out[0], FLAT)


# The ground-truth study (docs/normals.md prints the full table from the same module).


def errors(construction, **detail):
    macro, det, truth = gt.maps(construction, size=96, **detail)
    return {m: gt.angular_error(blend(macro, det, method=m), truth) for m in METHODS}


def test_partial_derivatives_are_exact_for_heights_along_an_axis():
    e = errors("axis")
    assert e["pd"].max() < tol.GROUND_TRUTH_EXACT_DEG
    assert e["sg"].max() < tol.GROUND_TRUTH_EXACT_DEG


def test_exact_blend_is_best_for_detail_on_macro_uvs_and_converges():
    coarse = errors("uv", tiles=24)
    fine = errors("uv", tiles=384)
    for e in (coarse, fine):
        best = min(METHODS, key=lambda m: e[m].mean())
        assert best == "exact" == DEFAULT_METHOD
        assert e["exact"].max() < min(e[m].max() for m in METHODS if m != "exact")
    # exact up to the macro curvature: the error vanishes with the detail's amplitude...
    assert fine["exact"].mean() < tol.GROUND_TRUTH_CURVATURE_DEG
    # ...while RNM keeps about a degree, however small the detail is.
    assert fine["rnm"].mean() > 0.5 and coarse["rnm"].mean() > 0.5


def test_rnm_is_best_for_detail_indexed_by_arc_length():
    e = errors("arclength", tiles=96)
    assert min(METHODS, key=lambda m: e[m].mean()) == "rnm"
    assert min(METHODS, key=lambda m: e[m].max()) == "rnm"
