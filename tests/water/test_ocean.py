"""The FFT ocean against brute-force sums, finite differences and closed forms: loop closure,
seams, Hermitian symmetry, the measured directional spectrum and Hs, frozen and aliased modes,
determinism, cascades and Gerstner sums."""

import math

import numpy as np
import pytest
import scipy.fft

from bakeshop.errors import ArgumentError
from bakeshop.water.cascades import cascade_sizes, cascades, repeat_distance, sum_cascades
from bakeshop.water.gerstner import gerstner, gerstner_frames, gerstner_waves
from bakeshop.water.ocean import evaluate, mode_normals, ocean, ocean_fields, ocean_frames
from bakeshop.water.spectra import PM_ALPHA, PM_BETA, U19_5_PER_U10, Spectrum
from bakeshop.water.textures import angle_between, pack_normals, quantise, unpack_normals
from tests.water.tolerances import (
    BAND_POWER_RTOL,
    ENCODED_SEAM_DEG,
    FFT_VS_SUM_RTOL,
    FLOAT32_FIELD,
    GERSTNER_FD_RAD,
    HS_RTOL,
    IMAGINARY_RESIDUE,
    LOOP_ANGLE_RAD,
    SLOPE_ANGLE_RAD,
)

ALL = ("height", "slope", "displacement", "jacobian", "normal")
SEA = Spectrum("jonswap", wind_speed=8.0, fetch=50e3, wind_direction=20.0)


@pytest.fixture(scope="module")
def small():
    return ocean(SEA, size=64.0, resolution=32, seed=3, loop_period=8.0)


@pytest.mark.slow
def test_fft_fields_are_the_brute_force_sums(small):
    frames = small.minimum_frames()
    f = ocean_fields(small, frames=frames, fields=ALL, choppiness=0.8, dtype="float64")
    x, y = small.positions()
    for frame in (0, 5):
        ref = evaluate(small, x, y, small.frame_times(frames)[frame], choppiness=0.8)
        for name in ALL:
            scale = np.abs(ref[name]).max()
            assert np.abs(f[name][frame] - ref[name]).max() < FFT_VS_SUM_RTOL * scale, name


@pytest.mark.slow
def test_loop_closes_with_quantised_frequencies_and_not_without():
    looped = ocean(SEA, size=64.0, resolution=64, seed=1, loop_period=6.0)
    free = ocean(SEA, size=64.0, resolution=64, seed=1)
    a = ocean_fields(looped, times=[0.0, 6.0], fields=("height", "normal"))
    b = ocean_fields(free, times=[0.0, 6.0], fields=("height", "normal"))
    scale = np.abs(a["height"][0]).max()
    assert np.abs(a["height"][1] - a["height"][0]).max() < FLOAT32_FIELD * scale
    assert angle_between(a["normal"][1], a["normal"][0]).max() < LOOP_ANGLE_RAD
    # without quantisation the field at T is another field (differences of its own size)
    assert np.abs(b["height"][1] - b["height"][0]).max() > 0.3 * scale
    assert angle_between(b["normal"][1], b["normal"][0]).max() > 0.05
    # on the frame grid, frame F is frame 0 bit for bit (phases from integer turns)
    n = looped.minimum_frames()
    grid = ocean_fields(looped, frames=n, fields=("normal",))["normal"]
    again = next(ocean_frames(looped, frames=n, fields=("normal",), batch=1))[1]["normal"][0]
    np.testing.assert_array_equal(grid[0], again)
    step = 2 * math.pi / n
    spectra_0 = looped.spectrum_at(0.0)
    spectra_t = looped.spectrum_at(n * step / (2 * math.pi) * 6.0)
    np.testing.assert_allclose(spectra_t, spectra_0, atol=1e-12 * np.abs(spectra_0).max())


def test_tiles_without_seams(small):
    """Each edge texel's value equals the brute-force field one patch further on, so the jump
    across the seam of the tiled texture is the field's own (float32: < 1e-6 of its range)."""
    frames = small.minimum_frames()
    f = ocean_fields(small, frames=frames, fields=ALL, choppiness=0.6)
    x, y = small.positions()
    t = small.frame_times(frames)[2]
    L = small.size
    for dx, dy, where in ((L, 0, np.s_[:, 0]), (0, L, np.s_[-1, :]), (-L, -L, np.s_[0, -1])):
        ref = evaluate(small, x[where] + dx, y[where] + dy, t, choppiness=0.6)
        for name in ALL:
            scale = np.abs(ref[name]).max()
            err = np.abs(f[name][2][where] - ref[name]).max()
            assert err < FLOAT32_FIELD * scale, (name, err / scale)


@pytest.mark.parametrize("channels", ["xyz", "xy"])
def test_seams_stay_under_half_a_degree_after_8_bit_encoding(small, channels):
    """8-bit (xyz) and BC5-ready two-channel (xy, z rebuilt) maps, tiled 2x2: every decoded
    texel, seams included, within 0.5 degrees of the exact normal at its tiled position."""
    frames = small.minimum_frames()
    normals = ocean_fields(small, frames=frames, fields=("normal",), choppiness=0.5)["normal"][0]
    stored = quantise(pack_normals(normals, channels=channels), 8)
    decoded = unpack_normals(stored / 255.0, channels=channels)
    tiled = np.tile(decoded, (2, 2, 1))
    c = (np.arange(2 * small.resolution) + 0.5) * small.texel
    x, y = np.meshgrid(c, 2 * small.size - c)
    exact = evaluate(small, x, y - small.size, 0.0, choppiness=0.5)["normal"]
    err = np.degrees(angle_between(tiled, exact))
    assert err.max() < ENCODED_SEAM_DEG
    seam = err[:, small.resolution - 1 : small.resolution + 1]
    assert seam.max() < ENCODED_SEAM_DEG


def test_spectrum_is_hermitian_and_the_inverse_fft_real(small):
    n = small.resolution
    for t in (0.0, 1.3):
        h = small.spectrum_at(t)
        partner = np.conj(h[(-np.arange(n)) % n][:, (-np.arange(n)) % n])
        np.testing.assert_allclose(h, partner, atol=1e-15 * np.abs(h).max())
        field = scipy.fft.ifft2(h.astype(np.complex64), norm="forward")
        assert np.abs(field.imag).max() < IMAGINARY_RESIDUE * np.abs(field.real).max()


def test_spectral_normals_match_finite_differences_for_single_modes():
    o = ocean(SEA, size=50.0, resolution=64, seed=7)
    x, y = o.positions()
    order = np.argsort(-o.mode_variance.ravel())
    for index in order[:4:2]:  # two strong modes (and their partners)
        mask = np.ones(o.mode_variance.shape, bool)
        mask.flat[index] = False
        single = o.without(mask)
        normals = ocean_fields(single, times=[0.7], fields=("normal",), dtype="float64")["normal"]
        eps = 1e-4

        def h(xx, yy, single=single):
            return evaluate(single, xx, yy, 0.7)["height"]

        hx = (h(x + eps, y) - h(x - eps, y)) / (2 * eps)
        hy = (h(x, y + eps) - h(x, y - eps)) / (2 * eps)
        fd = np.stack([-hx, -hy, np.ones_like(hx)], -1)
        fd /= np.linalg.norm(fd, axis=-1, keepdims=True)
        assert angle_between(normals[0], fd).max() < SLOPE_ANGLE_RAD


def _band_power(o, heights, frames):
    """Power of the waves travelling towards each lattice k, from the synthesised height
    frames alone: spatial FFT of every frame, then the temporal DFT picks the component that
    turns n(k) times per loop forwards (towards k), n from the dispersion relation."""
    spectra = np.fft.fft2(heights, axes=(1, 2)) / heights.shape[1] ** 2  # forward: h_hat
    k = np.hypot(o.kx, o.ky)
    n = np.rint(SEA_PM.omega(k) * o.loop_period / (2 * math.pi)).astype(int)
    f = np.arange(frames)[:, None, None]
    toward = (spectra * np.exp(2j * math.pi * n[None] * f / frames)).mean(0)
    return np.abs(toward) ** 2


SEA_PM = Spectrum("jonswap", wind_speed=10.0, fetch=40e3, wind_direction=30.0, spreading="cos2s",
                  spread=6.0, surface_tension=0.0)  # fmt: skip


@pytest.mark.slow
def test_measured_directional_spectrum_matches_the_target_per_band():
    """Averaged over seeds, the power travelling into each band of |k| and direction, measured
    from the generated height frames, is the spectrum's integral over the band within 5 %
    (the integral by adaptive quadrature in polar coordinates, not the lattice sum)."""
    from scipy import integrate

    size, res, period = 1600.0, 256, 30.0
    seeds = range(24)
    power = 0
    for seed in seeds:
        o = ocean(SEA_PM, size=size, resolution=res, seed=seed, loop_period=period)
        frames = o.minimum_frames()
        h = ocean_fields(o, frames=frames, fields=("height",))["height"]
        power = power + _band_power(o, h, frames)
    power /= len(seeds)
    k = np.hypot(o.kx, o.ky)
    theta = np.degrees(np.arctan2(o.ky, o.kx)) - 30.0
    theta = (theta + 180) % 360 - 180
    kp = SEA_PM._peak_wavenumber()
    k_edges = [0.6 * kp, 0.9 * kp, 1.3 * kp, 2.0 * kp]
    d_edges = [-60, -20, 20, 60]
    for k0, k1 in zip(k_edges[:-1], k_edges[1:], strict=True):
        for d0, d1 in zip(d_edges[:-1], d_edges[1:], strict=True):
            inside = (k >= k0) & (k < k1) & (theta >= d0) & (theta < d1)
            measured = 2 * power[inside].sum()  # E|h0|^2 = F dk^2 / 2 per mode
            target = integrate.dblquad(
                lambda kk, t: float(SEA_PM.density_polar(kk, t)),
                math.radians(d0 + 30),
                math.radians(d1 + 30),
                k0,
                k1,
                epsrel=1e-8,
            )[0]
            # lattice sampling: the band's area in the lattice differs from the exact band
            lattice = inside.sum() * (2 * math.pi / size) ** 2
            area = 0.5 * (k1**2 - k0**2) * math.radians(d1 - d0)
            assert measured == pytest.approx(target * lattice / area, rel=BAND_POWER_RTOL), (
                k0 / kp,
                d0,
            )


@pytest.mark.slow
def test_significant_wave_height_is_four_root_m0():
    """Pierson-Moskowitz over the lattice's disk [w_min, w_max]: the closed form
    m0 = alpha g^2 / (4 beta w0^4) (exp(-beta (w0/w_max)^4) - exp(-beta (w0/w_min)^4)),
    against 4 std(h) of the generated fields averaged over seeds."""
    g, u = 9.81, 10.0
    sp = Spectrum("pierson-moskowitz", wind_speed=u, surface_tension=0.0)
    size, res = 1200.0, 256
    k_max = math.pi * res / size
    o = None
    hs = []
    for seed in range(8):
        o = ocean(sp, size=size, resolution=res, seed=seed, k_range=(0, k_max))
        h = ocean_fields(o, times=[0.0], fields=("height",), dtype="float64")["height"][0]
        hs.append(4 * h.std())
    w0 = g / (U19_5_PER_U10 * u)
    w_min, w_max = math.sqrt(g * 2 * math.pi / size), math.sqrt(g * k_max)
    c = PM_ALPHA * g * g / (4 * PM_BETA * w0**4)
    m0 = c * (math.exp(-PM_BETA * (w0 / w_max) ** 4) - math.exp(-PM_BETA * (w0 / w_min) ** 4))
    assert np.mean(hs) == pytest.approx(4 * math.sqrt(m0), rel=HS_RTOL)
    assert o.report["hs"] == pytest.approx(4 * math.sqrt(m0), rel=HS_RTOL)


def test_frozen_modes_are_counted_and_carry_their_variance():
    period = 3.0
    keep = ocean(SEA, size=300.0, resolution=32, seed=2, loop_period=period)
    drop = ocean(SEA, size=300.0, resolution=32, seed=2, loop_period=period, frozen="drop")
    k = np.hypot(keep.kx, keep.ky)
    still = (SEA.omega(k) < math.pi / period) & (keep.mode_variance > 0)
    assert keep.report["frozen_modes"] == still.sum() > 0
    assert keep.report["frozen_variance"] == pytest.approx(keep.mode_variance[still].sum())
    assert drop.report["variance"] == pytest.approx(
        keep.report["variance"] - keep.report["frozen_variance"]
    )
    h = ocean_fields(keep, times=[0.0, 0.7], fields=("height",), dtype="float64")["height"]
    hs = ocean_fields(keep.without(~still), times=[0.0, 0.7], fields=("height",))["height"]
    np.testing.assert_allclose(hs[0], hs[1], atol=1e-6)  # frozen modes do not move
    assert np.abs(h[0] - h[1]).max() > 0.1


def test_too_few_frames_are_refused_with_the_reason(small):
    need = small.minimum_frames()
    with pytest.raises(ArgumentError, match=f"at least {need} frames"):
        next(ocean_frames(small, frames=need - 1))
    got = ocean_fields(small, frames=need - 3, fields=("height",), alias="drop")
    assert got["height"].shape[0] == need - 3


def test_same_seed_same_waves_at_any_resolution():
    a = ocean(SEA, size=64.0, resolution=32, seed=11)
    b = ocean(SEA, size=64.0, resolution=64, seed=11)
    c = ocean(SEA, size=64.0, resolution=32, seed=12)
    # the 32 lattice is the centre of the 64 lattice: same modes, same amplitudes
    f32 = np.fft.fftfreq(32, 1 / 32).astype(int)
    rows, cols = np.meshgrid(f32 % 64, f32 % 64, indexing="ij")
    h32 = a.amplitude * np.exp(-0.5j * (a.kx - a.ky) * a.texel)
    h64 = (b.amplitude * np.exp(-0.5j * (b.kx - b.ky) * b.texel))[rows, cols]
    live = a.mode_variance > 0
    np.testing.assert_allclose(h32[live], h64[live], rtol=1e-12)
    assert not np.allclose(a.amplitude, c.amplitude)
    # the normals are standard: mean 0, variance 1, uncorrelated
    xi = mode_normals(5, np.arange(-300, 300)[:, None], np.arange(-300, 300)[None, :])
    assert abs(xi.mean()) < 0.01 and abs(xi.var() - 1) < 0.01
    assert abs(np.corrcoef(xi[..., 0].ravel(), xi[..., 1].ravel())[0, 1]) < 0.01


def test_cascades_split_the_spectrum_without_counting_twice():
    sizes = cascade_sizes(500.0, 3)
    cs = cascades(SEA, sizes, resolution=64, seed=4, loop_period=20.0)
    k_nyq = math.pi * 64 / sizes[-1]
    total = sum(c.report["spectrum_variance"] for c in cs)
    assert total == pytest.approx(SEA.variance(math.pi / sizes[0], k_nyq), rel=1e-6)
    for a, b in zip(cs[:-1], cs[1:], strict=True):
        assert a.report["band"][1] == b.report["band"][0]
    assert cs[1].report["repeat_distance"] > 20 * sizes[0]
    assert repeat_distance(500.0, 125.0, 1.0) == 500.0
    # layered in a shader: each cascade sampled at its own scale and summed
    fields = [
        ocean_fields(c, frames=max(x.minimum_frames() for x in cs), fields=("height",))["height"][0]
        for c in cs
    ]
    x = np.array([1.0, 700.0])
    total = sum_cascades(fields, sizes, x, x)
    assert total.shape == (2,) and np.isfinite(total).all()


def test_one_gerstner_wave_normal_is_the_cross_product_of_its_tangents(small):
    w = gerstner_waves(small, 1)
    a, kx, ky = w.amplitude[0], w.kx[0], w.ky[0]
    k = math.hypot(kx, ky)
    lam = 0.7
    x = np.linspace(0, 30, 97)
    y = np.linspace(5, 20, 97)
    t = 1.1
    th = kx * x + ky * y - w.omega[0] * t + w.phase[0]
    tx = np.stack(
        [1 - lam * a * kx * kx / k * np.cos(th), -lam * a * ky * kx / k * np.cos(th),
         -a * kx * np.sin(th)], -1)  # fmt: skip
    ty = np.stack(
        [-lam * a * kx * ky / k * np.cos(th), 1 - lam * a * ky * ky / k * np.cos(th),
         -a * ky * np.sin(th)], -1)  # fmt: skip
    expected = np.cross(tx, ty)
    expected /= np.linalg.norm(expected, axis=-1, keepdims=True)
    got = gerstner(w, x, y, t, choppiness=lam)["normal"]
    assert angle_between(got, expected).max() < 1e-12


def test_gerstner_sum_normals_match_finite_differences_and_the_fft(small):
    w = gerstner_waves(small, 24)
    lam = 0.5
    x = np.random.default_rng(0).uniform(0, 64, 200)
    y = np.random.default_rng(1).uniform(0, 64, 200)
    eps = 1e-5

    def p(xx, yy):
        return gerstner(w, xx, yy, 0.4, choppiness=lam)["position"]

    tx = (p(x + eps, y) - p(x - eps, y)) / (2 * eps)
    ty = (p(x, y + eps) - p(x, y - eps)) / (2 * eps)
    fd = np.cross(tx, ty)
    fd /= np.linalg.norm(fd, axis=-1, keepdims=True)
    assert angle_between(gerstner(w, x, y, 0.4, choppiness=lam)["normal"], fd).max() < (
        GERSTNER_FD_RAD
    )
    # all modes summed directly are the FFT field
    everything = gerstner_waves(small)
    frames = small.minimum_frames()
    g = next(gerstner_frames(everything, resolution=32, frames=frames, fields=("normal",),
                             choppiness=lam))[1]["normal"][0]  # fmt: skip
    f = ocean_fields(small, frames=frames, fields=("normal",), choppiness=lam)["normal"][0]
    assert angle_between(g, f).max() < 1e-5


def test_bad_arguments_are_refused():
    with pytest.raises(ArgumentError):
        ocean(SEA, size=64.0, resolution=33)
    with pytest.raises(ArgumentError):
        ocean(SEA, size=-1.0, resolution=32)
    with pytest.raises(ArgumentError):
        ocean(SEA, size=64.0, resolution=32, loop_period=0.0)
    with pytest.raises(ArgumentError):
        ocean(SEA, size=64.0, resolution=32, seed=-1)
    o = ocean(SEA, size=64.0, resolution=32)
    with pytest.raises(ArgumentError):
        next(ocean_frames(o, frames=10))  # no loop period
    with pytest.raises(ArgumentError):
        next(ocean_frames(o, times=[0.0], fields=("colour",)))
    with pytest.raises(ArgumentError):
        next(ocean_frames(o, times=[0.0], choppiness=-1))


def test_a_lattice_too_large_to_seed_is_refused_with_the_number():
    with pytest.raises(ArgumentError, match="GiB to seed"):
        ocean(SEA, size=64.0, resolution=8192)


@pytest.mark.parametrize("wind", [0.5, 1.0, 3.0])
def test_a_light_wind_lattice_holds_the_spectrum_tail_of_its_disc(wind):
    """A light wind's peak lies far past the lattice's shortest wave: the band holds only the
    spectrum's steep tail, rising towards the band's edge. The spectrum's share (the closed
    form of test_significant_wave_height_is_four_root_m0 over dk/2 <= k < pi n / size) and the
    lattice's variance inside that disc agree (its corners, up to sqrt(2) times further out,
    are not compared: there a light wind's tail is larger than the whole disc's)."""
    g, size, res = 9.81, 64.0, 64
    sp = Spectrum("pierson-moskowitz", wind_speed=wind, surface_tension=0.0)
    r = ocean(sp, size=size, resolution=res).report
    dk, k_max = 2 * math.pi / size, math.pi * res / size
    w0 = g / (U19_5_PER_U10 * wind)
    w_min, w_max = math.sqrt(g * dk / 2), math.sqrt(g * k_max)
    c = PM_ALPHA * g * g / (4 * PM_BETA * w0**4)
    m0 = c * (math.exp(-PM_BETA * (w0 / w_max) ** 4) - math.exp(-PM_BETA * (w0 / w_min) ** 4))
    assert r["spectrum_variance"] == pytest.approx(m0, rel=1e-6)
    assert 0.75 < r["captured"] < 1.25, r["captured"]
