"""Time reading and writing a 4096x2048 RGB image: bakeshop.io vs OpenCV and OpenImageIO.

Formats: PFM (float32), Radiance .hdr (new-style RLE), OpenEXR (half, ZIP: bakeshop's default,
asked of the peers explicitly) and an 8-bit TGA (OpenCV has no TGA codec: Pillow stands in).
Contents: "smooth" (slow sinusoids, runs compress well) and "noisy" (log-normal noise, nothing
compresses). All readers read the same files, written by bakeshop.

Every measurement runs in a fresh subprocess and peak memory is the process's resident
high-water mark (``VmHWM``, reset just before the operation through ``/proc/self/clear_refs``; it
counts the C++ libraries' allocations that tracemalloc cannot see) minus the resident size just
before: the extra memory the operation needed, including the array a read returns. Pages of a
memory-mapped file count once touched. Times are the best of 3 after one warm-up run (imports,
first-touch page faults); "cpu" is the process's CPU time for the same run (all its threads),
which is steadier than wall time on a shared machine.

For PFM, bakeshop reads into memory (a memory map of a file that another program truncates kills
the process with SIGBUS): "memmap" is the map-based read it replaced, a ``numpy.memmap`` of the
file copied out flipped into private memory, what that read cost once every pixel was touched
(an open alone cost nothing). For TGA, bakeshop reads to and writes from float32 in [0, 1] (its
API), the peers uint8.

Run: ``.venv/bin/python benchmarks/bench_codecs.py`` (about two minutes); ``BENCH_FORMATS=pfm,exr``
runs some formats only.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import peers

HEIGHT, WIDTH = 2048, 4096
REPEATS = 3
FORMATS = {"pfm": ".pfm", "hdr": ".hdr", "exr": ".exr", "tga": ".tga"}
TOOLS = {
    "pfm": ["bakeshop", "opencv", "oiio"],
    "hdr": ["bakeshop", "opencv", "oiio"],
    "exr": ["bakeshop", "oiio"],  # the opencv-python wheels are built without OpenEXR
    "tga": ["bakeshop", "pillow", "oiio"],
}


def content(kind: str) -> np.ndarray:
    """The test image: float32 (H, W, 3); values in [0, 1] for TGA is the caller's clip."""
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float32)
    if kind == "smooth":
        image = np.stack(
            [np.sin(x / 700) + 1.5, np.cos(y / 300) + 1.2, (x + y) / 6000 + 0.1], axis=-1
        )
        return (image * 0.4).astype(np.float32)
    rng = np.random.default_rng(0)
    return rng.lognormal(-1.0, 1.0, (HEIGHT, WIDTH, 3)).astype(np.float32)


def as_ldr(image: np.ndarray) -> np.ndarray:
    return np.round(np.clip(image, 0, 1) * 255).astype(np.uint8)


# --- the operations, run inside a child process --------------------------------------------------


def reader(tool: str, fmt: str):
    if tool == "bakeshop":
        from bakeshop.io import read_image

        return lambda path: read_image(path)
    if tool == "memmap":
        from bakeshop.io import pfm

        def read(path):
            h = pfm._header(path, pfm.MAX_PIXELS)
            shape = (h["height"], h["width"], h["channels"])
            mapped = np.memmap(path, h["byteorder"] + "f4", "c", h["offset"], shape)
            return np.array(mapped[::-1])

        return read
    if tool == "opencv":
        import cv2

        return lambda path: cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if tool == "oiio":
        import OpenImageIO as oiio

        def read(path):
            inp = oiio.ImageInput.open(str(path))
            pixels = inp.read_image("uint8" if fmt == "tga" else "float")
            inp.close()
            return pixels

        return read
    if tool == "pillow":
        from PIL import Image

        return lambda path: np.asarray(Image.open(path))
    raise ValueError(tool)


def writer(tool: str, fmt: str):
    if tool == "bakeshop":
        from bakeshop.io import write_image

        return lambda path, image: write_image(path, image)
    if tool == "opencv":
        import cv2

        params = []
        if fmt == "exr":
            params = [
                cv2.IMWRITE_EXR_TYPE,
                cv2.IMWRITE_EXR_TYPE_HALF,
                cv2.IMWRITE_EXR_COMPRESSION,
                cv2.IMWRITE_EXR_COMPRESSION_ZIP,
            ]
        return lambda path, image: cv2.imwrite(str(path), image, params)
    if tool == "oiio":
        import OpenImageIO as oiio

        def write(path, image):
            pixel = "half" if fmt == "exr" else ("uint8" if image.dtype == np.uint8 else "float")
            spec = oiio.ImageSpec(WIDTH, HEIGHT, 3, pixel)
            if fmt == "exr":
                spec.attribute("compression", "zip")
            out = oiio.ImageOutput.create(str(path))
            out.open(str(path), spec)
            out.write_image(image)
            out.close()

        return write
    if tool == "pillow":
        from PIL import Image

        return lambda path, image: Image.fromarray(image).save(path)
    raise ValueError(tool)


def memory(field: str) -> int:
    """``VmRSS`` (resident now) or ``VmHWM`` (its high-water mark) of this process, in bytes."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    raise RuntimeError(field)


def reset_peak() -> None:
    """Restart the high-water mark at the current resident size (Linux >= 4.0)."""
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")


def child(tool: str, fmt: str, op: str, kind: str, workdir: Path) -> dict:
    source = workdir / f"{kind}{FORMATS[fmt]}"
    if op == "read":
        function = reader(tool, fmt)
        args = (source,)
    else:
        # Each tool gets its natural input, prepared before measuring: bakeshop float32 (values
        # in [0, 1] for TGA, which it quantises), the peers uint8 for TGA and BGR for OpenCV.
        ldr = fmt == "tga" and tool != "bakeshop"
        image = np.load(workdir / f"{kind}.{'u8' if ldr else 'f32'}.npy")
        if fmt == "tga" and tool == "bakeshop":
            image = np.clip(image, 0, 1)
        if tool == "opencv":
            image = np.ascontiguousarray(image[..., ::-1])
        function = writer(tool, fmt)
        args = (workdir / f"out_{tool}{FORMATS[fmt]}", image)
    function(*args)  # warm-up
    before = memory("VmRSS")
    reset_peak()
    result = function(*args)
    peak = memory("VmHWM") - before
    del result
    best = cpu = float("inf")
    for _ in range(REPEATS):
        start, start_cpu = time.perf_counter(), time.process_time()
        result = function(*args)
        best = min(best, time.perf_counter() - start)
        cpu = min(cpu, time.process_time() - start_cpu)
        del result
    return {"seconds": best, "cpu": cpu, "peak": max(peak, 0)}


# --- the parent: prepare files, run the children, print the table -------------------------------


def prepare(workdir: Path) -> None:
    from bakeshop.io import write_image

    for kind in ("smooth", "noisy"):
        image = content(kind)
        np.save(workdir / f"{kind}.f32.npy", image)
        np.save(workdir / f"{kind}.u8.npy", as_ldr(image))
        for fmt, ext in FORMATS.items():
            write_image(workdir / f"{kind}{ext}", np.clip(image, 0, 1) if fmt == "tga" else image)


def run(tool, fmt, op, kind, workdir) -> dict:
    env = dict(os.environ, OPENCV_IO_ENABLE_OPENEXR="1")
    out = subprocess.run(
        [sys.executable, __file__, "--child", tool, fmt, op, kind, str(workdir)],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


#: tool -> the peer it is (see peers.py).
PEER_OF = {"opencv": "opencv", "oiio": "oiio", "pillow": "pillow"}


def main() -> None:
    found = peers.Peers(["opencv", "oiio", "pillow"])
    decoded = HEIGHT * WIDTH * 3 * 4
    print(f"machine: {peers.machine()}")
    with tempfile.TemporaryDirectory(dir=os.environ.get("BENCH_TMP")) as d:
        workdir = Path(d)
        prepare(workdir)
        print(f"{WIDTH}x{HEIGHT} RGB; decoded float32 image {decoded / 2**20:.0f} MiB")
        print(
            f"{'format':6} {'content':7} {'op':5} {'tool':14} {'seconds':>8} {'cpu':>6} "
            f"{'x bakeshop':>10} {'peak MiB':>9} {'peak/img':>8} {'file MiB':>8}"
        )
        for fmt in os.environ.get("BENCH_FORMATS", ",".join(FORMATS)).split(","):
            for kind in ("smooth", "noisy"):
                size = (workdir / f"{kind}{FORMATS[fmt]}").stat().st_size / 2**20
                for op in ("read", "write"):
                    base = None
                    tools = [t for t in TOOLS[fmt] if t not in PEER_OF or found.present(t)]
                    if fmt == "pfm" and op == "read":
                        tools = ["bakeshop", "memmap", *tools[1:]]
                    for tool in tools:
                        r = run(tool, fmt, op, kind, workdir)
                        base = base or r["seconds"]
                        if tool in PEER_OF:
                            found.measured(PEER_OF[tool], f"{fmt} {op}")
                        print(
                            f"{fmt:6} {kind:7} {op:5} {tool:14} {r['seconds']:8.3f} "
                            f"{r['cpu']:6.3f} {r['seconds'] / base:10.2f} {r['peak'] / 2**20:9.0f} "
                            f"{r['peak'] / decoded:8.2f} {size:8.1f}",
                            flush=True,
                        )
    found.finish()


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        tool, fmt, op, kind, workdir = sys.argv[2:7]
        print(json.dumps(child(tool, fmt, op, kind, Path(workdir))))
    else:
        main()
