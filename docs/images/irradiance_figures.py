"""Make the pictures and the error table of docs/irradiance.md.

Pictures (docs/images/): irradiance_pair.png (a probe, its sun-removed probe, its sun DIM and
its shadow DIM, and the sun before and after removal), irradiance_methods.png (the relative
error of ``sh`` L = 2 and of ``auto`` against ``exact``), irradiance_suns.png (what sun
detection says on every shared probe). Table (printed as Markdown): ``auto``
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


def main():
    probe = read_image(probe_path("quarry_01"))
    pair = pair_figure(probe)
    say(f"sun: {pair.sun.to_dict()}")
    methods_figure(probe)
    suns_figure()
    table()


if __name__ == "__main__":
    main()
