"""Spectra and dispersion against closed forms and independent quadratures."""

import math

import numpy as np
import pytest
from scipy import integrate

from bakeshop.errors import ArgumentError
from bakeshop.water.spectra import (
    PM_ALPHA,
    PM_BETA,
    U19_5_PER_U10,
    Spectrum,
    dispersion,
    group_velocity,
    tma_depth_factor,
)

G = 9.81


def test_pierson_moskowitz_significant_wave_height_is_the_closed_form():
    # m0 = alpha g^2 / (4 beta w0^4), w0 = g / U19.5: Hs = 2 sqrt(alpha / beta) U19.5^2 / g
    for u10 in (5.0, 10.0, 20.0):
        sp = Spectrum("pierson-moskowitz", wind_speed=u10, surface_tension=0.0)
        u = U19_5_PER_U10 * u10
        expected = 2 * math.sqrt(PM_ALPHA / PM_BETA) * u * u / G
        assert sp.significant_wave_height() == pytest.approx(expected, rel=1e-7)
        assert expected == pytest.approx(0.2092 * u * u / G, rel=1e-3)  # the textbook 0.21


@pytest.mark.parametrize("kind", ["pierson-moskowitz", "jonswap"])
def test_variance_over_wave_numbers_equals_the_frequency_integral(kind):
    """spectrum.variance integrates S(w(k)) c_g dk over k; the frequency spectrum integrated
    over w directly must give the same number (deep water, gravity waves: a change of
    variables only)."""
    sp = Spectrum(kind, wind_speed=12.0, fetch=80e3, surface_tension=0.0)
    direct = integrate.quad(sp.frequency_density, 0.05, 2000, limit=800, epsrel=1e-11)[0]
    assert sp.variance() == pytest.approx(direct, rel=1e-6)


def test_tma_variance_is_the_frequency_integral_with_the_depth_factor():
    sp = Spectrum("tma", wind_speed=10.0, fetch=30e3, depth=6.0, surface_tension=0.0)

    def s_w(w):
        # k(w, d) by root finding, independently of the library's formula for phi
        from scipy.optimize import brentq

        k = brentq(lambda k: G * k * math.tanh(k * 6.0) - w * w, 1e-9, 10 + 2 * w * w / G)
        k_deep = w * w / G
        dk_dw = 1 / float(group_velocity(k, depth=6.0, surface_tension=0.0))
        phi = (k**-3 * dk_dw) / (k_deep**-3 * (2 * w / G))
        return float(sp.frequency_density(w)) * phi

    direct = integrate.quad(s_w, 0.05, 2000, limit=800, epsrel=1e-10)[0]
    assert sp.variance() == pytest.approx(direct, rel=1e-6)


def test_tma_depth_factor_limits_and_thompson_vincent():
    d = 5.0
    k = np.geomspace(1e-4, 50, 2000)
    phi = tma_depth_factor(k, d)
    w = dispersion(k, depth=d, surface_tension=0.0)
    wh = w * math.sqrt(d / G)
    # Thompson and Vincent (1983), the piecewise approximation quoted by Bouws et al. 1985
    tv = np.where(wh <= 1, 0.5 * wh**2, np.where(wh < 2, 1 - 0.5 * (2 - wh) ** 2, 1.0))
    assert np.abs(phi - tv).max() < 0.04
    assert phi[-1] == pytest.approx(1.0, abs=1e-12)
    assert phi[0] == pytest.approx(0.5 * wh[0] ** 2, rel=1e-3)


@pytest.mark.parametrize(
    "spreading,spread", [("mitsuyasu", 10.0), ("cos2s", 3.0), ("cos2s", 40.0), ("cos2", 1.0)]
)
def test_spreading_integrates_to_one(spreading, spread):
    sp = Spectrum("jonswap", spreading=spreading, spread=spread)
    for w in (0.5 * sp.peak_frequency, sp.peak_frequency, 3 * sp.peak_frequency):
        total = integrate.quad(
            lambda t, w=w: float(sp.directional_spreading(t, w)), -math.pi, math.pi, limit=200
        )[0]
        assert total == pytest.approx(1.0, rel=1e-9)


@pytest.mark.parametrize("kind", ["phillips", "jonswap", "tma"])
def test_the_plane_density_integrates_to_the_variance(kind):
    """A Cartesian Riemann sum of F(kx, ky) on a fine grid equals the adaptive polar
    quadrature of :meth:`variance` (different coordinates, different rule)."""
    sp = Spectrum(kind, wind_speed=9.0, fetch=40e3, depth=20.0 if kind == "tma" else math.inf,
                  wind_direction=30.0, cutoff=0.05, amplitude=2e-3)  # fmt: skip
    k_max = 4.0
    n = 1601
    k = np.linspace(-k_max, k_max, n)
    dk = k[1] - k[0]
    kx, ky = np.meshgrid(k, k)
    inside = np.hypot(kx, ky) < k_max
    riemann = (sp.density(kx, ky) * inside).sum() * dk * dk
    assert riemann == pytest.approx(sp.variance(0, k_max), rel=2e-3)


def test_waves_travel_with_the_wind():
    sp = Spectrum("jonswap", wind_direction=90.0)  # along +v
    k = 0.2
    assert sp.density(0, k) > 100 * sp.density(0, -k)
    assert sp.density(0, k) > 10 * sp.density(k, 0)  # cos^2s(45 deg), s ~ 4.7 here


def test_dispersion_limits():
    k = np.array([1e-3, 1e-2, 0.1])
    np.testing.assert_allclose(dispersion(k, surface_tension=0.0), np.sqrt(G * k), rtol=1e-15)
    # shallow water: w = k sqrt(g d) as k d -> 0
    d = 2.0
    assert float(dispersion(1e-5, depth=d, surface_tension=0.0)) == pytest.approx(
        1e-5 * math.sqrt(G * d), rel=1e-9
    )
    # capillary-gravity: the slowest phase speed (4 g sigma / rho)^(1/4) at k = sqrt(rho g / sigma)
    sigma = 0.0728
    km = math.sqrt(1000 * G / sigma)
    c = dispersion(np.linspace(0.5 * km, 2 * km, 20001)) / np.linspace(0.5 * km, 2 * km, 20001)
    assert c.min() == pytest.approx((4 * G * sigma / 1000) ** 0.25, rel=1e-7)
    assert 2 * math.pi / km == pytest.approx(0.0171, abs=1e-4)  # 1.7 cm


@pytest.mark.parametrize("depth", [math.inf, 3.0])
def test_group_velocity_is_the_derivative(depth):
    k = np.geomspace(1e-3, 3e3, 200)
    h = k * 1e-6
    fd = (dispersion(k + h, depth=depth) - dispersion(k - h, depth=depth)) / (2 * h)
    np.testing.assert_allclose(group_velocity(k, depth=depth), fd, rtol=1e-6)


def test_jonswap_fetch_and_fully_developed_cap():
    short = Spectrum("jonswap", wind_speed=10.0, fetch=10e3)
    long_ = Spectrum("jonswap", wind_speed=10.0, fetch=1e9)
    pm = Spectrum("pierson-moskowitz", wind_speed=10.0)
    assert short.peak_frequency > long_.peak_frequency
    assert long_.peak_frequency == pytest.approx(pm.peak_frequency, rel=1e-3)


@pytest.mark.parametrize(
    "options",
    [
        {"kind": "bogus"},
        {"wind_speed": 0.0},
        {"wind_speed": float("nan")},
        {"wind_speed": 1e-300},  # its square underflows: refused, not a division by zero
        {"fetch": -1.0},
        {"gamma": 0.5},
        {"spreading": "wide"},
        {"kind": "tma"},  # TMA needs a finite depth
        {"against_wind": 2.0},
        {"cutoff": float("inf")},
    ],
)
def test_bad_parameters_are_refused(options):
    with pytest.raises(ArgumentError):
        Spectrum(**options)


def test_sidecar_dict_is_json_ready():
    import json

    d = Spectrum("jonswap").to_dict()
    assert d["depth"] is None and d["units"]["wind_speed"] == "m/s"
    json.dumps(d)


def test_a_depth_past_the_float_range_is_deep_water():
    """``--depth 1e308`` is deep water, not NaN: k d overflows, tanh(k d) is 1 and the
    group velocity's d (1 - T^2) term is 0 (it was inf * 0)."""
    k = np.geomspace(1e-3, 1e3, 25)
    with np.errstate(all="raise"):
        deep = group_velocity(k)
        huge = group_velocity(k, depth=1e308)
        assert np.array_equal(dispersion(k, depth=1e308), dispersion(k))
    assert np.array_equal(huge, deep)
