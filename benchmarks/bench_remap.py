"""Panorama remapping: bakeshop vs py360convert (its cv2 and scipy paths) vs a plain cached
cv2.remap converter, float32 RGB, cold (first call: geometry built) and warm (cached).

Each measurement runs in its own subprocess so that peak memory (ru_maxrss above the process's
state once the input exists) and "cold" mean the same for everyone; bakeshop's compiled kernels
are loaded before the clock starts (cold is the geometry, not the import).
Wall and CPU times are both printed: on a shared machine the CPU seconds (all threads) are the
steadier figure; each figure is the median over PROCESSES processes.

    python benchmarks/bench_remap.py            # the issue's sizes
    python benchmarks/bench_remap.py --quick    # a quarter of each edge
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time

import peers

CASES = [
    # (case, source layout, source size, destination layout, destination size)
    ("latlong->cube", "latlong", 2048, "cube", 1024),
    ("cube->latlong", "cube", 1024, "latlong", 2048),
    ("mirrorball->cross", "mirrorball", 2048, "cross-vertical", 1024),
]
ENGINES = {
    "latlong->cube": ["bakeshop", "bakeshop-area", "py360-cv2", "py360-scipy", "cv2-cached"],
    "cube->latlong": ["bakeshop", "bakeshop-area", "py360-cv2", "py360-scipy", "cv2-cached"],
    "mirrorball->cross": ["bakeshop", "bakeshop-area", "cv2-cached"],
}
WARM_RUNS = 5
#: fresh processes per engine and case; the table shows each figure's median.
PROCESSES = 5


def _source(src: str, size: int):
    import numpy as np

    from bakeshop.sphere import layout

    rng = np.random.default_rng(0)
    shape = layout(src).shape(size)
    return rng.random(shape + (3,), dtype=np.float32)


def _cv2_converter(src: str, src_shape, dst: str, dst_size: int):
    """A plain converter: float32 maps of the destination texels into the source, built once
    (bakeshop's layout maps give the coordinates), then cv2.remap. A cube source is sampled as
    a horizontal strip of its faces (no filtering across face edges: what a simple converter
    does)."""
    import cv2
    import numpy as np

    from bakeshop.sphere import cube_to_view, layout

    s, d = layout(src), layout(dst)
    dirs, _ = d.base.directions(d.base.shape(dst_size))
    c = s.coordinates(dirs, src_shape)
    if s.cubic:
        f, x, y = c[..., 0], c[..., 1], c[..., 2]
        x = x + f * src_shape[2]
    else:
        x, y = c[..., 0], c[..., 1]
    # cv2 puts texel centres at integers
    mx = (x - 0.5).astype(np.float32).reshape(-1, x.shape[-1])
    my = (y - 0.5).astype(np.float32).reshape(-1, x.shape[-1])
    if d.base is not d:
        mx = cube_to_view(mx.reshape(dirs.shape[:-1]), dst, fill=-1).astype(np.float32)
        my = cube_to_view(my.reshape(dirs.shape[:-1]), dst, fill=-1).astype(np.float32)

    def run(image):
        flat = image.transpose(1, 0, 2, 3).reshape(image.shape[1], -1, 3) if s.cubic else image
        return cv2.remap(flat, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP)

    return run


def _make(engine: str, src: str, src_shape, dst: str, dst_size: int):
    """A function image -> output that builds its geometry on its first call."""
    if engine.startswith("bakeshop"):
        from bakeshop.sphere import remap

        filt = "area" if engine == "bakeshop-area" else "bilinear"
        return lambda image: remap(image, src, dst, dst_size, filter=filt)
    if engine.startswith("py360"):
        import py360convert
        import py360convert.utils

        if engine == "py360-scipy":
            py360convert.utils.cv2 = None
        if src == "latlong":
            return lambda image: py360convert.e2c(image, face_w=dst_size, cube_format="list")
        return lambda image: py360convert.c2e(
            list(image), h=dst_size, w=2 * dst_size, cube_format="list"
        )
    state = {}

    def cached_cv2(image):
        if "run" not in state:
            state["run"] = _cv2_converter(src, image.shape[:-1], dst, dst_size)
        return state["run"](image)

    return cached_cv2


def _child(case: str, engine: str, scale: int) -> dict:
    import resource

    _, src, ssize, dst, dsize = next(c for c in CASES if c[0] == case)
    ssize, dsize = ssize // scale, dsize // scale
    image = _source(src, ssize)
    if engine.startswith("bakeshop"):
        # load the compiled kernels outside the clock (an import, not the geometry)
        from bakeshop.sphere import remap

        small = _source(src, 8)
        remap(small, src, dst, 4, filter="area" if engine == "bakeshop-area" else "bilinear")
    fn = _make(engine, src, image.shape[:-1], dst, dsize)
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t, c = time.perf_counter(), time.process_time()
    fn(image)
    cold, cold_cpu = time.perf_counter() - t, time.process_time() - c
    warm = []
    for _ in range(WARM_RUNS):
        t, c = time.perf_counter(), time.process_time()
        fn(image)
        warm.append((time.perf_counter() - t, time.process_time() - c))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base
    w, w_cpu = sorted(warm)[len(warm) // 2]
    return {
        "cold": cold,
        "cold_cpu": cold_cpu,
        "warm": w,
        "warm_cpu": w_cpu,
        "peak_mib": peak / 1024,
    }


def _run(case: str, engine: str, scale: int) -> dict:
    """Median of each figure over PROCESSES fresh processes (a shared machine's noise)."""
    runs = []
    for _ in range(PROCESSES):
        out = subprocess.run(
            [sys.executable, __file__, "--child", case, engine, str(scale)],
            capture_output=True,
            text=True,
            check=True,
        )
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    return {k: sorted(r[k] for r in runs)[len(runs) // 2] for k in runs[0]}


def _scaling(scale: int) -> list[tuple[int, dict]]:
    rows = []
    for face in (256, 512, 1024):
        face //= scale
        out = subprocess.run(
            [sys.executable, __file__, "--scaling", str(face)],
            capture_output=True,
            text=True,
            check=True,
        )
        rows.append((face, json.loads(out.stdout.strip().splitlines()[-1])))
    return rows


def _scaling_child(face: int) -> dict:
    import resource

    from bakeshop.sphere import remap

    image = _source("latlong", 2048)
    remap(_source("latlong", 8), "latlong", "cube", 4)
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t = time.perf_counter()
    remap(image, "latlong", "cube", face)
    cold = time.perf_counter() - t
    t = time.perf_counter()
    remap(image, "latlong", "cube", face)
    warm = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base
    return {"cold": cold, "warm": warm, "peak_mib": peak / 1024}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a quarter of each edge")
    parser.add_argument("--child", nargs=3, metavar=("CASE", "ENGINE", "SCALE"), help="internal")
    parser.add_argument("--scaling", type=int, help="internal")
    args = parser.parse_args()
    if args.child:
        case, engine, scale = args.child
        print(json.dumps(_child(case, engine, int(scale))))
        return
    if args.scaling:
        print(json.dumps(_scaling_child(args.scaling)))
        return
    scale = 4 if args.quick else 1
    found = peers.Peers(["py360convert", "opencv"])
    needs = {"py360-cv2": ("py360convert", "opencv"), "py360-scipy": ("py360convert",),
             "cv2-cached": ("opencv",)}  # fmt: skip
    import platform

    cpu = next(
        (line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if "model name" in line),
        platform.processor(),
    )
    print(
        f"machine: {cpu}; float32 RGB; warm = median of {WARM_RUNS} calls; "
        f"each figure the median of {PROCESSES} processes"
    )
    for case, src, ssize, dst, dsize in CASES:
        ssize, dsize = ssize // scale, dsize // scale
        print(f"\n{case}: {src} {ssize} -> {dst} {dsize}")
        print(
            "| engine | cold s | cold CPU s | warm s | warm CPU s | peak MiB | warm / cv2-cached "
            "| warm / bakeshop |"
        )
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        engines = [e for e in ENGINES[case] if all(map(found.present, needs.get(e, ())))]
        results = {e: _run(case, e, scale) for e in engines}
        for e in engines:
            for peer in needs.get(e, ()):
                found.measured(peer, f"{case} {e}")
        ref_cv2 = results["cv2-cached"]["warm"] if "cv2-cached" in results else float("nan")
        ref_b = results["bakeshop"]["warm"]
        for e, r in results.items():
            print(
                f"| {e} | {r['cold']:.3f} | {r['cold_cpu']:.3f} | {r['warm']:.3f} | "
                f"{r['warm_cpu']:.3f} | {r['peak_mib']:.0f} | {r['warm'] / ref_cv2:.2f} | "
                f"{r['warm'] / ref_b:.2f} |"
            )
    print("\nscaling, latlong 4096x2048 -> cube, bilinear:")
    print("| face | output Mtexels | cold s | warm s | peak MiB |")
    print("|---:|---:|---:|---:|---:|")
    for face, r in _scaling(scale):
        mtex = 6 * face * face / 1e6
        print(f"| {face} | {mtex:.2f} | {r['cold']:.3f} | {r['warm']:.3f} | {r['peak_mib']:.0f} |")
    found.finish()


if __name__ == "__main__":
    main()
