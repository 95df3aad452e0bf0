"""The one area filter kernel still in numba: a cube's texels' exact overlaps with a latlong's
(``_cube_latlong.latlong_taps``), run before the compiled ``splat_exceptions``
(``src/sphere/area.hpp``), which takes them (``latlong_done``) and deposits the rest. It goes
when ``_cube_latlong`` is compiled (then ``splat_exceptions`` calls it directly)."""

from __future__ import annotations

import numba
from numpy import ndarray

from bakeshop.sphere._cube_latlong import latlong_taps


@numba.njit(parallel=True, cache=True, error_model="numpy")
def cube_latlong_taps(skind: int, sh: int, sw: int, omega: ndarray, dh: int, dw: int, rot: ndarray,
                      where: ndarray, parts: ndarray, offsets: ndarray, taps: ndarray,
                      weights: ndarray, counts: ndarray) -> None:  # fmt: skip
    """Texel k of ``where`` (a cube's, cut into parts): its exact overlaps with the latlong's
    texels at ``offsets[k]`` onwards, ``counts[k]`` of them (-1 where they do not apply, or
    where the texel is not cut)."""
    for k in numba.prange(where.shape[0]):
        p = where[k]
        f, r = divmod(p, sh * sw)
        j, i = divmod(r, sw)
        nx, ny = parts[p, 0], parts[p, 1]
        n = -1
        if max(nx, ny) > 1:
            n = latlong_taps(skind, sh, sw, f, i, j, rot, dh, dw, omega[p], offsets[k],
                             4 * nx * ny, taps, weights)  # fmt: skip
        counts[k] = n
