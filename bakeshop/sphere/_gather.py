"""The remap plan and gather kernels: nearest and seam-aware bilinear taps, built once per
(source, destination, rotation) and applied as one parallel gather (see
:mod:`bakeshop.sphere.sampling`).

The kernels are compiled (``src/sphere/gather.hpp``, bound in :mod:`bakeshop.sphere._native`);
this module names them for the callers outside the sampling code and holds the plan's
:data:`EXCEPTION` marker.
"""

from __future__ import annotations

import numba

from bakeshop.sphere._maps import is_cubic, is_disk, valid
from bakeshop.sphere._native import (
    gather_at,
    gather_bilinear,
    gather_nearest,
    gather_plan,
    gather_plan_clamped,
    plan,
    plan_exceptions,
    reorder_plan,
    taps_of,
)

__all__ = [
    "EXCEPTION",
    "block",
    "gather_at",
    "gather_bilinear",
    "gather_nearest",
    "gather_plan",
    "gather_plan_clamped",
    "plan",
    "plan_exceptions",
    "reorder_plan",
    "taps_of",
]

#: a remap plan's base index for a texel whose taps are not a 2x2 block (seams, rims, corners):
#: ``EXCEPTION - k`` points at row ``k`` of the plan's explicit taps.
EXCEPTION = -2

_jit = numba.njit(cache=True, error_model="numpy")


# the numba twin of gather.hpp's block, for the area filter's numba kernels (area.py,
# _area_kernels.py) until they are compiled too
@_jit
def block(kind: int, h: int, w: int, f: float, i0: int, j0: int, size: int) -> int:
    """Flat index of texel (f, i0, j0) when the size x size block from it holds ordinary
    texels of one image (one face, one disk, all valid), else -1: then ``resolve`` of block
    texel (a, b) is simply that index + b w + a."""
    if i0 < 0 or j0 < 0 or i0 + size > w or j0 + size > h:
        return -1
    if is_cubic(kind):
        return (int(f) * h + j0) * w + i0
    if is_disk(kind):
        n = h
        li = i0 % n
        if li + size > n:
            return -1
        for dj in range(size):
            for di in range(size):
                if not valid(kind, h, w, 0, li + di, j0 + dj):
                    return -1
    return j0 * w + i0
