"""Diffuse irradiance: closed forms, layouts, and the bound of ``auto`` against ``exact``."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import bakeshop.light as ir
from bakeshop.errors import ArgumentError
from bakeshop.io import read_image
from bakeshop.light import sh
from bakeshop.light.diffuse import compress
from bakeshop.sphere import layout, texels
from tests.files import PROBES, probe_path
from tests.tolerances import (
    FLOAT32_VALUE,
    IRRADIANCE_AUTO_MAX,
    IRRADIANCE_AUTO_RMS,
    IRRADIANCE_EXACT,
    UNIFORM_DIM,
)

#: test DIM size: small enough that "exact" from a 1024x512 probe takes a fraction of a second.
SIZE = (64, 32)


def _errors(got, ref):
    got, ref = np.asarray(got, np.float64), np.asarray(ref, np.float64)
    rms = np.sqrt(np.mean((got - ref) ** 2) / np.mean(ref**2))
    return rms, float(np.max(np.abs(got - ref) / np.abs(ref)))


def _env(name, size, f):
    """Evaluate a radiance function f(dirs) -> (..., 3) at the texels of a layout."""
    lay = layout(name)
    shape = lay.shape(size)
    dirs, valid = lay.directions(shape)
    return np.where(valid[..., None], f(dirs), 0).astype(np.float32)


def _sky(d):
    """A smooth sky: brighter and bluer up, a warm glow, a dim ground."""
    up = np.clip(d[..., 1], 0, None)[..., None]
    glow = np.clip(d @ np.array([0.6, 0.3, -0.74]) / 1.0, 0, None)[..., None] ** 8
    return 0.2 + np.array([0.5, 0.7, 1.2]) * up + np.array([3.0, 2.0, 1.0]) * glow


@pytest.mark.parametrize("method", ir.METHODS)
def test_uniform_environment_gives_one(method):
    env = np.ones((256, 512, 3), np.float32)
    dim = ir.irradiance(env, "latlong", size=SIZE, method=method)
    assert dim.shape == (32, 64, 3) and dim.dtype == np.float32
    # every method is a quadrature over the texels, with an O(texel angle^2) error
    np.testing.assert_allclose(dim, 1.0, atol=UNIFORM_DIM)


def test_exact_quadrature_converges_to_one_at_second_order():
    errs = []
    for rows in (32, 64, 128):
        env = np.ones((rows, 2 * rows, 1), np.float32)
        dim = ir.irradiance(env, "latlong", size=SIZE, method="exact")
        errs.append(np.abs(dim.astype(np.float64) - 1).max())
    assert errs[2] < 1e-4
    assert 3 < errs[0] / errs[1] < 5 and 3 < errs[1] / errs[2] < 5  # O(h^2)


def test_single_bright_texel_follows_the_cosine_law():
    lay = layout("latlong")
    shape = (128, 256)
    env = np.zeros(shape + (3,), np.float32)
    row, col = 40, 77
    env[row, col] = [1000.0, 500.0, 250.0]
    dirs, _ = lay.directions(shape)
    omega = lay.solid_angles(shape)
    w = dirs[row, col]
    normals, _ = lay.directions((45, 90))
    expected = env[row, col] * omega[row, col] * np.clip(normals @ w, 0, None)[..., None] / np.pi
    for method in ("exact", "auto"):
        dim = ir.irradiance(env, "latlong", size=(90, 45), method=method)
        np.testing.assert_allclose(dim, expected, rtol=1e-6, atol=1e-9, err_msg=method)


def test_small_cap_matches_the_closed_form():
    # a cap of angular radius r and radiance 1 seen whole from n at angle t: E = pi sin^2 r cos t
    r = math.radians(20)
    axis = np.array([0.2, 0.9, -0.3])
    axis /= np.linalg.norm(axis)
    env = _env("latlong", 512, lambda d: np.repeat((d @ axis > math.cos(r))[..., None], 3, -1))
    lay = layout("latlong")
    normals, _ = lay.directions(lay.shape((64, 32)))
    cos_t = normals @ axis
    whole = cos_t > math.sin(r) + 0.05
    dim = ir.irradiance(env, "latlong", size=(64, 32), method="exact")[..., 0]
    expected = math.sin(r) ** 2 * cos_t
    np.testing.assert_allclose(dim[whole], expected[whole], rtol=5e-3)


def test_same_environment_in_every_layout_gives_the_same_dim():
    ref = ir.irradiance(_env("latlong", 256, _sky), "latlong", size=SIZE, method="exact")
    for name, size in (("cube", 96), ("angular", 384), ("octahedral", 256), ("cross-vertical", 64)):
        for method in ("exact", "auto"):
            dim = ir.irradiance(_env(name, size, _sky), name, size=SIZE, method=method)
            rms, worst = _errors(dim, ref)
            assert worst < 2e-3, (name, method, worst)


@pytest.mark.parametrize("to, size", [("cube", 16), ("angular", 40), ("latlong", (36, 18))])
def test_output_layouts(to, size):
    env = _env("latlong", 128, _sky)
    dim = ir.irradiance(env, "latlong", to=to, size=size, method="exact")
    lay = layout(to)
    shape = lay.shape(size)
    assert dim.shape == shape + (3,)
    normals, valid = lay.directions(shape)
    assert np.all(dim[~valid] == 0)
    ref = ir.irradiance(env, "latlong", size=SIZE, method="exact")
    # the DIM is one function of the normal: sampled at the cube's normals from the latlong DIM
    # at a fine size they agree (bilinear sampling error of a smooth function)
    fine = ir.irradiance(env, "latlong", size=(256, 128), method="exact")
    from bakeshop.sphere import sample

    np.testing.assert_allclose(dim[valid], sample(fine, "latlong", normals[valid]), rtol=2e-3)
    assert ref.shape == (32, 64, 3)


def test_sh_order_2_is_exact_for_an_order_2_environment():
    # Funk-Hecke: a radiance of degree <= 2 has irradiance sum A_l L_lm Y_lm exactly
    c = np.zeros((9, 3))
    c[0] = 3.0
    c[2] = [0.8, 0.5, 0.2]
    c[6] = [0.4, 0.3, 0.1]
    c[8] = [0.2, -0.1, 0.3]
    env = _env("latlong", 256, lambda d: sh.evaluate(c, d))
    normals, _ = layout("latlong").directions((32, 64))
    analytic = sh.evaluate(sh.irradiance_coefficients(c), normals)
    for method in ("sh", "exact"):
        dim = ir.irradiance(env, "latlong", size=SIZE, method=method, order=2)
        np.testing.assert_allclose(dim, analytic, rtol=2e-4, atol=1e-5, err_msg=method)


def _probe(name):
    return read_image(probe_path(name))


@pytest.mark.parametrize("name", PROBES)
def test_auto_agrees_with_exact_on_real_probes(name):
    env = _probe(name)
    exact = ir.irradiance(env, "latlong", size=SIZE, method="exact")
    auto = ir.irradiance(env, "latlong", size=SIZE)
    rms, worst = _errors(auto, exact)
    print(f"{name}: auto vs exact rms {rms:.2e} max {worst:.2e}")
    assert rms < IRRADIANCE_AUTO_RMS and worst < IRRADIANCE_AUTO_MAX


@pytest.mark.parametrize("radius_deg, radiance", [(0.27, 1e5), (1.0, 3e3), (3.0, 100.0)])
def test_auto_agrees_with_exact_on_synthetic_suns(radius_deg, radiance):
    s = np.array([-0.4, 0.5, 0.6])
    s /= np.linalg.norm(s)
    cos_r = math.cos(math.radians(radius_deg))
    env = _env("latlong", 512, lambda d: _sky(d) + radiance * (d @ s > cos_r)[..., None])
    if not (env > 50).any():  # a sun smaller than a texel: light the nearest texel
        lay = layout("latlong")
        xy = lay.coordinates(s, env.shape[:2]).astype(int)
        env[xy[1], xy[0]] += radiance
    exact = ir.irradiance(env, "latlong", size=SIZE, method="exact")
    auto = ir.irradiance(env, "latlong", size=SIZE)
    rms, worst = _errors(auto, exact)
    assert rms < IRRADIANCE_AUTO_RMS and worst < IRRADIANCE_AUTO_MAX, (rms, worst)


def test_compress_keeps_energy_and_first_moment():
    rng = np.random.default_rng(0)
    env = rng.gamma(0.5, 2.0, size=(64, 128, 3)).astype(np.float32)
    env[10, 20] = 1e4
    values, dirs, omega, _ = texels(env, "latlong")
    cd, ce = compress(values, dirs, omega, base=8, hot_fraction=1e-3)
    energy = values * omega[:, None]
    np.testing.assert_allclose(ce.sum(0), energy.sum(0), rtol=1e-12)
    assert len(cd) < len(dirs) / 4
    np.testing.assert_allclose(np.linalg.norm(cd, axis=1), 1, atol=1e-12)
    # the bright texel stays a source of its own, at its own direction
    k = np.argmax(ce[:, 0])
    np.testing.assert_allclose(cd[k], dirs[10 * 128 + 20], atol=1e-12)


@pytest.mark.parametrize("n_sources", [3000, 200_000])
def test_cosine_sum_against_brute_force(n_sources):
    # the cone hierarchy (6 to thousands of large cones) changes nothing but rounding
    rng = np.random.default_rng(1)
    w = rng.normal(size=(n_sources, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    e = rng.random((n_sources, 2))
    n = rng.normal(size=(200, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    brute = np.clip(n @ w.T, 0, None) @ e
    np.testing.assert_allclose(ir.cosine_sum(n, w, e), brute, rtol=IRRADIANCE_EXACT)


def test_channels_and_bad_input():
    env = _env("latlong", 64, _sky)
    rgba = np.concatenate([env, np.ones(env.shape[:2] + (1,), np.float32)], -1)
    with_alpha = ir.irradiance(rgba, "latlong", size=SIZE)  # alpha carried (the contract)
    np.testing.assert_allclose(with_alpha[..., :3], ir.irradiance(env, "latlong", size=SIZE))
    grey = env[..., :1]
    np.testing.assert_allclose(
        ir.irradiance(grey, "latlong", size=SIZE, method="exact")[..., 0],
        ir.irradiance(env, "latlong", size=SIZE, method="exact")[..., 0],
        rtol=FLOAT32_VALUE,
    )
    bad = env.copy()
    bad[3, 4, 1] = np.nan
    for method in ir.METHODS:
        with pytest.raises(ArgumentError):
            ir.irradiance(bad, "latlong", size=SIZE, method=method)
    with pytest.raises(ArgumentError):
        ir.irradiance(env, "latlong", method="fast")
    with pytest.raises(ArgumentError):
        ir.irradiance(env, "cube")
    assert ir.irradiance(env[..., 0], "latlong", size=SIZE).shape == (32, 64)  # 2-D in, 2-D out
    with pytest.raises(ArgumentError):  # refused before anything is allocated
        ir.irradiance(env, "latlong", size=(40000, 20000))


def test_dim_pair_splits_the_sun():
    env = _probe("quarry_01")
    pair = ir.dim_pair(env, "latlong", size=SIZE)
    assert pair.sun is not None
    # the lit DIM is the probe's DIM; the shadow DIM is the painted probe's
    for got, probe in ((pair.sun_dim, env), (pair.shadow_dim, pair.shadow_probe)):
        exact = ir.irradiance(probe, "latlong", size=SIZE, method="exact")
        rms, worst = _errors(got, exact)
        assert rms < IRRADIANCE_AUTO_RMS and worst < IRRADIANCE_AUTO_MAX
    # their difference is the sun's cosine law, E_sun max(0, n.s) / pi
    normals, _ = layout("latlong").directions((32, 64))
    s = pair.sun
    law = np.clip(normals @ s.direction, 0, None)[..., None] * s.irradiance / np.pi
    diff = pair.sun_dim.astype(np.float64) - pair.shadow_dim
    # the sun region spans a few degrees: the law holds to that width at the terminator
    assert np.abs(diff - law).max() < 0.01 * law.max()
    assert pair.shadow_probe.shape == env.shape and pair.shadow_probe.dtype == env.dtype


def test_dim_pair_paints_a_copy_unless_told_to_paint_the_probe_itself():
    env = _probe("quarry_01")
    before = env.copy()
    pair = ir.dim_pair(env, "latlong", size=SIZE)
    np.testing.assert_array_equal(env, before)  # the caller's probe is untouched
    assert not np.array_equal(pair.shadow_probe, env)  # the sun is painted out of a copy
    in_place = ir.dim_pair(env, "latlong", size=SIZE, copy=False)
    assert np.shares_memory(in_place.shadow_probe, env)
    np.testing.assert_array_equal(env, pair.shadow_probe)
    np.testing.assert_array_equal(in_place.sun_dim, pair.sun_dim)


def test_dim_pair_without_a_sun():
    env = _probe("forest_slope")
    pair = ir.dim_pair(env, "latlong", size=SIZE)
    assert pair.sun is None
    np.testing.assert_array_equal(pair.sun_dim, pair.shadow_dim)
    np.testing.assert_array_equal(pair.shadow_probe, env)


@settings(max_examples=15, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    n_lights=st.integers(0, 12),
    peak=st.floats(1.0, 1e6),
)
def test_auto_bound_holds_on_random_skies_with_lights(seed, n_lights, peak):
    rng = np.random.default_rng(seed)
    tint = rng.uniform(0.2, 2.0, 3)
    env = (_env("latlong", 128, _sky) * tint).astype(np.float32)
    for _ in range(n_lights):  # point lights and small lamps of random power
        r, c = rng.integers(0, 128), rng.integers(0, 256)
        size = rng.integers(1, 4)
        env[r : r + size, c : c + size] += peak * rng.uniform(0, 1, 3).astype(np.float32)
    exact = ir.irradiance(env, "latlong", size=(32, 16), method="exact")
    auto = ir.irradiance(env, "latlong", size=(32, 16))
    rms, worst = _errors(auto, exact)
    assert rms < IRRADIANCE_AUTO_RMS and worst < IRRADIANCE_AUTO_MAX, (rms, worst)


def test_black_integer_and_cube_inputs():
    black = np.zeros((32, 64, 3), np.float32)
    for method in ir.METHODS:
        assert not ir.irradiance(black, "latlong", size=(8, 4), method=method).any()
    pair = ir.dim_pair(black, "latlong", size=(8, 4))
    assert pair.sun is None and not pair.sun_dim.any()
    ldr = np.full((32, 64, 3), 200, np.uint8)
    pair = ir.dim_pair(ldr, "latlong", size=(8, 4))
    assert pair.shadow_probe.dtype == np.float32 and pair.sun_dim.dtype == np.float32
    np.testing.assert_allclose(pair.sun_dim, 200, rtol=UNIFORM_DIM * 10)
    cube = np.ones((6, 16, 16, 3), np.float32)
    pair = ir.dim_pair(cube, "cube", to="cube", size=4)
    assert pair.sun_dim.shape == (6, 4, 4, 3) and pair.shadow_probe.shape == cube.shape
    np.testing.assert_allclose(pair.sun_dim, 1, atol=UNIFORM_DIM * 10)


def test_exact_agrees_with_an_independent_monte_carlo_estimate():
    # E(n) = 4 pi mean(L(w) max(0, n.w)) over uniform random directions, the radiance read by
    # the sphere's bilinear sampler: a different quadrature and a different reading of the
    # texels; they agree to the Monte Carlo noise and the bilinear smoothing (~0.3 %)
    from bakeshop.sphere import sample

    env = _probe("forest_slope")
    rng = np.random.default_rng(0)
    normals = rng.normal(size=(8, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    values, dirs, omega, _ = texels(env, "latlong")
    exact = ir.cosine_sum(normals, dirs, values * omega[:, None])
    n = 2_000_000
    z = 2 * (np.arange(n) + rng.random(n)) / n - 1  # stratified in z
    phi = 2 * np.pi * rng.random(n)
    r = np.sqrt(1 - z * z)
    d = np.stack([r * np.cos(phi), z, r * np.sin(phi)], 1)
    radiance = sample(env, "latlong", d).astype(np.float64)
    for normal, e in zip(normals, exact, strict=True):
        mc = 4 * np.pi * (radiance * np.clip(d @ normal, 0, None)[:, None]).mean(0)
        np.testing.assert_allclose(mc, e, rtol=1e-2)
