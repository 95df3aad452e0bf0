"""Exact hydrostatics of a closed mesh in calm water: displaced volume and Archimedes draft.

The volume of a closed mesh below the plane y = c is the sum of signed tetrahedra between a
point O on the plane and the parts of the triangles below it (divergence theorem). The cap that
closes the cut lies in the plane, so its tetrahedra with O are flat: no cap triangulation is
needed, and the result is exact up to rounding.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from bakeshop.errors import ArgumentError

#: Density of water, kg/m^3 (DESIGN.md).
RHO_WATER = 1000.0
#: Gravitational acceleration, m/s^2 (DESIGN.md).
GRAVITY = 9.81


def submerged_volume(triangles: np.ndarray, level: float) -> float:
    """Volume (m^3) of the closed mesh ``triangles`` (T, 3, 3) below the plane ``y = level``."""
    tri = np.asarray(triangles, dtype=np.float64) - np.array([0.0, level, 0.0])
    below = tri[:, :, 1] < 0.0
    n_below = below.sum(axis=1)
    total = _tetra(tri[n_below == 3]).sum()
    for count, odd in ((1, True), (2, False)):
        sel = tri[n_below == count]
        b = below[n_below == count]
        first = np.argmax(b if odd else ~b, axis=1)  # the vertex alone on its side
        roll = (first[:, None] + np.arange(3)) % 3
        p = np.take_along_axis(sel, roll[:, :, None], axis=1)
        a, bb, c = p[:, 0], p[:, 1], p[:, 2]
        ab = _cut(a, bb)
        ac = _cut(a, c)
        if odd:  # a below: keep triangle (a, ab, ac)
            total += _tetra(np.stack([a, ab, ac], axis=1)).sum()
        else:  # a above: keep quad (ab, b, c, ac)
            total += _tetra(np.stack([ab, bb, c], axis=1)).sum()
            total += _tetra(np.stack([ab, c, ac], axis=1)).sum()
    return float(total)


def archimedes_draft(
    triangles: np.ndarray, mass: float, *, rho_water: float = RHO_WATER
) -> float | None:
    """Draft (m) at which the mesh, held in its given orientation, displaces ``mass`` of water.

    Solves ``submerged_volume(level) = mass / rho_water`` for the water level by Brent's method
    and returns ``level - lowest vertex``. Returns ``None`` when the body is too dense to float.

    Parameters
    ----------
    triangles : (T, 3, 3) float64
        Closed, outward-oriented mesh in metres, posed as it floats (+Y up).
    mass : float
        kg.
    """
    tri = np.asarray(triangles, dtype=np.float64)
    if not (np.isfinite(mass) and mass > 0):
        raise ArgumentError(f"mass must be positive, got {mass!r}")
    lo, hi = tri[:, :, 1].min(), tri[:, :, 1].max()
    target = mass / rho_water
    if target >= submerged_volume(tri, hi):
        return None
    level = brentq(lambda c: submerged_volume(tri, c) - target, lo, hi, xtol=1e-12, rtol=1e-12)
    return float(level - lo)


def _cut(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Point where segment a-b crosses y = 0 (the two ends are on opposite sides)."""
    t = a[:, 1] / (a[:, 1] - b[:, 1])
    return a + t[:, None] * (b - a)


def _tetra(tri: np.ndarray) -> np.ndarray:
    """Signed volumes of the tetrahedra (origin, t0, t1, t2); the origin lies on the plane."""
    return np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0


def waterplane_area(triangles: np.ndarray, level: float, *, step: float = 1e-4) -> float:
    """Area (m^2) of the mesh's cut by the plane ``y = level``: dV/dlevel (central difference of
    the exact :func:`submerged_volume`, ``step`` in metres)."""
    return (
        submerged_volume(triangles, level + step) - submerged_volume(triangles, level - step)
    ) / (2 * step)
