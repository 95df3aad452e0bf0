"""Fresnel reflectance against the amplitude equations, and the flat-water bake."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.light.fresnel import WATER_IOR, fresnel_dielectric, fresnel_schlick
from tests.tolerances import FRESNEL_AMPLITUDE_ATOL


def fresnel_from_amplitudes(cos_i, n):
    """(rs^2 + rp^2) / 2 via Snell's law and the Fresnel amplitude coefficients (Born & Wolf)."""
    cos_i = np.asarray(cos_i, np.float64)
    with np.errstate(invalid="ignore"):  # 0/0 only at grazing under total reflection
        return _amplitudes(cos_i, n)


def _amplitudes(cos_i, n):
    sin_t = np.sqrt(1 - cos_i**2) / n
    cos_t = np.sqrt(np.maximum(1 - sin_t**2, 0))
    rs = (cos_i - n * cos_t) / (cos_i + n * cos_t)
    rp = (n * cos_i - cos_t) / (n * cos_i + cos_t)
    r = (rs**2 + rp**2) / 2
    return np.where(sin_t >= 1, 1.0, r)


def test_normal_incidence_and_grazing():
    assert fresnel_dielectric(1.0) == pytest.approx(((1.333 - 1) / (1.333 + 1)) ** 2, abs=1e-15)
    assert fresnel_dielectric(1.0) == pytest.approx(0.0204, abs=5e-5)
    assert fresnel_dielectric(0.0) == 1.0
    c = np.geomspace(1e-9, 1e-2, 50)
    r = fresnel_dielectric(c)
    assert np.all(np.diff(r) < 0) and r[0] > 1 - 1e-8  # tends to 1 at grazing


@pytest.mark.parametrize("n", [WATER_IOR, 1.5, 2.4, 1.0001])
def test_matches_fresnel_amplitude_equations(n):
    c = np.linspace(0, 1, 100001)
    np.testing.assert_allclose(
        fresnel_dielectric(c, n), fresnel_from_amplitudes(c, n), rtol=0, atol=FRESNEL_AMPLITUDE_ATOL
    )


def test_from_the_dense_side_total_internal_reflection():
    n = 1 / WATER_IOR  # looking up from under water
    critical = np.sqrt(1 - n**2)  # cos of the critical angle, 48.6 degrees
    c = np.linspace(0, 1, 20001)
    r = fresnel_dielectric(c, n)
    np.testing.assert_allclose(r, fresnel_from_amplitudes(c, n), atol=FRESNEL_AMPLITUDE_ATOL)
    assert np.all(r[c < critical] == 1.0) and np.all(r[c > critical + 1e-3] < 1)
    # reciprocity: same reflectance from both sides at refraction-related angles
    ci = np.linspace(0.05, 1, 50)
    ct = np.sqrt(1 - (1 - ci**2) / WATER_IOR**2)
    np.testing.assert_allclose(fresnel_dielectric(ci), fresnel_dielectric(ct, n), atol=1e-12)


def test_domain_dtype_nan():
    c32 = np.array([1.0000001, -0.2, np.nan, 0.5], np.float32)
    r = fresnel_dielectric(c32)
    assert r.dtype == np.float32
    assert r[0] == pytest.approx(0.020373, abs=1e-6) and r[1] == 1.0 and np.isnan(r[2])
    assert fresnel_dielectric(np.ones((2, 3, 4))).shape == (2, 3, 4)
    for bad in (0, -1.3, np.nan, np.inf):
        with pytest.raises(ArgumentError):
            fresnel_dielectric(0.5, bad)


def test_schlick_error_for_water():
    c = np.linspace(0, 1, 100001)
    exact = fresnel_dielectric(c)
    approx = fresnel_schlick(c)
    assert approx[-1] == pytest.approx(exact[-1], abs=1e-15) and approx[0] == exact[0] == 1
    err = approx - exact
    # the figures docs/fresnel.md quotes: largest +0.059 at 83.8 degrees, mean +0.010 over
    # cos_i, lowest -0.0094 at 56.8 degrees; the sign changes at 67.1 degrees
    worst = np.argmax(np.abs(err))
    assert err[worst] == pytest.approx(0.0592, abs=5e-4)
    assert np.degrees(np.arccos(c[worst])) == pytest.approx(83.8, abs=0.1)
    assert err.mean() == pytest.approx(0.0103, abs=5e-4)
    assert err.min() == pytest.approx(-0.00936, abs=5e-5)
    assert np.degrees(np.arccos(c[np.argmin(err)])) == pytest.approx(56.8, abs=0.1)
