"""``bakeshop bake-probe`` on large probes: wall time and peak memory of the whole command, in
its own process (``/usr/bin/time -v``: its maximum resident set size), for this branch and,
side by side, for another checkout (``--before DIR``, a source tree whose ``bakeshop`` package
is imported instead: e.g. ``git archive main | tar -x -C /tmp/main``).

    python benchmarks/bench_bake_probe.py                     # 8192 x 4096
    python benchmarks/bench_bake_probe.py --width 16384       # 16384 x 8192 (1.6 GB decoded)
    python benchmarks/bench_bake_probe.py --before /tmp/main

The probe is the repository's 1k probe (tests/data/kiara_1_dawn_1k.hdr) enlarged by an
integer factor (each texel repeated), with a sun disc of 0.27 degrees radius added 20 degrees
above the horizon (radiance 5e4: a clear noon sun's irradiance relative to its sky), written as
PFM by strips (reading it is then one pass over the bytes). Outputs are written as PFM and DDS
(the defaults otherwise). Each checkout first bakes the 1k probe once, untimed: imports and
first-touch page faults (a checkout from before the compiled core also fills its JIT's cache
there, a studio's second run). The page cache is not dropped: the
file was just written, so each run reads it from memory. "cpu" is the process's user + system
seconds (all threads): on a machine shared with other jobs it is the steadier figure.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SUN_RADIUS_DEG = 0.27
SUN_ELEVATION_DEG = 20.0
SUN_RADIANCE = 5.0e4


def make_probe(path: Path, width: int) -> None:
    """The enlarged 1k probe with a sun disc, written by strips (never whole in memory)."""
    from bakeshop.io import read_image
    from bakeshop.io.stream import write_strips

    small = read_image(ROOT / "tests" / "data" / "kiara_1_dawn_1k.hdr")[..., :3]
    sh, sw = small.shape[:2]
    factor = width // sw
    if factor * sw != width:
        raise SystemExit(f"--width must be a multiple of {sw}")
    h = sh * factor
    elevation = math.radians(SUN_ELEVATION_DEG)
    sun = np.array([0.3 * math.cos(elevation), math.sin(elevation), -0.95 * math.cos(elevation)])
    sun /= np.linalg.norm(sun)
    cos_radius = math.cos(math.radians(SUN_RADIUS_DEG))
    x = (np.arange(width) + 0.5) / width
    phi = (x - 0.5) * 2 * math.pi

    def strips(rows: int = 256):
        for top in range(0, h, rows):
            block = np.repeat(np.repeat(small[top // factor : (top + rows) // factor], factor, 0),
                              factor, 1)  # fmt: skip
            theta = math.pi * (np.arange(top, top + rows) + 0.5) / h
            d = np.stack(np.broadcast_arrays(np.sin(theta)[:, None] * np.sin(phi)[None, :],
                                             np.cos(theta)[:, None] + 0 * phi[None, :],
                                             -np.sin(theta)[:, None] * np.cos(phi)[None, :]),
                         axis=-1)  # fmt: skip
            disc = d @ sun >= cos_radius
            block = block.astype(np.float32, copy=True)
            block[disc] = SUN_RADIANCE
            yield block

    write_strips(path, (h, width, 3), strips())


def run(probe: Path, out: Path, source: Path | None) -> dict:
    """One ``bake-probe`` in its own process: wall and CPU seconds, peak MB and the command's
    own lines."""
    env = dict(os.environ)
    if source is not None:
        env["PYTHONPATH"] = str(source)
    command = ["/usr/bin/time", "-v", sys.executable, "-c",
               "import sys; from bakeshop.cli.main import main; sys.exit(main())",
               "bake-probe", str(probe), "-o", str(out), "--format", "pfm"]  # fmt: skip
    result = subprocess.run(command, capture_output=True, text=True, env=env, cwd=out.parent)
    if result.returncode:
        raise SystemExit(result.stderr[-3000:])
    wall = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", result.stderr)
    hours, minutes, seconds = (float(g) if g else 0.0 for g in wall.groups())
    peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", result.stderr)[1])
    cpu = sum(float(re.search(rf"{kind} time \(seconds\): ([\d.]+)", result.stderr)[1])
              for kind in ("User", "System"))  # fmt: skip
    return {"seconds": 3600 * hours + 60 * minutes + seconds, "cpu": cpu,
            "peak_mb": peak * 1024 / 1e6, "stdout": result.stdout}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--width", type=int, default=8192)
    parser.add_argument(
        "--before", type=Path, default=None, help="a source tree to time side by side"
    )
    parser.add_argument("--dir", default=None, help="where the probe and outputs are written")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(dir=args.dir) as tmp:
        folder = Path(tmp)
        probe = folder / f"probe_{args.width}.pfm"
        make_probe(probe, args.width)
        decoded = probe.stat().st_size / 1e6
        print(f"probe {args.width}x{args.width // 2} float RGB: {decoded:.0f} MB decoded")
        runs = [("this branch", None)]
        if args.before is not None:
            runs.append((f"before ({args.before})", args.before.resolve()))
        for _, source in runs:  # untimed: page faults (and an old checkout's JIT cache)
            run(ROOT / "tests" / "data" / "kiara_1_dawn_1k.hdr", folder / "warm", source)
        print("| bake-probe | seconds | cpu seconds | peak MB | peak / decoded |")
        print("| --- | ---: | ---: | ---: | ---: |")
        for k, (name, source) in enumerate(runs):
            r = run(probe, folder / f"out_{k}", source)
            print(f"| {name} | {r['seconds']:.1f} | {r['cpu']:.1f} | {r['peak_mb']:.0f} | "
                  f"{r['peak_mb'] / decoded:.1f}x |", flush=True)  # fmt: skip
            print(textwrap.indent(r["stdout"], "    "), file=sys.stderr)


if __name__ == "__main__":
    main()
