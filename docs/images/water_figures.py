"""Make the pictures and numbers of docs/water.md.

Pictures (docs/images/): water_tiled.png (an ocean frame tiled 2x2, shaded, and its normal
map), water_loop.png (loop closure with and without quantisation, and the frozen modes of a
short loop), water_spectrum.png (the measured directional spectrum against the target),
water_ripples.png (the analytic ring, its LUT, the wave equation), water_murk.png (Jerlov's
water types: spectra and the fade of a white target), water_shader.png (the reference shader
in OpenGL). Numbers (printed): loop, seam and spectrum figures quoted in the page.

Run: ``.venv/bin/python docs/images/water_figures.py``
"""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from bakeshop.image import srgb_encode
from bakeshop.io import read_image
from bakeshop.light.fresnel import bake_fresnel
from bakeshop.water import murk
from bakeshop.water.ocean import evaluate, ocean, ocean_fields
from bakeshop.water.ripples import WaveEquation, drop_crater, rain_atlas, ring_lut, ring_normals
from bakeshop.water.shader import WaterScene, look_at, render_water, scene_water
from bakeshop.water.spectra import Spectrum
from bakeshop.water.textures import angle_between, pack_normals, quantise, shade, unpack_normals

HERE = Path(__file__).parent


def save(fig: Figure, name: str) -> None:
    FigureCanvasAgg(fig)
    fig.savefig(HERE / name, dpi=100)
    print(f"wrote {name}")


def display(image):
    return np.clip(srgb_encode(np.clip(image, 0, 1)), 0, 1)


SEA = Spectrum("jonswap", wind_speed=8.0, fetch=60e3, wind_direction=25.0)


def tiled():
    o = ocean(SEA, size=40.0, resolution=256, seed=2, loop_period=8.0)
    frames = o.minimum_frames()
    normals = ocean_fields(o, frames=frames, fields=("normal",), choppiness=0.8,
                           batch=2)["normal"]  # fmt: skip
    fig = Figure(figsize=(12, 6.2))
    ax = fig.add_subplot(1, 2, 1)
    ax.imshow(display(np.tile(shade(normals[0]), (2, 2, 1))))
    ax.axhline(255.5, color="w", lw=0.5, ls=":")
    ax.axvline(255.5, color="w", lw=0.5, ls=":")
    ax.set_title("frame 0 tiled 2x2 (dotted: where the tiles meet)")
    ax.set_axis_off()
    ax = fig.add_subplot(1, 2, 2)
    ax.imshow(pack_normals(normals[0]))
    ax.set_title(f"its normal map (packed, OpenGL convention), 40 m, {frames} frames / 8 s")
    ax.set_axis_off()
    fig.tight_layout()
    save(fig, "water_tiled.png")
    # numbers: the seam, float32 and after 8-bit / BC5-ready encoding, on the eight columns
    # either side of the vertical seam of the 2x2 tiling (brute-force sums are costly)
    cols = np.arange(248, 264)
    c = (np.arange(2 * 256) + 0.5) * o.texel
    x, y = np.meshgrid(c[cols], 2 * o.size - c)
    exact = evaluate(o, x, y - o.size, 0.0, choppiness=0.8)["normal"]
    tiled_normals = np.tile(normals[0], (2, 2, 1))[:, cols]
    for name, ch in (("float32", None), ("8-bit xyz", "xyz"), ("8-bit xy (BC5-ready)", "xy")):
        if ch is None:
            decoded = tiled_normals
        else:
            decoded = unpack_normals(quantise(pack_normals(tiled_normals, channels=ch), 8) / 255,
                                     channels=ch)  # fmt: skip
        err = np.degrees(angle_between(decoded, exact))
        print(f"tile check {name}: max angle to the exact field {err.max():.4f} deg "
              f"(the two seam columns {err[:, 7:9].max():.4f} deg)")  # fmt: skip


def loop():
    looped = ocean(SEA, size=40.0, resolution=128, seed=2, loop_period=8.0)
    free = ocean(SEA, size=40.0, resolution=128, seed=2)
    t = np.linspace(0, 8, 33)
    a = ocean_fields(looped, times=np.concatenate([t, t + 8]), fields=("height",),
                     dtype="float64")["height"]  # fmt: skip
    b = ocean_fields(free, times=np.concatenate([t, t + 8]), fields=("height",),
                     dtype="float64")["height"]  # fmt: skip
    a32 = ocean_fields(looped, times=[0.0, 8.0], fields=("height",))["height"]
    ea = np.abs(a[33:] - a[:33]).max((1, 2))
    eb = np.abs(b[33:] - b[:33]).max((1, 2))
    print(f"loop: max |h(t + T) - h(t)| quantised {ea.max():.2e} m (float64), "
          f"{np.abs(a32[1] - a32[0]).max():.2e} m (float32); not quantised {eb.max():.2f} m; "
          f"field range {np.ptp(a[0]):.2f} m")  # fmt: skip
    periods = np.array([1, 2, 3, 4, 6, 8, 12, 16, 24, 32], float)
    frozen, shift = [], []
    for p in periods:
        o = ocean(SEA, size=200.0, resolution=128, seed=2, loop_period=p)
        frozen.append(100 * o.report["frozen_fraction"])
        shift.append(o.report["minimum_frames"])
    fig = Figure(figsize=(11, 4))
    ax = fig.add_subplot(1, 2, 1)
    ax.semilogy(t, np.maximum(ea, 1e-17), "o-", label="quantised to T = 8 s")
    ax.semilogy(t, eb, "s-", label="not quantised")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("max |h(t + T) - h(t)| (m)")
    ax.set_title("loop closure, 128^2 over 40 m (float64)")
    ax.legend()
    ax = fig.add_subplot(1, 2, 2)
    ax.semilogx(periods, frozen, "o-", color="C2")
    ax.set_xlabel("loop period T (s)")
    ax.set_ylabel("variance in frozen waves (%)", color="C2")
    ax2 = ax.twinx()
    ax2.semilogx(periods, shift, "s--", color="C3")
    ax2.set_ylabel("frames needed per loop", color="C3")
    ax.set_title("what a loop costs: 200 m patch, 128^2, JONSWAP 8 m/s")
    fig.tight_layout()
    save(fig, "water_loop.png")
    for p, f, n in zip(periods, frozen, shift, strict=True):
        print(f"  T = {p:4.0f} s: frozen {f:6.3f} % of the variance, at least {n} frames")


def spectrum():
    sea = Spectrum("jonswap", wind_speed=10.0, fetch=40e3, wind_direction=30.0,
                   spreading="cos2s", spread=6.0, surface_tension=0.0)  # fmt: skip
    size, res, period, seeds = 1600.0, 256, 30.0, 24
    power = 0
    for seed in range(seeds):
        o = ocean(sea, size=size, resolution=res, seed=seed, loop_period=period)
        frames = o.minimum_frames()
        h = ocean_fields(o, frames=frames, fields=("height",))["height"]
        spec = np.fft.fft2(h, axes=(1, 2)) / res**2
        k = np.hypot(o.kx, o.ky)
        n = np.rint(sea.omega(k) * period / (2 * math.pi)).astype(int)
        f = np.arange(frames)[:, None, None]
        power = power + np.abs((spec * np.exp(2j * math.pi * n[None] * f / frames)).mean(0)) ** 2
    power = 2 * power / seeds
    dk = 2 * math.pi / size
    k = np.hypot(o.kx, o.ky)
    theta = (np.degrees(np.arctan2(o.ky, o.kx)) - 30.0 + 180) % 360 - 180
    kp = sea._peak_wavenumber()
    edges = np.geomspace(0.5 * kp, 3 * kp, 13)
    fig = Figure(figsize=(11, 4))
    ax = fig.add_subplot(1, 2, 1)
    worst = 0.0
    for lo, hi, label, colour in ((-20, 20, "with the wind (+-20 deg)", "C0"),
                                  (40, 80, "40-80 deg off", "C1")):  # fmt: skip
        measured, target = [], []
        for k0, k1 in zip(edges[:-1], edges[1:], strict=True):
            inside = (k >= k0) & (k < k1) & (theta >= lo) & (theta < hi)
            measured.append(power[inside].sum() / (inside.sum() * dk * dk))
            target.append(o.mode_variance[inside].sum() / (inside.sum() * dk * dk))
            worst = max(worst, abs(measured[-1] / target[-1] - 1))
        centres = np.sqrt(edges[:-1] * edges[1:]) / kp
        ax.loglog(centres, target, "-", color=colour, label=f"target, {label}")
        ax.loglog(centres, measured, "o", color=colour, label=f"measured, {label}")
    ax.set_xlabel("k / k_peak")
    ax.set_ylabel("F(k) (m^4), band mean")
    ax.set_title(f"directional spectrum from the frames, {seeds} seeds")
    ax.legend(fontsize=7)
    print(f"spectrum: largest band deviation {100 * worst:.1f} % (24 seeds, 12 bands x 2 sectors)")
    ax = fig.add_subplot(1, 2, 2)
    pm = Spectrum("pierson-moskowitz", wind_speed=10.0, surface_tension=0.0)
    hs = []
    for seed in range(8):
        o = ocean(pm, size=1200.0, resolution=256, seed=seed, k_range=(0, math.pi * 256 / 1200))
        hs.append(4 * ocean_fields(o, times=[0.0], fields=("height",))["height"][0].std())
    g, u = 9.81, 10.0
    w0 = g / (1.026 * u)
    w_min, w_max = math.sqrt(g * 2 * math.pi / 1200), math.sqrt(g * math.pi * 256 / 1200)
    m0 = 8.1e-3 * g * g / (4 * 0.74 * w0**4) * (math.exp(-0.74 * (w0 / w_max) ** 4)
                                                 - math.exp(-0.74 * (w0 / w_min) ** 4))  # fmt: skip
    ax.bar(range(8), hs, color="C0", label="4 std(h) per seed")
    ax.axhline(4 * math.sqrt(m0), color="k", label=f"4 sqrt(m0) = {4 * math.sqrt(m0):.3f} m")
    ax.set_ylim(0.9 * min(hs), 1.05 * max(hs))
    ax.set_xlabel("seed")
    ax.set_ylabel("Hs (m)")
    ax.set_title("Pierson-Moskowitz, 10 m/s, 1200 m patch")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "water_spectrum.png")
    print(f"Hs: mean over 8 seeds {np.mean(hs):.4f} m vs 4 sqrt(m0) {4 * math.sqrt(m0):.4f} m "
          f"({100 * (np.mean(hs) / (4 * math.sqrt(m0)) - 1):+.2f} %)")  # fmt: skip


def ripples():
    crater = drop_crater(drop_diameter=0.004, drop_speed=6.0)
    times = [0.05, 0.15, 0.3, 0.5]
    normals = ring_normals(crater, size=0.25, resolution=256, times=times)
    lut = ring_lut(crater, radius=0.125, duration=0.8, radii=256, steps=256)
    sim = WaveEquation(256, 0.5, crater.front_speed, dt=0.5 * (0.5 / 256) / crater.front_speed,
                       damping=0.3)  # fmt: skip
    rng = np.random.default_rng(3)
    for _ in range(6):
        sim.add_impact(*rng.uniform(0, 0.5, 2), amplitude=crater.amplitude, width=crater.width)
        sim.step(120)
    fig = Figure(figsize=(14, 6.6))
    for i, (t, n) in enumerate(zip(times, normals, strict=True)):
        ax = fig.add_subplot(2, 4, i + 1)
        ax.imshow(display(shade(n)))
        ax.set_title(f"ring at t = {t:g} s (25 cm)")
        ax.set_axis_off()
    ax = fig.add_subplot(2, 4, 5)
    ax.imshow(lut[..., 1], aspect="auto", cmap="RdBu", extent=[0, 12.5, 0.8, 0],
              vmin=-np.abs(lut[..., 1]).max() / 3, vmax=np.abs(lut[..., 1]).max() / 3)  # fmt: skip
    ax.set_xlabel("r (cm)")
    ax.set_ylabel("t (s)")
    ax.set_title("ring LUT: d eta / dr")
    ax = fig.add_subplot(2, 4, 6)
    ax.imshow(rain_atlas(resolution=256, cells=4, seed=1)[..., [0, 1, 2]])
    ax.set_title("rain atlas (RG offset, B phase)")
    ax.set_axis_off()
    ax = fig.add_subplot(2, 4, 7)
    ax.imshow(display(shade(np.tile(sim.normals(), (2, 2, 1)))))
    ax.set_title("wave equation, 6 drops, tiled 2x2")
    ax.set_axis_off()
    ax = fig.add_subplot(2, 4, 8)
    r = np.linspace(0, 0.125, 256)
    for i in (40, 100, 180):
        ax.plot(100 * r, 1000 * lut[i, :, 0], label=f"t = {0.8 * i / 255:.2f} s")
    ax.set_xlabel("r (cm)")
    ax.set_ylabel("eta (mm)")
    ax.set_title(f"4 mm drop at 6 m/s: front {100 * crater.front_speed:.0f} cm/s")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "water_ripples.png")


def murk_figure():
    lam = murk.wavelengths()
    fig = Figure(figsize=(13, 8))
    ax = fig.add_subplot(2, 2, 1)
    ax.semilogy(lam, murk.pure_water_absorption(), "k", lw=2, label="pure water a_w (Pope & Fry)")
    for name, colour in (("I", "C0"), ("II", "C1"), ("III", "C2"), ("3C", "C3"), ("9C", "C4")):
        w = murk.water(name)
        ax.semilogy(lam, w.kd, "-", color=colour, label=f"Kd {name} (Jerlov)")
        ax.semilogy(lam, w.attenuation, "--", color=colour)
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel("1/m")
    ax.set_title("diffuse Kd (solid) and beam c = a + b (dashed)")
    ax.legend(fontsize=7, ncol=2)
    ax = fig.add_subplot(2, 2, 2)
    names = murk.WATER_TYPES
    beam = np.array([murk.channel_coefficients(murk.water(n))["e_folding"] for n in names])
    diff = np.array([murk.channel_coefficients(murk.water(n), which="diffuse")["e_folding"]
                     for n in names])  # fmt: skip
    x = np.arange(len(names))
    for ch, colour in enumerate(("r", "g", "b")):
        ax.semilogy(x, beam[:, ch], "o-", color=colour, label=f"line of sight 1/e, {colour}")
        ax.semilogy(x, diff[:, ch], "s:", color=colour, label=f"ambient light 1/e depth, {colour}")
    ax.set_xticks(x, names)
    ax.set_ylabel("metres")
    ax.set_title("per sRGB channel: where the light falls to 1/e")
    ax.legend(fontsize=7, ncol=2)
    ax = fig.add_subplot(2, 1, 2)
    d = np.linspace(0, 30, 600)
    rows = []
    for name in names:
        w = murk.water(name)
        t = murk.transmittance(w, d)[:, :3]
        rows.append(np.repeat((t + murk.inscatter(w, d, 0.0)[:, :3])[None], 24, 0))
    ax.imshow(display(np.concatenate(rows)), aspect="auto", extent=[0, 30, len(names), 0])
    ax.set_yticks(np.arange(len(names)) + 0.5, names)
    ax.set_xlabel("path length through water (m)")
    ax.set_title("a white target seen through water near the surface, per Jerlov type")
    fig.tight_layout()
    save(fig, "water_murk.png")
    print("murk (1/e distances, m, r g b):")
    for name, b, k in zip(names, beam, diff, strict=True):
        print(f"  {name:4s} line of sight {b[0]:6.2f} {b[1]:6.2f} {b[2]:6.2f}   "
              f"ambient light {k[0]:6.2f} {k[1]:6.2f} {k[2]:6.2f}   "
              f"visibility {murk.visibility(murk.water(name)):5.1f}")  # fmt: skip


def shader_picture():
    probe = resources.files("bakeshop.data").joinpath("default_probe.hdr")
    with resources.as_file(probe) as path:
        env = read_image(path)
    baked = bake_fresnel(env, "latlong", below="mirror") * 2**-3.0
    o = ocean(SEA, size=24.0, resolution=256, seed=5, loop_period=8.0)
    frames = o.minimum_frames()
    normals = ocean_fields(o, frames=frames, fields=("normal",), choppiness=0.8,
                           batch=2)["normal"]  # fmt: skip
    crater = drop_crater(drop_diameter=0.004, drop_speed=6.0)
    scene = WaterScene(
        normals=pack_normals(normals, channels="xy"),
        frame_rate=frames / 8.0,
        tile_size=24.0,
        normal_strength=0.6,
        environment=baked,
        bottom_depth=3.0,
        water=scene_water(murk.water("II")),
        rain=rain_atlas(resolution=256, cells=8, seed=2),
        ring=ring_lut(crater, radius=0.35 * 0.125, duration=0.8, radii=256, steps=256),
        rain_cell=0.125,
        rain_tile=1.0,
        ring_radius=0.35 * 0.125,
        ring_duration=0.8,
        ripple_strength=0.5,
    )
    view = look_at([0.0, 1.6, 0.0], [0.0, 0.0, -5.0], fov=60.0, aspect=1.6)
    image = render_water(scene, width=800, height=500, inv_view_proj=view, time=1.3)
    fig = Figure(figsize=(8, 5))
    ax = fig.add_axes([0, 0, 1, 1])
    ax.imshow(display(image[..., :3]))
    ax.set_axis_off()
    save(fig, "water_shader.png")


if __name__ == "__main__":
    tiled()
    loop()
    spectrum()
    ripples()
    murk_figure()
    shader_picture()
