"""The octahedral map (Engelhardt and Dachsbacher 2008)."""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np

from bakeshop.errors import ArgumentError
from bakeshop.sphere import _kinds
from bakeshop.sphere.layouts.base import (
    Layout,
)


class Octahedral(Layout):
    """Octahedral map (Engelhardt and Dachsbacher 2008), +Y at the centre.

    With ``a = 2u - 1`` (toward +X) and ``c = 2v - 1`` (toward +Z, so the top of the picture
    looks forward, -Z): inside the diamond ``|a| + |c| <= 1`` the octahedron point is
    ``(a, 1 - |a| - |c|, c)``; outside it the lower half is folded out,
    ``(sgn(a) (1 - |c|), 1 - |a| - |c|, sgn(c) (1 - |a|))``; ``d`` is that point normalised. The
    map is piecewise affine onto the octahedron, so each texel is two planar triangles whose
    solid angles are exact (Van Oosterom and Strackee 1983). Sizes must be even (the folds then
    run along texel edges and diagonals).
    """

    name = "octahedral"
    kind = _kinds.OCTAHEDRAL

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, n))

    def _check(self, shape: tuple[int, ...]) -> None:
        if len(shape) != 2 or shape[0] != shape[1] or shape[0] % 2:
            raise ArgumentError(
                f"an octahedral image must be square with an even edge; got (H, W) = {shape}"
            )

    def default_size(self, texels: int) -> int:
        return max(2, 2 * round(np.sqrt(texels) / 2))

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        n, _ = self.check_shape(shape)
        return _octahedral_solid_angles(n)


def _triangle_solid_angle(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Solid angle of the planar triangle pqr seen from the origin (Van Oosterom and Strackee,
    IEEE Trans. Biomed. Eng. 30 (1983) 125, doi:10.1109/TBME.1983.325207)."""
    lp, lq, lr = (np.linalg.norm(v, axis=-1) for v in (p, q, r))
    det = np.abs(np.einsum("...i,...i", p, np.cross(q, r)))
    den = (
        lp * lq * lr
        + np.einsum("...i,...i", p, q) * lr
        + np.einsum("...i,...i", p, r) * lq
        + np.einsum("...i,...i", q, r) * lp
    )
    return 2 * np.arctan2(det, den)


@functools.lru_cache(maxsize=8)
def _octahedral_solid_angles(n: int) -> np.ndarray:
    # the texel corners' directions (a triangle's solid angle depends only on its vertices'
    # directions: its edges project onto great circles)
    corners = np.arange(n + 1.0)
    x, y = np.meshgrid(corners, corners)
    d = Octahedral().directions_at(np.stack([x, y], axis=-1), (n, n))
    pts = {"00": d[:-1, :-1], "10": d[:-1, 1:], "01": d[1:, :-1], "11": d[1:, 1:]}
    e = 2 * np.arange(n + 1) / n - 1
    a0, a1 = e[None, :-1], e[None, 1:]
    c0, c1 = e[:-1, None], e[1:, None]
    # split each texel along the diagonal parallel to its quadrant's fold |a| + |c| = 1
    ac = (a0 + a1) * (c0 + c1) > 0
    anti = _triangle_solid_angle(pts["01"], pts["10"], pts["00"]) + _triangle_solid_angle(
        pts["01"], pts["10"], pts["11"]
    )
    main = _triangle_solid_angle(pts["00"], pts["11"], pts["10"]) + _triangle_solid_angle(
        pts["00"], pts["11"], pts["01"]
    )
    omega = np.where(ac, anti, main)
    omega.setflags(write=False)
    return omega
