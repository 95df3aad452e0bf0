"""Benchmark: normal-map blending at 4096x4096 and transfer onto a 2048x2048 UV layout.

Each job runs in a fresh subprocess (one warm-up run first), timed as the best of a few runs;
peak memory is the peak of the arrays allocated during one run (the output included, the
inputs not), measured with tracemalloc, reported as a multiple of the output's size; "with
inputs" adds the inputs the job needs in memory.

Peers: the same formulas written as plain numpy array expressions (what a Python pipeline
would do), timed in the same run. No open implementation of the transfer exists among the
installed packages (xNormal, Substance and Marmoset are closed tools), so it is timed alone,
with the share of each stage.

Run: .venv/bin/python benchmarks/bench_normals.py [--size 4096] [--transfer-size 2048]
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import time
import tracemalloc

import numpy as np


def _measure(fn, repeats=3):
    """Best time of ``repeats`` runs after a warm-up, and the peak of numpy allocations of one
    more run (tracemalloc sees every numpy array; the compiled kernels' own small buffers are not
    counted)."""
    fn()  # warm-up: loading the compiled kernels, first-touch page faults
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return best, peak


def _random_normals(n, seed, spread=0.4):
    rng = np.random.default_rng(seed)
    a = np.empty((n, n, 3), np.float32)
    a[..., :2] = rng.normal(scale=spread, size=(n, n, 2))
    a[..., 2] = 1
    a /= np.linalg.norm(a, axis=2, keepdims=True)
    return a


def _numpy_exact(m, d):
    k = d[..., 2] - d[..., 0] * m[..., 0] - d[..., 1] * m[..., 1]
    r = k[..., None] * m
    r[..., :2] += d[..., :2]
    return r / np.linalg.norm(r, axis=-1, keepdims=True)


def _numpy_rnm(m, d):
    t = m + np.array([0, 0, 1], np.float32)
    u = d * np.array([-1, -1, 1], np.float32)
    r = t * (np.sum(t * u, axis=-1, keepdims=True) / t[..., 2:]) - u
    return r / np.linalg.norm(r, axis=-1, keepdims=True)


def torus(segments=100, rings=50, radius=1.0, tube=0.35):
    """A torus of 2 * segments * rings triangles, one UV island inset in [0.02, 0.98]^2."""
    from bakeshop.normals.transfer import UVMesh

    i, j = np.meshgrid(np.arange(segments + 1), np.arange(rings + 1), indexing="ij")
    a, b = 2 * np.pi * i / segments, 2 * np.pi * j / rings
    centre = np.stack([np.cos(a), np.zeros_like(a), -np.sin(a)], -1)
    normal = np.cos(b)[..., None] * centre + np.sin(b)[..., None] * np.array([0, 1.0, 0])
    pos = radius * centre + tube * normal
    uv = 0.02 + 0.96 * np.stack([i / segments, j / rings], -1)
    idx = np.arange((segments + 1) * (rings + 1)).reshape(segments + 1, rings + 1)
    q = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], -1).reshape(-1, 4)
    faces = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])

    def flat(x):
        return x.reshape(-1, x.shape[-1])

    uv = flat(uv)
    return UVMesh(flat(pos), faces, flat(normal), uv, uv * (8, 4))


def job_blend(kind: str, size: int) -> dict:
    from bakeshop.normals.blend import blend

    m, d = _random_normals(size, 1), _random_normals(size, 2)
    fn = {
        "bakeshop exact": lambda: blend(m, d, method="exact"),
        "bakeshop rnm": lambda: blend(m, d, method="rnm"),
        "numpy exact": lambda: _numpy_exact(m, d),
        "numpy rnm": lambda: _numpy_rnm(m, d),
    }[kind]
    seconds, peak = _measure(fn)
    return {"seconds": seconds, "peak_bytes": peak, "output_bytes": m.nbytes}


def job_transfer(kind: str, size: int) -> dict:
    from bakeshop.normals import transfer as tr

    mesh = torus()
    detail = _random_normals(1024, 3, 0.3)
    projection = kind.split()[-1]
    stages = {}
    if kind.startswith("stage"):
        fns = {
            "tangents": lambda: tr.corner_tangents(
                mesh.positions, mesh.normals, mesh.uv, mesh.faces
            ),
            "rasterise": lambda: tr.rasterize_uv(mesh.uv, mesh.faces, (size, size)),
        }
        for name, fn in fns.items():
            stages[name] = _measure(fn, repeats=2)[0]
        face, _ = tr.rasterize_uv(mesh.uv, mesh.faces, (size, size))
        stages["dilate"] = _measure(
            lambda: tr.dilate(np.zeros((size, size, 3), np.float32), face >= 0), repeats=2
        )[0]
        return {"stages": stages, "triangles": len(mesh.faces)}
    seconds, peak = _measure(
        lambda: tr.transfer_detail(mesh, detail, (size, size), projection=projection, tile=6),
        repeats=2,
    )
    return {
        "seconds": seconds,
        "peak_bytes": peak,
        "output_bytes": size * size * 3 * 4,
        "triangles": len(mesh.faces),
    }


def _run(job: str, kind: str, size: int) -> dict:
    out = subprocess.run(
        [sys.executable, __file__, "--job", job, "--kind", kind, "--size", str(size)],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def _cpu() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--size", type=int, default=4096)
    p.add_argument("--transfer-size", type=int, default=2048)
    p.add_argument("--job")
    p.add_argument("--kind")
    args = p.parse_args()
    if args.job:
        result = (job_blend if args.job == "blend" else job_transfer)(args.kind, args.size)
        print(json.dumps(result))
        return
    import os

    print(f"machine: {_cpu()}, {os.cpu_count()} cores; numpy {np.__version__}")
    n = args.size
    print(f"\nblend two {n}x{n} float32 normal maps (output {n * n * 12 / 2**20:.0f} MiB)")
    print(f"{'implementation':<16}{'seconds':>9}{'vs bakeshop':>13}{'peak / output':>15}")
    rows = {
        k: _run("blend", k, n)
        for k in ("bakeshop exact", "numpy exact", "bakeshop rnm", "numpy rnm")
    }
    for k, r in rows.items():
        ref = rows["bakeshop " + k.split()[1]]["seconds"]
        print(
            f"{k:<16}{r['seconds']:>9.3f}{r['seconds'] / ref:>12.1f}x"
            f"{r['peak_bytes'] / r['output_bytes']:>14.2f}x"
        )
    s = args.transfer_size
    print(f"\ntransfer a 1024x1024 detail onto a {s}x{s} layout (torus, one UV island)")
    print(f"{'projection':<16}{'seconds':>9}{'triangles':>11}{'peak / output':>15}")
    for kind in ("uv2", "planar", "box", "triplanar"):
        r = _run("transfer", kind, s)
        print(
            f"{kind:<16}{r['seconds']:>9.3f}{r['triangles']:>11}"
            f"{r['peak_bytes'] / r['output_bytes']:>14.2f}x"
        )
    r = _run("transfer", "stage", s)
    print("stages: " + ", ".join(f"{k} {v:.3f} s" for k, v in r["stages"].items()))


if __name__ == "__main__":
    main()
