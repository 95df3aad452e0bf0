"""The split-sum DFG table against closed forms, brute-force quadrature and Karis' fit."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.light.dfg import dfg_approximation, dfg_table, dfg_terms
from tests.tolerances import DFG_FIT_MAX, DFG_FIT_RMS, DFG_QUADRATURE_ATOL, FLOAT32_VALUE


def quadrature(n_dot_v, roughness, visibility, steps=1200):
    """(A, B) by the midpoint rule over the hemisphere of light directions l, in (cos theta, phi).

    Independent of the importance-sampling code: it integrates f(l, v) (n.l) dl directly with
    the GGX distribution and the Smith visibility written out from the papers.
    """
    alpha = roughness**2
    mu = (np.arange(steps) + 0.5) / steps  # cos(theta_l), dl = dmu dphi
    phi = (np.arange(2 * steps) + 0.5) / (2 * steps) * np.pi  # symmetric in phi: half, x2
    mu, phi = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - mu**2)
    lx, ly, lz = s * np.cos(phi), s * np.sin(phi), mu
    vx, vz = np.sqrt(1 - n_dot_v**2), n_dot_v
    hx, hy, hz = lx + vx, ly, lz + vz
    norm = np.sqrt(hx**2 + hy**2 + hz**2)
    n_dot_h = hz / norm
    v_dot_h = (vx * hx + vz * hz) / norm
    a2 = alpha**2
    d = a2 / (np.pi * (n_dot_h**2 * (a2 - 1) + 1) ** 2)
    nl, nv = lz, n_dot_v
    if visibility == "schlick":
        k = alpha / 2
        g = nv / (nv * (1 - k) + k) * nl / (nl * (1 - k) + k)
        vis = g / (4 * nl * nv)
    else:  # Heitz 2014, eq. 99: G2 = 1 / (1 + Lambda(v) + Lambda(l))
        lam = lambda c: (-1 + np.sqrt(1 + a2 * (1 - c**2) / c**2)) / 2  # noqa: E731
        vis = 1 / (1 + lam(nv) + lam(nl)) / (4 * nl * nv)
    fc = (1 - v_dot_h) ** 5
    f = d * vis * nl
    dl = (1 / steps) * (np.pi / (2 * steps)) * 2
    return np.array([np.sum((1 - fc) * f) * dl, np.sum(fc * f) * dl])


@pytest.mark.parametrize("visibility", ["height-correlated", "schlick"])
@pytest.mark.parametrize(
    "n_dot_v, roughness",
    [(0.9, 0.4), (0.5, 0.5), (0.25, 0.7), (0.1, 0.9), (0.7, 1.0), (0.05, 0.6), (0.02, 1.0)],
)
def test_terms_match_brute_force_quadrature(n_dot_v, roughness, visibility):
    got = dfg_terms(n_dot_v, roughness, visibility=visibility)
    np.testing.assert_allclose(
        got, quadrature(n_dot_v, roughness, visibility), atol=DFG_QUADRATURE_ATOL
    )


@pytest.mark.parametrize("visibility", ["height-correlated", "schlick"])
def test_smooth_limit_is_schlick_fresnel(visibility):
    # A mirror reflects F(n.v) = F0 + (1 - F0) (1 - n.v)^5: A = 1 - Fc, B = Fc exactly.
    nv = np.array([1.0, 0.75, 0.5, 0.2, 0.05])
    got = dfg_terms(nv, 0.0, visibility=visibility)
    fc = (1 - nv) ** 5
    np.testing.assert_allclose(got, np.stack([1 - fc, fc], -1), atol=FLOAT32_VALUE)


def test_albedo_is_at_most_one_and_falls_with_roughness():
    table = dfg_table(32).astype(float)
    albedo = table.sum(-1)  # F0 = 1: the whole single-scattering albedo
    assert albedo.max() <= 1 + 1e-3 and table.min() >= 0
    # Seen head-on, rougher surfaces lose more energy to masking (single scattering).
    assert np.all(np.diff(albedo[:, -1]) < 1e-5)


def test_schlick_table_matches_karis_fit():
    size = 32
    table = dfg_table(size, visibility="schlick").astype(float)
    centres = (np.arange(size) + 0.5) / size
    nv, r = np.meshgrid(centres, centres)
    diff = table - dfg_approximation(nv, r)
    assert np.sqrt(np.mean(diff**2)) < DFG_FIT_RMS
    assert np.abs(diff).max() < DFG_FIT_MAX
    # The fit's own anchor: a smooth surface seen head-on reflects F0 (A ~ 1, B ~ 0).
    np.testing.assert_allclose(dfg_approximation(1.0, 0.0), [0.994, 0.006], atol=1e-3)
    np.testing.assert_allclose(dfg_terms(1.0, 0.0, visibility="schlick"), [1.0, 0.0], atol=1e-6)


def test_table_layout_columns_n_dot_v_rows_roughness():
    table = dfg_table(8, samples=256)
    assert table.shape == (8, 8, 2) and table.dtype == np.float32
    np.testing.assert_allclose(
        table[2, 5], dfg_terms((5 + 0.5) / 8, (2 + 0.5) / 8, samples=256), rtol=FLOAT32_VALUE
    )


def test_terms_broadcast():
    got = dfg_terms(np.full((2, 3), 0.5), np.array([0.1, 0.5, 0.9]))
    assert got.shape == (2, 3, 2)
    np.testing.assert_array_equal(got[0], got[1])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"n_dot_v": 1.5, "roughness": 0.5},
        {"n_dot_v": 0.5, "roughness": -0.1},
        {"n_dot_v": np.nan, "roughness": 0.5},
        {"n_dot_v": 0.5, "roughness": 0.5, "samples": 0},
        {"n_dot_v": 0.5, "roughness": 0.5, "visibility": "kelemen"},
    ],
)
def test_bad_arguments(kwargs):
    with pytest.raises(ArgumentError):
        dfg_terms(**kwargs)


@pytest.mark.parametrize("size", [0, 100_000])
def test_bad_table_size(size):
    with pytest.raises(ArgumentError):
        dfg_table(size)
