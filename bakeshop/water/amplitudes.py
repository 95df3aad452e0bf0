"""Deterministic amplitudes of an ocean's lattice modes: standard normals from a counter-based hash
(SplitMix64) of the seed and each mode's integer indices, the same on any machine, at any
resolution and in any order of evaluation (the kernel: ``src/water/amplitudes.hpp``)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError
from bakeshop.water import _native


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
    _native.mode_normals(int(seed), mx.ravel(), my.ravel(), out)
    return out.reshape(mx.shape + (2,))


def _check_seed(seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not (0 <= seed < 2**63):
        raise ArgumentError(f"seed must be an integer in [0, 2^63), got {seed!r}")
    return int(seed)


# --- the patch ----------------------------------------------------------------------------------
