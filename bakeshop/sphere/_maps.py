"""The layouts' maps as scalar numba functions: the one implementation of each formula.

A layout is named here by a kind number and two integers ``(h, w)`` (a cube: ``h = w = S``).
Texel coordinates are ``(face, x, y)`` with texel ``i``'s centre at ``x = i + 0.5``; flat
layouts have face 0. The :class:`~bakeshop.sphere.layouts.Layout` classes and the sampling
kernels call these functions, so a direction is computed the same way everywhere.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from bakeshop.sphere.cube import FACE_BASES

LATLONG, ANGULAR, MIRRORBALL, DUAL_PARABOLOID, OCTAHEDRAL, CUBE = range(6)

#: a disk texel is valid when it reaches this far (in r^2) into the disk: texels that only
#: touch the rim (solid angle below ~1e-13 of the texel's) are left out.
DISK_OVERLAP_EPS = 1e-9
#: the area filter averages (splats) where a destination texel is at least this many source
#: texels across, interpolates bilinearly where it is at most one, and blends between.
AREA_SPLAT_RATIO = 1.5
#: the area filter averages only where the deposits cover at least this fraction of a
#: destination texel's solid angle (blending towards bilinear below): the deposits of boxes
#: that do not tile exactly cover each texel to within a few percent.
AREA_COVERAGE = 0.75
#: most parts a source texel is cut into along each of its axes by the area filter.
AREA_MAX_PARTS = 2048

_BASES = np.ascontiguousarray(FACE_BASES)
_jit = numba.njit(cache=True, error_model="numpy")


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
def atan2(y, x):
    """``math.atan2(y, x)`` within 2e-14 rad (signed zeros as libm; NaN or infinite input: NaN).

    Branch-free (selects only), so that loops over it vectorise: ~2 ns per call in a loop
    against ~15 ns for libm's. Reduction to ``t = min / max`` in [0, 1], then to
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
def latlong_xy(h, w, x, y, z):
    """A latlong's continuous coordinates (x, y) of direction (x, y, z): longitude
    ``phi = atan2(x, -z)``, colatitude ``theta = atan2(hypot(x, z), y)``."""
    phi = atan2(x, -z)
    theta = atan2(math.sqrt(x * x + z * z), y)
    return (phi / (2 * math.pi) + 0.5) * w, theta / math.pi * h


# --- directions at coordinates ------------------------------------------------------------------


@_jit
def _disk_direction(kind, a, b, disk):
    """Direction of disk point (a, b) (b up); valid beyond the rim for angular (theta > pi) and
    dual-paraboloid (the other hemisphere); the mirror ball is clamped to its rim."""
    r2 = a * a + b * b
    if kind == ANGULAR:
        r = math.sqrt(r2)
        s = math.pi if r == 0.0 else math.sin(math.pi * r) / r
        return a * s, b * s, math.cos(math.pi * r)
    if kind == MIRRORBALL:
        r2 = min(r2, 1.0)
        nz = math.sqrt(1.0 - r2)
        return 2 * nz * a, 2 * nz * b, 1.0 - 2 * r2
    k = 1.0 / (1.0 + r2)
    side = -1.0 if disk == 0 else 1.0
    return -side * 2 * a * k, 2 * b * k, side * (1.0 - r2) * k


@_jit
def _octahedron_point(a, c):
    aa, ac = abs(a), abs(c)
    y = 1.0 - aa - ac
    if y >= 0:
        return a, y, c
    sa = -1.0 if a < 0 else 1.0
    sc = -1.0 if c < 0 else 1.0
    return sa * (1.0 - ac), y, sc * (1.0 - aa)


@_jit
def direction(kind, h, w, f, x, y):
    """Unit direction at coordinates (f, x, y). Outside a disk: the disk's nearest point."""
    if kind == LATLONG:
        phi = 2 * math.pi * (x / w - 0.5)
        theta = math.pi * y / h
        st = math.sin(theta)
        return st * math.sin(phi), math.cos(theta), -st * math.cos(phi)
    if kind == CUBE:
        sc = 2 * x / w - 1
        tc = 2 * y / h - 1
        fi = min(max(int(f), 0), 5)
        dx = _BASES[fi, 0, 0] + sc * _BASES[fi, 1, 0] + tc * _BASES[fi, 2, 0]
        dy = _BASES[fi, 0, 1] + sc * _BASES[fi, 1, 1] + tc * _BASES[fi, 2, 1]
        dz = _BASES[fi, 0, 2] + sc * _BASES[fi, 1, 2] + tc * _BASES[fi, 2, 2]
    elif kind == OCTAHEDRAL:
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


# --- coordinates of directions ------------------------------------------------------------------


@_jit
def cube_face(x, y, z):
    """OpenGL's major-axis rule: (face, sc, tc), sc and tc in [-1, 1] (ties: x, then y)."""
    ax, ay, az = abs(x), abs(y), abs(z)
    if ax >= ay and ax >= az:
        f, ma = (0 if x >= 0 else 1), ax
    elif ay >= az:
        f, ma = (2 if y >= 0 else 3), ay
    else:
        f, ma = (4 if z >= 0 else 5), az
    if ma == 0:
        ma = 1.0
    sc = (x * _BASES[f, 1, 0] + y * _BASES[f, 1, 1] + z * _BASES[f, 1, 2]) / ma
    tc = (x * _BASES[f, 2, 0] + y * _BASES[f, 2, 1] + z * _BASES[f, 2, 2]) / ma
    return f, sc, tc


@_jit
def coordinates(kind, h, w, x, y, z):
    """Continuous coordinates (f, x, y) of direction (x, y, z) (need not be unit)."""
    if kind == LATLONG:
        u, v = latlong_xy(h, w, x, y, z)
        return 0, u, v
    if kind == CUBE:
        f, sc, tc = cube_face(x, y, z)
        return f, (sc + 1) / 2 * w, (tc + 1) / 2 * h
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
    if kind == ANGULAR or kind == MIRRORBALL:
        rho = math.sqrt(x * x + y * y)
        if kind == ANGULAR:
            r = math.atan2(rho, z) / math.pi
        else:
            norm = math.sqrt(rho * rho + z * z)
            zn = z / norm if norm > 0 else 1.0
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
def valid(kind, h, w, f, i, j):
    """Whether texel (f, i, j) holds data: disk texels must overlap the open disk."""
    if kind == ANGULAR or kind == MIRRORBALL or kind == DUAL_PARABOLOID:
        n = h
        li = i % n
        ta = max(abs(2 * (li + 0.5) / n - 1) - 1 / n, 0.0)
        tb = max(abs(2 * (j + 0.5) / n - 1) - 1 / n, 0.0)
        return ta * ta + tb * tb < 1 - DISK_OVERLAP_EPS
    return True


@_jit
def resolve(kind, h, w, f, i, j, x):
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
    if kind == CUBE:
        s = w
        out_i = i < 0 or i >= s
        out_j = j < 0 or j >= s
        if not out_i and not out_j:
            return (int(f) * s + j) * s + i
        if out_i and out_j:
            return -1
        # OpenGL's seamless rule: the texel across the edge at the same place along it
        sc = 2 * (i + 0.5) / s - 1
        tc = 2 * (j + 0.5) / s - 1
        eps = 1e-9
        if out_i:
            sc = math.copysign(1 + eps, sc)
        else:
            tc = math.copysign(1 + eps, tc)
        fi = int(f)
        dx = _BASES[fi, 0, 0] + sc * _BASES[fi, 1, 0] + tc * _BASES[fi, 2, 0]
        dy = _BASES[fi, 0, 1] + sc * _BASES[fi, 1, 1] + tc * _BASES[fi, 2, 1]
        dz = _BASES[fi, 0, 2] + sc * _BASES[fi, 1, 2] + tc * _BASES[fi, 2, 2]
        g, gs, gt = cube_face(dx, dy, dz)
        gi = min(max(int(math.floor((gs + 1) / 2 * s)), 0), s - 1)
        gj = min(max(int(math.floor((gt + 1) / 2 * s)), 0), s - 1)
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
    # the mirror ball's whole rim looks at -Z, so there the texel radially inside stands in
    if kind == MIRRORBALL:
        pull = max(0.0, 1 - 1.5 / n) / r
        a *= pull
        b *= pull
    dx, dy, dz = _disk_direction(kind, a, b, disk)
    _, cx, cy = coordinates(kind, h, w, dx, dy, dz)
    ci = min(max(int(math.floor(cx)), 0), w - 1)
    cj = min(max(int(math.floor(cy)), 0), h - 1)
    return cj * w + ci


# --- drivers ------------------------------------------------------------------------------------


@numba.njit(parallel=True, cache=True, error_model="numpy")
def directions_at(kind, h, w, coords, out):
    for p in numba.prange(coords.shape[0]):
        out[p, 0], out[p, 1], out[p, 2] = direction(
            kind, h, w, coords[p, 0], coords[p, 1], coords[p, 2]
        )


@numba.njit(parallel=True, cache=True, error_model="numpy")
def coordinates_of(kind, h, w, dirs, out):
    for p in numba.prange(dirs.shape[0]):
        f, x, y = coordinates(kind, h, w, dirs[p, 0], dirs[p, 1], dirs[p, 2])
        out[p, 0], out[p, 1], out[p, 2] = f, x, y


@_jit
def _rotate(rot, x, y, z):
    # R^T d: what the output shows at d is what the input showed at R^T d
    return (
        rot[0, 0] * x + rot[1, 0] * y + rot[2, 0] * z,
        rot[0, 1] * x + rot[1, 1] * y + rot[2, 1] * z,
        rot[0, 2] * x + rot[1, 2] * y + rot[2, 2] * z,
    )


@_jit
def _taps(kind, h, w, f, x, y, nearest, index, frac, p):
    if not (abs(x) < 1e18 and abs(y) < 1e18):
        # a NaN or infinite direction: no texel
        for k in range(index.shape[1]):
            index[p, k] = -1
        return
    if nearest:
        index[p, 0] = resolve(kind, h, w, f, int(math.floor(x)), int(math.floor(y)), x)
        return
    xs, ys = x - 0.5, y - 0.5
    x0, y0 = math.floor(xs), math.floor(ys)
    frac[p, 0], frac[p, 1] = xs - x0, ys - y0
    i0, j0 = int(x0), int(y0)
    index[p, 0] = resolve(kind, h, w, f, i0, j0, x)
    index[p, 1] = resolve(kind, h, w, f, i0 + 1, j0, x)
    index[p, 2] = resolve(kind, h, w, f, i0, j0 + 1, x)
    index[p, 3] = resolve(kind, h, w, f, i0 + 1, j0 + 1, x)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def taps_of(kind, h, w, dirs, nearest, index, frac):
    """Source taps for sampling layout (kind, h, w) at directions ``dirs`` (m, 3)."""
    for p in numba.prange(dirs.shape[0]):
        f, x, y = coordinates(kind, h, w, dirs[p, 0], dirs[p, 1], dirs[p, 2])
        _taps(kind, h, w, f, x, y, nearest, index, frac, p)


#: a remap plan's base index for a texel whose taps are not a 2x2 block (seams, rims, corners):
#: ``EXCEPTION - k`` points at row ``k`` of the plan's explicit taps.
EXCEPTION = -2


@_jit
def _block(kind, h, w, f, i0, j0, size):
    """Flat index of texel (f, i0, j0) when the size x size block from it holds ordinary
    texels of one image (one face, one disk, all valid), else -1: then ``resolve`` of block
    texel (a, b) is simply that index + b w + a."""
    if i0 < 0 or j0 < 0 or i0 + size > w or j0 + size > h:
        return -1
    if kind == CUBE:
        return (int(f) * h + j0) * w + i0
    if kind == ANGULAR or kind == MIRRORBALL or kind == DUAL_PARABOLOID:
        n = h
        li = i0 % n
        if li + size > n:
            return -1
        for dj in range(size):
            for di in range(size):
                if not valid(kind, h, w, 0, li + di, j0 + dj):
                    return -1
    return j0 * w + i0


@_jit
def _plan_direction(dkind, dh, dw, f, i, j, rot, trig):
    """Direction of destination texel (f, i, j)'s centre, rotated into the source's frame."""
    if dkind == LATLONG:
        x, y, z = trig[2, j] * trig[0, i], trig[3, j], -trig[2, j] * trig[1, i]
    else:
        x, y, z = direction(dkind, dh, dw, f, i + 0.5, j + 0.5)
    return _rotate(rot, x, y, z)


@_jit
def _plan_trig(dkind, dh, dw):
    # a latlong's directions are products of per-column and per-row sines and cosines
    trig = np.empty((4, max(dh, dw)))
    if dkind == LATLONG:
        for i in range(dw):
            phi = 2 * math.pi * ((i + 0.5) / dw - 0.5)
            trig[0, i], trig[1, i] = math.sin(phi), math.cos(phi)
        for j in range(dh):
            theta = math.pi * (j + 0.5) / dh
            trig[2, j], trig[3, j] = math.sin(theta), math.cos(theta)
    return trig


@_jit
def _latlong_row(h, w, xs, ys, zs, us, vs):
    # a loop of selects and arithmetic only: it vectorises
    for i in range(xs.shape[0]):
        us[i], vs[i] = latlong_xy(h, w, xs[i], ys[i], zs[i])


@numba.njit(parallel=True, cache=True, error_model="numpy")
def plan(skind, sh, sw, dkind, dh, dw, faces, rot, nearest, base, frac, src, out):
    """The remap plan of every destination texel centre, one destination row at a time.

    Nearest: ``base[p]`` is the source texel (-1: invalid destination texel). Bilinear:
    ``base[p]`` is the flat index of the upper-left tap of an ordinary 2x2 block (the taps are
    base, +1, +sw, +sw+1), ``EXCEPTION`` where the taps cross a seam (resolved afterwards by
    :func:`plan_exceptions`) or -1 for an invalid texel; ``frac[p]`` holds the fractions,
    float32 (as :func:`taps_of` computes them, so that ``sample`` and ``remap`` agree exactly).
    Unless ``out`` is empty, the plan is also applied to the flat image ``src`` on the way
    (the EXCEPTION texels are left to :func:`gather_at`): a first remap reads no plan back.
    """
    apply = out.shape[0] > 0
    no_taps = np.empty((0, 4), np.int32)
    trig = _plan_trig(dkind, dh, dw)
    for row in numba.prange(faces * dh):
        f = row // dh
        j = row - f * dh
        xs, ys, zs = np.empty(dw), np.empty(dw), np.empty(dw)
        us, vs = np.empty(dw), np.empty(dw)
        sf = np.zeros(dw, np.int64)
        for i in range(dw):
            xs[i], ys[i], zs[i] = _plan_direction(dkind, dh, dw, f, i, j, rot, trig)
        if skind == LATLONG:
            _latlong_row(sh, sw, xs, ys, zs, us, vs)
        else:
            for i in range(dw):
                sf[i], us[i], vs[i] = coordinates(skind, sh, sw, xs[i], ys[i], zs[i])
        for i in range(dw):
            p = row * dw + i
            sx, sy = us[i], vs[i]
            if not valid(dkind, dh, dw, f, i, j) or not (abs(sx) < 1e18 and abs(sy) < 1e18):
                base[p] = -1
            elif nearest:
                base[p] = resolve(
                    skind, sh, sw, sf[i], int(math.floor(sx)), int(math.floor(sy)), sx
                )
            else:
                xf, yf = sx - 0.5, sy - 0.5
                x0, y0 = math.floor(xf), math.floor(yf)
                frac[p, 0], frac[p, 1] = xf - x0, yf - y0
                b = _block(skind, sh, sw, sf[i], int(x0), int(y0), 2)
                base[p] = b if b >= 0 else EXCEPTION
            if apply:
                if nearest:
                    for c in range(src.shape[1]):
                        out[p, c] = src[base[p], c] if base[p] >= 0 else 0
                elif base[p] != EXCEPTION:
                    _gather_texel(src, sw, base, frac, no_taps, p, out)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def plan_exceptions(skind, sh, sw, dkind, dh, dw, rot, where, taps):
    """The four seam-aware taps of the plan's EXCEPTION texels ``where`` (-1: a cube corner)."""
    per = dh * dw
    trig = _plan_trig(dkind, dh, dw)
    for k in numba.prange(where.shape[0]):
        f, r = divmod(where[k], per)
        j, i = divmod(r, dw)
        x, y, z = _plan_direction(dkind, dh, dw, f, i, j, rot, trig)
        sf, sx, sy = coordinates(skind, sh, sw, x, y, z)
        i0, j0 = int(math.floor(sx - 0.5)), int(math.floor(sy - 0.5))
        taps[k, 0] = resolve(skind, sh, sw, sf, i0, j0, sx)
        taps[k, 1] = resolve(skind, sh, sw, sf, i0 + 1, j0, sx)
        taps[k, 2] = resolve(skind, sh, sw, sf, i0, j0 + 1, sx)
        taps[k, 3] = resolve(skind, sh, sw, sf, i0 + 1, j0 + 1, sx)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def reorder_plan(base, frac, order, out_base, out_frac):
    """The plan (:func:`plan`) of texels ``order`` (-1: none, an invalid texel)."""
    for p in numba.prange(order.shape[0]):
        k = order[p]
        out_base[p] = base[k] if k >= 0 else -1
        if out_frac.shape[0] > 0:
            out_frac[p, 0] = frac[k, 0] if k >= 0 else 0
            out_frac[p, 1] = frac[k, 1] if k >= 0 else 0


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_at(src, row, base, frac, taps, where, out):
    """:func:`gather_plan` for the output texels ``where`` only."""
    for k in numba.prange(where.shape[0]):
        _gather_texel(src, row, base, frac, taps, where[k], out)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_plan(src, row, base, frac, taps, out):
    """Apply a bilinear remap plan (see :func:`plan`): ``row`` is the source's row stride
    (its width). Weights are computed in the image's type (float32 stays float32)."""
    for p in numba.prange(base.shape[0]):
        _gather_texel(src, row, base, frac, taps, p, out)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _gather_texel(src, row, base, frac, taps, p, out):
    """out[p] from the bilinear plan (see :func:`plan`); inlined: a call costs 2x here."""
    nc = src.shape[1]
    one = src.dtype.type(1)
    b = base[p]
    if b == -1:
        for c in range(nc):
            out[p, c] = 0
        return
    fx, fy = src.dtype.type(frac[p, 0]), src.dtype.type(frac[p, 1])
    if b >= 0:
        i0, i1, i2, i3 = b, b + 1, b + row, b + row + 1
    else:
        k = EXCEPTION - b
        i0, i1, i2, i3 = taps[k, 0], taps[k, 1], taps[k, 2], taps[k, 3]
    gx, gy = one - fx, one - fy
    w0, w1, w2, w3 = gx * gy, fx * gy, gx * fy, fx * fy
    if i0 >= 0 and i1 >= 0 and i2 >= 0 and i3 >= 0:
        for c in range(nc):
            out[p, c] = w0 * src[i0, c] + w1 * src[i1, c] + w2 * src[i2, c] + w3 * src[i3, c]
    else:
        for c in range(nc):
            out[p, c] = _bilinear(src, i0, i1, i2, i3, fx, fy, c)


@_jit
def _bilinear(src, i0, i1, i2, i3, fx, fy, c):
    w0, w1 = (1 - fx) * (1 - fy), fx * (1 - fy)
    w2, w3 = (1 - fx) * fy, fx * fy
    if i0 >= 0 and i1 >= 0 and i2 >= 0 and i3 >= 0:
        return w0 * src[i0, c] + w1 * src[i1, c] + w2 * src[i2, c] + w3 * src[i3, c]
    # a cube corner: the missing texel is the mean of the other three (OpenGL)
    v0 = src[i0, c] if i0 >= 0 else 0.0
    v1 = src[i1, c] if i1 >= 0 else 0.0
    v2 = src[i2, c] if i2 >= 0 else 0.0
    v3 = src[i3, c] if i3 >= 0 else 0.0
    m = (v0 + v1 + v2 + v3) / 3
    v0 = v0 if i0 >= 0 else m
    v1 = v1 if i1 >= 0 else m
    v2 = v2 if i2 >= 0 else m
    v3 = v3 if i3 >= 0 else m
    return w0 * v0 + w1 * v1 + w2 * v2 + w3 * v3


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_nearest(src, index, out):
    for p in numba.prange(index.shape[0]):
        i = index[p, 0]
        for c in range(src.shape[1]):
            out[p, c] = src[i, c] if i >= 0 else 0


@numba.njit(parallel=True, cache=True, error_model="numpy")
def gather_bilinear(src, index, frac, out):
    """out[p] = bilinear blend of the four taps of ``index[p]`` with fractions ``frac[p]``;
    all taps -1: 0 (an invalid texel); one tap -1: a cube corner (the mean of the other three).
    Weights are computed in the image's type (float32 stays float32)."""
    nc = src.shape[1]
    one = src.dtype.type(1)
    for p in numba.prange(index.shape[0]):
        i0, i1, i2, i3 = index[p, 0], index[p, 1], index[p, 2], index[p, 3]
        fx, fy = src.dtype.type(frac[p, 0]), src.dtype.type(frac[p, 1])
        gx, gy = one - fx, one - fy
        w0, w1, w2, w3 = gx * gy, fx * gy, gx * fy, fx * fy
        if i0 >= 0 and i1 >= 0 and i2 >= 0 and i3 >= 0:
            for c in range(nc):
                out[p, c] = w0 * src[i0, c] + w1 * src[i1, c] + w2 * src[i2, c] + w3 * src[i3, c]
        elif i0 < 0 and i1 < 0:
            for c in range(nc):
                out[p, c] = 0
        else:
            for c in range(nc):
                out[p, c] = _bilinear(src, i0, i1, i2, i3, fx, fy, c)


@_jit
def _box_weights(c, half, lo, out):
    """Overlaps of [c - half, c + half] with texels lo..lo+2 (texel q spans [q, q + 1]) as
    fractions of its length; for a point (half ~ 0), 1 for the texel containing it."""
    for k in range(3):
        a, b = lo + k, lo + k + 1
        if half < 1e-9:
            out[k] = 1.0 if a <= c < b else 0.0
        else:
            out[k] = max(0.0, min(b, c + half) - max(a, c - half)) / (2 * half)


@_jit
def _local(kind, h, w, x, y, z, cf, cx, cy):
    """Coordinates of (x, y, z) continued across the seams around the centre (cf, cx, cy), for
    differences: a cube's face plane extended, a latlong's longitude unwrapped, an octahedral
    map unfolded over its edges, a paraboloid continued into the other hemisphere and an
    angular map through its rim."""
    if kind == CUBE:
        fi = int(cf)
        n = x * _BASES[fi, 0, 0] + y * _BASES[fi, 0, 1] + z * _BASES[fi, 0, 2]
        sc = (x * _BASES[fi, 1, 0] + y * _BASES[fi, 1, 1] + z * _BASES[fi, 1, 2]) / n
        tc = (x * _BASES[fi, 2, 0] + y * _BASES[fi, 2, 1] + z * _BASES[fi, 2, 2]) / n
        return (sc + 1) / 2 * w, (tc + 1) / 2 * h
    if kind == DUAL_PARABOLOID:
        n = h
        disk = min(max(math.floor(cx / n), 0), 1)
        norm = math.sqrt(x * x + y * y + z * z)
        right = x / norm if disk == 0 else -x / norm
        fwd = -z / norm if disk == 0 else z / norm
        a, b = right / (1 + fwd), y / norm / (1 + fwd)
        return (a + 1) / 2 * n + disk * n, (1 - b) / 2 * n
    _, u, v = coordinates(kind, h, w, x, y, z)
    if kind == LATLONG:
        return u - w * math.floor((u - cx) / w + 0.5), v
    best_u, best_v = u, v
    if kind == OCTAHEDRAL:
        n = w
        for du in (-1, 0, 1):
            for dv in (-1, 0, 1):
                # beyond an edge the map continues mirrored: (u, v) -> (2n - u, n - v), ...
                cu = u if du == 0 else (1 + du) * n - u
                cv = v if dv == 0 else (1 + dv) * n - v
                if du != 0 and dv == 0:
                    cv = n - v
                if dv != 0 and du == 0:
                    cu = n - u
                if (cu - cx) ** 2 + (cv - cy) ** 2 < (best_u - cx) ** 2 + (best_v - cy) ** 2:
                    best_u, best_v = cu, cv
    elif kind == ANGULAR:
        n = h
        a, b = 2 * u / n - 1, 1 - 2 * v / n
        r = math.hypot(a, b)
        if r > 0:
            # through the rim (-Z) the map continues at radius 2 - r on the opposite side
            k = (r - 2) / r
            cu, cv = (a * k + 1) / 2 * n, (1 - b * k) / 2 * n
            if (cu - cx) ** 2 + (cv - cy) ** 2 < (u - cx) ** 2 + (v - cy) ** 2:
                best_u, best_v = cu, cv
    return best_u, best_v


@_jit
def _half_texel_trig(h, w):
    """sin and cos of a latlong's longitude at every half texel (row 0, 1) and of its
    colatitude (rows 2, 3): ``direction`` at (k/2, l/2) without trigonometry."""
    trig = np.empty((4, 2 * max(h, w) + 1))
    for k in range(2 * w + 1):
        phi = 2 * math.pi * (k / (2 * w) - 0.5)
        trig[0, k], trig[1, k] = math.sin(phi), math.cos(phi)
    for k in range(2 * h + 1):
        theta = math.pi * k / (2 * h)
        trig[2, k], trig[3, k] = math.sin(theta), math.cos(theta)
    return trig


@_jit
def _source_direction(kind, h, w, f, u2, v2, trig):
    """``direction`` at the half-texel position (u2 / 2, v2 / 2)."""
    if kind == LATLONG:
        return trig[2, v2] * trig[0, u2], trig[3, v2], -trig[2, v2] * trig[1, u2]
    return direction(kind, h, w, f, u2 / 2, v2 / 2)


@_jit
def _image(skind, sh, sw, f, u2, v2, trig, rot, dkind, dh, dw, cf, cx, cy):
    x, y, z = _source_direction(skind, sh, sw, f, u2, v2, trig)
    x, y, z = _rotate(rot.T, x, y, z)
    return _local(dkind, dh, dw, x, y, z, cf, cx, cy)


@_jit
def _band_centroid(t0, t1):
    """The colatitude of the centroid of the band t0 <= theta <= t1 (weighted by sin theta:
    [sin t - t cos t] / [-cos t] over the band) and the band's cos t0 - cos t1; a texel at a
    pole holds its energy 2/3 of the way out, not halfway."""
    band = math.cos(t0) - math.cos(t1)
    if not band > 1e-300:
        return 0.5 * (t0 + t1), 0.0
    moment = math.sin(t1) - math.sin(t0) - (t1 * math.cos(t1) - t0 * math.cos(t0))
    return moment / band, band


@_jit
def _footprint(skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw):
    """Source texel (f, i, j) in destination coordinates: (face, centre x, centre y, half
    widths of the box bounding its locally affine image (at most 1/2), its narrower width)."""
    x, y, z = _source_direction(skind, sh, sw, f, 2 * i + 1, 2 * j + 1, trig)
    x, y, z = _rotate(rot.T, x, y, z)
    df, cx, cy = coordinates(dkind, dh, dw, x, y, z)
    # the footprint: twice the images of the centre-to-edge-midpoint steps
    b0, b1 = _image(skind, sh, sw, f, 2 * i + 2, 2 * j + 1, trig, rot, dkind, dh, dw, df, cx, cy)
    d0, d1 = _image(skind, sh, sw, f, 2 * i + 1, 2 * j + 2, trig, rot, dkind, dh, dw, df, cx, cy)
    ex0, ex1, ey0, ey1 = 2 * (b0 - cx), 2 * (b1 - cy), 2 * (d0 - cx), 2 * (d1 - cy)
    if skind == LATLONG:
        # centred on the texel's centroid
        theta, _ = _band_centroid(math.pi * j / sh, math.pi * (j + 1) / sh)
        st = math.sin(theta)
        x, y, z = st * trig[0, 2 * i + 1], math.cos(theta), -st * trig[1, 2 * i + 1]
        x, y, z = _rotate(rot.T, x, y, z)
        cx, cy = _local(dkind, dh, dw, x, y, z, df, cx, cy)
    hx = 0.5 * (abs(ex0) + abs(ey0))
    hy = 0.5 * (abs(ex1) + abs(ey1))
    hx = hx if hx >= 0 else 0.0  # NaN at a degenerate point: a point
    hy = hy if hy >= 0 else 0.0
    # the narrower width (area over length): an upsampled texel is wider than a destination
    # texel across every direction
    length = math.sqrt(max(ex0 * ex0 + ex1 * ex1, ey0 * ey0 + ey1 * ey1))
    width = abs(ex0 * ey1 - ex1 * ey0) / length if length > 0 else 0.0
    nx = _parts(max(abs(ex0), abs(ex1)))
    ny = _parts(max(abs(ey0), abs(ey1)))
    return df, cx, cy, min(0.5, hx), min(0.5, hy), width, nx, ny


@_jit
def _parts(extent):
    """Into how many parts a source texel ``extent`` destination texels long is cut so that
    each is at most 1 / AREA_SPLAT_RATIO long (1 for NaN; at most AREA_MAX_PARTS)."""
    if not extent * AREA_SPLAT_RATIO > 1:
        return 1
    return int(min(AREA_MAX_PARTS, math.ceil(extent * AREA_SPLAT_RATIO)))


@_jit
def _part_footprint(skind, sh, sw, f, u, v, du, dv, rot, dkind, dh, dw):
    """The part of a source texel centred at (f, u, v), du x dv source texels large, in
    destination coordinates: (face, centre x, centre y, half widths of its bounding box (at
    most 1/2), its solid angle (the tangent parallelogram's area))."""
    x, y, z = direction(skind, sh, sw, f, u, v)
    ax, ay, az = direction(skind, sh, sw, f, u + du / 2, v)
    bx, by, bz = direction(skind, sh, sw, f, u, v + dv / 2)
    return _part_of(x, y, z, ax, ay, az, bx, by, bz, rot, dkind, dh, dw)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _latlong_unit(sp, cp, st, ct):
    """``direction`` of a latlong from the sines and cosines of longitude and colatitude."""
    x, y, z = st * sp, ct, -st * cp
    norm = math.sqrt(x * x + y * y + z * z)
    return x / norm, y / norm, z / norm


@_jit
def _part_of(x, y, z, ax, ay, az, bx, by, bz, rot, dkind, dh, dw):
    """:func:`_part_footprint` from the source directions at the part's centre (x, y, z) and
    at the midpoints of its right (a) and lower (b) edges."""
    x, y, z = _rotate(rot.T, x, y, z)
    df, cx, cy = coordinates(dkind, dh, dw, x, y, z)
    om = 4 * math.sqrt(
        ((ay - y) * (bz - z) - (az - z) * (by - y)) ** 2
        + ((az - z) * (bx - x) - (ax - x) * (bz - z)) ** 2
        + ((ax - x) * (by - y) - (ay - y) * (bx - x)) ** 2
    )
    ax, ay, az = _rotate(rot.T, ax, ay, az)
    bx, by, bz = _rotate(rot.T, bx, by, bz)
    b0, b1 = _local(dkind, dh, dw, ax, ay, az, df, cx, cy)
    d0, d1 = _local(dkind, dh, dw, bx, by, bz, df, cx, cy)
    hx = abs(b0 - cx) + abs(d0 - cx)
    hy = abs(b1 - cy) + abs(d1 - cy)
    hx = hx if hx >= 0 else 0.0
    hy = hy if hy >= 0 else 0.0
    return df, cx, cy, min(0.5, hx), min(0.5, hy), om if om >= 0 else 0.0


@numba.njit(cache=True, error_model="numpy", inline="always")
def _deposit(acc, t, b, row, wq, p, om, values):
    """acc[t, q] += w values for the 3 x 3 destination texels from flat index b (rows ``row``
    apart), weights w = om x (x weight) x (y weight) from the splat plan's ``wq[p]``."""
    wx0, wx1, wy0, wy1 = float(wq[p, 0]), float(wq[p, 1]), float(wq[p, 2]), float(wq[p, 3])
    wx2 = max(0.0, 1.0 - wx0 - wx1)
    for yb in range(3):
        wy = wy0 if yb == 0 else (wy1 if yb == 1 else max(0.0, 1.0 - wy0 - wy1))
        if wy == 0:
            continue
        wy *= om
        q0 = b + yb * row
        for c in range(values.shape[0]):
            v = wy * values[c]
            acc[t, q0, c] += wx0 * v
            acc[t, q0 + 1, c] += wx1 * v
            acc[t, q0 + 2, c] += wx2 * v


@numba.njit(parallel=True, cache=True, error_model="numpy")
def splat_plan(skind, sh, sw, sfaces, omega, dkind, dh, dw, rot, anchor, wq, scale, width, parts,
               acc):  # fmt: skip
    """The area filter's geometry, per source texel ``p`` (transposed by :func:`splat_rows`).

    A source texel's footprint in destination coordinates is the box bounding its (locally
    affine) image, at most one destination texel wide; it deposits into the destination texels
    that box overlaps (within the 3 x 3 around it) in proportion to the overlap, so that its
    whole energy is deposited.
    ``anchor[p]``: flat index of the upper-left of the 3 x 3 destination texels when they are
    one ordinary block (deposit into anchor + b dw + a), ``EXCEPTION`` across a seam or where
    the texel is more than 1 / AREA_SPLAT_RATIO destination texels long (see
    :func:`splat_exceptions`; ``parts[p]``: into how many parts it is cut along x and y), -1
    for none; ``wq[p]``: the first two overlap fractions along x and along y, float32 (the
    third is the rest, so they sum to 1);
    ``scale[p]``: omega; ``width[p]``: the footprint's narrower width in destination texels.
    The ordinary texels' weights and weighted widths are summed into ``acc[t, q, :2]``, one
    partial sum per chunk ``t``. The rotation ``rot`` moves what the source shows at ``d`` to
    ``R d``.
    """
    trig = _half_texel_trig(sh, sw)
    rows = sfaces * sh
    chunks = acc.shape[0]
    for t in numba.prange(chunks):
        wx = np.empty(3)
        wy = np.empty(3)
        values = np.ones(2)
        for row in range(t * rows // chunks, (t + 1) * rows // chunks):
            f = row // sh
            j = row - f * sh
            for i in range(sw):
                p = row * sw + i
                om = omega[p]
                anchor[p] = -1
                if om <= 0:
                    continue
                df, cx, cy, hx, hy, wd, nx, ny = _footprint(
                    skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw
                )
                parts[p, 0], parts[p, 1] = nx, ny
                scale[p] = om
                if nx * ny > 1:
                    # wider than a destination texel: deposited in parts (splat_exceptions)
                    anchor[p] = EXCEPTION
                    width[p] = min(wd, 0.5)
                    continue
                lx = int(math.floor(cx - 0.5 - hx))
                ly = int(math.floor(cy - 0.5 - hy))
                _box_weights(cx, hx, lx, wx)
                _box_weights(cy, hy, ly, wy)
                width[p] = wd
                wq[p, 0], wq[p, 1], wq[p, 2], wq[p, 3] = wx[0], wx[1], wy[0], wy[1]
                b = _block(dkind, dh, dw, df, lx, ly, 3)
                anchor[p] = b if b >= 0 else EXCEPTION
                if b >= 0:
                    values[1] = width[p]
                    _deposit(acc, t, b, dw, wq, p, scale[p], values)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def splat_exceptions(skind, sh, sw, omega, dkind, dh, dw, rot, where, parts, offsets, taps,
                     weights, counts):  # fmt: skip
    """The explicit taps and weights (summing to omega) of the splat plan's EXCEPTION texels
    ``where``: texel k's entries are ``offsets[k]:offsets[k] + counts[k]`` (room for 4 per
    part). A texel whose 3 x 3 destination texels cross a seam deposits into them (-1: a cube
    corner, left out); a texel cut into nx x ny parts (``parts``) deposits each part's solid
    angle into the texels the part's box overlaps (within the 3 x 3 around its centre), so
    that a texel wider than the destination's texels is shared among all the texels it
    overlaps. Repeated taps are merged, in increasing order."""
    trig = _half_texel_trig(sh, sw)
    for k in numba.prange(where.shape[0]):
        wx = np.empty(3)
        wy = np.empty(3)
        p = where[k]
        f, r = divmod(p, sh * sw)
        j, i = divmod(r, sw)
        nx, ny = parts[p, 0], parts[p, 1]
        o = offsets[k]
        e = o
        for b in range(ny):
            if skind == LATLONG:
                # the parts' directions from one sine and cosine per row and column (as
                # ``direction`` computes them)
                # each part centred on its centroid, with its exact solid angle
                theta, band = _band_centroid(math.pi * (j + b / ny) / sh,
                                             math.pi * (j + (b + 1) / ny) / sh)  # fmt: skip
                st, ct = math.sin(theta), math.cos(theta)
                theta += math.pi / ny / 2 / sh
                st2, ct2 = math.sin(theta), math.cos(theta)
            for a in range(nx):
                if nx * ny == 1:
                    df, cx, cy, hx, hy, _, _, _ = _footprint(
                        skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw
                    )
                    om = 1.0
                elif skind == LATLONG:
                    u = i + (a + 0.5) / nx
                    phi = 2 * math.pi * (u / sw - 0.5)
                    sp, cp = math.sin(phi), math.cos(phi)
                    phi = 2 * math.pi * ((u + 1 / nx / 2) / sw - 0.5)
                    sp2, cp2 = math.sin(phi), math.cos(phi)
                    x, y, z = _latlong_unit(sp, cp, st, ct)
                    ax, ay, az = _latlong_unit(sp2, cp2, st, ct)
                    bx, by, bz = _latlong_unit(sp, cp, st2, ct2)
                    df, cx, cy, hx, hy, _ = _part_of(
                        x, y, z, ax, ay, az, bx, by, bz, rot, dkind, dh, dw
                    )
                    om = 2 * math.pi / sw / nx * band
                else:
                    df, cx, cy, hx, hy, om = _part_footprint(
                        skind, sh, sw, f, i + (a + 0.5) / nx, j + (b + 0.5) / ny, 1 / nx, 1 / ny,
                        rot, dkind, dh, dw,
                    )  # fmt: skip
                lx = int(math.floor(cx - 0.5 - hx))
                ly = int(math.floor(cy - 0.5 - hy))
                _box_weights(cx, hx, lx, wx)
                _box_weights(cy, hy, ly, wy)
                for yb in range(3):
                    for xa in range(3):
                        wt = om * wx[xa] * wy[yb]
                        if wt > 0:
                            q = resolve(dkind, dh, dw, df, lx + xa, ly + yb, cx)
                            if q >= 0:
                                taps[e] = q
                                weights[e] = wt
                                e += 1
        counts[k] = _merge_taps(taps, weights, o, e, omega[p])


@_jit
def _merge_taps(taps, weights, o, e, om):
    """Merge the repeated taps of entries o..e-1 (in increasing tap order) and scale their
    weights to sum ``om``; returns how many remain (at o onwards). In place by insertion sort
    for the few taps of most texels (no allocation); through a dense scratch array over the
    taps' range for the many of a texel cut into many parts (the range of a few destination
    rows), else by sorting."""
    lo, hi = taps[o], taps[o]
    for m in range(o, e):
        lo, hi = min(lo, taps[m]), max(hi, taps[m])
    n = 0
    if e - o > 144 and hi - lo < 64 * (e - o):
        dense = np.zeros(hi - lo + 1)
        for m in range(o, e):
            dense[taps[m] - lo] += weights[m]
        for c in range(hi - lo + 1):
            if dense[c] > 0:
                taps[o + n] = lo + c
                weights[o + n] = dense[c]
                n += 1
    else:
        if e - o <= 144:
            for m in range(o, e):
                tq, tw = taps[m], weights[m]
                c = m
                while c > o and taps[c - 1] > tq:
                    taps[c], weights[c] = taps[c - 1], weights[c - 1]
                    c -= 1
                taps[c], weights[c] = tq, tw
        else:
            order = np.argsort(taps[o:e], kind="mergesort")
            ts = taps[o:e][order]
            ws = weights[o:e][order]
            taps[o:e] = ts
            weights[o:e] = ws
        for m in range(o, e):
            if n > 0 and taps[o + n - 1] == taps[m]:
                weights[o + n - 1] += weights[m]
            else:
                taps[o + n] = taps[m]
                weights[o + n] = weights[m]
                n += 1
    total = 0.0
    for m in range(o, o + n):
        total += weights[m]
    for m in range(o, o + n):
        weights[m] = om * weights[m] / total if total > 0 else 0.0
    return n


@numba.njit(parallel=True, cache=True, error_model="numpy")
def compact_exceptions(at, counts, taps, weights, ends, out_taps, out_weights):
    """Copy texel k's ``counts[k]`` merged entries from ``at[k]`` in ``taps``/``weights`` (the
    buffers :func:`splat_exceptions` filled) to ``ends[k] - counts[k]`` in the outputs."""
    for k in numba.prange(counts.shape[0]):
        src = at[k]
        dst = ends[k] - counts[k]
        for m in range(counts[k]):
            out_taps[dst + m] = taps[src + m]
            out_weights[dst + m] = weights[src + m]


@_jit
def _deposit_exception(acc, t, offsets, taps, weights, k, values):
    for m in range(offsets[k], offsets[k + 1]):
        q = taps[m]
        w = weights[m]
        for c in range(values.shape[0]):
            acc[t, q, c] += w * values[c]


@_jit
def deposit_exceptions(where, offsets, taps, weights, width, acc):
    """Add the EXCEPTION texels' weights and weighted widths to ``acc[0, q, :2]``."""
    values = np.ones(2)
    for k in range(where.shape[0]):
        values[1] = width[where[k]]
        _deposit_exception(acc, 0, offsets, taps, weights, k, values)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def splat_rows(anchor, wq, scale, row, offsets, taps, weights, alpha, inverse, cursor, fill,
               indices, values):  # fmt: skip
    """The splat plan (:func:`splat_plan`, :func:`splat_exceptions`) transposed into rows, one
    per destination texel q with alpha > 0: source texel p's weight w into q becomes the entry
    (p, w alpha[q] inverse[q]) of row q. Chunk t of the source texels counts its entries per
    row into ``cursor[t, q]`` (``fill`` False), or writes them at ``cursor[t, q]`` onwards
    (``fill`` True; the chunks' starts in each row), so that each row lists p in order."""
    n = anchor.shape[0]
    chunks = cursor.shape[0]
    for t in numba.prange(chunks):
        for p in range(t * n // chunks, (t + 1) * n // chunks):
            b = anchor[p]
            if b >= 0:
                wx0, wx1 = float(wq[p, 0]), float(wq[p, 1])
                wy0, wy1 = float(wq[p, 2]), float(wq[p, 3])
                wx2, wy2 = max(0.0, 1.0 - wx0 - wx1), max(0.0, 1.0 - wy0 - wy1)
                for yb in range(3):
                    wy = wy0 if yb == 0 else (wy1 if yb == 1 else wy2)
                    for xa in range(3):
                        w = scale[p] * wy * (wx0 if xa == 0 else (wx1 if xa == 1 else wx2))
                        q = b + yb * row + xa
                        if w > 0 and alpha[q] > 0:
                            if fill:
                                e = cursor[t, q]
                                indices[e] = p
                                values[e] = w * alpha[q] * inverse[q]
                            cursor[t, q] += 1
            elif b != -1:
                k = EXCEPTION - b
                for m in range(offsets[k], offsets[k + 1]):
                    q = taps[m]
                    if weights[m] > 0 and alpha[q] > 0:
                        if fill:
                            e = cursor[t, q]
                            indices[e] = p
                            values[e] = weights[m] * alpha[q] * inverse[q]
                        cursor[t, q] += 1


@numba.njit(parallel=True, cache=True, error_model="numpy")
def area_alpha(acc, omega, alpha, inverse):
    """The area filter's blend per destination texel from the splat of ones and of the
    source footprints' widths (``acc[t, q] = (sum w, sum w width)``): alpha = 1 (the splat's
    mean) where the source texels (or their parts) landing there are at most
    1/AREA_SPLAT_RATIO of it across (in their narrower direction) and cover it, which
    splat_plan's cutting of wide texels into parts ensures wherever it is covered; 0
    (bilinear) where nothing lands, linear between; ``inverse`` = 1 / sum w."""
    for p in numba.prange(alpha.shape[0]):
        wsum = 0.0
        width = 0.0
        for t in range(acc.shape[0]):
            wsum += acc[t, p, 0]
            width += acc[t, p, 1]
        a = 0.0
        if wsum > 0:
            width /= wsum
            ratio = 1 / width if width > 0 else AREA_SPLAT_RATIO
            a = min(1.0, max(0.0, (ratio - 1) / (AREA_SPLAT_RATIO - 1)))
            if omega[p] > 0:
                a *= min(1.0, wsum / (AREA_COVERAGE * omega[p]))
        alpha[p] = a
        inverse[p] = 1 / wsum if wsum > 0 else 0.0


@numba.njit(cache=True, error_model="numpy")
def row_starts(cursor, extra, indptr):
    """Row q holds sum_t cursor[t, q] + extra[q] entries: ``indptr`` their running sum, and
    ``cursor[t, q]`` becomes where chunk t's entries of row q start (after the earlier
    chunks')."""
    total = 0
    for q in range(extra.shape[0]):
        indptr[q] = total
        for t in range(cursor.shape[0]):
            count = cursor[t, q]
            cursor[t, q] = total
            total += count
        total += extra[q]
    indptr[extra.shape[0]] = total


@numba.njit(parallel=True, cache=True, error_model="numpy")
def bilinear_rows(alpha, row, base, frac, taps, indptr, counts, fill, indices, values):
    """Append to row q (at ``indptr[q + 1] - counts[q]``) the bilinear taps of the plan
    (:func:`plan`) weighted by 1 - alpha[q], where alpha[q] < 1 (``fill``); else count them
    into ``counts[q]``. A cube corner's missing tap (the mean of the other three) gives a third
    of its weight to each of them."""
    for q in numba.prange(alpha.shape[0]):
        b = base[q]
        if alpha[q] >= 1 or b == -1:
            continue
        if b >= 0:
            i0, i1, i2, i3 = b, b + 1, b + row, b + row + 1
        else:
            x = EXCEPTION - b
            i0, i1, i2, i3 = taps[x, 0], taps[x, 1], taps[x, 2], taps[x, 3]
        if not fill:
            counts[q] = (i0 >= 0) + (i1 >= 0) + (i2 >= 0) + (i3 >= 0)
            continue
        fx, fy = float(frac[q, 0]), float(frac[q, 1])
        w0, w1, w2, w3 = (1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy
        lost = (w0 if i0 < 0 else 0.0) + (w1 if i1 < 0 else 0.0)
        lost += (w2 if i2 < 0 else 0.0) + (w3 if i3 < 0 else 0.0)
        scale = 1.0 - alpha[q]
        e = indptr[q + 1] - counts[q]
        for k in range(4):
            i = i0 if k == 0 else (i1 if k == 1 else (i2 if k == 2 else i3))
            w = w0 if k == 0 else (w1 if k == 1 else (w2 if k == 2 else w3))
            if i >= 0:
                indices[e] = i
                values[e] = scale * (w + lost / 3)
                e += 1


@numba.njit(parallel=True, cache=True, error_model="numpy")
def scale_rows(indptr, indices, values, factor):
    """Multiply each entry by ``factor`` of its column (none: all 1), then scale each nonempty
    row to sum 1."""
    scaled = factor.shape[0] > 0
    for q in numba.prange(indptr.shape[0] - 1):
        total = 0.0
        for e in range(indptr[q], indptr[q + 1]):
            if scaled:
                values[e] = values[e] * factor[indices[e]]
            total += values[e]
        if total > 0:
            for e in range(indptr[q], indptr[q + 1]):
                values[e] = values[e] / total


@numba.njit(parallel=True, cache=True, error_model="numpy")
def balance_rows(indptr, indices, values, omega_out, col, sums):
    """One pass of the area filter's balancing of M = diag(r) K diag(col) (K: ``values``):
    the row scales r making every nonempty row sum 1, and the energy each column then sends,
    sum_q omega_out[q] r[q] K[q, p] (x col[p] to come), as partial sums per chunk of rows in
    ``sums`` (zero on entry: :func:`balance_columns` clears them as it reads them)."""
    m = indptr.shape[0] - 1
    chunks = sums.shape[0]
    for t in numba.prange(chunks):
        for q in range(t * m // chunks, (t + 1) * m // chunks):
            total = 0.0
            for e in range(indptr[q], indptr[q + 1]):
                total += values[e] * col[indices[e]]
            if total > 0:
                scale = omega_out[q] / total
                for e in range(indptr[q], indptr[q + 1]):
                    sums[t, indices[e]] += scale * values[e]


@numba.njit(parallel=True, cache=True, error_model="numpy")
def balance_columns(sums, omega_in, col, step):
    """The column step, over-relaxed with momentum: where source texel p sends ``sent`` =
    col[p] x (sum of its partial sums) > 0, log col[p] moves by ``step[p]`` = 1.5 log(omega_in
    / sent) + 0.5 x its previous step (kept as the factor exp(step), so no logarithms).
    Returns the largest |omega_in / sent - 1|."""
    err = 0.0
    for p in numba.prange(omega_in.shape[0]):
        sent = 0.0
        for t in range(sums.shape[0]):
            sent += sums[t, p]
            sums[t, p] = 0.0
        sent *= col[p]
        if sent > 0:
            r = omega_in[p] / sent
            err = max(err, abs(r - 1))
            step[p] = r * math.sqrt(r * step[p])
            col[p] *= step[p]
    return err


@numba.njit(parallel=True, cache=True, error_model="numpy")
def reorder_rows(indptr, indices, values, order, out_indptr, out_indices, out_values):
    """Row p of the output matrix = row order[p] of the input (empty where -1)."""
    for p in numba.prange(order.shape[0]):
        q = order[p]
        if q >= 0:
            o = out_indptr[p]
            for e in range(indptr[q], indptr[q + 1]):
                out_indices[o] = indices[e]
                out_values[o] = values[e]
                o += 1


@numba.njit(parallel=True, cache=True, error_model="numpy")
def area_gather(src, indptr, indices, values, out):
    """The area filter applied: out[q] = sum over row q of weight x src[p], in float64, four
    channels at a time in registers."""
    nc = out.shape[1]
    for q in numba.prange(out.shape[0]):
        for c in range(0, nc, 4):
            k = min(4, nc - c)
            s0 = s1 = s2 = s3 = 0.0
            for e in range(indptr[q], indptr[q + 1]):
                p, w = indices[e], float(values[e])
                s0 += w * src[p, c]
                if k > 1:
                    s1 += w * src[p, c + 1]
                if k > 2:
                    s2 += w * src[p, c + 2]
                if k > 3:
                    s3 += w * src[p, c + 3]
            out[q, c] = s0
            if k > 1:
                out[q, c + 1] = s1
            if k > 2:
                out[q, c + 2] = s2
            if k > 3:
                out[q, c + 3] = s3
