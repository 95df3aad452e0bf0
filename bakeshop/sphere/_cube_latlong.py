"""The area filter's exact deposits of a cube texel into a latlong's texels: its overlaps
with them, integrated (see :mod:`bakeshop.sphere._area_kernels`, whose ``splat_exceptions``
calls this for every texel of a cube cut into parts on its way to a latlong).

Cutting a texel into parts small enough for box deposits approximates its overlaps (a 64^2
cube into a 128x64 latlong: 1.3e-2 RRMS off the brute-force area average, 2.6e-3 with these)
and is slow where a texel is long: around a latlong's poles, where a texel covers a few rows
and up to thousands of columns (34 k texels of a 6 x 1024^2 cube made 26 M parts).

The compiled ``latlong_taps`` (``src/sphere/cube_latlong.hpp``, bound in
:mod:`bakeshop.sphere._native`) is the same arithmetic, bit for bit; these numba functions stay
only while the area filter's numba ``splat_exceptions`` calls them, and go with it."""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy import ndarray

from bakeshop.sphere._maps import direction, rotate

#: a cube texel's overlaps are integrated when every corner is in one hemisphere, at least
#: this far from the equator (|y|: its gnomonic image at most 50 from the pole's tangent point;
#: the texels across the equator are cut into parts).
AREA_EXACT_Y = 0.02
#: the nodes of 2-point Gauss-Legendre on [-1, 1] (both weights 1).
_GAUSS_NODES = np.array([-math.sqrt(1 / 3), math.sqrt(1 / 3)])

_jit = numba.njit(cache=True, error_model="numpy")


@_jit
def _chord(px: ndarray, py: ndarray, orient: float, cp: float, sp: float) -> tuple[float, float]:
    """Where the ray from the origin towards (cp, sp) is inside the convex quadrilateral
    (``px``, ``py``; ``orient`` the sign of its area): its distances (lo, hi), lo >= hi if
    nowhere."""
    lo, hi = 0.0, math.inf
    for k in range(4):
        ex, ey = px[(k + 1) % 4] - px[k], py[(k + 1) % 4] - py[k]
        # inside: orient * cross(e, t u - v) >= 0, that is t alpha >= beta
        alpha = orient * (ex * sp - ey * cp)
        beta = orient * (ex * py[k] - ey * px[k])
        if alpha > 0:
            lo = max(lo, beta / alpha)
        elif alpha < 0:
            hi = min(hi, beta / alpha)
        elif beta > 0:
            return 0.0, 0.0
    return lo, hi


@_jit
def _segment_distance(ax: float, ay: float, bx: float, by: float) -> float:
    """Distance from the origin to the segment from (ax, ay) to (bx, by)."""
    ex, ey = bx - ax, by - ay
    t = min(1.0, max(0.0, -(ax * ex + ay * ey) / (ex * ex + ey * ey)))
    return math.hypot(ax + t * ex, ay + t * ey)


@_jit
def _longitude(x: float, y: float, around: bool, centre: float) -> float:
    """The longitude of point (x, y) of the tangent plane in the turn of the columns: within pi
    of ``centre`` unless ``around`` (in (-pi, pi] then)."""
    phi = math.atan2(y, x)
    return phi if around else centre + (phi - centre + math.pi) % (2 * math.pi) - math.pi


@_jit
def _crossings(ax: float, ay: float, bx: float, by: float, radius: float, around: bool,
               centre: float, breaks: ndarray, n: int) -> int:  # fmt: skip
    """Append to ``breaks[n:]`` the longitudes where the segment from (ax, ay) to (bx, by)
    crosses the circle of ``radius`` (in the turn of the columns: within pi of ``centre``
    unless ``around``); returns the new count."""
    ex, ey = bx - ax, by - ay
    ee, ae = ex * ex + ey * ey, ax * ex + ay * ey
    disc = ae * ae - ee * (ax * ax + ay * ay - radius * radius)
    if not (disc > 0 and ee > 0):  # an infinite radius too
        return n
    for t in ((-ae - math.sqrt(disc)) / ee, (-ae + math.sqrt(disc)) / ee):
        if 0 < t < 1:
            breaks[n] = _longitude(ax + t * ex, ay + t * ey, around, centre)
            n += 1
    return n


@_jit
def _overlaps(px: ndarray, py: ndarray, orient: float, breaks: ndarray, a: float, b: float,
              radii: ndarray, out: ndarray) -> None:  # fmt: skip
    """Add to ``out[r]`` the solid angle of the quadrilateral's part between longitudes a < b
    and radii ``radii[r]`` to ``radii[r + 1]``: the integral of 1 / sqrt(1 + lo^2) -
    1 / sqrt(1 + hi^2) over the longitudes, piece by piece between ``breaks`` (sorted: the
    longitudes of its corners and of its edges' crossings of the rings, between which the
    clipped chord's ends follow one curve each, smoothly), each piece by 2-point
    Gauss-Legendre."""
    lo_end = a
    for k in range(breaks.shape[0] + 1):
        hi_end = b if k == breaks.shape[0] else min(b, breaks[k])
        if hi_end > lo_end:
            mid, half = 0.5 * (lo_end + hi_end), 0.5 * (hi_end - lo_end)
            for g in range(2):
                phi = mid + half * _GAUSS_NODES[g]
                lo, hi = _chord(px, py, orient, math.cos(phi), math.sin(phi))
                if hi > lo:
                    for r in range(out.shape[0]):
                        near, far = max(lo, radii[r]), min(hi, radii[r + 1])
                        if far > near:
                            out[r] += half * (
                                1 / math.sqrt(1 + near * near) - 1 / math.sqrt(1 + far * far)
                            )
            lo_end = hi_end


@_jit
def latlong_taps(skind: int, sh: int, sw: int, f: int, i: int, j: int, rot: ndarray, dh: int,
                 dw: int, om: float, o: int, room: int, taps: ndarray,
                 weights: ndarray) -> int:  # fmt: skip
    """Source cube texel (f, i, j)'s overlaps with the texels of a latlong destination
    (``dh`` x ``dw``) at ``o`` onwards, at most ``room`` of them, in increasing order, weights
    scaled to sum ``om``; -1 where it does not apply (its corners not all in one hemisphere,
    AREA_EXACT_Y from the equator, or more overlaps than ``room``).

    A cube texel's edges are great circles, so its gnomonic image on the pole's tangent plane,
    P = (-z, x) / |y| (the longitude is P's angle, tan of the angle from the pole its length),
    is a convex quadrilateral, and a latlong texel is an annular sector there. With
    dOmega = r dr dphi / (1 + r^2)^(3/2), the overlap is the integral over the sector's
    longitudes of 1 / sqrt(1 + lo^2) - 1 / sqrt(1 + hi^2), [lo, hi] the ray's chord through the
    quadrilateral clipped to the sector's radii (:func:`_overlaps`): to 1e-5 of the texel's
    solid angle."""
    corner_data = np.empty(12)
    px, py, corners = corner_data[:4], corner_data[4:8], corner_data[8:]
    sign = 0.0
    for k in range(4):
        corner_x = i + 1 if k == 1 or k == 2 else i
        x, y, z = direction(skind, sh, sw, f, corner_x, j + 1 if k >= 2 else j)
        x, y, z = rotate(rot.T, x, y, z)
        if not abs(y) >= AREA_EXACT_Y or y * sign < 0:
            return -1
        sign = 1.0 if y > 0 else -1.0
        px[k], py[k] = -z / abs(y), x / abs(y)
    area = 0.0
    for k in range(4):
        area += px[k] * py[(k + 1) % 4] - px[(k + 1) % 4] * py[k]
    orient = 1.0 if area > 0 else -1.0
    # the radii and longitudes the quadrilateral spans (all longitudes round the pole), the
    # corners' longitudes in the same turn as the columns' (unwrapped: c0 may be out of range)
    r_min, r_max, around = math.inf, 0.0, True
    for k in range(4):
        n = (k + 1) % 4
        r_max = max(r_max, math.hypot(px[k], py[k]))
        r_min = min(r_min, _segment_distance(px[k], py[k], px[n], py[n]))
        around &= orient * (px[n] - px[k]) * py[k] - orient * (py[n] - py[k]) * px[k] <= 0
    centre = 0.0
    if not around:
        centre = math.atan2(py.sum(), px.sum())
    for k in range(4):
        corners[k] = _longitude(px[k], py[k], around, centre)
    if around:
        r_min, c0, count = 0.0, 0, dw
    else:
        c0 = int(math.floor((corners.min() / (2 * math.pi) + 0.5) * dw))
        count = min(dw, int(math.floor((corners.max() / (2 * math.pi) + 0.5) * dw)) - c0 + 1)
    # the rows between those radii: colatitude atan r from the north pole, pi - atan r south
    t0, t1 = math.atan(r_min) / math.pi * dh, math.atan(r_max) / math.pi * dh
    if sign < 0:
        t0, t1 = dh - t1, dh - t0
    j0, j1 = max(0, int(math.floor(t0))), min(dh - 1, int(math.floor(t1)))
    rows = j1 - j0 + 1
    if rows * count > room:
        return -1
    # the rows' rings, out from the pole (row j0 + r north, j1 - r south): radii tan of the
    # angle from the pole (infinite past the equator)
    scratch = np.zeros(9 * rows + 13 + count * rows)
    radii, breaks = scratch[: rows + 1], scratch[rows + 1 : 9 * rows + 13]
    window = scratch[9 * rows + 13 :].reshape((count, rows))
    breaks[:4] = corners
    found = 4
    for r in range(rows + 1):
        a = math.pi * (j0 + r if sign > 0 else dh - j1 - 1 + r) / dh
        radii[r] = math.tan(a) if a < 0.5 * math.pi else math.inf
        for k in range(4):
            found = _crossings(px[k], py[k], px[(k + 1) % 4], py[(k + 1) % 4], radii[r],
                               around, centre, breaks, found)  # fmt: skip
    breaks = breaks[:found]
    breaks.sort()
    dphi = 2 * math.pi / dw
    for m in range(count):
        phi = dphi * (c0 + m) - math.pi
        _overlaps(px, py, orient, breaks, phi, phi + dphi, radii, window[m])
    # column c0 + m is texel (c0 + m) % dw: increasing from m = dw - (c0 % dw), then from 0
    start = dw - c0 % dw
    n, total = 0, 0.0
    for row in range(j0, j1 + 1):
        r = row - j0 if sign > 0 else j1 - row
        for m0, m1 in ((start, count), (0, min(start, count))):
            for m in range(m0, m1):
                w = window[m, r]
                if w > 0:
                    taps[o + n] = row * dw + (c0 + m) % dw
                    weights[o + n] = w
                    total += w
                    n += 1
    if not total > 0:
        return -1
    for e in range(o, o + n):
        weights[e] = weights[e] * (om / total)
    return n
