"""Time the fresnel bake of a 4096x2048 latlong (target: under a second) and the LDR encode.

Peers (no tool does this bake, so the peers are the two ways one would write it in numpy):

- numpy per texel: the layout's texel directions, the exact reflectance formula as numpy
  array expressions, a multiply (what bakeshop did before it had a kernel of its own);
- bakeshop, geometry cached: a second bake of the same layout, shape and up axis reuses the
  texel cosines (cached for the last two), as a batch of probes does;
- numpy per row: latlong-only shortcut with up = +Y, where a row shares one angle: 2048
  reflectances and a broadcast multiply (the floor for this one case: one pass over the image).

Also the 8-bit sRGB encode of the bake (exposure, clamp, IEC 61966-2-1, round) against
OpenImageIO's colorconvert + quantise, and a cold run: a new process that imports bakeshop,
bakes and exits (the kernels are compiled at install: nothing to compile or fill first), the
cost a CLI user sees.

Prints seconds (best of 3, warm), ratio to bakeshop, and peak traced memory (tracemalloc) in
multiples of the input image (96 MiB).
"""

from __future__ import annotations

import subprocess
import sys
import time
import tracemalloc

import numpy as np
import peers

from bakeshop import sphere
from bakeshop.image import exposure, to_srgb8
from bakeshop.light.fresnel import WATER_IOR, bake_fresnel
from bakeshop.sphere import clear_caches

H, W = 2048, 4096


def first_bake(image):
    """The bake of a shape not seen before: texel cosines computed, not taken from the cache."""
    clear_caches()
    return bake_fresnel(image, "latlong")


def numpy_per_texel(image):
    dirs, valid = sphere.layout("latlong").directions(image.shape[:2])
    c = dirs[..., 1]
    n = WATER_IOR
    g = np.sqrt(n * n - 1 + c * c)
    r = 0.5 * ((g - c) / (g + c)) ** 2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1)) ** 2)
    return image * np.where(valid & (c >= 0), r, 0)[..., None].astype(np.float32)


def numpy_per_row(image):
    c = np.cos(np.pi * (np.arange(image.shape[0]) + 0.5) / image.shape[0])
    n = WATER_IOR
    cp = np.maximum(c, 0)
    g = np.sqrt(n * n - 1 + cp * cp)
    r = 0.5 * ((g - cp) / (g + cp)) ** 2 * (1 + ((cp * (g + cp) - 1) / (cp * (g - cp) + 1)) ** 2)
    return image * np.where(c >= 0, r, 0).astype(np.float32)[:, None, None]


def oiio_srgb8(image):
    import OpenImageIO as oiio

    buf = oiio.ImageBufAlgo.colorconvert(oiio.ImageBuf(np.clip(image, 0, 1)), "linear", "sRGB")
    return np.clip(np.rint(buf.get_pixels(oiio.FLOAT) * 255), 0, 255).astype(np.uint8)


def measure(function, image, repeats=3):
    function(image)  # warm: imports, page faults, caches
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        out = function(image)
        best = min(best, time.perf_counter() - start)
    tracemalloc.start()
    function(image)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return best, out, peak


COLD = """
import time, numpy as np
start = time.perf_counter()
from bakeshop.light.fresnel import bake_fresnel
imported = time.perf_counter()
bake_fresnel(np.ones((2, 4, 3), np.float32), "latlong")
loaded = time.perf_counter()
bake_fresnel(np.ones(({h}, {w}, 3), np.float32), "latlong")
print(imported - start, loaded - imported, time.perf_counter() - loaded)
"""


def cold_run():
    """Best of 3 new processes: (import, loading the compiled kernels, the bake) in seconds."""
    best = None
    for _ in range(3):
        out = subprocess.run(
            [sys.executable, "-c", COLD.format(h=H, w=W)],
            capture_output=True,
            text=True,
            check=True,
        )
        times = tuple(map(float, out.stdout.split()))
        best = times if best is None or sum(times) < sum(best) else best
    return best


def table(title, peers, image, check):
    print(title)
    print(f"  {'tool':<26} {'seconds':>8} {'x bakeshop':>10} {'peak/in':>8}  check")
    base = None
    reference = None
    for name, function in peers.items():
        seconds, out, peak = measure(function, image)
        base = base or seconds
        reference = out if reference is None else reference
        print(
            f"  {name:<26} {seconds:8.3f} {seconds / base:10.2f} {peak / image.nbytes:8.2f}  "
            f"{check(out, reference)}"
        )


def main():
    found = peers.Peers(["oiio"])
    print(f"machine: {peers.machine()}")
    rng = np.random.default_rng(0)
    image = rng.lognormal(0.0, 1.5, (H, W, 3)).astype(np.float32)
    print(f"input {W}x{H}x3 float32 latlong ({image.nbytes / 2**20:.0f} MiB)")

    def rel(out, ref):
        return f"max rel diff {np.max(np.abs(out - ref) / np.maximum(ref, 1e-30)):.1e}"

    table(
        "fresnel bake (ior 1.333, up +Y, below zero)",
        {
            "bakeshop bake_fresnel": first_bake,
            "bakeshop, geometry cached": lambda im: bake_fresnel(im, "latlong"),
            "numpy per texel": numpy_per_texel,
            "numpy per row (latlong)": numpy_per_row,
        },
        image,
        rel,
    )
    baked = exposure(bake_fresnel(image, "latlong"), -1.0)

    def steps(out, ref):
        return f"max diff {np.abs(out.astype(int) - ref.astype(int)).max()} steps"

    encoders = {"bakeshop to_srgb8": to_srgb8}
    if found.present("oiio"):
        encoders["OpenImageIO colorconvert"] = oiio_srgb8
    table("8-bit sRGB encode of the bake", encoders, baked, steps)
    if found.present("oiio"):
        found.measured("oiio", "sRGB encode")
    imported, loaded, baked = cold_run()
    print(
        f"cold (new process, best of 3): import {imported:.2f} s, "
        f"loading the kernels {loaded:.2f} s, bake {baked:.3f} s"
    )
    found.finish()


if __name__ == "__main__":
    main()
