"""Make the pictures and the error table of docs/irradiance.md.

Pictures (docs/images/): irradiance_pair.png (a probe, its sun-removed probe, its sun DIM and
its shadow DIM, and the sun before and after removal), irradiance_methods.png (the relative
error of ``sh`` L = 2 and of ``auto`` against ``exact``), irradiance_suns.png (what sun
detection says on every test probe), irradiance_sh_windows.png (the order-2 SH DIM of the
embedded default probe under each window, with its negative fraction and error; ``python
irradiance_figures.py windows`` makes this one alone). Table (printed as Markdown): ``auto``
and ``sh`` L = 2 against ``exact`` on every probe of tests/data at 360x180.

Run: ``.venv/bin/python docs/images/irradiance_figures.py`` (a few minutes: ``exact`` runs at
360x180 from each 1024x512 probe).
"""

from __future__ import annotations

import io
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # tests.files

import bakeshop.light as ir
from bakeshop.image import auto_exposure, exposure, to_srgb8
from bakeshop.io import read_image
from bakeshop.light.sun import find_sun
from bakeshop.sphere import layout
from tests.files import probe_path

HERE = Path(__file__).resolve().parent
NAMES = [
    "quarry_01",
    "rooitou_park",
    "venice_sunset",
    "st_fagans_interior",
    "kiara_1_dawn",
    "forest_slope",
    "studio_small_03",
]
DPI = 100


def say(line: str) -> None:
    sys.stdout.write(line + "\n")


def save(fig, name):
    """Save a figure as an optimised RGB PNG (the docs keep each picture under 300 KB)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    Image.open(buffer).convert("RGB").save(HERE / name, optimize=True)


def picture(image, ev):
    return to_srgb8(exposure(image, ev))


def errors(got, ref):
    got, ref = np.asarray(got, np.float64), np.asarray(ref, np.float64)
    rel = np.abs(got - ref) / ref
    return np.sqrt(np.mean((got - ref) ** 2) / np.mean(ref**2)), rel.max(), rel


def pair_figure(probe):
    pair = ir.dim_pair(probe, "latlong")
    s = pair.sun
    ev = -2.5
    fig, axes = plt.subplots(3, 2, figsize=(8.4, 7.2), dpi=DPI)
    panels = [
        (probe, "probe (Quarry 01, 1024x512)"),
        (pair.shadow_probe, "shadow_probe: the sun painted out"),
        (pair.sun_dim, "sun_dim (360x180, E/pi)"),
        (pair.shadow_dim, "shadow_dim"),
    ]
    for ax, (img, title) in zip(axes.flat[:4], panels, strict=True):
        ax.imshow(picture(img, ev))
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    # the sun before and after, 8 degrees around it, at a darker exposure
    xy = layout("latlong").coordinates(s.direction, probe.shape[:2])
    x, y = int(xy[0]), int(xy[1])
    r = 24
    for ax, img, title in (
        (axes[2, 0], probe, "the sun (8 deg crop)"),
        (axes[2, 1], pair.shadow_probe, "after removal (harmonic fill)"),
    ):
        ax.imshow(picture(img[y - r : y + r, x - 2 * r : x + 2 * r], -6.0))
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    fig.tight_layout()
    save(fig, "irradiance_pair.png")
    return pair


def methods_figure(probe):
    exact = ir.irradiance(probe, "latlong", method="exact")
    auto = ir.irradiance(probe, "latlong")
    sh2 = ir.irradiance(probe, "latlong", method="sh", order=2)
    fig, axes = plt.subplots(1, 2, figsize=(9.6, 2.8), dpi=DPI)
    for ax, got, title, vmax in (
        (axes[0], sh2, "sh, L = 2: relative error", 0.3),
        (axes[1], auto, "auto: relative error", 5e-4),
    ):
        rms, worst, rel = errors(got, exact)
        im = ax.imshow(rel.max(-1), cmap="magma", vmin=0, vmax=vmax)
        ax.set_title(f"{title} (rms {rms:.1e}, max {worst:.1e})", fontsize=9)
        ax.axis("off")
        fig.colorbar(im, ax=ax, fraction=0.025)
    fig.tight_layout()
    save(fig, "irradiance_methods.png")


def suns_figure():
    fig, axes = plt.subplots(4, 2, figsize=(7.2, 6.9), dpi=80)
    for ax, name in zip(axes.flat, NAMES + [None], strict=True):
        ax.axis("off")
        if name is None:
            continue
        probe = read_image(probe_path(name))
        found = find_sun(probe, "latlong")
        ax.imshow(picture(probe, auto_exposure(probe)))
        if found is None:
            ax.set_title(f"{name}: no sun", fontsize=9)
            continue
        x, y = layout("latlong").coordinates(found.direction, probe.shape[:2])
        ax.add_patch(plt.Circle((x, y), 18, fill=False, color="red", linewidth=1.2))
        ax.set_title(
            f"{name}: sun, {found.angular_radius_deg:.2f} deg, elevation "
            f"{np.degrees(np.arcsin(found.direction[1])):.1f} deg",
            fontsize=9,
        )
    fig.tight_layout()
    save(fig, "irradiance_suns.png")


def table():
    say("| probe | sun | auto RMS | auto max | sh L=2 RMS | sh L=2 max |")
    say("|---|---|---|---|---|---|")
    for name in NAMES:
        probe = read_image(probe_path(name))
        exact = ir.irradiance(probe, "latlong", method="exact")
        auto = ir.irradiance(probe, "latlong")
        sh2 = ir.irradiance(probe, "latlong", method="sh", order=2)
        a_rms, a_max, _ = errors(auto, exact)
        s_rms, s_max, _ = errors(sh2, exact)
        sun = ir.dim_pair(probe, "latlong", size=(36, 18)).sun
        found = "yes" if sun is not None else "none"
        say(f"| {name} | {found} | {a_rms:.1e} | {a_max:.1e} | {s_rms:.1e} | {s_max:.1e} |")


def windows_figure():
    """The default probe's order-2 SH DIM, raw and under each window, against the exact DIM."""
    from bakeshop.data import default_probe_path
    from bakeshop.light import sh

    probe = read_image(default_probe_path())
    exact = ir.irradiance(probe, "latlong", size=(256, 128))
    lay = layout("latlong")
    dirs, _ = lay.directions((128, 256))
    omega = lay.solid_angles((128, 256))
    coeffs = ir.sh_coefficients(probe, "latlong", order=2)
    ev = float(np.log2(0.18 / np.average(exact.mean(axis=-1), weights=omega)))
    fig, axes = plt.subplots(2, 3, figsize=(10.5, 4.5), dpi=DPI)
    panels = [("exact DIM (method auto)", exact)]
    for window in ("none", "hanning", "lanczos", "minimal"):
        irr = sh.windowed_irradiance(coeffs, window=window)
        dim = sh.evaluate(irr.coefficients, dirs)
        rms = np.sqrt(np.average(((dim - exact) ** 2).mean(-1), weights=omega))
        rms /= np.sqrt(np.average((exact**2).mean(-1), weights=omega))
        factors = ", ".join(f"{v:.3f}" for v in irr.window.factors)
        title = (
            f"SH L=2, {window} window ({factors})\n"
            f"< 0 on {100 * irr.negative:.2f}% of the sphere, RMS error {100 * rms:.1f}%"
        )
        say(f"| {window} | {factors} | {100 * irr.negative:.2f}% | {100 * rms:.1f}% |")
        panels.append((title, dim))
    negative = sh.evaluate(sh.irradiance_coefficients(coeffs), dirs).min(axis=-1) < 0
    for ax, (title, dim) in zip(axes.flat, panels, strict=False):
        shown = picture(np.maximum(dim, 0), ev)
        if title.startswith("SH L=2, none"):
            shown = shown.copy()
            shown[negative] = (255, 0, 255)  # where the raw DIM is below zero
            title += " (magenta)"
        ax.imshow(shown)
        ax.set_title(title, fontsize=7.5)
        ax.axis("off")
    axes.flat[-1].axis("off")
    fig.tight_layout()
    save(fig, "irradiance_sh_windows.png")


def main():
    if sys.argv[1:] == ["windows"]:
        windows_figure()
        return
    windows_figure()
    probe = read_image(probe_path("quarry_01"))
    pair = pair_figure(probe)
    say(f"sun: {pair.sun.to_dict()}")
    methods_figure(probe)
    suns_figure()
    table()


if __name__ == "__main__":
    main()
