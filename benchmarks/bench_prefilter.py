"""Time specular prefiltering: the GGX and Phong cube mip chains (6x256, 9 levels).

Inputs: Poly Haven's Rooitou Park probe (the embedded default probe,
``bakeshop/data/default_probe.hdr``, 1024x512, a visible sun) as it is and upsampled to 4096x2048
(bilinear). Each case runs in a fresh process, warmed on a tiny input first (imports, loading
the compiled kernels), and reports the best of 3 wall times, the CPU time of that run (both
cores count), the time spent remapping the latlong to the source cube, the peak traced numpy
memory and the process's peak RSS.

No peer runs here: these are library calls, and the peers (cmgen's GGX ``--ibl-ld``, cmft's
Phong radiance filter) are commands; ``bench_commands.py`` (job ``ggx-4k``) runs them against
``bakeshop prefilter`` whole process against whole process.

The last table extrapolates brute-force convolution (every source texel for every output texel
of levels 1-8, from the 6x256 source cube) from a measured pair rate of the same kernel.

Usage: python benchmarks/bench_prefilter.py
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import peers

PROBE = Path(__file__).resolve().parents[1] / "bakeshop" / "data" / "default_probe.hdr"
SIZE, MIPS = 256, 9


def load(width: int) -> np.ndarray:
    import cv2

    from bakeshop.io import read_image

    probe = read_image(PROBE)
    if probe.shape[1] != width:
        probe = cv2.resize(probe, (width, width // 2), interpolation=cv2.INTER_LINEAR)
    return probe


def run_case(brdf: str, width: int) -> dict:
    """One measurement, in this process (called through a subprocess by :func:`main`)."""
    from bakeshop.light import specular

    run = specular.prefilter_ggx if brdf == "ggx" else specular.prefilter_phong
    run(np.ones((32, 64, 3), np.float32), layout="latlong", size=8, mips=4)  # warm
    probe = load(width)
    best = cpu = None
    for _ in range(3):
        c0, t0 = time.process_time(), time.perf_counter()
        run(probe, layout="latlong", size=SIZE, mips=MIPS)
        t, c = time.perf_counter() - t0, time.process_time() - c0
        if best is None or t < best:
            best, cpu = t, c
    t0 = time.perf_counter()
    specular.source_cube(probe, layout="latlong", size=SIZE)
    remap = time.perf_counter() - t0
    tracemalloc.start()
    run(probe, layout="latlong", size=SIZE, mips=MIPS)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    return {
        "seconds": best,
        "cpu": cpu,
        "remap": remap,
        "peak": peak,
        "rss": rss,
        "input": probe.nbytes,
    }


def pair_rate() -> float:
    """Texel pairs per second of the exact GGX convolution kernel (both cores)."""
    from bakeshop.light import specular
    from bakeshop.sphere import layout

    cube = layout("cube")
    src_dirs = np.ascontiguousarray(cube.directions((6, 64, 64))[0].reshape(-1, 3))
    omega = cube.solid_angles((6, 64, 64)).reshape(-1)
    values = np.ones((src_dirs.shape[0], 3))
    dirs = np.ascontiguousarray(cube.directions((6, 32, 32))[0].reshape(-1, 3))
    args = (dirs, src_dirs, omega, values, True, 0.0625**2, 0.0)
    acc, total = np.zeros((dirs.shape[0], 3)), np.zeros(dirs.shape[0])
    specular._lobe_kernel(*args, acc, total)  # warm
    t0 = time.perf_counter()
    specular._lobe_kernel(*args, acc, total)
    return dirs.shape[0] * src_dirs.shape[0] / (time.perf_counter() - t0)


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--case":
        print(json.dumps(run_case(sys.argv[2], int(sys.argv[3]))))
        return
    model = next(
        (line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if "model name" in line),
        "unknown CPU",
    )
    print(f"machine: {model}, {os.cpu_count()} cores; load average {os.getloadavg()[0]:.1f}")
    print(f"GGX and Phong chains, 6x{SIZE}, {MIPS} levels, from {PROBE.name} (latlong)\n")
    header = (
        f"{'input':>9} {'filter':>6} {'seconds':>8} {'cpu s':>6} {'remap s':>7} "
        f"{'peak MiB':>8} {'RSS MiB':>7}"
    )
    print(header)
    for width in (4096, 1024):
        for brdf in ("ggx", "phong"):
            out = subprocess.run(
                [sys.executable, __file__, "--case", brdf, str(width)],
                check=True,
                capture_output=True,
                text=True,
            ).stdout
            r = json.loads(out.strip().splitlines()[-1])
            print(
                f"{width}x{width // 2:<4} {brdf:>6} {r['seconds']:8.2f} {r['cpu']:6.2f} "
                f"{r['remap']:7.2f} {r['peak'] / 2**20:8.0f} {r['rss'] / 2**20:7.0f}"
            )
    rate = pair_rate()
    outputs = sum(6 * (SIZE >> m) ** 2 for m in range(1, MIPS))
    pairs = outputs * 6 * SIZE**2
    print(
        f"\nbrute force from the 6x{SIZE} cube: {outputs} output texels x {6 * SIZE**2} source "
        f"texels = {pairs:.2e} pairs at {rate:.2e} pairs/s (measured, same kernel) = "
        f"{pairs / rate:.0f} s"
    )
    peers.Peers([]).finish()


if __name__ == "__main__":
    main()
