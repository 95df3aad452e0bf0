"""The numba kernels of ocean frame synthesis (:mod:`bakeshop.water.ocean`): the spectra of a batch
of frames (looped through a phase table, or at free times) and the normals of the displaced
surface."""

from __future__ import annotations

import math

import numba
import numpy as np

#: A folded texel (J <= 0, the surface passes through itself) has no outward normal; its
#: normal's z is clamped to this before normalising (such texels are foam).
FOLD_FLOOR = 1e-3


@numba.njit(parallel=True, cache=True)
def _loop_spectra(
    a: np.ndarray,
    b: np.ndarray,
    cycles: np.ndarray,
    frames: np.ndarray,
    table: np.ndarray,
    mult: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """out[f, p] = (a P + b conj(P)) mult[p] with P = table[(n f) mod F], table[i] =
    exp(-2 pi i i / F): integer turns, so frame F is frame 0 exactly, and no trigonometry."""
    n_rows, n_cols = a.shape
    npairs = mult.shape[0]
    count = table.size
    for r in numba.prange(n_rows):
        for c in range(n_cols):
            ar = a[r, c]
            br = b[r, c]
            if ar == 0 and br == 0:
                for f in range(frames.size):
                    for p in range(npairs):
                        out[f, p, r, c] = 0
                continue
            nc = np.int64(cycles[r, c]) % count
            for f in range(frames.size):
                ph = table[(nc * (np.int64(frames[f]) % count)) % count]
                h = ar * ph + br * ph.conjugate()
                for p in range(npairs):
                    out[f, p, r, c] = h * mult[p, r, c]


@numba.njit(parallel=True, cache=True)
def _free_spectra(
    a: np.ndarray,
    b: np.ndarray,
    omega: np.ndarray,
    times: np.ndarray,
    mult: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """out[f, p] = (a e^{-i w t_f} + b e^{i w t_f}) mult[p] for arbitrary times."""
    n_rows, n_cols = a.shape
    npairs = mult.shape[0]
    for r in numba.prange(n_rows):
        for c in range(n_cols):
            ar = a[r, c]
            br = b[r, c]
            for f in range(times.size):
                angle = -((omega[r, c] * times[f]) % (2.0 * math.pi))
                ph = complex(math.cos(angle), math.sin(angle))
                h = ar * ph + br * ph.conjugate()
                for p in range(npairs):
                    out[f, p, r, c] = h * mult[p, r, c]


@numba.njit(parallel=True, cache=True)
def _normals(
    slope: np.ndarray, stretch: np.ndarray, height: np.ndarray, lam: float, out: np.ndarray
) -> None:  # pragma: no cover - compiled
    """Unit normals of the displaced surface from the packed FFT outputs (see module doc)."""
    frames, rows, cols = slope.shape
    for fr in numba.prange(frames * rows):
        f = fr // rows
        r = fr % rows
        for c in range(cols):
            hx = slope[f, r, c].real
            hy = slope[f, r, c].imag
            dxx = lam * stretch[f, r, c].real
            dyy = lam * stretch[f, r, c].imag
            dxy = lam * height[f, r, c].imag
            nx = -hx * (1.0 + dyy) + dxy * hy
            ny = -hy * (1.0 + dxx) + dxy * hx
            nz = (1.0 + dxx) * (1.0 + dyy) - dxy * dxy
            if nz < FOLD_FLOOR:
                nz = FOLD_FLOOR
            s = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
            out[f, r, c, 0] = nx * s
            out[f, r, c, 1] = ny * s
            out[f, r, c, 2] = nz * s


@numba.njit(parallel=True, cache=True)
def _flat_normals(slope: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover - compiled
    """Unit normals (-hx, -hy, 1) / |.| of the undisplaced surface."""
    frames, rows, cols = slope.shape
    for fr in numba.prange(frames * rows):
        f = fr // rows
        r = fr % rows
        for c in range(cols):
            hx = slope[f, r, c].real
            hy = slope[f, r, c].imag
            s = 1.0 / math.sqrt(hx * hx + hy * hy + 1.0)
            out[f, r, c, 0] = -hx * s
            out[f, r, c, 1] = -hy * s
            out[f, r, c, 2] = s
