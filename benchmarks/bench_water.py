"""Time the water bakes: looping ocean normals (slopes and choppiness), the wave equation and
the murk tables, against plain numpy and against the FFT floor, in one run.

Ocean normals, 256^2 x 64 frames and 1024^2 x 128 frames, JONSWAP, choppiness 0.8 (the normal
of the displaced surface needs five real fields: two slopes and three displacement derivatives):

- bakeshop: ``ocean_frames(fields=("normal",), choppiness=0.8)``: per frame one C++ pass
  builds three packed complex64 spectra (two real fields per complex FFT) with phases from an
  integer turn table, scipy's FFT (2 threads) inverts them, one C++ pass makes unit normals;
  frames in batches of at most 256 MiB (the frames are consumed, not kept);
- numpy reference: the same sum written plainly, per frame: complex exp of every mode,
  h_hat = a e^{-iwt} + b e^{iwt}, five separate numpy inverse FFTs (complex128), normals with
  array expressions (timed on a subset of frames at 1024^2 and scaled, said so in the table);
- FFT floor: only the three complex64 inverse FFTs per frame that bakeshop's packing needs,
  with numpy's FFT (one thread) and scipy's (2 threads): nothing can be faster than its FFTs.

Wave equation: steps of a 1024^2 periodic grid (the 9-point isotropic stencil), C++ vs the
same stencil in numpy (np.roll), in ns per cell-step.

Murk: the tables and LUTs of a Jerlov type (spectral integration over 129 wavelengths).

Each ocean size runs twice: with both cores (the kernels' and scipy's FFT threads) and with one
thread each, whose CPU seconds a loaded machine disturbs least. Prints seconds (best of 3 for small
jobs, 1 for large), CPU seconds, ratios to the scipy FFT floor of the same thread count, and
peak traced memory (tracemalloc) of bakeshop's ocean runs.
"""

from __future__ import annotations

import math
import os
import platform
import resource
import time
import tracemalloc

import numpy as np
import scipy.fft

import bakeshop.threads
from bakeshop.water import murk
from bakeshop.water.ocean import ocean, ocean_frames
from bakeshop.water.ripples import WaveEquation
from bakeshop.water.spectra import Spectrum

SEA = Spectrum("jonswap", wind_speed=10.0, fetch=100e3)
LAMBDA = 0.8


def timed(function, repeats=1):
    best_wall, best_cpu, out = math.inf, math.inf, None
    for _ in range(repeats):
        c0 = time.process_time()
        t0 = time.perf_counter()
        out = function()
        best_wall = min(best_wall, time.perf_counter() - t0)
        best_cpu = min(best_cpu, time.process_time() - c0)
    return best_wall, best_cpu, out


def bakeshop_normals(o, frames, threads=None):
    count = 0
    for _, batch in ocean_frames(o, frames=frames, fields=("normal",), choppiness=LAMBDA,
                                 workers=threads):  # fmt: skip
        count += batch["normal"].shape[0]
    return count


def numpy_normals(o, frames, subset):
    """The plain numpy sum, on ``subset`` of the frames."""
    kx, ky = o.kx, o.ky
    k = np.hypot(kx, ky)
    inv_k = np.divide(1.0, k, out=np.zeros_like(k), where=k > 0)
    for f in range(subset):
        t = f * o.loop_period / frames
        phase = np.exp(-1j * o.omega * t)
        h = o.amplitude * phase + o.partner * np.conj(phase)
        hx = np.fft.ifft2(1j * kx * h).real * h.size
        hy = np.fft.ifft2(1j * ky * h).real * h.size
        dxx = np.fft.ifft2(-kx * kx * inv_k * h).real * h.size * LAMBDA
        dyy = np.fft.ifft2(-ky * ky * inv_k * h).real * h.size * LAMBDA
        dxy = np.fft.ifft2(-kx * ky * inv_k * h).real * h.size * LAMBDA
        n = np.stack([-hx * (1 + dyy) + dxy * hy, -hy * (1 + dxx) + dxy * hx,
                      np.maximum((1 + dxx) * (1 + dyy) - dxy * dxy, 1e-3)], -1)  # fmt: skip
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return subset


def fft_floor(n, frames, library, threads=None):
    data = (np.random.default_rng(0).normal(size=(3, n, n)) * (1 + 1j)).astype(np.complex64)
    for _ in range(frames):
        if library == "numpy":
            np.fft.ifft2(data)
        else:
            scipy.fft.ifft2(data, workers=threads or os.cpu_count())
    return frames


def ocean_rows(n, frames, size, subset, threads, reference):
    """Rows of one size at ``threads`` threads (the kernels and scipy); ``reference``: the numpy
    reference's row, measured once (it is single-threaded), or None to measure it."""
    before = bakeshop.threads.count()
    bakeshop.threads.use(threads)
    o = ocean(SEA, size=size, resolution=n, seed=1, loop_period=max(8.0, frames / 8))
    frames = max(frames, o.minimum_frames())
    # compile and warm the caches: one batch of one frame
    next(ocean_frames(o, frames=frames, fields=("normal",), choppiness=LAMBDA, batch=1))
    rows = []
    wall, cpu, _ = timed(lambda: bakeshop_normals(o, frames, threads), 3 if n <= 256 else 1)
    tracemalloc.start()
    bakeshop_normals(o, frames, threads)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    rows.append(("bakeshop", wall, cpu, peak))
    if reference is None:
        w, c, _ = timed(lambda: numpy_normals(o, frames, subset))
        reference = (f"numpy reference{'' if subset == frames else ' (scaled)'}",
                     w * frames / subset, c * frames / subset, None)  # fmt: skip
    rows.append(reference)
    w, c, _ = timed(lambda: fft_floor(n, frames, "numpy"), 3 if n <= 256 else 1)
    rows.append(("FFT floor, numpy (1 thread)", w, c, None))
    w, c, _ = timed(lambda: fft_floor(n, frames, "scipy", threads), 3 if n <= 256 else 1)
    rows.append((f"FFT floor, scipy ({threads} thread{'s' if threads > 1 else ''})", w, c, None))
    bakeshop.threads.use(before)
    return frames, rows


def wave_rows(n=1024, steps=40):
    sim = WaveEquation(n, 1.0, 0.25, dt=0.5 / n / 0.25)
    sim.height[:] = np.random.default_rng(0).normal(size=(n, n)) * 1e-3
    sim.step(2)
    w, c, _ = timed(lambda: sim.step(steps), 3)
    h, v = sim.height.copy(), sim.velocity.copy()
    c2dt = sim.speed**2 * sim.dt / (6 * sim.dx**2)

    def numpy_steps():
        nonlocal h, v
        for _ in range(steps):
            edge = np.roll(h, 1, 0) + np.roll(h, -1, 0) + np.roll(h, 1, 1) + np.roll(h, -1, 1)
            rolled = np.roll(h, 1, 0)
            corner = np.roll(rolled, 1, 1) + np.roll(rolled, -1, 1)
            rolled = np.roll(h, -1, 0)
            corner += np.roll(rolled, 1, 1) + np.roll(rolled, -1, 1)
            v += c2dt * (4 * edge + corner - 20 * h)
            h += sim.dt * v

    wn, cn, _ = timed(numpy_steps, 3)
    cells = n * n * steps
    return [("bakeshop (C++)", w / cells * 1e9, c / cells * 1e9),
            ("numpy (np.roll)", wn / cells * 1e9, cn / cells * 1e9)]  # fmt: skip


def murk_rows():
    rows = []
    for label, job in (
        ("water('II') (IOPs from Kd)", lambda: murk.water("II")),
        ("engine_constants", lambda: murk.engine_constants(murk.water("II"))),
        (
            "murk_lut 64 x 32",
            lambda: murk.murk_lut(murk.water("II"), max_distance=30, max_depth=20),
        ),  # fmt: skip
        (
            "murk_lut 256 x 256",
            lambda: murk.murk_lut(
                murk.water("II"), max_distance=30, max_depth=20, distances=256, depths=256
            ),
        ),  # fmt: skip
    ):
        job()
        w, c, _ = timed(job, 3)
        rows.append((label, w, c))
    return rows


def main():
    cpu = platform.processor() or platform.machine()
    print(f"# bench_water: {cpu}, {os.cpu_count()} cores, numpy {np.__version__}, "
          f"scipy {scipy.__version__}, load average {os.getloadavg()[0]:.1f}")  # fmt: skip
    for n, frames, size, subset in ((256, 64, 64.0, 64), (1024, 128, 256.0, 16)):
        reference = None
        for threads in (os.cpu_count(), 1):
            frames_used, rows = ocean_rows(n, frames, size, subset, threads, reference)
            reference = rows[1]
            print(f"\nocean normals {n}^2 x {frames_used} frames (slopes + choppiness), "
                  f"{threads} thread{'s' if threads > 1 else ''}")  # fmt: skip
            print(f"{'method':32s} {'seconds':>9s} {'cpu':>8s} {'x floor':>8s} "
                  f"{'cpu x floor':>11s} {'ms/frame':>9s} {'peak MiB':>9s}")  # fmt: skip
            floor_wall, floor_cpu = rows[3][1], rows[3][2]
            for name, wall, cpu_s, peak in rows:
                peak_text = f"{peak / 2**20:9.0f}" if peak is not None else f"{'':9s}"
                print(f"{name:32s} {wall:9.3f} {cpu_s:8.3f} {wall / floor_wall:8.2f} "
                      f"{cpu_s / floor_cpu:11.2f} {1000 * wall / frames_used:9.2f} "
                      f"{peak_text}")  # fmt: skip
    print("\nwave equation 1024^2, periodic, 9-point isotropic stencil")
    print(f"{'method':32s} {'ns/cell-step':>13s} {'cpu ns':>8s}")
    for name, w, c in wave_rows():
        print(f"{name:32s} {w:13.2f} {c:8.2f}")
    print("\nmurk tables (Jerlov II)")
    print(f"{'job':32s} {'seconds':>9s} {'cpu':>8s}")
    for name, w, c in murk_rows():
        print(f"{name:32s} {w:9.4f} {c:8.4f}")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"\nprocess peak resident memory {peak:.0f} MiB")


if __name__ == "__main__":
    main()
