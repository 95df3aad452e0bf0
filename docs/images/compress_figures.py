"""Make docs/images/compress_quality.png: what BC6H, RGBD-in-BC7 and RGBM-in-BC7 keep of the
sunny probe (around the sun, at two exposures) and the PSNR of each exposure of the
multi-exposure PSNR, for the sunny and the dawn probe.

Run: ``.venv/bin/python docs/images/compress_figures.py``
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from bakeshop.image import srgb_encode
from bakeshop.io import read_image
from bakeshop.io.compress.pipeline import compress_levels
from bakeshop.io.compress.quality import EXPOSURES, mpsnr

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
FORMATS = ("bc6h", "rgbd-bc7", "rgbm-bc7")


def decoded(image):
    """The 2-D image through each format, decoded by bakeshop (sun clamped at 65504)."""
    out = {"original": image}
    for name in FORMATS:
        result = compress_levels([image], name, cube=False, overflow="clamp")
        out[name] = result.decoded[0]
    return out


def main():
    sunny = read_image(ROOT / "bakeshop" / "data" / "default_probe.hdr")
    dawn = read_image(ROOT / "tests" / "data" / "kiara_1_dawn_1k.hdr")
    sun_row, sun_col = np.unravel_index(np.argmax(sunny[..., 0]), sunny.shape[:2])
    crop = (slice(sun_row - 40, sun_row + 40), slice(sun_col - 80, sun_col + 80))
    versions = decoded(sunny)
    fig = Figure(figsize=(12, 7.2), dpi=100)
    FigureCanvasAgg(fig)
    grid = fig.add_gridspec(3, 4, height_ratios=[1, 1, 1.3])
    for row, stops in enumerate((-6, 0)):
        for col, (name, image) in enumerate(versions.items()):
            ax = fig.add_subplot(grid[row, col])
            picture = srgb_encode(np.clip(image[crop] * 2.0**stops, 0, 1))
            ax.imshow(picture, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if row == 0:
                label = name if name == "original" else f"{name}: {mpsnr(sunny, image):.1f} dB"
                ax.set_title(label, fontsize=10)
            if col == 0:
                ax.set_ylabel(f"exposure 2^{stops}", fontsize=9)
    ax = fig.add_subplot(grid[2, :])
    colours = {"bc6h": "tab:blue", "rgbd-bc7": "tab:orange", "rgbm-bc7": "tab:green"}
    for probe_name, probe, style in (("sunny", sunny, "-"), ("dawn", dawn, "--")):
        for name, image in decoded(probe).items():
            if name == "original":
                continue
            per = [mpsnr(probe, image, exposures=[c]) for c in EXPOSURES]
            ax.plot(EXPOSURES, per, style, marker="o", color=colours[name],
                    label=f"{probe_name} latlong, {name}")  # fmt: skip
    ax.set_xlabel("exposure stop c (image scaled by 2^c, gamma 2.2, 8 bits)")
    ax.set_ylabel("PSNR at that exposure (dB)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=3)
    fig.suptitle(
        "The sunny probe around its sun through each format (decoded by bakeshop), and the "
        "PSNR of each exposure of the multi-exposure PSNR",
        fontsize=11,
    )
    fig.tight_layout()
    fig.savefig(HERE / "compress_quality.png")


if __name__ == "__main__":
    main()
