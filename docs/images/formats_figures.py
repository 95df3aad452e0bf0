"""Make docs/images/formats_orientations.png: the default probe stored in each of the eight
Radiance orientations, as bakeshop, OpenCV and OpenImageIO (after ImageBufAlgo.reorient) read it.

Run: ``.venv/bin/python docs/images/formats_figures.py``
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import cv2
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import OpenImageIO as oiio

import bakeshop
from bakeshop.image import resize_area, srgb_encode
from bakeshop.io import read_image

ORIENTATIONS = ["-Y +X", "-Y -X", "+Y +X", "+Y -X", "+X -Y", "+X +Y", "-X -Y", "-X +Y"]
HERE = Path(__file__).resolve().parent


def rgbe_bytes(image):
    """Flat RGBE bytes of ``image`` as bakeshop writes them (read back from a flat file)."""
    from bakeshop.io import write_image

    with tempfile.TemporaryDirectory() as d:
        write_image(Path(d) / "f.hdr", image, rle=False)
        data = (Path(d) / "f.hdr").read_bytes()
    return np.frombuffer(data[-image.shape[0] * image.shape[1] * 4 :], np.uint8).reshape(
        image.shape[0], image.shape[1], 4
    )


def file_order(picture, orientation):
    """Scanlines in the order of ``orientation`` (Radiance's pix2loc; y points up)."""
    view = picture
    if "+Y" in orientation:
        view = view[::-1]
    if "-X" in orientation:
        view = view[:, ::-1]
    if orientation.startswith(("+X", "-X")):
        view = view.transpose(1, 0, 2)
    return np.ascontiguousarray(view)


def main():
    probe = read_image(Path(bakeshop.__file__).parent / "data" / "default_probe.hdr")
    small = resize_area(probe, (128, 64))
    pixels = rgbe_bytes(small)
    rows = {"bakeshop": [], "OpenCV": [], "OpenImageIO\nreoriented": []}
    with tempfile.TemporaryDirectory() as d:
        for orientation in ORIENTATIONS:
            axes = orientation.split()
            size = {"X": 128, "Y": 64}
            resolution = " ".join(f"{a} {size[a[1]]}" for a in axes)
            path = os.path.join(d, "o.hdr")
            with open(path, "wb") as f:
                f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + resolution.encode() + b"\n")
                f.write(file_order(pixels, orientation).tobytes())
            rows["bakeshop"].append(read_image(path))
            theirs = cv2.imread(path, cv2.IMREAD_UNCHANGED)
            rows["OpenCV"].append(None if theirs is None else theirs[..., ::-1])
            buf = oiio.ImageBufAlgo.reorient(oiio.ImageBuf(path))
            rows["OpenImageIO\nreoriented"].append(buf.get_pixels(oiio.FLOAT))
    fig, axes = plt.subplots(3, 8, figsize=(13, 3.2), dpi=80)
    for r, (reader, images) in enumerate(rows.items()):
        for c, image in enumerate(images):
            ax = axes[r, c]
            ax.set_xticks([])
            ax.set_yticks([])
            if image is None:
                ax.text(0.5, 0.5, "no image", ha="center", va="center", color="0.4")
            else:
                ax.imshow(srgb_encode(np.clip(image * 0.5, 0, 1)))
            if r == 0:
                ax.set_title(orientation_label(ORIENTATIONS[c]), fontsize=10, family="monospace")
            if c == 0:
                ax.set_ylabel(reader, fontsize=9)
    fig.tight_layout()
    fig.savefig(HERE / "formats_orientations.png")


def orientation_label(orientation):
    a, b = orientation.split()
    size = {"X": "W", "Y": "H"}
    return f"{a} {size[a[1]]} {b} {size[b[1]]}"


if __name__ == "__main__":
    main()
