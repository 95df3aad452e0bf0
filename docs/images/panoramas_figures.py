"""Make the pictures of docs/panoramas.md: the default probe in every layout.

Each picture is bakeshop.sphere.remap of bakeshop/data/default_probe.hdr (area filter),
tone-mapped simply: one exposure for all, clipped, sRGB-encoded to 8 bits. The cross and
face-set pictures carry the face labels.

Run: ``.venv/bin/python docs/images/panoramas_figures.py``
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from PIL import Image

from bakeshop import sphere
from bakeshop.image import exposure, to_srgb8
from bakeshop.io import read_image

HERE = Path(__file__).resolve().parent
PROBE = HERE.parents[1] / "bakeshop" / "data" / "default_probe.hdr"
#: exposure in EV: the probe's sky around mid-grey.
EV = -1.0

PICTURES = {
    # file suffix: (layout, size)
    "latlong": ("latlong", (512, 256)),
    "angular": ("angular", 256),
    "mirrorball": ("mirrorball", 256),
    "angular_physical": ("angular-physical", 256),
    "mirrorball_physical": ("mirrorball-physical", 256),
    "openexr_latlong": ("openexr-latlong", (512, 256)),
    "octahedral": ("octahedral", 256),
    "dual_paraboloid": ("dual-paraboloid", 192),
    "cross_horizontal": ("cross-horizontal", 96),
    "strip_horizontal": ("strip-horizontal", 80),
}


def ldr(image) -> np.ndarray:
    return to_srgb8(exposure(image, EV))


def save(name: str, image) -> Path:
    path = HERE / f"panoramas_{name}.png"
    Image.fromarray(ldr(image)).save(path, optimize=True)
    return path


def labelled(image, layout: str, face_size: int, labels, title: str, name: str) -> Path:
    """A cube picture with each square's face label drawn on it."""
    fig, ax = plt.subplots(figsize=(image.shape[1] / 100, image.shape[0] / 100 + 0.35), dpi=100)
    ax.imshow(ldr(image), interpolation="nearest")
    for (col, row), text in labels.items():
        ax.text(
            (col + 0.5) * face_size,
            (row + 0.5) * face_size,
            text,
            color="white",
            ha="center",
            va="center",
            fontsize=11,
            fontweight="bold",
            bbox={"facecolor": "black", "alpha": 0.45, "pad": 2, "linewidth": 0},
        )
    for k in range(image.shape[1] // face_size + 1):
        ax.axvline(k * face_size - 0.5, color="white", lw=0.5, alpha=0.6)
    for k in range(image.shape[0] // face_size + 1):
        ax.axhline(k * face_size - 0.5, color="white", lw=0.5, alpha=0.6)
    ax.set_title(title, fontsize=9)
    ax.set_axis_off()
    fig.tight_layout(pad=0.2)
    path = HERE / f"panoramas_{name}.png"
    fig.savefig(path)
    plt.close(fig)
    return path


def main() -> None:
    probe = read_image(PROBE)
    written = [save(name, sphere.remap(probe, "latlong", lay, size, filter="area"))
               for name, (lay, size) in PICTURES.items()]  # fmt: skip
    s = 96
    cross = sphere.remap(probe, "latlong", "cross-vertical", s, filter="area")
    slots = {(1, 0): "+Y", (0, 1): "-X", (1, 1): "+Z", (2, 1): "+X", (1, 2): "-Y",
             (1, 3): "-Z (turned 180)"}  # fmt: skip
    written.append(
        labelled(
            cross,
            "cross-vertical",
            s,
            slots,
            "cross-vertical\n(left-handed slots, centre forward)",
            "cross_vertical",
        )  # fmt: skip
    )
    e = 64
    stacked = sphere.remap(probe, "latlong", "openexr-cube", e, filter="area")
    written.append(
        labelled(
            np.concatenate(np.split(stacked, 6, axis=0), axis=1),
            "openexr-cube",
            e,
            {(k, 0): lab for k, lab in enumerate(sphere.FACE_LABELS)},
            "openexr-cube (its faces, top to bottom in the file)",
            "openexr_cube",
        )  # fmt: skip
    )
    cube = sphere.remap(probe, "latlong", "cube", s, filter="area")
    for convention in ("opengl", "directx"):
        faces = sphere.cube_to_faces(cube, convention=convention)
        strip = np.concatenate(list(faces), axis=1)
        labels = {(k, 0): f"{k}: {lab}" for k, lab in enumerate(sphere.cube.FACE_LABELS)}
        written.append(
            labelled(
                strip,
                "faces",
                s,
                labels,
                f"--convention {convention}: face i as uploaded to "
                "GL_TEXTURE_CUBE_MAP_POSITIVE_X + i",
                f"faces_{convention}",
            )  # fmt: skip
        )
    for path in written:
        sys.stdout.write(f"{path.relative_to(HERE.parents[1])}: {path.stat().st_size >> 10} KiB\n")


if __name__ == "__main__":
    main()
