"""Make the pictures of docs/specular.md and docs/bake-probe.md from the embedded default probe.

Usage: python docs/images/specular_figures.py  (writes docs/images/specular_*.png and
bake_probe_contact_sheet.png)
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

from bakeshop.image import auto_exposure, to_srgb8, tonemap  # noqa: E402
from bakeshop.io import read_image  # noqa: E402
from bakeshop.light import dfg, probe, specular  # noqa: E402
from bakeshop.sphere import remap  # noqa: E402

HERE = Path(__file__).resolve().parent


def save_png(path: Path, rgb: np.ndarray, scale: float = 1.0) -> None:
    """Save a figure as PNG, optionally scaled (to keep the contact sheet under 300 KB)."""
    img = Image.fromarray(rgb)
    if scale != 1.0:
        img = img.resize((round(img.width * scale), round(img.height * scale)), Image.LANCZOS)
    img.save(path, optimize=True)
    print(f"{path.name}: {path.stat().st_size / 1024:.0f} KB")  # noqa: T201


def chains(image) -> None:
    ev = auto_exposure(remap(image, "latlong", "latlong", 128, filter="area"))
    ggx = specular.prefilter_ggx(image, layout="latlong", size=128, mips=8)
    phong = specular.prefilter_phong(image, layout="latlong", size=128, mips=8)
    fig, axes = plt.subplots(4, 4, figsize=(13, 5.6), dpi=80)
    exps = specular.phong_exponents(8)
    for m in range(8):
        for row, chain, label in (
            (m // 4, ggx, f"GGX mip {m}: roughness {m / 7:.3g}"),
            (2 + m // 4, phong, f"Phong mip {m}: exponent {exps[m]:.3g}"),
        ):
            ax = axes[row, m % 4]
            thumb = remap(chain[m], "cube", "latlong", 96, filter="area")
            ax.imshow(to_srgb8(tonemap(thumb, ev=ev, operator="aces")))
            ax.set_title(f"{label} ({chain[m].shape[1]}px)", fontsize=8)
            ax.axis("off")
    fig.tight_layout()
    fig.canvas.draw()
    save_png(HERE / "specular_mips.png", np.asarray(fig.canvas.buffer_rgba())[..., :3].copy())
    plt.close(fig)


def dfg_figure() -> None:
    table = dfg.dfg_table(128).astype(float)
    ue4 = dfg.dfg_table(128, visibility="schlick").astype(float)
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), dpi=80)
    for ax, k, name in ((axes[0], 0, "scale A (on F0)"), (axes[1], 1, "bias B")):
        im = ax.imshow(table[..., k], extent=(0, 1, 1, 0), cmap="magma")
        ax.set_xlabel("n.v")
        ax.set_ylabel("roughness")
        ax.set_title(f"{name}, height-correlated Smith", fontsize=9)
        fig.colorbar(im, ax=ax, fraction=0.046)
    nv = (np.arange(128) + 0.5) / 128
    ax = axes[2]
    for j, colour in ((16, "C0"), (64, "C1"), (112, "C2")):
        r = (j + 0.5) / 128
        fit = dfg.dfg_approximation(nv, r)
        ax.plot(nv, table[j, :, 0], colour, label=f"r={r:.2f} height-corr.")
        ax.plot(nv, ue4[j, :, 0], colour, ls="--", label="UE4 Schlick-Smith")
        ax.plot(nv, fit[:, 0], colour, ls=":", label="Karis' fit of UE4")
    ax.set_xlabel("n.v")
    ax.set_title("scale A along three rows", fontsize=9)
    ax.legend(fontsize=6, ncol=3, loc="lower right")
    fig.tight_layout()
    fig.canvas.draw()
    save_png(HERE / "specular_dfg.png", np.asarray(fig.canvas.buffer_rgba())[..., :3].copy())
    plt.close(fig)


def contact_sheet(image) -> None:
    bake = probe.bake_probe(image, "latlong")
    save_png(HERE / "bake_probe_contact_sheet.png", probe.contact_sheet(bake, image), 0.66)


def main():
    image = read_image(Path(str(files("bakeshop") / "data" / "default_probe.hdr")))
    chains(image)
    dfg_figure()
    contact_sheet(image)


if __name__ == "__main__":
    main()
