"""Murk: the shipped tables against their publications' stated values, the colour matching fit
against the CIE table (colour-science), Beer-Lambert composition, Jerlov type I's red light,
beam vs diffuse attenuation, the underwater path (straight and refracted, against Fermat's
principle by brute force), visibility, LUTs and engine constants."""

import math

import colour
import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.water import murk
from tests.water.tolerances import CMF_FIT_ATOL, PATH_RTOL


def test_pope_and_fry_minimum_and_jerlov_type_one_red():
    lam, a = murk.wavelengths(), murk.pure_water_absorption()
    # Pope and Fry's abstract: the minimum, 0.0044 1/m, lies at 417.5 nm
    assert lam[np.argmin(a)] == 417.5 and a.min() == pytest.approx(0.0044, abs=5e-5)
    assert (lam[0], lam[-1], len(lam)) == (380.0, 700.0, 129)
    names, grid, kd = murk.jerlov_kd_table()
    k650 = kd[list(grid).index(650.0), names.index("I")]
    assert k650 == 0.36 and 1 / k650 == pytest.approx(2.78, abs=0.01)  # red light 1/e at 2.8 m
    # the red channel of white light in type I water: 1/e near 2.8-3 m down
    red = murk.channel_coefficients(murk.water("I"), which="diffuse")["e_folding"][0]
    assert 2.7 < red < 3.2
    # water types are ordered: Kd at 450 nm grows from I to 9C
    k450 = kd[list(grid).index(450.0)]
    assert (np.diff(k450) > 0).all()


def test_colour_matching_fit_against_the_cie_table():
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    table = np.stack([np.interp(murk.wavelengths(), cmfs.wavelengths, cmfs.values[:, i])
                      for i in range(3)], -1)  # fmt: skip
    assert np.abs(murk.colour_matching() - table).max() < CMF_FIT_ATOL
    # white light through nothing is white: every channel transmits 1
    np.testing.assert_allclose(murk.band(np.ones(murk.wavelengths().size)), 1, rtol=1e-12)


def test_channel_weights_against_colour_science_with_d65():
    """The band transmittance of a water with our 6504 K blackbody and fitted CMFs vs
    colour-science's CIE 1931 table, D65 and its own XYZ -> sRGB matrix."""
    w = murk.water("II")
    lam = murk.wavelengths()
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    d65 = colour.SDS_ILLUMINANTS["D65"]
    xyz_bar = np.stack([np.interp(lam, cmfs.wavelengths, cmfs.values[:, i]) for i in range(3)], -1)
    light = np.interp(lam, d65.wavelengths, d65.values)
    m = colour.models.RGB_COLOURSPACE_sRGB.matrix_XYZ_to_RGB
    for d in (0.5, 2.0, 5.0):
        spectrum = light * np.exp(-w.attenuation * d)
        ref = m @ (spectrum @ xyz_bar) / (m @ (light @ xyz_bar))
        assert murk.transmittance(w, d)[:3] == pytest.approx(ref, abs=0.01)


def test_beer_lambert_composes():
    w = murk.water("IB")
    c = w.attenuation
    a, b = 1.7, 3.2
    np.testing.assert_allclose(np.exp(-c * (a + b)), np.exp(-c * a) * np.exp(-c * b), rtol=1e-14)
    k = murk.channel_coefficients(w)["rgb"]
    np.testing.assert_allclose(np.exp(-k * (a + b)), np.exp(-k * a) * np.exp(-k * b), rtol=1e-14)
    # the band integrals do not compose exactly (the light's spectrum changes on the way):
    # say by how much, and that it is the reddening the per-channel constants approximate
    t = murk.transmittance(w, [a, b, a + b])
    assert np.abs(t[2, :3] - t[0, :3] * t[1, :3]).max() < 0.05


def test_beam_attenuation_exceeds_diffuse_attenuation_in_natural_waters():
    for name in murk.WATER_TYPES[1:]:
        w = murk.water(name)
        assert (w.attenuation >= w.kd).all(), name
        assert (w.absorption >= murk.pure_water_absorption()).all()
    # pure water scatters almost nothing: there Kd = a / mu_d exceeds c = a + b, as it should
    pure = murk.water("pure")
    assert (pure.kd > pure.attenuation).any()


def test_gordon_relation_gives_back_jerlov_kd_where_not_floored():
    w = murk.water("III")
    predicted = 1.0395 * (w.absorption + w.backscattering) / murk._refracted_cosine(30.0)
    free = w.absorption > murk.pure_water_absorption()
    np.testing.assert_allclose(predicted[free], w.kd[free], rtol=1e-12)
    assert w.floored < 0.05


def test_straight_path_fraction_is_p_over_e_plus_p():
    e, p, x = 1.7, 2.3, 6.0
    total = math.hypot(x, e + p)
    # independent: intersect the segment from (0, e) to (x, -p) with the plane y = 0
    s = e / (e + p)
    crossing = np.array([s * x, 0.0])
    under = np.linalg.norm(np.array([x, -p]) - crossing)
    assert murk.underwater_path(e, p, x) == pytest.approx(under, rel=1e-14)
    assert murk.underwater_path(e, p, x) / total == pytest.approx(p / (e + p), rel=1e-14)
    # an eye under water sees through water all the way
    assert murk.underwater_path(-1.0, 2.0, 3.0) == pytest.approx(math.hypot(3.0, 1.0))


def test_refracted_path_obeys_fermat_and_snell():
    e, p, x, n = 3.0, 2.0, 7.0, murk.WATER_IOR
    s = np.linspace(0, x, 2_000_001)
    optical = np.hypot(s, e) + n * np.hypot(x - s, p)
    best = s[np.argmin(optical)]
    expected = math.hypot(x - best, p)
    got = murk.underwater_path(e, p, x, refraction=True)
    assert got == pytest.approx(expected, rel=PATH_RTOL)
    crossing = x - math.sqrt(got * got - p * p)
    sin_i = crossing / math.hypot(crossing, e)
    sin_t = (x - crossing) / got
    assert sin_i == pytest.approx(n * sin_t, rel=1e-9)
    assert got < murk.underwater_path(e, p, x)  # refraction steepens the underwater leg


def test_visibility_round_trip_and_limit():
    for v in (3.0, 10.0, 25.0):
        assert murk.visibility(murk.from_visibility(v, "II")) == pytest.approx(v, rel=1e-9)
    clearest = murk.visibility(murk.water("pure"))
    with pytest.raises(ArgumentError, match="beyond pure sea water"):
        murk.from_visibility(clearest * 1.01)


def test_luts_and_inscatter_limits():
    w = murk.water("II")
    lut = murk.murk_lut(w, max_distance=20, max_depth=10, distances=16, depths=8)
    assert lut["transmittance"].shape == (16, 3) and lut["inscatter"].shape == (8, 16, 3)
    np.testing.assert_allclose(lut["transmittance"][0], 1, atol=1e-6)
    np.testing.assert_allclose(lut["inscatter"][:, 0], 0, atol=1e-9)
    np.testing.assert_allclose(lut["transmittance"], murk.transmittance(w, lut["distances"])[:, :3],
                               rtol=1e-6)  # fmt: skip
    # in-scatter grows towards its value at infinity (to within the sRGB red channel's
    # negative lobe, which makes the band integral not quite monotonic) and falls with depth
    far = murk.inscatter(w, 1e6, 0.0)
    assert (lut["inscatter"][0, -1] <= 1.01 * far[:3]).all()
    deeper = murk.inscatter(w, 1e6, 5.0)[:3] / far[:3]
    assert (deeper < 1).all()


def test_engine_constants_are_consistent():
    w = murk.water("IB")
    k = murk.engine_constants(w)
    ue = k["unreal_single_layer_water"]
    crest = k["crest"]
    np.testing.assert_allclose(
        ue["absorption_coefficients_per_cm"] * 100, crest["absorption_per_m"]
    )
    assert 0.5 < ue["phase_g"] < PARTICLE_G_MAX
    assert k["unity_hdrp"]["absorption_distance_m"] == pytest.approx(
        1 / murk.channel_coefficients(w)["luminance"]
    )
    fog = k["source"]
    assert fog["fog_end_m"] > fog["fog_start_m"] >= 0 and fog["max_error"] < 0.25
    src = murk.glsl_function(w)
    assert "vec3 waterTransmittance(float d)" in src and "WATER_C" in src


PARTICLE_G_MAX = murk.PARTICLE_G


def test_bad_inputs_are_refused():
    with pytest.raises(ArgumentError):
        murk.water("IV")
    with pytest.raises(ArgumentError):
        murk.transmittance(murk.water("I"), -1.0)
    with pytest.raises(ArgumentError):
        murk.underwater_path(1.0, -1.0, 2.0)
    with pytest.raises(ArgumentError):
        murk.from_visibility(0.0)
