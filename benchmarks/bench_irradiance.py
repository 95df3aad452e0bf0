"""Time diffuse irradiance on the team's 12.6-megapixel probe: the DIM pair, SH and exact.

The probe is Poly Haven's Quarry 01 (1024x512, a clear sky with a small, very bright sun)
upsampled bilinearly to 5020x2510 (OpenCV), the size of the team's probes. Jobs:

- ``pair``: ``dim_pair``: find and paint out the sun, then the sun DIM and the shadow DIM
  (360x180 latlong each) by ``auto``, from the full-resolution probe;
- ``auto``: one 360x180 DIM by ``auto`` (no sun split);
- ``sh2``: one 360x180 DIM by ``sh`` with L = 2 (projection of all 12.6 M texels);
- ``exact-90x45``: ``exact`` from the full probe to a 90x45 DIM, and the errors of ``pair``'s
  sun DIM and of ``sh2`` against it (the pair is computed at 90x45 for the comparison);
- ``exact-full``: ``exact`` from the full probe to the full 360x180 DIM (every texel for every
  output texel, summed by cones: O(M N^(2/3)));
- ``brute``: the O(M N) brute force HDRShop runs, at its best (float64 matrix products on
  cache-sized tiles, numpy's BLAS, one thread per processor) at 64800 x 131072 pairs,
  extrapolated to 64800 x 12.6 M;
- ``command``: the whole ``bakeshop -q dims`` command on the probe as a .hdr file: start-up,
  reading, the pair, and writing sun_dim.hdr, shadow_dim.hdr, shadow_probe.hdr and sun.json.

Each job runs in a fresh subprocess after one small warm-up (imports, first-touch page
faults); "cpu" is the process's CPU time over the run (all threads), steadier than wall time
on a shared machine; peak is the resident high-water mark (``VmHWM``, reset before the job)
minus the resident size before: the extra memory the job needed.

No peer runs here: these are library calls, and the peers (cmgen, cmft) are commands.
``bench_commands.py`` runs them against ``bakeshop dims`` and ``irradiance`` whole process
against whole process on the same probe (job ``dims-12mp``). HDRShop's O(M N) algorithm is
measured at its best by the ``brute`` job.

Run: ``.venv/bin/python benchmarks/bench_irradiance.py`` (about two minutes).
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import peers

ROOT = Path(__file__).resolve().parents[1]
SOURCE = ROOT / "tests" / "data" / "quarry_01_1k.hdr"
WIDTH, HEIGHT = 5020, 2510
DIM = (360, 180)
JOBS = ["pair", "auto", "sh2", "exact-90x45", "exact-full", "brute", "command"]


def memory(field: str) -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    raise RuntimeError(field)


def reset_peak() -> None:
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")


def errors(got, ref) -> dict:
    got, ref = np.asarray(got, np.float64), np.asarray(ref, np.float64)
    return {
        "rms": float(np.sqrt(np.mean((got - ref) ** 2) / np.mean(ref**2))),
        "max": float(np.max(np.abs(got - ref) / ref)),
    }


def child(job: str, workdir: Path) -> dict:
    import bakeshop.light as ir

    probe = np.load(workdir / "probe.npy")
    small = probe[::40, ::40].copy()
    ir.dim_pair(small, "latlong", size=(36, 18))  # warm-up: load the compiled kernels
    ir.irradiance(small, "latlong", size=(36, 18), method="sh")
    extra: dict = {}
    reset_peak()
    before = memory("VmRSS")
    start, start_cpu = time.perf_counter(), time.process_time()
    if job == "pair":
        pair = ir.dim_pair(probe, "latlong", size=DIM)
        extra["sun"] = None if pair.sun is None else pair.sun.to_dict()
    elif job == "auto":
        ir.irradiance(probe, "latlong", size=DIM)
    elif job == "sh2":
        ir.irradiance(probe, "latlong", size=DIM, method="sh", order=2)
    elif job == "exact-90x45":
        exact = ir.irradiance(probe, "latlong", size=(90, 45), method="exact")
    elif job == "exact-full":
        ir.irradiance(probe, "latlong", size=DIM, method="exact")
    elif job == "brute":
        extra.update(brute(probe))
    seconds, cpu = time.perf_counter() - start, time.process_time() - start_cpu
    peak = memory("VmHWM") - before
    if job == "exact-90x45":
        pair = ir.dim_pair(probe, "latlong", size=(90, 45))
        sh2 = ir.irradiance(probe, "latlong", size=(90, 45), method="sh", order=2)
        extra["pair_vs_exact"] = errors(pair.sun_dim, exact)
        extra["sh2_vs_exact"] = errors(sh2, exact)
    return {"seconds": seconds, "cpu": cpu, "peak": max(peak, 0), **extra}


def _brute(normals, dirs, energy, out, rows=64, columns=4096):
    """``out[i] = sum_j max(normals[i] . dirs[:, j], 0) energy[:, j]``: tiles of ``rows`` output
    texels x ``columns`` source texels (2 MiB of cosines, in cache), one block of rows per task,
    as many threads as processors (numpy releases the GIL in its matrix products; the job's
    process runs BLAS on one thread, so that the tiles' products do not spawn more)."""

    def block(i):
        acc = np.zeros((min(rows, len(normals) - i), 3))
        cos = np.empty((len(acc), columns))
        for j in range(0, dirs.shape[1], columns):
            c = cos[:, : min(columns, dirs.shape[1] - j)]
            np.matmul(normals[i : i + rows], dirs[:, j : j + columns], out=c)
            np.maximum(c, 0.0, out=c)
            acc += c @ energy[:, j : j + columns].T
        out[i : i + rows] = acc

    with ThreadPoolExecutor(len(os.sched_getaffinity(0))) as pool:
        list(pool.map(block, range(0, len(normals), rows)))


def brute(probe) -> dict:
    """HDRShop's algorithm, every source texel for every output texel, at its best: float64
    matrix products on cache-sized tiles, multi-threaded, on 64800 x 131072 pairs."""
    from bakeshop.sphere import layout

    lay = layout("latlong")
    src = probe[::7, ::7]  # 359 x 718 texels ~ 258 k
    h, w = src.shape[:2]
    d, _ = lay.directions((h, w))
    e = src.reshape(-1, 3) * lay.solid_angles((h, w)).reshape(-1, 1)
    n_src = min(h * w, 131072)
    d = np.ascontiguousarray(d.reshape(-1, 3)[:n_src].T, np.float64)
    e = np.ascontiguousarray(e[:n_src].T, np.float64)
    n = np.ascontiguousarray(lay.directions((DIM[1], DIM[0]))[0].reshape(-1, 3), np.float64)
    out = np.empty((len(n), 3))
    _brute(n[:8], d, e, out[:8])  # warm-up: threads, page faults
    start = time.perf_counter()
    _brute(n, d, e, out)
    seconds = time.perf_counter() - start
    pairs = len(n) * n_src
    return {"pairs": pairs, "pairs_per_s": pairs / seconds}


def run(job: str, workdir: Path) -> dict:
    if job == "command":
        out = workdir / "dims"
        start, cpu = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run(
            [
                str(ROOT / ".venv" / "bin" / "bakeshop"),
                "-q",
                "dims",
                str(workdir / "probe.hdr"),
                "-o",
                str(out),
            ],
            check=True,
            capture_output=True,
        )
        used = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = used.ru_utime + used.ru_stime - cpu.ru_utime - cpu.ru_stime
        return {"seconds": time.perf_counter() - start, "cpu": cpu}
    # the brute force threads its tiles itself: BLAS on one thread per tile
    one_blas = {"OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"} if job == "brute" else {}
    out = subprocess.run(
        [sys.executable, __file__, "--child", job, str(workdir)],
        env=dict(os.environ, **one_blas),
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def prepare(workdir: Path) -> None:
    import cv2

    from bakeshop.io import read_image, write_image

    small = read_image(SOURCE)
    probe = cv2.resize(small, (WIDTH, HEIGHT), interpolation=cv2.INTER_LINEAR)
    np.save(workdir / "probe.npy", probe)
    write_image(workdir / "probe.hdr", probe)


def main() -> None:
    if len(sys.argv) == 4 and sys.argv[1] == "--child":
        print(json.dumps(child(sys.argv[2], Path(sys.argv[3]))))
        return
    jobs = sys.argv[1:] or JOBS
    cpu_model = next(
        (line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if "model name" in line),
        "?",
    )
    print(
        f"machine: {cpu_model}, {os.cpu_count()} cores; probe {WIDTH}x{HEIGHT} "
        f"({WIDTH * HEIGHT / 1e6:.1f} MP) from {SOURCE.name}; DIM {DIM[0]}x{DIM[1]}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp)
        prepare(workdir)
        results = {job: run(job, workdir) for job in jobs}
    mp = WIDTH * HEIGHT / 1e6
    pixels = DIM[0] * DIM[1]
    print(f"\n{'job':<34}{'wall s':>9}{'cpu s':>9}{'peak MB':>9}   notes")
    for job, r in results.items():
        note = ""
        if job == "pair":
            per_mp = r["seconds"] / mp
            note = f"{per_mp * 1e3:.0f} ms/MP"
        elif job == "exact-90x45":
            note = (
                f"pair vs exact rms {r['pair_vs_exact']['rms']:.1e} max "
                f"{r['pair_vs_exact']['max']:.1e}; sh2 vs exact rms "
                f"{r['sh2_vs_exact']['rms']:.1e} max {r['sh2_vs_exact']['max']:.1e}"
            )
        elif job == "brute":
            full = pixels * WIDTH * HEIGHT / r["pairs_per_s"]
            note = (
                f"{r['pairs_per_s'] / 1e9:.2f} G pairs/s -> {full:.0f} s for 360x180 from "
                f"12.6 MP ({full / 3600:.1f} h)"
            )
            if "exact-full" in results:
                note += f"; exact-full is x{full / results['exact-full']['seconds']:.0f} faster"
        elif job == "command":
            note = "start-up, read .hdr, pair, write 3 .hdr + sun.json"
        peak = f"{r['peak'] / 2**20:9.0f}" if "peak" in r else f"{'':>9}"
        cpu = f"{r['cpu']:9.2f}" if "cpu" in r else f"{'':>9}"
        print(f"{job:<34}{r['seconds']:9.2f}{cpu}{peak}   {note}")
    if "pair" in results and results["pair"].get("sun"):
        print("\nsun:", json.dumps(results["pair"]["sun"]))
    peers.Peers([]).finish()


if __name__ == "__main__":
    main()
