"""Images larger than memory: chunked resize, remap and DIM pair against pyvips and a plain
numpy strip reader, each job in its own process so that its peak memory (ru_maxrss) is its own.

    python benchmarks/bench_huge.py                 # 16384 x 8192 float RGB (1.6 GB)
    python benchmarks/bench_huge.py --width 32768   # 32768 x 16384 (6.4 GB): the issue's size
    python benchmarks/bench_huge.py --width 8192 --memory 512MB

Jobs: resize by 8 (bakeshop from PFM and zarr; pyvips from a float TIFF, its wheel reads no
PFM/Radiance/EXR; numpy reading 256-row strips with pread and averaging 8x8 blocks: the
physical limit, one pass over the bytes); remap to a latlong of 1/8 the width and to 6 cube
faces of 1/16 the width; the DIM pair (method auto). Times are wall seconds of the job alone
(the file is written first; the page cache is dropped for the file before each job with
posix_fadvise, so every job reads from disk as the first would).
"""

from __future__ import annotations

import argparse
import json
import os
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
    fd = os.open(path, os.O_RDONLY) if os.path.isfile(path) else None
    if fd is not None:
        os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED); os.close(fd)
    started = time.perf_counter()
    if job.startswith("bakeshop"):
        from bakeshop.huge import Engine, dim_pair, remap, resize
        engine = Engine("threads", memory=memory)
        if job.endswith("resize"):
            out = resize(path, (width // 8, width // 16), engine=engine)
        elif job.endswith("remap-latlong"):
            out = remap(path, "latlong", "latlong", (width // 8, width // 16), filter="area",
                        engine=engine)
        elif job.endswith("remap-cube"):
            out = remap(path, "latlong", "cube", width // 16, filter="area", engine=engine)
        elif job.endswith("dims"):
            out = dim_pair(path, "latlong", engine=engine).sun_dim
    elif job == "pyvips-resize":
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
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(json.dumps({"seconds": seconds, "peak": peak, "mean": float(np.mean(out))}))
    """
)


def run(job: str, path: Path, width: int, memory: str) -> dict:
    result = subprocess.run([sys.executable, "-c", _JOB, job, str(path), str(width), memory],
                            capture_output=True, text=True, cwd=ROOT)  # fmt: skip
    if result.returncode:
        return {"error": result.stderr.strip().splitlines()[-1]}
    return json.loads(result.stdout.strip().splitlines()[-1])


def make_inputs(folder: Path, width: int) -> dict[str, Path]:
    """A latlong sky with a small sun, written by strips as PFM, then converted to zarr and a
    float TIFF (pyvips' input)."""
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
    write_strips(paths["pfm"], (h, width, 3), strips())
    reader = open_image(paths["pfm"])
    for key in ("zarr", "tif"):
        write_strips(paths[key], reader.shape,
                     (reader.read((t, min(t + rows, h))) for t in range(0, h, rows)))  # fmt: skip
    return paths


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width", type=int, default=16384)
    parser.add_argument("--memory", default="2GB")
    parser.add_argument("--dir", default=None, help="where the inputs are written")
    args = parser.parse_args()
    found = peers.Peers(["pyvips"])
    folder = Path(args.dir or tempfile.mkdtemp(prefix="bench_huge_"))
    w = args.width
    print(f"machine: {os.cpu_count()} cores; image {w}x{w // 2} float RGB "
          f"({w * w // 2 * 12 / 1e9:.2f} GB); --memory {args.memory}")  # fmt: skip
    started = time.perf_counter()
    paths = make_inputs(folder, w)
    print(f"inputs written in {time.perf_counter() - started:.0f} s to {folder}")
    jobs = [
        ("numpy-strips", "pfm"),
        ("bakeshop-resize", "pfm"),
        ("bakeshop-resize", "zarr"),
        ("pyvips-resize", "tif"),
        ("bakeshop-remap-latlong", "pfm"),
        ("bakeshop-remap-cube", "pfm"),
        ("bakeshop-dims", "pfm"),
    ]
    results = {}
    print(f"{'job':<26}{'input':<7}{'seconds':>9}{'peak MB':>10}{'GB/s':>7}")
    size = w * (w // 2) * 12
    for job, kind in jobs:
        if job.startswith("pyvips") and not found.present("pyvips"):
            continue
        r = run(job, paths[kind], w, args.memory)
        results[(job, kind)] = r
        if "error" in r:
            print(f"{job:<26}{kind:<7}  {r['error']}")
            continue
        if job.startswith("pyvips"):
            found.measured("pyvips", "resize")
        print(f"{job:<26}{kind:<7}{r['seconds']:9.1f}{r['peak'] / 1e6:10.0f}"
              f"{size / r['seconds'] / 1e9:7.2f}")  # fmt: skip
    base = results[("numpy-strips", "pfm")]
    ours = results[("bakeshop-resize", "pfm")]
    vips = results.get(("pyvips-resize", "tif"), {"error": "not measured"})
    if all("error" not in r for r in (base, ours, vips)):
        print(f"resize: bakeshop / one pass of numpy pread {ours['seconds'] / base['seconds']:.2f}x"
              f", bakeshop / pyvips {ours['seconds'] / vips['seconds']:.2f}x time, "
              f"{ours['peak'] / vips['peak']:.2f}x peak")  # fmt: skip
    found.finish()


if __name__ == "__main__":
    main()
