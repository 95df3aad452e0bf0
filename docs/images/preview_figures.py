"""Make the pictures of docs/preview.md from the bake `make demo` writes.

Pictures (docs/images/): preview_sky.png, preview_balls.png, preview_golf.png and
preview_golf_shadow_dim.png (the course lit by the shadow DIM everywhere) rendered offscreen
(moderngl over EGL, llvmpipe); preview_reference.png (the balls: the render, the numpy reference
of every pixel, and their difference in 8-bit code values, x32), with its statistics printed.

Run: ``make demo && .venv/bin/python docs/images/preview_figures.py [BAKE_DIR]`` (about a
minute; BAKE_DIR defaults to ./demo).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from bakeshop.image import to_picture
from bakeshop.io import write_image
from bakeshop.preview import Renderer, View, bake_exposure, read_bake
from bakeshop.preview.reference import shade_balls

HERE = Path(__file__).resolve().parent


def picture(linear, ev):
    return to_picture(np.asarray(linear, np.float32)[..., :3], ev=ev, operator="aces").pixels


def main(folder: str = "demo") -> None:
    bake = read_bake(folder)
    ev = bake_exposure(bake)
    with Renderer(bake) as r:
        for name, view in (
            ("sky", View("sky", 960, 540)),
            ("balls", View("balls", 960, 540)),
            ("golf", View("golf", 960, 540)),
            ("golf_shadow_dim", View("golf", 960, 540, diffuse="shadow")),
        ):
            write_image(HERE / f"preview_{name}.png", picture(r.render(view), ev))
        small = View("balls", 480, 270)
        rendered = r.render(small)[..., :3]
    rows, cols = np.mgrid[0 : small.height, 0 : small.width].reshape(2, -1)
    reference, _ = shade_balls(bake, small, rows, cols)
    reference = reference.reshape(rendered.shape)
    a, b = picture(rendered, ev).astype(int), picture(reference, ev).astype(int)
    diff = np.abs(a - b).max(axis=-1)
    print(
        f"balls {small.width}x{small.height}, every pixel: max {diff.max()} codes, "
        f"mean {np.abs(a - b).mean():.4f}, over 1 code: {(diff > 1).sum()} pixels "
        f"({100 * (diff > 1).mean():.3f}%), exactly equal: {100 * (diff == 0).mean():.2f}%"
    )
    shown = np.repeat(np.clip(diff * 32, 0, 255).astype(np.uint8)[..., None], 3, axis=-1)
    gap = np.full((small.height, 8, 3), 255, np.uint8)
    strip = np.concatenate([a.astype(np.uint8), gap, b.astype(np.uint8), gap, shown], axis=1)
    write_image(HERE / "preview_reference.png", strip)


if __name__ == "__main__":
    main(*sys.argv[1:])
