"""The blend methods' formulas as one numba kernel over the texels
(:func:`bakeshop.normals.blend.blend` documents them): apart from the module so that the
methods' names load without numba."""

from __future__ import annotations

import math

import numba
import numpy as np

_TINY = 1e-30


# One fused loop over the texels (numba, parallel): read both normals, scale the detail's
# height, blend with the method's formula in float64, renormalise, write. The method is picked
# by its index in METHODS inside the loop (a branch the CPU predicts perfectly).


@numba.njit(cache=True, inline="always")
def _overlay1(a: float, b: float) -> float:
    a = (a + 1) * 0.5
    b = (b + 1) * 0.5
    r = 2 * a * b if a < 0.5 else 1 - 2 * (1 - a) * (1 - b)
    return r * 2 - 1


@numba.njit(cache=True, inline="always")
def _formula(
    method: int, x1: float, y1: float, z1: float, x2: float, y2: float, z2: float
) -> tuple[float, float, float]:
    if method == 0:  # exact
        k = z2 - x2 * x1 - y2 * y1
        return k * x1 + x2, k * y1 + y2, k * z1
    if method == 1:  # rnm; n1 = (0, 0, -1) has no rotation
        tz = max(z1 + 1, 1e-12)
        k = (-x1 * x2 - y1 * y2 + tz * z2) / tz
        return x1 * k + x2, y1 * k + y2, tz * k - z2
    if method == 2:  # sg: Mikkelsen's surfgradFromPerturbedNormal (n1) and surfgradFromTBN
        # (n2), both relative to the vertex frame; resolve normalize(vN - sg1 - sg2)
        k1 = z1 if abs(z1) > _TINY else _TINY
        k2 = z2 if abs(z2) > _TINY else _TINY
        return x1 / k1 + x2 / k2, y1 / k1 + y2 / k2, 1.0
    if method == 3:  # pd
        return x1 * z2 + x2 * z1, y1 * z2 + y2 * z1, z1 * z2
    if method == 4:  # whiteout
        return x1 + x2, y1 + y2, z1 * z2
    if method == 5:  # udn
        return x1 + x2, y1 + y2, z1
    if method == 6:  # overlay on packed R and G, multiply on packed B
        return _overlay1(x1, x2), _overlay1(y1, y2), (z1 + 1) * (z2 + 1) * 0.5 - 1
    return x1 + x2, y1 + y2, z1 + z2 - 1  # linear


@numba.njit(cache=True, parallel=True)
def blend_texels(
    method: int, m: np.ndarray, d: np.ndarray, strength: np.ndarray, out: np.ndarray
) -> None:
    n = m.shape[0]
    per_texel = strength.shape[0] > 1
    for i in numba.prange(n):
        s = np.float64(strength[i] if per_texel else strength[0])
        x2 = s * np.float64(d[i, 0])
        y2 = s * np.float64(d[i, 1])
        z2 = np.float64(d[i, 2])
        length = math.sqrt(x2 * x2 + y2 * y2 + z2 * z2)
        if length > 0:
            x2 /= length
            y2 /= length
            z2 /= length
        x, y, z = _formula(
            method, np.float64(m[i, 0]), np.float64(m[i, 1]), np.float64(m[i, 2]), x2, y2, z2
        )
        length = math.sqrt(x * x + y * y + z * z)
        if length > 0 and math.isfinite(length):
            out[i, 0] = x / length
            out[i, 1] = y / length
            out[i, 2] = z / length
        else:
            out[i, 0] = 0.0
            out[i, 1] = 0.0
            out[i, 2] = 1.0
