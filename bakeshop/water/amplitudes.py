"""Deterministic amplitudes of an ocean's lattice modes: standard normals from a counter-based hash
(SplitMix64) of the seed and each mode's integer indices, the same on any machine, at any
resolution and in any order of evaluation."""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError


@numba.njit(cache=True)
def _splitmix64(z: np.uint64) -> np.uint64:  # pragma: no cover - compiled
    z = z + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


@numba.njit(cache=True)
def _mode_normals(
    seed: int, mx: np.ndarray, my: np.ndarray, out: np.ndarray
) -> None:  # pragma: no cover - compiled
    """Two independent standard normals per lattice mode (mx[i], my[i]), from a hash of the
    seed and the mode's integer indices (Box-Muller on two 53-bit uniforms)."""
    base = _splitmix64(np.uint64(seed))
    scale = 2.0**-53
    for i in range(mx.size):
        state = _splitmix64(base ^ np.uint64(np.int64(mx[i])))
        state = _splitmix64(state ^ np.uint64(np.int64(my[i]) * np.int64(0x5851F42D)))
        u1 = (float(_splitmix64(state) >> np.uint64(11)) + 0.5) * scale
        u2 = float(_splitmix64(state ^ np.uint64(0xD1B54A32D192ED03)) >> np.uint64(11)) + 0.5
        u2 *= scale
        r = math.sqrt(-2.0 * math.log(u1))
        out[i, 0] = r * math.cos(2.0 * math.pi * u2)
        out[i, 1] = r * math.sin(2.0 * math.pi * u2)


def mode_normals(seed: int, mx: ArrayLike, my: ArrayLike) -> np.ndarray:
    """Standard normal pairs (xi_r, xi_i) of lattice modes with integer indices (mx, my).

    A counter-based hash (SplitMix64) of ``seed`` and the indices: the same mode gets the same
    numbers whatever the resolution, the patch, the order of evaluation or the machine.

    Returns
    -------
    (..., 2) float64, the shape of ``mx`` plus 2.
    """
    mx = np.asarray(mx, dtype=np.int64)
    my = np.asarray(my, dtype=np.int64)
    mx, my = np.broadcast_arrays(mx, my)
    out = np.empty((mx.size, 2))
    _mode_normals(int(seed), mx.ravel(), my.ravel(), out)
    return out.reshape(mx.shape + (2,))


def _check_seed(seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not (0 <= seed < 2**63):
        raise ArgumentError(f"seed must be an integer in [0, 2^63), got {seed!r}")
    return int(seed)


# --- the patch ----------------------------------------------------------------------------------
