"""The numba kernels of :mod:`bakeshop.light.specular`: filtered importance sampling over the
padded mip pyramid, and the exact lobe sums."""

from __future__ import annotations

import math

import numba
import numpy as np

from bakeshop.sphere.kernels import cube_face


@numba.njit(cache=True, inline="always", fastmath=True)
def _bilinear(
    pyramid: np.ndarray,
    offsets: np.ndarray,
    sizes: np.ndarray,
    level: int,
    face: int,
    sc: float,
    tc: float,
) -> tuple[float, float, float, float]:
    """The bilinear RGBA value of pyramid ``level`` at face coordinates (sc, tc)."""
    s = sizes[level]
    p = s + 2
    # continuous coordinate (sc + 1) / 2 * s, shifted by the one-texel padding, minus 0.5
    px = (sc + 1.0) * 0.5 * s + 0.5
    py = (tc + 1.0) * 0.5 * s + 0.5
    i0 = min(max(int(px), 0), s)
    j0 = min(max(int(py), 0), s)
    fx = min(max(px - i0, 0.0), 1.0)
    fy = min(max(py - j0, 0.0), 1.0)
    t = offsets[level] + ((face * p + j0) * p + i0) * 4
    r = p * 4
    w00 = (1.0 - fx) * (1.0 - fy)
    w10 = fx * (1.0 - fy)
    w01 = (1.0 - fx) * fy
    w11 = fx * fy
    v0 = w00 * pyramid[t] + w10 * pyramid[t + 4] + w01 * pyramid[t + r] + w11 * pyramid[t + r + 4]
    v1 = (
        w00 * pyramid[t + 1]
        + w10 * pyramid[t + 5]
        + w01 * pyramid[t + r + 1]
        + w11 * pyramid[t + r + 5]
    )
    v2 = (
        w00 * pyramid[t + 2]
        + w10 * pyramid[t + 6]
        + w01 * pyramid[t + r + 2]
        + w11 * pyramid[t + r + 6]
    )
    v3 = (
        w00 * pyramid[t + 3]
        + w10 * pyramid[t + 7]
        + w01 * pyramid[t + r + 3]
        + w11 * pyramid[t + r + 7]
    )
    return v0, v1, v2, v3


@numba.njit(cache=True, parallel=True, fastmath=True)
def _filter_kernel(
    dirs: np.ndarray,
    samples: np.ndarray,
    pyramid: np.ndarray,
    offsets: np.ndarray,
    sizes: np.ndarray,
    lod_bias: float,
    log2_fit: np.ndarray,
    out: np.ndarray,
) -> None:
    """out[p] = sum_k w_k L(l_k(p)) / sum_k w_k, each L read at its filtered-importance level.

    ``log2_fit`` holds polynomial coefficients of log2(q) on [1, 3] (highest power first).
    """
    top = sizes.size - 1
    s0 = float(sizes[0])
    # log2 of a level-0 texel's solid angle at a face centre: (2 / s0)^2
    log_texel = 2.0 * math.log2(2.0 / s0)
    total = 0.0
    for k in range(samples.shape[0]):
        total += samples[k, 3]
    for p in numba.prange(dirs.shape[0]):
        nx, ny, nz = dirs[p, 0], dirs[p, 1], dirs[p, 2]
        # Duff et al. 2017: a continuous orthonormal frame (t, b, n) except across n.z = 0
        sign = 1.0 if nz >= 0.0 else -1.0
        a = -1.0 / (sign + nz)
        b = nx * ny * a
        tx, ty, tz = 1.0 + sign * nx * nx * a, sign * b, -sign * nx
        bx, by, bz = b, sign + ny * ny * a, -ny
        a0 = a1 = a2 = a3 = 0.0
        for k in range(samples.shape[0]):
            lx, ly, lz = samples[k, 0], samples[k, 1], samples[k, 2]
            x = lx * tx + ly * bx + lz * nx
            y = lx * ty + ly * by + lz * ny
            z = lx * tz + ly * bz + lz * nz
            face, sc, tc = cube_face(x, y, z)
            # the texel solid angle where l lands is (2 / s0)^2 / (1 + sc^2 + tc^2)^1.5
            q = 1.0 + sc * sc + tc * tc
            log2_q = log2_fit[0]
            for i in range(1, log2_fit.size):
                log2_q = log2_q * q + log2_fit[i]
            lod = 0.5 * (samples[k, 4] - log_texel) + 0.75 * log2_q
            lod = min(max(lod + lod_bias, 0.0), float(top))
            lo = int(lod)
            f = lod - lo
            w = samples[k, 3]
            v0, v1, v2, v3 = _bilinear(pyramid, offsets, sizes, lo, face, sc, tc)
            if f > 0.0 and lo < top:
                u0, u1, u2, u3 = _bilinear(pyramid, offsets, sizes, lo + 1, face, sc, tc)
                v0 += f * (u0 - v0)
                v1 += f * (u1 - v1)
                v2 += f * (u2 - v2)
                v3 += f * (u3 - v3)
            a0 += w * v0
            a1 += w * v1
            a2 += w * v2
            a3 += w * v3
        out[p, 0] = a0 / total
        out[p, 1] = a1 / total
        out[p, 2] = a2 / total
        out[p, 3] = a3 / total


@numba.njit(cache=True, parallel=True)
def _lobe_kernel(
    dirs: np.ndarray,
    src_dirs: np.ndarray,
    src_omega: np.ndarray,
    src_values: np.ndarray,
    ggx: bool,
    param: float,
    cos_cut: float,
    acc: np.ndarray,
    total: np.ndarray,
) -> None:
    """acc[p] = sum_j w(n_p . l_j) Omega_j L_j and total[p] = sum_j w(n_p . l_j) Omega_j.

    The lobe w is GGX's D(h) (n.l) up to the constant alpha^2 / pi (param = alpha^2), or Phong's
    (n.l)^e (param = e), over n.l > ``cos_cut`` (where w has fallen below 1e-10 of its peak).
    """
    channels = src_values.shape[1]
    for p in numba.prange(dirs.shape[0]):
        nx, ny, nz = dirs[p, 0], dirs[p, 1], dirs[p, 2]
        t = 0.0
        for j in range(src_dirs.shape[0]):
            nl = nx * src_dirs[j, 0] + ny * src_dirs[j, 1] + nz * src_dirs[j, 2]
            if nl <= cos_cut:
                continue
            if ggx:
                # (n.h)^2 = (1 + n.l) / 2 for h = normalize(n + l)
                q = 0.5 * (1.0 + nl) * (param - 1.0) + 1.0
                w = nl / (q * q) * src_omega[j]
            else:
                w = nl**param * src_omega[j]
            t += w
            for c in range(channels):
                acc[p, c] += w * src_values[j, c]
        total[p] = t
