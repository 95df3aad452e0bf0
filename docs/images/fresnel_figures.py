"""Make the pictures and tables of docs/fresnel.md and docs/tonemap.md.

Pictures (docs/images/): fresnel_curve.png (exact vs Schlick), fresnel_bake.png (a probe, its
8-bit bake and where the baked lookup differs from the runtime path), fresnel_normal_error.png
(normal-mapped water), tonemap_operators.png, tonemap_metering.png, tonemap_adaptation.png.
Tables (printed as Markdown): the flat-water error over the real probes of tests/data
and the normal-mapped error over RMS slopes.

Run: ``.venv/bin/python docs/images/fresnel_figures.py``
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # tests.files

from bakeshop import sphere
from bakeshop.image import (
    adapt_exposure,
    auto_exposure,
    exposure,
    metering_weights,
    srgb_decode,
    to_srgb8,
    tonemap,
)
from bakeshop.io import read_image
from bakeshop.light.fresnel import (
    RMS_SLOPES,
    bake_fresnel,
    flat_water_error,
    fresnel_dielectric,
    fresnel_schlick,
    ldr_exposure,
    normal_mapped_error,
)
from tests.files import PROBES, probe_path

HERE = Path(__file__).resolve().parent
DPI = 100


def say(line: str) -> None:
    sys.stdout.write(line + "\n")


def save(fig, name):
    fig.savefig(HERE / name, dpi=DPI)
    plt.close(fig)
    say(f"wrote docs/images/{name} ({(HERE / name).stat().st_size // 1024} KiB)")


def curve_figure():
    theta = np.linspace(0, 90, 901)
    c = np.cos(np.radians(theta))
    exact, schlick = fresnel_dielectric(c), fresnel_schlick(c)
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.4))
    a.plot(theta, exact, label="exact (unpolarised)")
    a.plot(theta, schlick, "--", label="Schlick")
    a.set(xlabel="angle of incidence (deg)", ylabel="reflectance R", title="water, n = 1.333")
    a.legend()
    b.plot(theta, schlick - exact)
    b.axhline(0, color="grey", lw=0.5)
    b.set(xlabel="angle of incidence (deg)", ylabel="Schlick - exact", title="Schlick's error")
    fig.tight_layout()
    save(fig, "fresnel_curve.png")


def bake_figure(env):
    """The probe, its 8-bit bake, and the baked-vs-runtime error over the upper hemisphere."""
    baked = bake_fresnel(env, "latlong", below="mirror")
    ev = ldr_exposure(baked, "latlong")
    codes = to_srgb8(exposure(baked, ev))
    # error map: bilinear lookups at the texel centres of a 2x finer latlong's upper half,
    # shown as the largest error in each 4x4 block of lookups
    h = env.shape[0] * 2
    dirs, _ = sphere.layout("latlong").directions((h, 2 * h))
    dirs = dirs[: h // 2]
    texture = srgb_decode(codes.astype(np.float32) / 255)
    baked_path = to_srgb8(sphere.sample(texture, "latlong", dirs)).astype(int)
    runtime = sphere.sample(env, "latlong", dirs) * fresnel_dielectric(dirs[..., 1])[..., None]
    runtime_path = to_srgb8(runtime * 2.0**ev).astype(int)
    err = np.abs(baked_path - runtime_path).max(axis=-1)
    err = err.reshape(err.shape[0] // 4, 4, err.shape[1] // 4, 4).max(axis=(1, 3))
    preview = to_srgb8(tonemap(env, ev=auto_exposure(env), operator="aces"))
    fig, axes = plt.subplots(3, 1, figsize=(5.6, 7.2))
    axes[0].imshow(preview)
    axes[0].set_title("probe (ACES preview)")
    axes[1].imshow(codes)
    axes[1].set_title(f"8-bit fresnel bake, below = mirror, exposure {ev:+.2f} EV")
    colours = matplotlib.colors.ListedColormap(["black", "#5b3c88", "#f08c2e", "#fff07a"])
    im = axes[2].imshow(np.minimum(err, 3), cmap=colours, vmin=-0.5, vmax=3.5)
    axes[2].set_title("max |baked - runtime| per 4x4 lookups (8-bit steps)")
    bar = fig.colorbar(im, ax=axes[2], orientation="horizontal", fraction=0.05, ticks=[0, 1, 2, 3])
    bar.ax.set_xticklabels(["0", "1", "2", "3+"])
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    save(fig, "fresnel_bake.png")


def flat_table():
    say(
        "\n| probe | peak | EV | max all | max unclipped | max clean | mean clean | "
        "> 1 step (clean) | horizon | footprint clipped | clipped |"
    )
    say("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in PROBES:
        env = read_image(probe_path(name))
        ev = ldr_exposure(bake_fresnel(env, "latlong"), "latlong")
        for below, filt in (("zero", "bilinear"), ("mirror", "bilinear"), ("mirror", "nearest")):
            r = flat_water_error(env, "latlong", ev=ev, below=below, filter=filt)
            say(
                f"| {name}_1k ({below}, {filt}) | {env.max():.3g} | {ev:+.2f} | {r['max']} | "
                f"{r['max_unclipped']} | {r['max_clean']} | {r['mean_clean']:.3f} | "
                f"{100 * r['over_one_clean']:.4f}% | {100 * r['horizon']:.2f}% | "
                f"{100 * r['footprint_clipped']:.3f}% | {100 * r['clipped']:.3f}% |"
            )


def normal_figure():
    edges = [0, 2, 5, 10, 15, 20, 30, 45, 60, 90]
    rows = [normal_mapped_error(s, elevations=edges) for s in RMS_SLOPES]
    say(
        "\n| RMS slope | mean abs dR | p99 abs dR | mean rel | p99 rel | bias rel | "
        "normal faces away | r below plane |"
    )
    say("|---|---|---|---|---|---|---|---|")
    for r in rows:
        say(
            f"| {r['rms_slope']:.2f} | {r['mean_abs']:.4f} | {r['p99_abs']:.3f} | "
            f"{100 * r['mean_rel']:.1f}% | {100 * r['p99_rel']:.0f}% | "
            f"{100 * r['bias_rel']:+.1f}% | "
            f"{100 * r['back_facing']:.1f}% | {100 * r['below_horizon']:.1f}% |"
        )
    fig, (a, b) = plt.subplots(1, 2, figsize=(9.5, 3.6))
    s = [r["rms_slope"] for r in rows]
    a.plot(s, [100 * r["mean_rel"] for r in rows], "o-", label="mean |dR/R|")
    a.plot(s, [100 * r["p99_rel"] for r in rows], "s--", label="99th percentile")
    a.set(
        xscale="log",
        yscale="log",
        xlabel="RMS slope s",
        ylabel="relative error of R (%)",
        title="baked vs true fresnel, all eye directions",
    )
    a.set_xticks(s, [f"{v:g}" for v in s])
    a.minorticks_off()
    a.legend(fontsize=8)
    mids = [(lo + hi) / 2 for lo, hi in zip(edges[:-1], edges[1:], strict=True)]
    for k, r in enumerate(rows):
        b.plot(
            mids,
            [100 * e["mean_rel"] for e in r["by_elevation"]],
            "o-",
            color=f"C{k}",
            label=f"s = {r['rms_slope']:g}",
        )
        b.plot(mids, [100 * e["p99_rel"] for e in r["by_elevation"]], ":", color=f"C{k}")
    b.set(
        yscale="log",
        xlabel="eye elevation above the water (deg)",
        ylabel="|dR/R| (%): mean, 99th pct dotted",
        title="by view elevation",
    )
    b.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "fresnel_normal_error.png")


def tonemap_figures(env):
    ev = auto_exposure(env)
    panels = [
        ("none (clamp)", tonemap(env, ev=ev, operator="none")),
        ("reinhard, white 4", tonemap(env, ev=ev, operator="reinhard", white=4)),
        ("aces (Hill)", tonemap(env, ev=ev, operator="aces")),
    ]
    fig, axes = plt.subplots(3, 1, figsize=(5.2, 7.0))
    for ax, (title, image) in zip(axes, panels, strict=True):
        ax.imshow(to_srgb8(image))
        ax.set_title(f"{title}, auto exposure {ev:+.2f} EV")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    save(fig, "tonemap_operators.png")

    fig, axes = plt.subplots(1, 3, figsize=(9.5, 2.6))
    for ax, w in zip(axes, (0.0, 0.75, 1.0), strict=True):
        weights = metering_weights((180, 320), center_weight=w)
        ax.imshow(weights, cmap="viridis", vmin=0)
        ax.set_title(f"metering weight, W = {w:g}")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    save(fig, "tonemap_metering.png")

    fps = 30
    t = np.arange(0, 8, 1 / fps)
    targets = np.where(t < 1, 0.0, np.where(t < 4, -4.0, 0.0))  # bright from 1 s to 4 s
    evs = adapt_exposure(targets, frame_time=1 / fps, tau_brighter=0.5, tau_darker=2.0)
    fig, ax = plt.subplots(figsize=(6.4, 3))
    ax.plot(t, targets, "--", color="grey", label="metered target")
    ax.plot(t, evs, label="adapted exposure")
    for t0, tau, target, start in ((1, 0.5, -4, 0), (4, 2.0, 0, evs[4 * fps - 1])):
        ax.plot([t0 + tau], [start + (target - start) * (1 - np.exp(-1))], "o", color="C3")
    ax.set(
        xlabel="time (s)",
        ylabel="EV",
        title="adaptation: 63% of a step after one time constant (dots)",
    )
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "tonemap_adaptation.png")


def main():
    curve_figure()
    bake_figure(read_image(probe_path("venice_sunset")))
    tonemap_figures(read_image(probe_path("venice_sunset")))
    normal_figure()
    flat_table()


if __name__ == "__main__":
    main()
