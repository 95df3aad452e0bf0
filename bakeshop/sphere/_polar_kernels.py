"""The area filter's exact deposits of cube texels around a latlong destination's poles, where
a texel covers a few rows but tens to thousands of columns (a polar cap is as many texels
round as the whole equator): cut into parts small enough for box deposits, 34 k such texels
of a 6 x 1024^2 cube made 26 M parts for 1.6 M matrix entries (see
:mod:`bakeshop.sphere._area_kernels`, whose ``splat_exceptions`` calls this)."""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy import ndarray

from bakeshop.sphere._maps import direction, rotate

#: a cube texel takes the exact path when every corner is within 60 degrees of the pole
#: (|y| >= 1/2: its gnomonic image at most tan 60 = 1.7 from the pole's tangent point).
AREA_POLAR_Y = 0.5
#: longitudes per destination texel in the exact overlaps' integral (midpoint rule).
AREA_POLAR_SAMPLES = 8

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
def polar_taps(skind: int, sh: int, sw: int, f: int, i: int, j: int, rot: ndarray, dh: int,
               dw: int, om: float, o: int, room: int, taps: ndarray,
               weights: ndarray) -> int:  # fmt: skip
    """Source cube texel (f, i, j)'s overlaps with the texels of a latlong destination
    (``dh`` x ``dw``) at ``o`` onwards, at most ``room`` of them, in increasing order, weights
    scaled to sum ``om``; -1 where it does not apply (a corner more than 60 degrees from the
    pole its centre is nearer, or more overlaps than ``room``).

    A cube texel's edges are great circles, so its gnomonic image on the pole's tangent plane,
    P = (-z, x) / |y| (the longitude is P's angle, tan of the angle from the pole its length),
    is a convex quadrilateral, and a latlong texel is an annular sector there. With
    dOmega = r dr dphi / (1 + r^2)^(3/2), the overlap is the integral over the sector's
    longitudes of 1 / sqrt(1 + lo^2) - 1 / sqrt(1 + hi^2), [lo, hi] the ray's chord through the
    quadrilateral clipped to the sector's radii: by the midpoint rule, AREA_POLAR_SAMPLES
    longitudes per destination texel."""
    px, py = np.empty(4), np.empty(4)
    sign = 0.0
    for k in range(4):
        corner_x = i + 1 if k == 1 or k == 2 else i
        x, y, z = direction(skind, sh, sw, f, corner_x, j + 1 if k >= 2 else j)
        x, y, z = rotate(rot.T, x, y, z)
        if not abs(y) >= AREA_POLAR_Y or y * sign < 0:
            return -1
        sign = 1.0 if y > 0 else -1.0
        px[k], py[k] = -z / abs(y), x / abs(y)
    area = 0.0
    for k in range(4):
        area += px[k] * py[(k + 1) % 4] - px[(k + 1) % 4] * py[k]
    orient = 1.0 if area > 0 else -1.0
    # the radii and longitudes the quadrilateral spans (all longitudes round the pole)
    r_min, r_max, around = math.inf, 0.0, True
    for k in range(4):
        n = (k + 1) % 4
        r_max = max(r_max, math.hypot(px[k], py[k]))
        r_min = min(r_min, _segment_distance(px[k], py[k], px[n], py[n]))
        around &= orient * (px[n] - px[k]) * py[k] - orient * (py[n] - py[k]) * px[k] <= 0
    if around:
        r_min, c0, count = 0.0, 0, dw
    else:
        centre = math.atan2(py.sum(), px.sum())
        low, high = math.inf, -math.inf
        for k in range(4):
            d = (math.atan2(py[k], px[k]) - centre + math.pi) % (2 * math.pi) - math.pi
            low, high = min(low, d), max(high, d)
        u0 = ((centre + low) / (2 * math.pi) + 0.5) * dw
        u1 = ((centre + high) / (2 * math.pi) + 0.5) * dw
        c0 = int(math.floor(u0))
        count = min(dw, int(math.floor(u1)) - c0 + 1)
        c0 %= dw
    # the rows between those radii: colatitude atan r from the north pole, pi - atan r south
    t0, t1 = math.atan(r_min) / math.pi * dh, math.atan(r_max) / math.pi * dh
    if sign < 0:
        t0, t1 = dh - t1, dh - t0
    j0, j1 = max(0, int(math.floor(t0))), min(dh - 1, int(math.floor(t1)))
    # the columns in increasing order: [c0, c0 + count), wrapped round into two runs
    runs = ((c0, min(dw, c0 + count)), (0, max(0, c0 + count - dw)))
    dphi = 2 * math.pi / dw
    n, total = 0, 0.0
    for jd in range(j0, j1 + 1):
        a0, a1 = math.pi * jd / dh, math.pi * (jd + 1) / dh
        if sign < 0:
            a0, a1 = math.pi - a1, math.pi - a0
        ra = math.tan(a0)
        rb = math.tan(a1) if a1 < 0.5 * math.pi else math.inf
        for run in (runs[1], runs[0]):
            for c in range(run[0], run[1]):
                w = 0.0
                for s in range(AREA_POLAR_SAMPLES):
                    phi = dphi * (c + (s + 0.5) / AREA_POLAR_SAMPLES) - math.pi
                    lo, hi = _chord(px, py, orient, math.cos(phi), math.sin(phi))
                    lo, hi = max(lo, ra), min(hi, rb)
                    if hi > lo:
                        w += 1 / math.sqrt(1 + lo * lo) - 1 / math.sqrt(1 + hi * hi)
                if w > 0:
                    if n == room:
                        return -1
                    taps[o + n] = jd * dw + c
                    weights[o + n] = w
                    total += w
                    n += 1
    if not total > 0:
        return -1
    for e in range(o, o + n):
        weights[e] = weights[e] * (om / total)
    return n
