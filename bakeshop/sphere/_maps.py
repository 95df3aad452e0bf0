"""The layouts' maps as scalar numba functions, for the numba kernels not yet compiled.

The one implementation of each formula is ``src/sphere/maps.hpp`` (same names, same
arithmetic, bit for bit), which the layouts, the remap plans and gathers, the windows and the
texel kernels run through :mod:`bakeshop.sphere._native`. These numba twins stay only while
numba kernels call them: the area filter's (:mod:`bakeshop.sphere._area_kernels`,
:mod:`bakeshop.sphere.area`, :mod:`bakeshop.sphere._cube_latlong`, ``_gather.block``) and, through
:mod:`bakeshop.sphere.kernels`, the specular prefilter's; they go with the last of them.

A layout is named here by a kind number and two integers ``(h, w)`` (a cube: ``h = w = S``).
Texel coordinates are ``(face, x, y)`` with texel ``i``'s centre at ``x = i + 0.5``; flat
layouts have face 0.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from bakeshop.sphere._kinds import (
    ANGULAR,
    ANGULAR_PHYSICAL,
    CUBE,
    DISK_OVERLAP_EPS,
    DUAL_PARABOLOID,
    LATLONG,
    MIRRORBALL,
    MIRRORBALL_PHYSICAL,
    OCTAHEDRAL,
    OPENEXR_CUBE,
    OPENEXR_LATLONG,
)
from bakeshop.sphere.cube import FACE_BASES, OPENEXR_FACE_BASES

_BASES = np.ascontiguousarray(FACE_BASES)
_EXR_BASES = np.ascontiguousarray(OPENEXR_FACE_BASES)
_jit = numba.njit(cache=True, error_model="numpy")


@numba.njit(cache=True, inline="always")
def is_disk(kind: int) -> bool:
    """Whether layout ``kind`` is made of disks (angular, mirror ball, dual paraboloid)."""
    return (
        kind == ANGULAR
        or kind == MIRRORBALL
        or kind == DUAL_PARABOLOID
        or kind == ANGULAR_PHYSICAL
        or kind == MIRRORBALL_PHYSICAL
    )


@numba.njit(cache=True, inline="always")
def is_cubic(kind: int) -> bool:
    """Whether layout ``kind`` is six square faces (``h = w = S``, face axis ``f``): the
    OpenGL cube and OpenEXR's cube environment."""
    return kind == CUBE or kind == OPENEXR_CUBE


@numba.njit(cache=True, inline="always")
def _cube_scale(kind: int, n: int) -> int:
    """Texel centres per face edge minus what the face coordinate's [-1, 1] spans in texels:
    OpenGL's faces span their S texels' outer edges, OpenEXR's their first and last texel
    centres (ImfEnvmap: position ``p`` of ``S`` is ``2 p / (S - 1) - 1``)."""
    return n if kind == CUBE else n - 1


@numba.njit(cache=True, inline="always")
def _cube_offset(kind: int) -> float:
    return 0.0 if kind == CUBE else 0.5


# --- arctangent -------------------------------------------------------------------------------

#: atan(t) / t as a polynomial in t^2 for |t| <= tan(pi / 12) (least squares on Chebyshev nodes;
#: atan within 2e-14 rad).
_A0, _A1, _A2, _A3, _A4, _A5, _A6 = (
    0.9999999999999367,
    -0.3333333332462878,
    0.19999998048207981,
    -0.14285549688091495,
    0.11104470935202516,
    -0.0895215121939283,
    0.062219062319738394,
)
_TAN_PI_12 = 2.0 - math.sqrt(3.0)
_SQRT3 = math.sqrt(3.0)


@_jit
def atan2(y: float, x: float) -> float:
    """``math.atan2(y, x)`` within 2e-14 rad (signed zeros as libm; NaN or infinite input: NaN).

    Branch-free (selects only), so that loops over it vectorise (its speed against libm's is in
    docs/BENCHMARKS.md, remap). Reduction to ``t = min / max`` in [0, 1], then to
    ``|t| <= tan(pi/12)`` by ``atan(t) = pi/6 + atan((sqrt(3) t - 1) / (t + sqrt(3)))``, then a
    degree-13 odd polynomial.
    """
    ax, ay = abs(x), abs(y)
    swap = ay > ax
    t = min(ax, ay) / max(max(ax, ay), 1e-300)
    reduce = t > _TAN_PI_12
    t = (t * _SQRT3 - 1.0) / (t + _SQRT3) if reduce else t
    q = t * t
    p = (((((_A6 * q + _A5) * q + _A4) * q + _A3) * q + _A2) * q + _A1) * q + _A0
    r = t * p + (math.pi / 6 if reduce else 0.0)
    r = math.pi / 2 - r if swap else r
    r = math.pi - r if math.copysign(1.0, x) < 0.0 else r
    # x - x is NaN for NaN or infinite x, else 0
    return math.copysign(r + (x - x) + (y - y), y)


@numba.njit(cache=True, error_model="numpy", inline="always")
def latlong_xy(h: int, w: int, x: float, y: float, z: float) -> tuple[float, float]:
    """A latlong's continuous coordinates (x, y) of direction (x, y, z): longitude
    ``phi = atan2(x, -z)``, colatitude ``theta = atan2(hypot(x, z), y)``."""
    phi = atan2(x, -z)
    theta = atan2(math.sqrt(x * x + z * z), y)
    return (phi / (2 * math.pi) + 0.5) * w, theta / math.pi * h


# --- directions at coordinates ------------------------------------------------------------------


@_jit
def _disk_direction(kind: int, a: float, b: float, disk: int) -> tuple[float, float, float]:
    """Direction of disk point (a, b) (b up); valid beyond the rim for angular (theta > pi) and
    dual-paraboloid (the other hemisphere); the mirror ball is clamped to its rim.

    Angular and mirror ball: ``(a/r sin theta, b/r sin theta, -cos theta)`` (HDRShop: centre
    -Z), ``theta = pi r`` (angular) or ``r = sin(theta / 2)`` (mirror ball); their physical
    variants have ``+cos theta`` (centre +Z)."""
    r2 = a * a + b * b
    if kind == ANGULAR or kind == ANGULAR_PHYSICAL:
        r = math.sqrt(r2)
        s = math.pi if r == 0.0 else math.sin(math.pi * r) / r
        c = math.cos(math.pi * r)
        # HDRShop: the centre looks forward (-Z); the physical reflection: behind (+Z)
        return a * s, b * s, c if kind == ANGULAR_PHYSICAL else -c
    if kind == MIRRORBALL or kind == MIRRORBALL_PHYSICAL:
        r2 = min(r2, 1.0)
        nz = math.sqrt(1.0 - r2)
        c = 1.0 - 2 * r2
        return 2 * nz * a, 2 * nz * b, c if kind == MIRRORBALL_PHYSICAL else -c
    k = 1.0 / (1.0 + r2)
    side = -1.0 if disk == 0 else 1.0
    return -side * 2 * a * k, 2 * b * k, side * (1.0 - r2) * k


@_jit
def _octahedron_point(a: float, c: float) -> tuple[float, float, float]:
    aa, ac = abs(a), abs(c)
    y = 1.0 - aa - ac
    if y >= 0:
        return a, y, c
    sa = -1.0 if a < 0 else 1.0
    sc = -1.0 if c < 0 else 1.0
    return sa * (1.0 - ac), y, sc * (1.0 - aa)


@_jit
def direction(
    kind: int, h: int, w: int, f: float, x: float, y: float
) -> tuple[float, float, float]:
    """Unit direction at coordinates (f, x, y). Outside a disk: the disk's nearest point."""
    if kind == LATLONG:
        phi = 2 * math.pi * (x / w - 0.5)
        theta = math.pi * y / h
        st = math.sin(theta)
        return st * math.sin(phi), math.cos(theta), -st * math.cos(phi)
    if kind == OPENEXR_LATLONG:
        # ImfEnvmap: the first and last columns' centres are longitude +pi and -pi, the first
        # and last rows' latitude +pi/2 and -pi/2; longitude 0 is +Z, pi/2 is +X
        lon = -2 * math.pi * ((x - 0.5) / (w - 1) - 0.5)
        lat = -math.pi * ((y - 0.5) / (h - 1) - 0.5)
        cl = math.cos(lat)
        return math.sin(lon) * cl, math.sin(lat), math.cos(lon) * cl
    if is_cubic(kind):
        return _face_direction(kind, w, min(max(int(f), 0), 5), x, y)
    if kind == OCTAHEDRAL:
        dx, dy, dz = _octahedron_point(2 * x / w - 1, 2 * y / h - 1)
    else:
        n = h
        disk = min(max(math.floor(x / n), 0), w // n - 1)
        a = 2 * (x - disk * n) / n - 1
        b = 1 - 2 * y / n
        r2 = a * a + b * b
        if r2 > 1:
            r = math.sqrt(r2)
            a /= r
            b /= r
        dx, dy, dz = _disk_direction(kind, a, b, disk)
    norm = math.sqrt(dx * dx + dy * dy + dz * dz)
    return dx / norm, dy / norm, dz / norm


@numba.njit(cache=True, error_model="numpy", inline="always")
def _face_direction(kind: int, w: int, fi: int, x: float, y: float) -> tuple[float, float, float]:
    """``direction`` at (fi, x, y) of a cube of face edge ``w``: N + sc U + tc V, normalised."""
    n = _cube_scale(kind, w)
    o = _cube_offset(kind)
    sc = 2 * (x - o) / n - 1
    tc = 2 * (y - o) / n - 1
    bases = _BASES if kind == CUBE else _EXR_BASES
    dx = bases[fi, 0, 0] + sc * bases[fi, 1, 0] + tc * bases[fi, 2, 0]
    dy = bases[fi, 0, 1] + sc * bases[fi, 1, 1] + tc * bases[fi, 2, 1]
    dz = bases[fi, 0, 2] + sc * bases[fi, 1, 2] + tc * bases[fi, 2, 2]
    norm = math.sqrt(dx * dx + dy * dy + dz * dz)
    return dx / norm, dy / norm, dz / norm


# --- coordinates of directions ------------------------------------------------------------------


@_jit
def cube_face(x: float, y: float, z: float) -> tuple[int, float, float]:
    """OpenGL's major-axis rule: (face, sc, tc), sc and tc in [-1, 1] (ties: x, then y)."""
    return _major_face(_BASES, x, y, z)


@_jit
def _major_face(bases: np.ndarray, x: float, y: float, z: float) -> tuple[int, float, float]:
    """(face, sc, tc) of the face table ``bases`` (``N + sc U + tc V``) by the major axis; the
    face order and tie rule are OpenGL's and ImfEnvmap's alike (ties: x, then y)."""
    ax, ay, az = abs(x), abs(y), abs(z)
    if ax >= ay and ax >= az:
        f, ma = (0 if x >= 0 else 1), ax
    elif ay >= az:
        f, ma = (2 if y >= 0 else 3), ay
    else:
        f, ma = (4 if z >= 0 else 5), az
    if ma == 0:
        ma = 1.0
    sc = (x * bases[f, 1, 0] + y * bases[f, 1, 1] + z * bases[f, 1, 2]) / ma
    tc = (x * bases[f, 2, 0] + y * bases[f, 2, 1] + z * bases[f, 2, 2]) / ma
    return f, sc, tc


@_jit
def coordinates(
    kind: int, h: int, w: int, x: float, y: float, z: float
) -> tuple[float, float, float]:
    """Continuous coordinates (f, x, y) of direction (x, y, z) (need not be unit)."""
    if kind == LATLONG:
        u, v = latlong_xy(h, w, x, y, z)
        return 0, u, v
    if kind == OPENEXR_LATLONG:
        lon = atan2(x, z)
        lat = atan2(y, math.sqrt(x * x + z * z))
        return 0, (0.5 - lon / (2 * math.pi)) * (w - 1) + 0.5, (0.5 - lat / math.pi) * (h - 1) + 0.5
    if is_cubic(kind):
        f, sc, tc = _major_face(_BASES if kind == CUBE else _EXR_BASES, x, y, z)
        n = _cube_scale(kind, w)
        o = _cube_offset(kind)
        return f, (sc + 1) / 2 * n + o, (tc + 1) / 2 * n + o
    if kind == OCTAHEDRAL:
        norm1 = abs(x) + abs(y) + abs(z)
        if norm1 == 0:
            norm1 = 1.0
        px, py, pz = x / norm1, y / norm1, z / norm1
        if py < 0:
            sx = -1.0 if px < 0 else 1.0
            sz = -1.0 if pz < 0 else 1.0
            px, pz = sx * (1 - abs(pz)), sz * (1 - abs(px))
        return 0, (px + 1) / 2 * w, (pz + 1) / 2 * h
    n = h
    disk = 0
    if kind != DUAL_PARABOLOID:
        rho = math.sqrt(x * x + y * y)
        # the component along the centre's direction: -z (HDRShop), +z (physical)
        zc = z if kind == ANGULAR_PHYSICAL or kind == MIRRORBALL_PHYSICAL else -z
        if kind == ANGULAR or kind == ANGULAR_PHYSICAL:
            r = math.atan2(rho, zc) / math.pi
        else:
            norm = math.sqrt(rho * rho + zc * zc)
            zn = zc / norm if norm > 0 else 1.0
            r = math.sqrt(min(max((1 - zn) / 2, 0.0), 1.0))
        # (cos, sin) of the azimuth atan2(y, x); along the axis (0, 0)'s azimuth, 0
        a, b = (r * x / rho, r * y / rho) if rho > 0 else (r, 0.0)
    else:
        norm = math.sqrt(x * x + y * y + z * z)
        if norm == 0:
            norm = 1.0
        xn, yn, zn = x / norm, y / norm, z / norm
        if zn > 0:
            disk = 1
            xn = -xn
        fz = abs(zn)
        a, b = xn / (1 + fz), yn / (1 + fz)
    return 0, (a + 1) / 2 * n + disk * n, (1 - b) / 2 * n


# --- texels -----------------------------------------------------------------------------------


@_jit
def valid(kind: int, h: int, w: int, f: float, i: int, j: int) -> bool:
    """Whether texel (f, i, j) holds data: disk texels must overlap the open disk."""
    if is_disk(kind):
        n = h
        li = i % n
        ta = max(abs(2 * (li + 0.5) / n - 1) - 1 / n, 0.0)
        tb = max(abs(2 * (j + 0.5) / n - 1) - 1 / n, 0.0)
        return ta * ta + tb * tb < 1 - DISK_OVERLAP_EPS
    return True


@_jit
def resolve(kind: int, h: int, w: int, f: float, i: int, j: int, x: float) -> int:
    """Flat index of integer texel (f, i, j), which may lie one texel outside the image (or the
    disk), as the neighbour of a sample at column coordinate ``x``; -1 for a cube corner."""
    if kind == LATLONG:
        if 0 <= i < w and 0 <= j < h:
            return j * w + i
        if j < 0 or j >= h:
            # across a pole: the same row, half a turn away
            i += w // 2
            j = min(max(j, 0), h - 1)
        return j * w + i % w
    if kind == OPENEXR_LATLONG:
        if 0 <= i < w and 0 <= j < h:
            return j * w + i
        turn = w - 1  # the last column repeats the first's meridian
        if j < 0 or j >= h:
            # rows 0 and h - 1 are the poles: beyond one, the row as far from it, half a turn
            # away (to the nearest column when the turn is odd)
            j = -j if j < 0 else 2 * (h - 1) - j
            j = min(max(j, 0), h - 1)
            i += turn // 2
        return j * w + i % turn
    if is_cubic(kind):
        s = w
        out_i = i < 0 or i >= s
        out_j = j < 0 or j >= s
        if not out_i and not out_j:
            return (int(f) * s + j) * s + i
        if out_i and out_j:
            return -1
        fi = int(f)
        bases = _BASES if kind == CUBE else _EXR_BASES
        n = _cube_scale(kind, s)
        o = _cube_offset(kind)
        sc = 2 * (i + 0.5 - o) / n - 1
        tc = 2 * (j + 0.5 - o) / n - 1
        if kind == CUBE:
            # OpenGL's seamless rule: the texel across the edge at the same place along it
            eps = 1e-9
            if out_i:
                sc = math.copysign(1 + eps, sc)
            else:
                tc = math.copysign(1 + eps, tc)
        # (OpenEXR's edge texels lie on the edge, shared by both faces: the texel one step
        # beyond is the other face's second row, where the face plane extended looks)
        dx = bases[fi, 0, 0] + sc * bases[fi, 1, 0] + tc * bases[fi, 2, 0]
        dy = bases[fi, 0, 1] + sc * bases[fi, 1, 1] + tc * bases[fi, 2, 1]
        dz = bases[fi, 0, 2] + sc * bases[fi, 1, 2] + tc * bases[fi, 2, 2]
        g, gs, gt = _major_face(bases, dx, dy, dz)
        gi = min(max(int(math.floor((gs + 1) / 2 * n + o)), 0), s - 1)
        gj = min(max(int(math.floor((gt + 1) / 2 * n + o)), 0), s - 1)
        return (g * s + gj) * s + gi
    if kind == OCTAHEDRAL:
        n = w
        out_i = i < 0 or i >= n
        out_j = j < 0 or j >= n
        i = min(max(i, 0), n - 1)
        j = min(max(j, 0), n - 1)
        # beyond an edge the map folds back mirrored; beyond a corner is the opposite corner
        if out_j:
            i = n - 1 - i
        if out_i:
            j = n - 1 - j
        return j * n + i
    n = h
    disk = min(max(math.floor(x / n), 0), w // n - 1)
    li = i - disk * n
    a = 2 * (li + 0.5) / n - 1
    b = 1 - 2 * (j + 0.5) / n
    if 0 <= li < n and 0 <= j < n and valid(kind, h, w, 0, li, j):
        return j * w + li + disk * n
    r = math.hypot(a, b)
    # beyond the rim: the disk texel that looks where this one would (the formula continued);
    # the mirror ball's whole rim looks one way (+Z; -Z for the physical variant), so there
    # the texel radially inside stands in
    if kind == MIRRORBALL or kind == MIRRORBALL_PHYSICAL:
        pull = max(0.0, 1 - 1.5 / n) / r
        a *= pull
        b *= pull
    dx, dy, dz = _disk_direction(kind, a, b, disk)
    _, cx, cy = coordinates(kind, h, w, dx, dy, dz)
    ci = min(max(int(math.floor(cx)), 0), w - 1)
    cj = min(max(int(math.floor(cy)), 0), h - 1)
    return cj * w + ci


@_jit
def rotate(rot: np.ndarray, x: float, y: float, z: float) -> tuple[float, float, float]:
    # R^T d: what the output shows at d is what the input showed at R^T d
    return (
        rot[0, 0] * x + rot[1, 0] * y + rot[2, 0] * z,
        rot[0, 1] * x + rot[1, 1] * y + rot[2, 1] * z,
        rot[0, 2] * x + rot[1, 2] * y + rot[2, 2] * z,
    )
