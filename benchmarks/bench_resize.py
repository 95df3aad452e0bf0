"""Time energy-preserving downsampling: bakeshop.image vs OpenCV INTER_AREA and Pillow BOX.

An 8192x4096 float32 RGB image (384 MiB) is reduced to an integer factor (2048x1024) and to a
non-integer one (1000x500). The tools are called in turn, warm, REPEATS times (argument 1,
default 7); prints the median wall and CPU seconds (all threads) with the CPU minimum, the ratio
of CPU medians to bakeshop's (the steadier figure on a shared machine), the mean's relative
error, and peak traced memory in multiples of the input.
"""

from __future__ import annotations

import functools
import sys
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


def peak_memory(function, image, size):
    """The output and peak traced allocation of one (warm) call."""
    tracemalloc.start()
    out = function(image, size)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return out, peak


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    found = peers.Peers(["opencv", "pillow"])
    print(f"machine: {peers.machine()}")
    rng = np.random.default_rng(0)
    image = rng.lognormal(0.0, 2.0, (4096, 8192, 3)).astype(np.float32)
    mean = image.mean(dtype=np.float64)
    print(f"input 8192x4096x3 float32 ({image.nbytes / 2**20:.0f} MiB), {repeats} calls each")
    print(
        f"{'size':>10} {'tool':>18} {'wall s':>6} {'CPU s':>6} {'CPU min':>7} "
        f"{'x bakeshop':>10} {'mean err':>9} {'peak/in':>7}"
    )
    for size in [(2048, 1024), (1000, 500)]:
        tools = {
            name: function
            for name, (peer, function) in TOOLS.items()
            if peer is None or found.present(peer)
        }
        for function in tools.values():
            function(image, size)  # warm: loading the kernels, page faults, caches
        times = peers.alternate(
            {name: functools.partial(peers.call, functools.partial(function, image, size))
             for name, function in tools.items()},
            repeats,
        )  # fmt: skip
        outs = {name: peak_memory(function, image, size) for name, function in tools.items()}
        base = times["bakeshop"]["cpu"]
        for name, (out, peak) in outs.items():
            peer = TOOLS[name][0]
            if peer is not None:
                found.measured(peer, f"{size[0]}x{size[1]}")
            t = times[name]
            err = abs(out.mean(dtype=np.float64) / mean - 1)
            print(
                f"{size[0]}x{size[1]:<5} {name:>18} {t['wall']:6.3f} {t['cpu']:6.3f} "
                f"{t['cpu_min']:7.3f} {t['cpu'] / base:10.2f} {err:9.1e} "
                f"{peak / image.nbytes:7.2f}"
            )
    print(f"after: {peers.machine()}")
    found.finish()


if __name__ == "__main__":
    main()
