"""Engine presets: cube faces under each engine's lookup in a real OpenGL driver, Godot's
panorama against its sky shader's formula, the roughness of each level against the engines'
own roughness-to-LOD functions, and the SH layouts against the shader polynomials that read
them (Unity's ShadeSH9, three.js' SphericalHarmonics3 and shGetIrradianceAt, Filament's
Irradiance_SphericalHarmonics)."""

import math

import numpy as np
import pytest

from bakeshop import engines
from bakeshop.light import sh
from bakeshop.sphere import cube_to_faces, layout, sample
from tests.sphere.test_opengl import gl, gl_sample, random_directions, unambiguous  # noqa: F401


def test_directx_lookup_is_bakeshops_directx_face_set():
    cube = np.random.default_rng(0).random((6, 8, 8, 3)).astype(np.float32)
    np.testing.assert_array_equal(
        engines.cube_faces(cube, "unity"), cube_to_faces(cube, convention="directx")
    )
    assert engines.cube_faces(cube, "generic") is cube


@pytest.mark.parametrize("name", ["unity", "unreal", "three", "filament", "generic"])
def test_driver_finds_the_engines_faces_under_its_lookup(gl, name):  # noqa: F811
    """The engine's shader looks world direction d up at M d: the driver must return bakeshop's
    texel for d from the engine's faces, exactly (NEAREST)."""
    s = 16
    cube = np.random.default_rng(1).random((6, s, s, 3)).astype(np.float32)
    preset = engines.engine(name)
    faces = engines.cube_faces(cube, preset)
    d = random_directions(20000, seed=3)
    m = np.asarray(preset.lookup, np.float64)
    looked_up = d @ m.T
    ok = unambiguous(d, s) & unambiguous(looked_up, s)
    assert ok.sum() > 18000
    driver = gl_sample(gl, faces, looked_up)
    ours = sample(cube, "cube", d, filter="nearest")
    np.testing.assert_array_equal(driver[ok], ours[ok])


def test_godot_panorama_follows_its_sky_shader():
    """Godot's sky.glsl: u = atan2(x, -z) / 2 pi (wrapped to [0, 1)), v = acos(y) / pi."""
    h, w = 16, 32
    latlong = np.arange(h * w, dtype=np.float32).reshape(h, w, 1)
    pano = engines.panorama(latlong, "godot")
    d = random_directions(5000, seed=4)
    u = np.arctan2(d[:, 0], -d[:, 2]) / (2 * np.pi) % 1.0
    v = np.arccos(np.clip(d[:, 1], -1, 1)) / np.pi
    col, row = np.floor(u * w).astype(int), np.floor(v * h).astype(int)
    godot = pano[row, col, 0]
    c = layout("latlong").coordinates(d, (h, w))
    ours = latlong[np.floor(c[:, 1]).astype(int), np.floor(c[:, 0]).astype(int), 0]
    away = (np.abs((u * w) % 1 - 0.5) < 0.49) & (np.abs((v * h) % 1 - 0.5) < 0.49)
    np.testing.assert_array_equal(godot[away], ours[away])


def test_roughness_per_level_inverts_each_engines_lod_function():
    unity = engines.mip_roughness("unity", 7)
    for m, r in enumerate(unity):
        assert r * (1.7 - 0.7 * r) * 6 == pytest.approx(
            m, abs=1e-9
        )  # PerceptualRoughnessToMipmapLevel
    filament = engines.mip_roughness("filament", 9)
    for m, r in enumerate(filament):
        assert 8 * r * (2 - r) == pytest.approx(m, abs=1e-9)  # perceptualRoughnessToLod
    np.testing.assert_allclose(engines.mip_roughness("generic", 9), np.arange(9) / 8, atol=1e-12)
    assert engines.mip_roughness("three", 9) is None  # three.js builds its own PMREM


@pytest.fixture(scope="module")
def radiance():
    return np.random.default_rng(5).normal(size=(9, 3))


def polynomials(n):
    x, y, z = n[:, 0], n[:, 1], n[:, 2]
    return np.stack(
        [np.ones_like(x), y, z, x, x * y, y * z, 3 * z * z - 1, x * z, x * x - y * y], 1
    )


def e_over_pi(radiance, d):
    return sh.evaluate(sh.irradiance_coefficients(radiance), d)


def test_three_sh_is_radiance_in_threes_basis(radiance):
    d = random_directions(500, seed=6)
    c = np.asarray(engines.sh_export(radiance, "three")["coefficients"])
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    # SphericalHarmonics3.getBasisAt constants (three.js src/math/SphericalHarmonics3.js)
    basis = np.stack([0.282095 * np.ones_like(x), 0.488603 * y, 0.488603 * z, 0.488603 * x,
                      1.092548 * x * y, 1.092548 * y * z, 0.315392 * (3 * z * z - 1),
                      1.092548 * x * z, 0.546274 * (x * x - y * y)], 1)  # fmt: skip
    np.testing.assert_allclose(basis @ c, sh.evaluate(radiance, d), atol=1e-5)
    # shGetIrradianceAt (lights_pars_begin.glsl) convolves them to irradiance E
    k = [0.886227, 2 * 0.511664, 2 * 0.511664, 2 * 0.511664, 2 * 0.429043, 2 * 0.429043]
    irradiance = (
        c[0] * k[0] + np.outer(y, c[1]) * k[1] + np.outer(z, c[2]) * k[2]
        + np.outer(x, c[3]) * k[3] + np.outer(x * y, c[4]) * k[4] + np.outer(y * z, c[5]) * k[5]
        + np.outer(0.743125 * z * z - 0.247708, c[6]) + np.outer(2 * 0.429043 * x * z, c[7])
        + np.outer(0.429043 * (x * x - y * y), c[8])
    )  # fmt: skip
    np.testing.assert_allclose(irradiance, math.pi * e_over_pi(radiance, d), atol=1e-4)


def test_unity_sh_evaluates_to_e_over_pi_in_shadesh9(radiance):
    """Unity's shader constants from SphericalHarmonicsL2 (SetSHEMapConstants): SHA = (sh[3],
    sh[1], sh[2], sh[0] - sh[6]), SHB = (sh[4], sh[5], 3 sh[6], sh[7]), SHC = sh[8]; ShadeSH9
    (UnityCG.cginc) evaluates them at Unity's normal, whose z is bakeshop's -z."""
    d = random_directions(500, seed=7)
    c = np.asarray(engines.sh_export(radiance, "unity")["coefficients"])  # [channel][k]
    n = d * [1, 1, -1]
    x, y, z = n[:, 0], n[:, 1], n[:, 2]
    out = np.empty((len(d), 3))
    for ch in range(3):
        s = c[ch]
        sha = np.array([s[3], s[1], s[2], s[0] - s[6]])
        shb = np.array([s[4], s[5], 3 * s[6], s[7]])
        l0l1 = np.stack([x, y, z, np.ones_like(x)], 1) @ sha
        vb = np.stack([x * y, y * z, z * z, z * x], 1)
        out[:, ch] = l0l1 + vb @ shb + s[8] * (x * x - y * y)
    np.testing.assert_allclose(out, e_over_pi(radiance, d), atol=1e-9)
    flat = engines.sh_export(radiance, "unity")["flat"]
    assert len(flat) == 27 and flat[9 * 2 + 4] == c[2][4]  # sh[channel, k] at channel * 9 + k


def test_filament_sh_is_prescaled_e_over_pi(radiance):
    d = random_directions(500, seed=8)
    c = np.asarray(engines.sh_export(radiance, "filament")["iblSH"])
    np.testing.assert_allclose(polynomials(d) @ c, e_over_pi(radiance, d), atol=1e-9)


def test_engines_without_sh_and_with_panoramas_say_so():
    from bakeshop.errors import ArgumentError

    with pytest.raises(ArgumentError):
        engines.sh_export(np.zeros((9, 3)), "unreal")
    with pytest.raises(ArgumentError):
        engines.cube_faces(np.zeros((6, 4, 4, 3)), "godot")
    with pytest.raises(ArgumentError):
        engines.engine("cryengine")
