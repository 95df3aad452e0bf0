"""Hostile files: what reading a decompression bomb, or an OpenEXR with 120 channels besides
RGB, costs bakeshop and OpenImageIO, in the same run.

Files (built here by tests/io/bombs.py, nothing downloaded): four 16384 x 16384 bombs (old-style
Radiance runs, zip OpenEXR, RLE TGA, deflated PNG; 128 KiB to 4 MiB each) and a 2048 x 1024 zip
OpenEXR of R, G, B and 120 more half channels. Each read runs in a fresh child process; "peak" is
the resident high-water mark (VmHWM, reset just before the read) minus the resident size before:
the memory the read needed, after the imports (any command's cost, not the file's). The
children may grow to MEMORY_LIMIT (address space), so that a peer decoding a bomb cannot take
the shared machine down; a read that hits it says so.

bakeshop refuses the bombs from their headers (its decode budget, :mod:`bakeshop.io.budget`);
OpenImageIO decodes what it can. For the 120-channel file both read only R, G, B
(``read_image(chbegin=0, chend=3)`` for OpenImageIO), and OpenImageIO also reads everything.

Run: ``.venv/bin/python benchmarks/bench_hostile.py`` (about a minute).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import peers

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

#: address space a child may use: above any decode here but one, below the machine's memory
MEMORY_LIMIT = 8 << 30
SIDE = 16384
AOVS = 120


def build(folder: Path) -> dict[str, Path]:
    from tests.io import bombs

    made = {
        "hdr bomb": (bombs.radiance_old_rle(SIDE, SIDE), "bomb.hdr"),
        "exr bomb": (bombs.exr_zip(SIDE, SIDE), "bomb.exr"),
        "tga bomb": (bombs.tga_rle(SIDE, SIDE), "bomb.tga"),
        "png bomb": (bombs.png_deflate(SIDE, SIDE), "bomb.png"),
        "exr + 120 channels": (
            bombs.exr_zip(2048, 1024, ("B", "G", "R", *(f"aov{i:03d}" for i in range(AOVS)))),
            "aovs.exr",
        ),
    }
    paths = {}
    for case, (data, name) in made.items():
        paths[case] = folder / name
        paths[case].write_bytes(data)
    return paths


# --- inside a child ---------------------------------------------------------------------------


def memory(field: str) -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    raise RuntimeError(field)


def child(tool: str, path: str) -> dict:
    import resource
    import time

    if tool == "bakeshop":
        import bakeshop.io.exr
        import bakeshop.io.ldr
        import bakeshop.io.rgbe
        import bakeshop.io.tga  # noqa: F401 - imports are not the read's cost
        from bakeshop.io import read_image

        def read():
            return read_image(path).shape
    else:
        import OpenImageIO as oiio

        def read():
            inp = oiio.ImageInput.open(path)
            if inp is None:
                raise RuntimeError(oiio.geterror()[:80])
            try:
                if tool == "oiio rgb":
                    pixels = inp.read_image(0, 0, 0, 3, "float")
                else:
                    pixels = inp.read_image("float")
                if pixels is None:
                    raise RuntimeError(inp.geterror()[:80])
                return pixels.shape
            finally:
                inp.close()

    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    before = memory("VmRSS")
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
    start = time.perf_counter()
    try:
        outcome = f"decoded {tuple(read())}"
    except MemoryError:
        outcome = "out of memory"
    except Exception as e:
        outcome = f"{'refused' if 'bomb' in str(e) else 'error'}: {str(e)[:60]}"
    seconds = time.perf_counter() - start
    return {"seconds": seconds, "peak": max(memory("VmHWM") - before, 0), "outcome": outcome}


# --- the parent ---------------------------------------------------------------------------------


def run(tool: str, path: Path) -> dict:
    done = subprocess.run(
        [sys.executable, __file__, "--child", tool, str(path)],
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )
    if done.returncode != 0:
        return {"seconds": float("nan"), "peak": 0, "outcome": f"crashed ({done.returncode})"}
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    found = peers.Peers(["oiio"])
    print(f"machine: {peers.machine()}")
    with tempfile.TemporaryDirectory(dir=os.environ.get("BENCH_TMP")) as d:
        paths = build(Path(d))
        print(f"{'file':20} {'KiB':>6} {'tool':9} {'seconds':>8} {'peak MiB':>9}  outcome")
        for case, path in paths.items():
            tools = ["bakeshop", "oiio"] + (["oiio rgb"] if "channels" in case else [])
            for tool in tools if found.present("oiio") else ["bakeshop"]:
                r = run(tool, path)
                if tool.startswith("oiio"):
                    found.measured("oiio", case)
                print(
                    f"{case:20} {path.stat().st_size / 1024:6.0f} {tool:9} {r['seconds']:8.3f} "
                    f"{r['peak'] / 2**20:9.0f}  {r['outcome']}",
                    flush=True,
                )
    found.finish()


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        print(json.dumps(child(sys.argv[2], sys.argv[3])))
    else:
        main()
