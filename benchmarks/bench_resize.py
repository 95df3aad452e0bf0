"""Time energy-preserving downsampling: bakeshop.image vs OpenCV INTER_AREA and Pillow BOX.

An 8192x4096 float32 RGB image (384 MiB) is reduced to an integer factor (2048x1024) and to a
non-integer one (1000x500). Prints seconds (best of 3, warm), ratios to bakeshop, the mean's
relative error, and peak traced memory in multiples of the input.
"""

from __future__ import annotations

import time
import tracemalloc

import numpy as np
import peers

from bakeshop.image import resize_area


def opencv_area(image, size):
    import cv2

    return cv2.resize(image, size, interpolation=cv2.INTER_AREA)


def pillow_box(image, size):
    from PIL import Image

    channels = [Image.fromarray(image[:, :, c], mode="F") for c in range(image.shape[2])]
    return np.dstack([np.asarray(ch.resize(size, Image.Resampling.BOX)) for ch in channels])


#: name -> (the peer it is, or None for bakeshop; the function).
TOOLS = {
    "bakeshop": (None, resize_area),
    "opencv INTER_AREA": ("opencv", opencv_area),
    "pillow BOX": ("pillow", pillow_box),
}


def measure(function, image, size, repeats=3):
    function(image, size)  # warm: numba compilation, caches
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        out = function(image, size)
        best = min(best, time.perf_counter() - start)
    tracemalloc.start()
    function(image, size)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return best, out, peak


def main():
    found = peers.Peers(["opencv", "pillow"])
    print(f"machine: {peers.machine()}")
    rng = np.random.default_rng(0)
    image = rng.lognormal(0.0, 2.0, (4096, 8192, 3)).astype(np.float32)
    mean = image.mean(dtype=np.float64)
    print(f"input 8192x4096x3 float32 ({image.nbytes / 2**20:.0f} MiB)")
    print(
        f"{'size':>10} {'tool':>18} {'seconds':>8} {'x bakeshop':>10} {'mean err':>9} "
        f"{'peak/in':>7}"
    )
    for size in [(2048, 1024), (1000, 500)]:
        base = None
        for name, (peer, function) in TOOLS.items():
            if peer is not None and not found.present(peer):
                continue
            seconds, out, peak = measure(function, image, size)
            if peer is not None:
                found.measured(peer, f"{size[0]}x{size[1]}")
            base = base or seconds
            err = abs(out.mean(dtype=np.float64) / mean - 1)
            print(
                f"{size[0]}x{size[1]:<5} {name:>18} {seconds:8.3f} {seconds / base:10.2f} "
                f"{err:9.1e} {peak / image.nbytes:7.2f}"
            )
    found.finish()


if __name__ == "__main__":
    main()
