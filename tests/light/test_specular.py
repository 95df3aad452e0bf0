"""Specular prefiltering against brute-force convolution, closed forms and invariants."""

import numpy as np
import pytest
from scipy import integrate

import bakeshop.light.specular as specular
from bakeshop.errors import ArgumentError
from bakeshop.io import read_image
from bakeshop.light import _native
from bakeshop.light.specular import (
    mip_roughness,
    phong_exponents,
    prefilter_ggx,
    prefilter_phong,
    source_cube,
)
from bakeshop.sphere import cube_to_view, layout, remap, sample
from tests.files import probe_path
from tests.tolerances import (
    EXACT,
    FIS_MAX,
    FIS_RMS,
    FLOAT32_VALUE,
    PREFILTER_ENERGY_RTOL,
    PREFILTER_MAX,
    PREFILTER_RMS,
    UNIFORM_RTOL,
)

CUBE = layout("cube")


def brute_force(src, size, lobe):
    """Every output texel as the normalised lobe-weighted sum over every source texel."""
    s = src.shape[1]
    dirs_in = CUBE.directions((6, s, s))[0].reshape(-1, 3)
    omega = CUBE.solid_angles((6, s, s)).reshape(-1)
    dirs_out = CUBE.directions((6, size, size))[0].reshape(-1, 3)
    values = src.reshape(-1, src.shape[-1]).astype(float)
    out = np.empty((dirs_out.shape[0], values.shape[1]))
    for i in range(0, dirs_out.shape[0], 512):
        nl = dirs_out[i : i + 512] @ dirs_in.T
        w = np.where(nl > 0, lobe(np.maximum(nl, 0)), 0) * omega
        out[i : i + 512] = (w @ values) / w.sum(1, keepdims=True)
    return out.reshape(6, size, size, -1)


def ggx_lobe(roughness):
    a2 = roughness**4
    # D(h) (n.l) with (n.h)^2 = (1 + n.l) / 2 for n = v
    return lambda nl: a2 / (np.pi * (((1 + nl) / 2) * (a2 - 1) + 1) ** 2) * nl


def phong_lobe(e):
    return lambda nl: nl**e


def relative_errors(got, ref):
    rms = np.sqrt(np.mean((got - ref) ** 2) / np.mean(ref**2))
    return rms, np.abs(got / ref - 1).max()


@pytest.fixture(scope="module")
def sunny_cube():
    probe = read_image(probe_path("quarry_01"))
    return remap(probe, "latlong", "cube", 48, filter="area")


def test_roughness_zero_returns_the_source():
    rng = np.random.default_rng(1)
    cube = (rng.random((6, 16, 16, 3)) * 10).astype(np.float32)
    chain = prefilter_ggx(cube, "cube", size=16, mips=5)
    assert np.abs(chain[0] - cube).max() == EXACT
    assert [level.shape for level in chain] == [(6, s, s, 3) for s in (16, 8, 4, 2, 1)]
    assert all(level.dtype == np.float32 for level in chain)
    # the source in another layout: level 0 is its area remap to the cube
    latlong = (rng.random((32, 64, 3)) * 10).astype(np.float32)
    chain = prefilter_ggx(latlong, "latlong", size=8, mips=2)
    np.testing.assert_array_equal(chain[0], remap(latlong, "latlong", "cube", 8, filter="area"))


@pytest.mark.parametrize("view", ["cross-vertical", "strip-horizontal"])
def test_a_cross_gives_the_chain_of_its_cube(view):
    rng = np.random.default_rng(2)
    cube = (rng.random((6, 16, 16, 3)) * 10).astype(np.float32)
    picture = cube_to_view(cube, view)
    for a, b in zip(
        prefilter_ggx(picture, view, size=16, mips=3),
        prefilter_ggx(cube, "cube", size=16, mips=3),
        strict=True,
    ):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("brdf", ["ggx", "phong"])
def test_uniform_environment_stays_uniform(brdf):
    # the lobes are normalised: a uniform environment of any value comes out unchanged
    latlong = np.full((64, 128, 3), 2.5, np.float32)
    latlong[..., 1] = 0.25
    run = prefilter_ggx if brdf == "ggx" else prefilter_phong
    for level in run(latlong, layout="latlong", size=32, mips=6):
        np.testing.assert_allclose(level[..., 0], 2.5, rtol=UNIFORM_RTOL)
        np.testing.assert_allclose(level[..., 1], 0.25, rtol=UNIFORM_RTOL)


@pytest.mark.slow
def test_ggx_matches_brute_force_on_a_sunny_probe(sunny_cube):
    chain = prefilter_ggx(sunny_cube, "cube", size=48, mips=4)
    for m, r in enumerate(mip_roughness(4)[1:], 1):
        rms, worst = relative_errors(chain[m], brute_force(sunny_cube, 48 >> m, ggx_lobe(r)))
        assert rms < PREFILTER_RMS and worst < PREFILTER_MAX, (m, rms, worst)


@pytest.mark.slow
def test_phong_matches_brute_force_on_a_sunny_probe(sunny_cube):
    chain = prefilter_phong(sunny_cube, "cube", size=48, mips=4)
    for m, e in enumerate(phong_exponents(4)[1:], 1):
        rms, worst = relative_errors(chain[m], brute_force(sunny_cube, 48 >> m, phong_lobe(e)))
        assert rms < PREFILTER_RMS and worst < PREFILTER_MAX, (m, rms, worst)


@pytest.mark.slow
@pytest.mark.parametrize("brdf, m", [("ggx", 1), ("ggx", 2), ("phong", 1), ("phong", 2)])
def test_importance_sampling_alone_matches_brute_force(sunny_cube, monkeypatch, brdf, m):
    # No exact convolution of the rest: the path the narrow lobes of big cubes take.
    monkeypatch.setattr(specular, "EXACT_BUDGET", 0)
    if brdf == "ggx":
        r = [0, 0.2, 0.4]
        got = prefilter_ggx(sunny_cube, "cube", size=48, mips=3, roughness=r)[m]
        ref = brute_force(sunny_cube, 48 >> m, ggx_lobe(r[m]))
    else:
        e = [np.inf, 300, 40]
        got = prefilter_phong(sunny_cube, "cube", size=48, mips=3, exponents=e)[m]
        ref = brute_force(sunny_cube, 48 >> m, phong_lobe(e[m]))
    rms, worst = relative_errors(got, ref)
    assert rms < FIS_RMS and worst < FIS_MAX, (rms, worst)


def test_a_point_light_gives_the_normalised_lobe(monkeypatch):
    # One bright texel of radiance L and solid angle w: every output texel must see
    # L w (e + 1) / (2 pi) (n.l)^e (Phong) and L w D(h) (n.l) / integral(D(h) (n.l) dl) (GGX),
    # with the normaliser integrated here by scipy, independently. (The whole texel goes the
    # exact bright-texel path: no part of it is left to the coarser rest.)
    monkeypatch.setattr(specular, "BRIGHT_RATIO", 1e-9)
    s = 32
    cube = np.zeros((6, s, s, 1), np.float32)
    cube[4, 11, 13] = 1e6
    light = CUBE.directions((6, s, s))[0][4, 11, 13]
    energy = 1e6 * CUBE.solid_angles((6, s, s))[4, 11, 13]
    dirs = CUBE.directions((6, 8, 8))[0]
    nl = np.maximum(dirs @ light, 0)
    e = 12.0
    got = prefilter_phong(cube, "cube", size=s, mips=3, exponents=[np.inf, 1e9, e])[2][..., 0]
    np.testing.assert_allclose(got, energy * (e + 1) / (2 * np.pi) * nl**e, rtol=1e-4, atol=1e-6)
    r = 0.6
    a2 = r**4
    d = lambda c: a2 / (np.pi * (((1 + c) / 2) * (a2 - 1) + 1) ** 2)  # noqa: E731
    norm = 2 * np.pi * integrate.quad(lambda c: d(c) * c, 0, 1, epsabs=0, epsrel=1e-10)[0]
    got = prefilter_ggx(cube, "cube", size=s, mips=3, roughness=[0, 0.1, r])[2][..., 0]
    np.testing.assert_allclose(got, energy * d(nl) * nl / norm, rtol=1e-4, atol=1e-6)


@pytest.mark.parametrize("r", [0.01, 0.03, 0.08])
@pytest.mark.parametrize("out_size", [32, 16])
def test_a_sun_under_a_mirror_like_lobe_keeps_its_energy(monkeypatch, r, out_size):
    # A lobe narrower than a texel cannot be point-sampled: the sun must land whole in the
    # texels around it (energy L w, as the closed form), never multiplied by w / (pi alpha^2)
    # (a 1e4 sun came out as 5e7) nor lost between texel centres.
    monkeypatch.setattr(specular, "BRIGHT_RATIO", 1e-9)
    s = 32
    cube = np.zeros((6, s, s, 1), np.float32)
    cube[1, 5, 20] = 1e4
    energy = 1e4 * CUBE.solid_angles((6, s, s))[1, 5, 20]
    level = prefilter_ggx(cube, "cube", size=s, mips=2, roughness=[r, r])[s // out_size - 1]
    got = float(np.sum(level[..., 0] * CUBE.solid_angles((6, out_size, out_size))))
    assert got == pytest.approx(energy, rel=PREFILTER_ENERGY_RTOL)
    assert level.max() <= 1e4 * (s / out_size) ** 2 * (1 + PREFILTER_ENERGY_RTOL)


def test_bilinear_lookup_agrees_with_the_sphere_sampler():
    # The kernel's own cube addressing (OpenGL's major-axis rule, FACE_BASES, padded faces)
    # against bakeshop.sphere.sample, away from the cube's corners where the filters differ.
    rng = np.random.default_rng(3)
    cube = rng.random((6, 8, 8, 4)).astype(np.float32)
    flat, offsets, sizes = specular._pyramid(cube)
    d = rng.normal(size=(4000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    _, x, y = np.moveaxis(CUBE.coordinates(d, (6, 8, 8)), -1, 0)
    d = d[(np.abs(x - 4) < 3) | (np.abs(y - 4) < 3)]

    # one sample along the lobe's axis, weight 1, at a solid angle so small that its level is
    # 0: the filter kernel returns the bilinear lookup of level 0 in each direction
    axis = np.array([[0.0, 0.0, 1.0, 1.0, -1e9]])
    got = np.empty((len(d), 4))
    _native.filter(d, axis, flat, offsets, sizes, 0.0, specular._LOG2_FIT, got)
    np.testing.assert_allclose(got, sample(cube, "cube", d), atol=FLOAT32_VALUE)


def test_defaults_and_mappings():
    np.testing.assert_allclose(mip_roughness(9), np.arange(9) / 8)
    np.testing.assert_allclose(phong_exponents(9)[[0, 4, 8]], [2048, 64, 2])
    assert source_cube(np.ones((6, 4, 4)), "cube", size=4).shape == (6, 4, 4, 1)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"mips": 10},  # a 256 cube has 9 levels
        {"mips": 0},
        {"roughness": [0, 0.5]},
        {"roughness": [0, 0.5, 1.5] + [1] * 6},
        {"samples": 0},
        {"size": 0},
    ],
)
def test_bad_arguments(kwargs):
    with pytest.raises(ArgumentError):
        prefilter_ggx(np.ones((6, 8, 8, 3), np.float32), "cube", **kwargs)


def test_bad_environments():
    bad = np.ones((6, 8, 8, 3), np.float32)
    bad[0, 0, 0, 0] = np.nan
    with pytest.raises(ArgumentError, match="NaN"):
        prefilter_ggx(bad, "cube", size=8, mips=2)
    with pytest.raises(ArgumentError):
        prefilter_phong(np.ones((6, 8, 8, 3)), "cube", size=8, mips=2, exponents=[1, -1])
    with pytest.raises(ArgumentError):
        prefilter_ggx(np.ones((8, 8, 5)), "latlong", size=8, mips=1)
