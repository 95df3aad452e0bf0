"""Images larger than memory: chunked resize, remap and DIM pair against pyvips and a plain
numpy strip reader, each job in its own process so that its peak memory is its own.

    python benchmarks/bench_huge.py                 # 16384 x 8192 float RGB (1.6 GB)
    python benchmarks/bench_huge.py --width 32768 --memory 1GB \\
        --jobs numpy-strips,resize,remap-latlong,remap-cube,dims   # 6.4 GB: the issue's size
    python benchmarks/bench_huge.py --jobs numpy-strips,resize,pyvips,cluster-1,cluster-2

Jobs (``--jobs``, default all): ``numpy-strips`` (256-row strips read with ``preadv`` and
averaged 8x8: one pass over the bytes, the physical limit); ``resize`` by 8 (bakeshop from PFM;
``resize-zarr`` from zarr); ``pyvips`` ``shrink(8, 8)`` from a float TIFF (its wheel reads no
PFM/Radiance/EXR); ``remap-latlong`` to 1/8 the width and ``remap-cube`` to 6 faces of 1/16 the
width (area filter); ``dims`` the DIM pair (method auto); ``cluster-N`` the resize on a
dask.distributed LocalCluster of N single-threaded worker processes started by the job (the
cluster's start is not timed). Only the inputs the jobs need are written, and deleted at the
end unless ``--keep``.

Per job: wall seconds, CPU seconds (user + system of every thread, and of the cluster's
workers: steadier than wall time on a shared machine), peak memory (VmHWM of the process, reset
when it starts: a forked child inherits its parent's; ru_maxrss of the largest worker on a
cluster), the load average before and after, and the ratios to
the numpy pass. The page cache is dropped for the input before each job (posix_fadvise), so
every job reads from disk as the first would.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np
import peers

ROOT = Path(__file__).resolve().parents[1]

_JOB = textwrap.dedent(
    """
    import json, os, resource, sys, time
    import numpy as np
    job, path, width, memory = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]

    def cpu(who=resource.RUSAGE_SELF):
        r = resource.getrusage(who)
        return r.ru_utime + r.ru_stime

    def drop(path):
        for root, _, files in os.walk(path) if os.path.isdir(path) else [("", [], [path])]:
            for name in files:
                fd = os.open(os.path.join(root, name), os.O_RDONLY)
                os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
                os.close(fd)

    def peak():
        with open("/proc/self/status") as f:
            return next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmHWM:"))

    # the high-water mark starts again from this process's own memory (a child inherits its
    # parent's at fork, and ru_maxrss with it)
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
    extra = {}
    if job.startswith("cluster-"):
        import distributed
        n = int(job.split("-")[1])
        cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                           dashboard_address=None, memory_limit=0)
        client = distributed.Client(cluster)
        def usage():
            r = resource.getrusage(resource.RUSAGE_SELF)
            return r.ru_utime + r.ru_stime, r.ru_maxrss * 1024
        from bakeshop.huge import Engine
        client.run(lambda: __import__("bakeshop.huge"))  # workers import before the clock
        before = client.run(usage)
    drop(path)
    started, started_cpu = time.perf_counter(), cpu()
    if job in ("resize", "resize-zarr", "remap-latlong", "remap-cube", "dims"):
        from bakeshop.huge import Engine, dim_pair, remap, resize
        engine = Engine("threads", memory=memory)
        if job.startswith("resize"):
            out = resize(path, (width // 8, width // 16), engine=engine)
        elif job == "remap-latlong":
            out = remap(path, "latlong", "latlong", (width // 8, width // 16), filter="area",
                        engine=engine)
        elif job == "remap-cube":
            out = remap(path, "latlong", "cube", width // 16, filter="area", engine=engine)
        else:
            out = dim_pair(path, "latlong", engine=engine).sun_dim
    elif job.startswith("cluster-"):
        from bakeshop.huge import resize
        out = resize(path, (width // 8, width // 16), engine=Engine(client, memory=memory))
    elif job == "pyvips":
        import pyvips
        out = pyvips.Image.new_from_file(path, access="sequential").shrink(8, 8).numpy()
    elif job == "numpy-strips":
        from bakeshop.io.stream import open_image
        r = open_image(path)
        h, w, c = r.shape
        fd = os.open(path, os.O_RDONLY)
        out = np.empty((h // 8, w // 8, c), np.float32)
        rows = 256
        buf = np.empty(rows * w * c, np.float32)
        for top in range(0, h, rows):
            os.preadv(fd, [memoryview(buf).cast("B")], r.offset + top * w * c * 4)
            block = buf.reshape(rows, w, c)
            small = block.reshape(rows // 8, 8, w // 8, 8, c).mean((1, 3))
            out[top // 8 : (top + rows) // 8] = small
        os.close(fd)
    seconds = time.perf_counter() - started
    used = cpu() - started_cpu
    if job.startswith("cluster-"):
        after = client.run(usage)
        used += sum(after[k][0] - before[k][0] for k in after)
        extra["worker_peak"] = max(a[1] for a in after.values())
        client.close()
        cluster.close()
    print(json.dumps({"seconds": seconds, "cpu": used, "peak": peak(),
                      "mean": float(np.mean(out)), **extra}))
    """
)

#: job -> the input it reads.
JOBS = {
    "numpy-strips": "pfm",
    "resize": "pfm",
    "resize-zarr": "zarr",
    "pyvips": "tif",
    "remap-latlong": "pfm",
    "remap-cube": "pfm",
    "dims": "pfm",
    "cluster-1": "pfm",
    "cluster-2": "pfm",
}


def run(job: str, path: Path, width: int, memory: str) -> dict:
    load = os.getloadavg()[0]
    result = subprocess.run([sys.executable, "-c", _JOB, job, str(path), str(width), memory],
                            capture_output=True, text=True, cwd=ROOT)  # fmt: skip
    if result.returncode:
        return {"error": result.stderr.strip().splitlines()[-1]}
    out = json.loads(result.stdout.strip().splitlines()[-1])
    out["load"] = (load, os.getloadavg()[0])
    return out


def _present(path: Path, shape) -> bool:
    """True when ``path`` holds an image of ``shape`` (kept from an earlier run with --keep)."""
    from bakeshop.io.stream import open_image

    try:
        return path.exists() and tuple(open_image(path).shape) == tuple(shape)
    except Exception:
        return False


def make_inputs(folder: Path, width: int, kinds: set[str]) -> dict[str, Path]:
    """A latlong sky with a small sun, written by strips as PFM, then converted to zarr and a
    float TIFF (pyvips' input) when ``kinds`` asks for them."""
    from bakeshop.io.stream import open_image, write_strips

    h = width // 2
    rows = 512
    y = np.arange(rows)[:, None]
    x = np.arange(width)[None, :]

    def strips():
        for top in range(0, h, rows):
            sky = 1 + 0.5 * np.sin((x + 0.0) / 97.0) * np.cos((y + top) / 53.0)
            block = np.repeat(sky[:, :, None], 3, axis=2).astype(np.float32)
            if top <= h // 5 < top + rows:
                block[h // 5 - top, width // 3 : width // 3 + 2] = 50000.0
            yield block

    paths = {"pfm": folder / "pano.pfm", "zarr": folder / "pano.zarr", "tif": folder / "pano.tif"}
    if not _present(paths["pfm"], (h, width, 3)):
        write_strips(paths["pfm"], (h, width, 3), strips())
    reader = open_image(paths["pfm"])
    for key in sorted(k for k in kinds - {"pfm"} if not _present(paths[k], reader.shape)):
        write_strips(paths[key], reader.shape,
                     (reader.read((t, min(t + rows, h))) for t in range(0, h, rows)))  # fmt: skip
    return paths


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width", type=int, default=16384)
    parser.add_argument("--memory", default="2GB")
    parser.add_argument(
        "--jobs", default=",".join(JOBS), help="comma-separated, of: " + ", ".join(JOBS)
    )
    parser.add_argument(
        "--dir", default=None, help="where the inputs are written (those already there are used)"
    )
    parser.add_argument("--keep", action="store_true", help="keep the inputs")
    args = parser.parse_args()
    jobs = args.jobs.split(",")
    unknown = [j for j in jobs if j not in JOBS]
    if unknown:
        parser.error(f"unknown jobs {unknown}")
    found = peers.Peers(["pyvips"] if "pyvips" in jobs else [])
    jobs = [j for j in jobs if j != "pyvips" or found.present("pyvips")]
    folder = Path(args.dir) if args.dir else Path(tempfile.mkdtemp(prefix="bench_huge_"))
    folder.mkdir(parents=True, exist_ok=True)
    w = args.width
    size = w * (w // 2) * 12
    print(f"machine: {peers.machine()}; image {w}x{w // 2} float RGB ({size / 1e9:.2f} GB); "
          f"--memory {args.memory}")  # fmt: skip
    try:
        started = time.perf_counter()
        paths = make_inputs(folder, w, {JOBS[j] for j in jobs})
        print(f"inputs written in {time.perf_counter() - started:.0f} s to {folder}")
        results = {}
        print(f"{'job':<15}{'input':<7}{'seconds':>9}{'cpu s':>8}{'peak MB':>9}{'GB/s':>7}"
              f"{'vs numpy':>10}{'(cpu)':>7}  load")  # fmt: skip
        for job in jobs:
            r = run(job, paths[JOBS[job]], w, args.memory)
            results[job] = r
            if "error" in r:
                print(f"{job:<15}{JOBS[job]:<7}  {r['error']}")
                continue
            if job == "pyvips":
                found.measured("pyvips", "resize")
            base = results.get("numpy-strips", {})
            ratio = cpu = ""
            if "seconds" in base:
                ratio = f"{r['seconds'] / base['seconds']:.2f}x"
                cpu = f"{r['cpu'] / base['cpu']:.2f}x"
            workers = ""
            if "worker_peak" in r:
                workers = f"  largest worker's peak {r['worker_peak'] / 1e6:.0f} MB"
            print(f"{job:<15}{JOBS[job]:<7}{r['seconds']:9.1f}{r['cpu']:8.1f}"
                  f"{r['peak'] / 1e6:9.0f}{size / r['seconds'] / 1e9:7.3f}{ratio:>10}{cpu:>7}  "
                  f"{r['load'][0]:.1f} -> {r['load'][1]:.1f}{workers}")  # fmt: skip
        ours, vips = results.get("resize", {}), results.get("pyvips", {})
        if "seconds" in ours and "seconds" in vips:
            print(
                f"resize: bakeshop / pyvips {ours['seconds'] / vips['seconds']:.2f}x time, "
                f"{ours['cpu'] / vips['cpu']:.2f}x cpu, {ours['peak'] / vips['peak']:.2f}x peak"
            )
        print(json.dumps(results))
    finally:
        if args.keep:
            print(f"inputs kept in {folder}")
        else:
            shutil.rmtree(folder)
    found.finish()


if __name__ == "__main__":
    main()
