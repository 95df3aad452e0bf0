"""Time to first image of ``bakeshop preview`` at 1280x720: reading the bake, the context and
uploads, each scene cold (first draw: shader compile, shadow map, water textures) and warm.

No peer renders a bake's own files (three.js's PMREM re-filters the environment; Filament's
cmgen/viewer and cmftStudio are interactive GPU applications): the figures are bakeshop's alone,
against the issue's target of a preview in under 2 s warm. The physical limit on this machine is
llvmpipe's rasterisation on 2 shared cores (no GPU).

Run: ``make demo && .venv/bin/python benchmarks/bench_preview.py [BAKE_DIR]``.
"""

from __future__ import annotations

import os
import platform
import sys
import time

from bakeshop.image import to_picture
from bakeshop.preview import Renderer, View, read_bake

REPEATS = 3


def main(folder: str = "demo") -> None:
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"load {os.getloadavg()[0]:.1f}")  # fmt: skip
    t = time.perf_counter()
    bake = read_bake(folder)
    print(f"read_bake                {time.perf_counter() - t:7.2f} s")
    t = time.perf_counter()
    with Renderer(bake) as r:
        print(f"context + upload         {time.perf_counter() - t:7.2f} s")
        for scene in ("sky", "balls", "golf"):
            view = View(scene, 1280, 720)
            times = []
            for _ in range(1 + REPEATS):
                t = time.perf_counter()
                linear = r.render(view)[..., :3]
                to_picture(linear, ev=0.0, operator="aces")
                times.append(time.perf_counter() - t)
            warm = sorted(times[1:])[len(times[1:]) // 2]
            print(f"{scene:6s} 1280x720  cold {times[0]:7.2f} s   warm (median of {REPEATS}) "
                  f"{warm:6.2f} s")  # fmt: skip


if __name__ == "__main__":
    main(*sys.argv[1:])
