"""Ripples: the analytic ring against a 2-D FFT solution of the same linear problem, the wave
equation against the exact (Hankel) solution of the continuous equation: front at c t, amplitude
times sqrt(r) constant along the crest, isotropy, the CFL bound, edges; the rain atlas tiles."""

import math

import numpy as np
import pytest
from scipy import special
from scipy.ndimage import map_coordinates

from bakeshop.errors import ArgumentError
from bakeshop.water.ripples import (
    CFL_LIMIT,
    Crater,
    Impact,
    Source,
    WaveEquation,
    drop_crater,
    height_normals,
    rain_atlas,
    ring,
    ring_lut,
    ring_normals,
    ring_texture,
    simulate,
)
from bakeshop.water.spectra import dispersion
from tests.water.tolerances import (
    RING_VS_FFT_RTOL,
    WAVE_AMPLITUDE_RTOL,
    WAVE_EXACT_RTOL,
    WAVE_ISOTROPY_RTOL,
    WAVE_SPEED_RTOL,
)


def test_analytic_ring_is_the_fft_solution_of_the_same_problem():
    """The Hankel-quadrature ring equals an independent solution: the initial crater on a
    large periodic grid, each Fourier mode turned by cos(omega t) exp(-2 nu k^2 t) with the
    capillary-gravity dispersion, inverse FFT."""
    crater = Crater(amplitude=2e-3, width=0.01)
    n, size = 1024, 1.2
    dx = size / n
    c = (np.arange(n) - n // 2) * dx
    x, y = np.meshgrid(c, c)
    eta0 = -crater.amplitude * np.exp(-(x * x + y * y) / crater.width**2)
    k1 = 2 * np.pi * np.fft.fftfreq(n, dx)
    k = np.hypot(*np.meshgrid(k1, k1))
    spectrum = np.fft.fft2(np.fft.ifftshift(eta0))
    r = np.linspace(0, 0.4, 400)
    times = [0.1, 0.35]
    eta, _ = ring(crater, r, times)
    for i, t in enumerate(times):
        turned = spectrum * np.cos(crater.omega(k) * t) * np.exp(-2 * crater.viscosity * k * k * t)
        field = np.fft.fftshift(np.fft.ifft2(turned).real)
        along = map_coordinates(field, [np.full_like(r, n // 2), n // 2 + r / dx], order=3)
        scale = np.abs(eta[i]).max()
        assert np.abs(along - eta[i]).max() < RING_VS_FFT_RTOL * scale


def test_ring_slope_is_the_radial_derivative_and_the_front_moves_at_the_group_velocity():
    crater = Crater(amplitude=1e-3, width=0.006, viscosity=0.0)
    r = np.linspace(0.001, 0.3, 3000)
    eta, slope = ring(crater, r, [0.4])
    fd = np.gradient(eta[0], r)
    assert np.abs(fd - slope[0])[5:-5].max() < 2e-3 * np.abs(slope[0]).max()
    # the energy centre of the ring (eta^2 r weighted) moves at c_g(k0)
    times = np.array([0.3, 0.6])
    eta, _ = ring(crater, r, times)
    centre = (eta**2 * r * r).sum(1) / (eta**2 * r).sum(1)
    speed = (centre[1] - centre[0]) / (times[1] - times[0])
    assert speed == pytest.approx(crater.front_speed, rel=0.1)  # broad-band ring: ~10 %


def test_drop_crater_carries_the_requested_energy():
    c = drop_crater(drop_diameter=0.004, drop_speed=6.0, energy_fraction=0.05)
    mass = 1000 * math.pi * 0.004**3 / 6
    assert c.energy == pytest.approx(0.05 * 0.5 * mass * 36, rel=1e-12)
    assert c.width == pytest.approx(0.008)
    # the depression's potential energy by quadrature: 1/2 rho g eta^2 + 1/2 sigma |grad eta|^2
    r = np.linspace(0, 10 * c.width, 200001)
    eta = -c.amplitude * np.exp(-((r / c.width) ** 2))
    deta = np.gradient(eta, r)
    e = np.trapezoid((0.5 * 1000 * 9.81 * eta**2 + 0.5 * 0.0728 * deta**2) * 2 * np.pi * r, r)
    assert e == pytest.approx(c.energy, rel=1e-6)
    with pytest.raises(ArgumentError):
        drop_crater(drop_diameter=-1, drop_speed=1)
    with pytest.raises(ArgumentError):
        drop_crater(drop_diameter=0.004, drop_speed=1, energy_fraction=2)


def exact_wave(r, t, amplitude, width, c):
    """The continuous wave equation's solution from a Gaussian dent at rest (Hankel form)."""
    k = np.linspace(0, 10 / width, 20001)
    e = -amplitude * width**2 / 2 * np.exp(-((k * width) ** 2) / 4)
    return (special.j0(np.outer(r, k)) @ (e * np.cos(c * k * t) * k)) * (k[1] - k[0])


@pytest.fixture(scope="module")
def rings():
    """A dent 12 cells wide on a 512^2 periodic grid, sampled along the axis and the
    diagonal at four times (the crest travels 40 dent widths)."""
    n, size, c = 512, 0.5, 0.25
    dx = size / n
    sim = WaveEquation(n, size, c, dt=0.3 * dx / c)
    a, amp = 12 * dx, 1e-3
    sim.add_impact(0.25, 0.25, amplitude=amp, width=a)
    r = np.arange(0, 0.23, dx / 4)
    out = []
    for t, h in simulate(sim, frames=4, steps_per_frame=167):
        rows = {}
        for name, (ux, uy) in {"axis": (1, 0), "diagonal": (0.5**0.5, 0.5**0.5)}.items():
            px, py = 0.25 + r * ux, 0.25 + r * uy
            rows[name] = map_coordinates(h, [(size - py) / dx - 0.5, px / dx - 0.5], order=3)
        out.append((t, rows))
    return r, out, (amp, a, c)


def _crest(r, v):
    i = int(np.argmax(v))
    a, b, c = v[i - 1], v[i], v[i + 1]
    off = 0.5 * (a - c) / (a - 2 * b + c)
    return r[i] + off * (r[1] - r[0]), b - 0.25 * (a - c) * off


@pytest.mark.slow
def test_wave_front_moves_at_c_and_round(rings):
    r, frames, (amp, a, c) = rings
    (t1, f1), (t2, f2) = frames[1], frames[3]
    for name in ("axis", "diagonal"):
        speed = (_crest(r, f2[name])[0] - _crest(r, f1[name])[0]) / (t2 - t1)
        assert speed == pytest.approx(c, rel=WAVE_SPEED_RTOL)
    axis = _crest(r, f2["axis"])[0] - _crest(r, f1["axis"])[0]
    diagonal = _crest(r, f2["diagonal"])[0] - _crest(r, f1["diagonal"])[0]
    assert diagonal == pytest.approx(axis, rel=WAVE_ISOTROPY_RTOL)


@pytest.mark.slow
def test_crest_amplitude_falls_as_one_over_root_r(rings):
    r, frames, (amp, a, c) = rings
    products = []
    for t, f in frames[1:]:
        radius, height = _crest(r, f["axis"])
        products.append(height * math.sqrt(radius))
        exact = exact_wave(r, t, amp, a, c)
        assert np.abs(f["axis"] - exact).max() < WAVE_EXACT_RTOL * np.abs(exact).max()
    assert max(products) == pytest.approx(min(products), rel=WAVE_AMPLITUDE_RTOL)


def test_steps_above_the_cfl_limit_are_refused():
    dx = 1.0 / 64
    WaveEquation(64, 1.0, 1.0, dt=CFL_LIMIT * dx)
    with pytest.raises(ArgumentError, match="sqrt\\(3\\)/2"):
        WaveEquation(64, 1.0, 1.0, dt=1.01 * CFL_LIMIT * dx)
    # and the limit is real: just above it the scheme blows up, just below it does not
    for courant, stable in ((0.99 * CFL_LIMIT, True), (1.02 * CFL_LIMIT, False)):
        sim = WaveEquation(64, 1.0, 1.0, dt=min(courant, CFL_LIMIT) * dx)
        sim.dt = courant * dx  # bypass the guard to probe the scheme itself
        sim.height[:] = np.random.default_rng(0).normal(size=(64, 64)) * 1e-3
        sim.step(2000)
        assert bool(np.abs(sim.height).max() < 1) is stable


def test_damping_acts_on_velocity_only_and_energy_decays_at_its_rate():
    gamma = 0.8
    sim = WaveEquation(128, 1.0, 0.25, dt=0.5 / 128 / 0.25, damping=gamma)
    sim.height[:] = 1e-3  # a uniform offset is not pulled back: no restoring force
    sim.step(200)
    np.testing.assert_allclose(sim.height, 1e-3, rtol=1e-12)
    sim = WaveEquation(128, 1.0, 0.25, dt=0.5 / 128 / 0.25, damping=gamma)
    sim.add_impact(0.5, 0.5, amplitude=1e-3, width=0.05)

    def energy():
        h = sim.height
        hx = (np.roll(h, -1, 1) - h) / sim.dx
        hy = (np.roll(h, -1, 0) - h) / sim.dx
        return 0.5 * (sim.velocity**2).sum() + 0.5 * sim.speed**2 * (hx**2 + hy**2).sum()

    sim.step(100)
    e1, t1 = energy(), sim.time
    sim.step(400)
    rate = -math.log(energy() / e1) / (sim.time - t1)
    assert rate == pytest.approx(gamma, rel=0.05)  # E ~ exp(-gamma t)


def test_absorbing_edges_keep_far_less_energy_than_reflecting_ones():
    kept = {}
    for edges in ("reflect", "absorb"):
        sim = WaveEquation(128, 1.0, 0.25, dt=0.5 / 128 / 0.25, edges=edges)
        sim.add_impact(0.5, 0.5, amplitude=1e-3, width=0.03)
        sim.step(int(3.0 / sim.dt))  # the ring has reached every edge
        kept[edges] = (sim.height**2).sum() + (sim.velocity**2).sum() / 0.25**2
    assert kept["absorb"] < 0.05 * kept["reflect"]


def test_sources_and_impacts_make_waves():
    sim = WaveEquation(64, 1.0, 0.25, dt=0.5 / 64 / 0.25)
    boat = Source(position=lambda t: (0.2 + 0.1 * t, 0.5), radius=0.03, strength=-0.5, stop=2.0)
    frames = list(simulate(sim, frames=3, steps_per_frame=50, sources=[boat],
                           impacts=[Impact(0.8, 0.8, 0.05, 1e-3, 0.03)]))  # fmt: skip
    assert np.abs(frames[-1][1]).max() > 1e-5


def test_height_normals_of_a_plane_are_exact():
    dx = 0.01
    n = 32
    x = (np.arange(n) + 0.5) * dx
    xx, yy = np.meshgrid(x, n * dx - x)
    h = 0.3 * xx - 0.1 * yy
    normals = height_normals(h, dx, periodic=False)
    expected = np.array([-0.3, 0.1, 1.0]) / math.sqrt(1.1)
    np.testing.assert_allclose(normals, np.broadcast_to(expected, normals.shape), atol=1e-6)


def test_ring_outputs_and_the_rain_atlas_tile():
    crater = drop_crater(drop_diameter=0.003, drop_speed=5.0)
    normals = ring_normals(crater, size=0.2, resolution=64, times=[0.05, 0.1])
    assert normals.shape == (2, 64, 64, 3)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=-1), 1, atol=1e-6)
    lut = ring_lut(crater, radius=0.1, duration=0.5, radii=32, steps=16)
    assert lut.shape == (16, 32, 3)
    atlas = rain_atlas(resolution=64, cells=4, seed=3, margin=0.3)
    # every texel within a cell refers to that cell's drop; the texel at the drop is centred
    d = atlas[..., :2] * 2 - 1
    r = np.hypot(d[..., 0], d[..., 1])
    assert (atlas[..., 3][r <= 0.3] == 1).all() and (atlas[..., 3][r > 0.3] == 0).all()
    # phases are constant within a cell and the atlas tiles: cells never cross the edges
    cell = 16
    for i in range(4):
        for j in range(4):
            block = atlas[i * cell : (i + 1) * cell, j * cell : (j + 1) * cell, 2]
            assert np.ptp(block) == 0
    with pytest.raises(ArgumentError):
        rain_atlas(resolution=64, cells=5)


def test_dispersion_of_ripples_has_the_capillary_minimum():
    k = np.linspace(100, 1000, 10000)
    c = dispersion(k) / k
    assert c.min() == pytest.approx(0.2315, abs=5e-4)  # m/s, at about 1.7 cm


def test_ring_texture_time_channel_is_when_the_exact_slope_peaks():
    crater = Crater(amplitude=1e-3, width=0.006)
    texture, info = ring_texture(crater, size=0.2, resolution=64, duration=0.6, steps=301)
    # at a texel on the +x axis, B x duration is the time of the strongest slope there
    n = 64
    row, col = n // 2 - 1, n - 8  # tangent y just above the centre line, x = 0.07 m
    x = (col + 0.5) * 0.2 / n - 0.1
    y = 0.1 - (row + 0.5) * 0.2 / n
    r = math.hypot(x, y)
    t = np.linspace(0, 0.6, 301)
    slope = ring(crater, [r], t)[1][:, 0]
    assert texture[row, col, 2] * 0.6 == pytest.approx(t[np.argmax(np.abs(slope))], abs=0.01)
    assert texture[row, col, 3] * info["slope_max"] == pytest.approx(np.abs(slope).max(), rel=0.02)
    np.testing.assert_allclose(texture[row, col, 0] * 2 - 1, x / r, atol=1e-6)
    # the energy arrives later farther out: B grows with r
    b_axis = texture[n // 2, n // 2 :, 2]
    assert (np.diff(b_axis[4:-4]) >= 0).mean() > 0.9
