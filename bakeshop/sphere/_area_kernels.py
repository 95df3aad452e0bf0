"""The area filter's geometry: source texels' footprints in the destination, their deposits
(box overlaps, of the whole texel or of its parts) and the blend towards bilinear (see
:mod:`bakeshop.sphere.area`, which drives them; :mod:`bakeshop.sphere._matrix_kernels` makes
the deposits a matrix, balances and applies it)."""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy import ndarray

from bakeshop.sphere._cube_latlong import latlong_taps
from bakeshop.sphere._gather import EXCEPTION, block
from bakeshop.sphere._maps import (
    ANGULAR,
    ANGULAR_PHYSICAL,
    CUBE,
    DUAL_PARABOLOID,
    LATLONG,
    MIRRORBALL,
    MIRRORBALL_PHYSICAL,
    OCTAHEDRAL,
    OPENEXR_LATLONG,
    coordinates,
    direction,
    is_cubic,
    resolve,
    rotate,
)
from bakeshop.sphere.cube import FACE_BASES, OPENEXR_FACE_BASES

#: the area filter averages (splats) where a destination texel is at least this many source
#: texels across, interpolates bilinearly where it is at most one, and blends between.
AREA_SPLAT_RATIO = 1.5
#: the area filter averages only where the deposits cover at least this fraction of a
#: destination texel's solid angle (blending towards bilinear below): the deposits of boxes
#: that do not tile exactly cover each texel to within a few percent.
AREA_COVERAGE = 0.75
#: most parts a source texel is cut into along each of its axes by the area filter.
AREA_MAX_PARTS = 2048
#: a texel cut into at most this many parts along each axis, whose image lies in one image (or
#: face) within a window of at most AREA_WINDOW x AREA_WINDOW destination texels, is deposited
#: through its affine image (:func:`_window_taps`).
AREA_AFFINE_PARTS = 4
AREA_WINDOW = 8

_BASES = np.ascontiguousarray(FACE_BASES)
_EXR_BASES = np.ascontiguousarray(OPENEXR_FACE_BASES)
_jit = numba.njit(cache=True, error_model="numpy")


@numba.njit(cache=True, error_model="numpy", inline="always")
def _bent(skind: int, h: int, w: int, i: int, j: int, dkind: int) -> bool:
    """Whether source texel (i, j)'s image may be far from a parallelogram: within two texels
    of where its layout is singular (a latlong's poles, the rim of an angular map or a mirror
    ball, each the one direction behind), or in an octahedral map on either side (its octants'
    creases fold what crosses them; 3 % further from the brute-force average otherwise)."""
    if skind == OCTAHEDRAL or dkind == OCTAHEDRAL:
        return True
    if skind == LATLONG or skind == OPENEXR_LATLONG:
        return j < 2 or j > h - 3
    if (
        skind == ANGULAR
        or skind == ANGULAR_PHYSICAL
        or skind == MIRRORBALL
        or skind == MIRRORBALL_PHYSICAL
    ):
        n = h
        a, b = 2 * (i % n + 0.5) / n - 1, 1 - 2 * (j + 0.5) / n
        return a * a + b * b > (1 - 4 / n) ** 2
    return False


@numba.njit(cache=True, error_model="numpy", inline="always")
def _overlap(c: float, half: float, q: int) -> float:
    """The overlap of [c - half, c + half] with texel q ([q, q + 1]) as a fraction of its
    length (texel q spans [q, q + 1]); for a point (half ~ 0), 1 for the texel holding it."""
    if half < 1e-9:
        return 1.0 if q <= c < q + 1 else 0.0
    return max(0.0, min(q + 1, c + half) - max(q, c - half)) / (2 * half)


@_jit
def _box_weights(c: float, half: float, lo: int, out: ndarray) -> None:
    """:func:`_overlap` with texels lo..lo+2."""
    for k in range(3):
        out[k] = _overlap(c, half, lo + k)


@_jit
def _local(kind: int, h: int, w: int, x: float, y: float, z: float, cf: float, cx: float,
           cy: float) -> tuple[float, float]:  # fmt: skip
    """Coordinates of (x, y, z) continued across the seams around the centre (cf, cx, cy), for
    differences: a cube's face plane extended, a latlong's longitude unwrapped, an octahedral
    map unfolded over its edges, a paraboloid continued into the other hemisphere and an
    angular map through its rim."""
    if is_cubic(kind):
        fi = int(cf)
        bases = _BASES if kind == CUBE else _EXR_BASES
        n = x * bases[fi, 0, 0] + y * bases[fi, 0, 1] + z * bases[fi, 0, 2]
        sc = (x * bases[fi, 1, 0] + y * bases[fi, 1, 1] + z * bases[fi, 1, 2]) / n
        tc = (x * bases[fi, 2, 0] + y * bases[fi, 2, 1] + z * bases[fi, 2, 2]) / n
        if kind == CUBE:
            return (sc + 1) / 2 * w, (tc + 1) / 2 * h
        # OpenEXR's faces: +-1 at the first and last texel centres
        return (sc + 1) / 2 * (w - 1) + 0.5, (tc + 1) / 2 * (h - 1) + 0.5
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
    if kind == OPENEXR_LATLONG:
        # a turn is w - 1 columns (the last repeats the first's meridian)
        return u - (w - 1) * math.floor((u - cx) / (w - 1) + 0.5), v
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
    elif kind == ANGULAR or kind == ANGULAR_PHYSICAL:
        n = h
        a, b = 2 * u / n - 1, 1 - 2 * v / n
        r = math.hypot(a, b)
        if r > 0:
            # through the rim (+Z; -Z for the physical variant) the map continues at radius
            # 2 - r on the opposite side
            k = (r - 2) / r
            cu, cv = (a * k + 1) / 2 * n, (1 - b * k) / 2 * n
            if (cu - cx) ** 2 + (cv - cy) ** 2 < (u - cx) ** 2 + (v - cy) ** 2:
                best_u, best_v = cu, cv
    return best_u, best_v


@_jit
def _half_texel_trig(h: int, w: int) -> ndarray:
    """Sin and cos of a latlong's longitude at every half texel (row 0, 1) and of its
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
def _source_direction(kind: int, h: int, w: int, f: float, u2: int, v2: int,
                      trig: ndarray) -> tuple[float, float, float]:  # fmt: skip
    """``direction`` at the half-texel position (u2 / 2, v2 / 2)."""
    if kind == LATLONG:
        return trig[2, v2] * trig[0, u2], trig[3, v2], -trig[2, v2] * trig[1, u2]
    return direction(kind, h, w, f, u2 / 2, v2 / 2)


@_jit
def _image(skind: int, sh: int, sw: int, f: float, u2: int, v2: int, trig: ndarray, rot: ndarray,
           dkind: int, dh: int, dw: int, cf: float, cx: float,
           cy: float) -> tuple[float, float]:  # fmt: skip
    x, y, z = _source_direction(skind, sh, sw, f, u2, v2, trig)
    x, y, z = rotate(rot.T, x, y, z)
    return _local(dkind, dh, dw, x, y, z, cf, cx, cy)


@_jit
def _band_centroid(t0: float, t1: float) -> tuple[float, float]:
    """The colatitude of the centroid of the band t0 <= theta <= t1 (weighted by sin theta:
    [sin t - t cos t] / [-cos t] over the band) and the band's cos t0 - cos t1; a texel at a
    pole holds its energy 2/3 of the way out, not halfway."""
    return _band_centroid_of(t0, t1, math.sin(t0), math.cos(t0), math.sin(t1), math.cos(t1))


@_jit
def _band_centroid_of(t0: float, t1: float, s0: float, c0: float, s1: float,
                      c1: float) -> tuple[float, float]:  # fmt: skip
    """:func:`_band_centroid` from the sines (s) and cosines (c) of t0 and t1."""
    band = c0 - c1
    if not band > 1e-300:
        return 0.5 * (t0 + t1), 0.0
    moment = s1 - s0 - (t1 * c1 - t0 * c0)
    return moment / band, band


@_jit
def _affine_image(skind: int, sh: int, sw: int, f: float, i: int, j: int, trig: ndarray,
                  rot: ndarray, dkind: int, dh: int,
                  dw: int) -> tuple[float, float, float, float, float, float, float]:  # fmt: skip
    """Source texel (f, i, j)'s locally affine image in destination coordinates: the face and
    centre (cx, cy) of its centre's image and the images (ex0, ex1), (ey0, ey1) of its two
    axes (twice the images of the centre-to-edge-midpoint steps)."""
    x, y, z = _source_direction(skind, sh, sw, f, 2 * i + 1, 2 * j + 1, trig)
    x, y, z = rotate(rot.T, x, y, z)
    df, cx, cy = coordinates(dkind, dh, dw, x, y, z)
    b0, b1 = _image(skind, sh, sw, f, 2 * i + 2, 2 * j + 1, trig, rot, dkind, dh, dw, df, cx, cy)
    d0, d1 = _image(skind, sh, sw, f, 2 * i + 1, 2 * j + 2, trig, rot, dkind, dh, dw, df, cx, cy)
    return df, cx, cy, 2 * (b0 - cx), 2 * (b1 - cy), 2 * (d0 - cx), 2 * (d1 - cy)


@_jit
def _footprint(skind: int, sh: int, sw: int, f: float, i: int, j: int, trig: ndarray, rot: ndarray,
               dkind: int, dh: int,
               dw: int) -> tuple[float, float, float, float, float, float, int, int]:  # fmt: skip
    """Source texel (f, i, j) in destination coordinates: (face, centre x, centre y, half
    widths of the box bounding its locally affine image (at most 1/2), its narrower width)."""
    df, cx, cy, ex0, ex1, ey0, ey1 = _affine_image(skind, sh, sw, f, i, j, trig, rot, dkind, dh,
                                                   dw)  # fmt: skip
    if skind == LATLONG:
        # centred on the texel's centroid
        theta, _ = _band_centroid(math.pi * j / sh, math.pi * (j + 1) / sh)
        st = math.sin(theta)
        x, y, z = st * trig[0, 2 * i + 1], math.cos(theta), -st * trig[1, 2 * i + 1]
        x, y, z = rotate(rot.T, x, y, z)
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
def _parts(extent: float) -> int:
    """Into how many parts a source texel ``extent`` destination texels long is cut so that
    each is at most 1 / AREA_SPLAT_RATIO long (1 for NaN; at most AREA_MAX_PARTS)."""
    if not extent * AREA_SPLAT_RATIO > 1:
        return 1
    return int(min(AREA_MAX_PARTS, math.ceil(extent * AREA_SPLAT_RATIO)))


@_jit
def _part_footprint(skind: int, sh: int, sw: int, f: float, u: float, v: float, du: float,
                    dv: float, rot: ndarray, dkind: int, dh: int,
                    dw: int) -> tuple[float, float, float, float, float, float]:  # fmt: skip
    """The part of a source texel centred at (f, u, v), du x dv source texels large, in
    destination coordinates: (face, centre x, centre y, half widths of its bounding box (at
    most 1/2), its solid angle (the tangent parallelogram's area))."""
    x, y, z = direction(skind, sh, sw, f, u, v)
    ax, ay, az = direction(skind, sh, sw, f, u + du / 2, v)
    bx, by, bz = direction(skind, sh, sw, f, u, v + dv / 2)
    return _part_of(x, y, z, ax, ay, az, bx, by, bz, rot, dkind, dh, dw)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _latlong_unit(sp: float, cp: float, st: float,
                  ct: float) -> tuple[float, float, float]:  # fmt: skip
    """``direction`` of a latlong from the sines and cosines of longitude and colatitude."""
    x, y, z = st * sp, ct, -st * cp
    norm = math.sqrt(x * x + y * y + z * z)
    return x / norm, y / norm, z / norm


@_jit
def _part_of(x: float, y: float, z: float, ax: float, ay: float, az: float, bx: float, by: float,
             bz: float, rot: ndarray, dkind: int, dh: int,
             dw: int) -> tuple[float, float, float, float, float, float]:  # fmt: skip
    """:func:`_part_footprint` from the source directions at the part's centre (x, y, z) and
    at the midpoints of its right (a) and lower (b) edges."""
    x, y, z = rotate(rot.T, x, y, z)
    df, cx, cy = coordinates(dkind, dh, dw, x, y, z)
    om = 4 * math.sqrt(
        ((ay - y) * (bz - z) - (az - z) * (by - y)) ** 2
        + ((az - z) * (bx - x) - (ax - x) * (bz - z)) ** 2
        + ((ax - x) * (by - y) - (ay - y) * (bx - x)) ** 2
    )
    ax, ay, az = rotate(rot.T, ax, ay, az)
    bx, by, bz = rotate(rot.T, bx, by, bz)
    b0, b1 = _local(dkind, dh, dw, ax, ay, az, df, cx, cy)
    d0, d1 = _local(dkind, dh, dw, bx, by, bz, df, cx, cy)
    hx = abs(b0 - cx) + abs(d0 - cx)
    hy = abs(b1 - cy) + abs(d1 - cy)
    hx = hx if hx >= 0 else 0.0
    hy = hy if hy >= 0 else 0.0
    return df, cx, cy, min(0.5, hx), min(0.5, hy), om if om >= 0 else 0.0


@numba.njit(cache=True, error_model="numpy", inline="always")
def _deposit(acc: ndarray, t: int, b: int, row: int, wq: ndarray, p: int, om: float,
             values: ndarray) -> None:  # fmt: skip
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
def splat_plan(skind: int, sh: int, sw: int, sfaces: int, omega: ndarray, dkind: int, dh: int,
               dw: int, rot: ndarray, anchor: ndarray, wq: ndarray, scale: ndarray, width: ndarray,
               parts: ndarray, acc: ndarray) -> None:  # fmt: skip
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
                b = block(dkind, dh, dw, df, lx, ly, 3)
                anchor[p] = b if b >= 0 else EXCEPTION
                if b >= 0:
                    values[1] = width[p]
                    _deposit(acc, t, b, dw, wq, p, scale[p], values)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def splat_exceptions(skind: int, sh: int, sw: int, omega: ndarray, dkind: int, dh: int, dw: int,
                     rot: ndarray, where: ndarray, parts: ndarray, offsets: ndarray, taps: ndarray,
                     weights: ndarray, counts: ndarray) -> None:  # fmt: skip
    """The explicit taps and weights (summing to omega) of the splat plan's EXCEPTION texels
    ``where``: texel k's entries are ``offsets[k]:offsets[k] + counts[k]`` (room for 4 per
    part). A texel whose 3 x 3 destination texels cross a seam deposits into them (-1: a cube
    corner, left out); a texel cut into nx x ny parts (``parts``) deposits each part's solid
    angle into the texels the part's box overlaps (within the 3 x 3 around its centre), so
    that a texel wider than the destination's texels is shared among all the texels it
    overlaps: through its affine image where it is cut into few parts away from seams
    (:func:`_window_taps`), else part by part (:func:`_part_taps`); a cube texel into a
    latlong deposits its exact overlaps instead (``_cube_latlong.latlong_taps``). Taps in
    increasing order."""
    trig = _half_texel_trig(sh, sw)
    for k in numba.prange(where.shape[0]):
        p = where[k]
        f, r = divmod(p, sh * sw)
        j, i = divmod(r, sw)
        nx, ny = parts[p, 0], parts[p, 1]
        n = -1
        if is_cubic(skind) and dkind == LATLONG and max(nx, ny) > 1:
            n = latlong_taps(skind, sh, sw, f, i, j, rot, dh, dw, omega[p], offsets[k],
                             4 * nx * ny, taps, weights)  # fmt: skip
        elif 1 < nx * ny and nx <= AREA_AFFINE_PARTS and ny <= AREA_AFFINE_PARTS:
            n = _window_taps(skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw, nx, ny, omega[p],
                             offsets[k], taps, weights)  # fmt: skip
        if n < 0:
            n = _part_taps(skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw, nx, ny, omega[p],
                           offsets[k], taps, weights)  # fmt: skip
        counts[k] = n


@_jit
def _window_taps(skind: int, sh: int, sw: int, f: int, i: int, j: int, trig: ndarray,
                 rot: ndarray, dkind: int, dh: int, dw: int, nx: int, ny: int, om: float, o: int,
                 taps: ndarray, weights: ndarray) -> int:  # fmt: skip
    """Source texel (f, i, j)'s merged taps at ``o`` onwards through its affine image: its
    centre c and the images ex, ey of its axes (one projection each), part (a, b)'s centre
    c + ((a + 1/2) / nx - 1/2) ex + ((b + 1/2) / ny - 1/2) ey, its box |ex| / nx + |ey| / ny
    wide (at most one destination texel, as a projected part's), its weight its share of the
    texel's solid angle (a latlong's band, else equal), deposited by box overlaps into a dense
    window of destination texels whose nonzero texels are the taps, in increasing order with no
    sorting. -1 where it does not apply: a window crossing a seam or larger than AREA_WINDOW or
    than the 4 nx ny entries of room, a texel whose image may bend (:func:`_bent`)."""
    if _bent(skind, sh, sw, i, j, dkind):
        return -1
    df, cx, cy, ex0, ex1, ey0, ey1 = _affine_image(skind, sh, sw, f, i, j, trig, rot, dkind, dh,
                                                   dw)  # fmt: skip
    rx, ry = 0.5 * (abs(ex0) + abs(ey0)), 0.5 * (abs(ex1) + abs(ey1))
    if not (rx < AREA_WINDOW and ry < AREA_WINDOW):  # NaN too
        return -1
    x0, y0 = int(math.floor(cx - rx)), int(math.floor(cy - ry))
    wx, wy = int(math.floor(cx + rx)) - x0 + 1, int(math.floor(cy + ry)) - y0 + 1
    if max(wx, wy) > AREA_WINDOW or wx * wy > 4 * nx * ny:
        return -1
    base = block(dkind, dh, dw, df, x0, y0, max(wx, wy))
    if base < 0:
        return -1
    window = np.zeros((wy, wx))
    col = np.empty(wx)
    # each part's box, at most one destination texel wide (as _part_of's)
    hx = min(0.5, 0.5 * (abs(ex0) / nx + abs(ey0) / ny))
    hy = min(0.5, 0.5 * (abs(ex1) / nx + abs(ey1) / ny))
    for b in range(ny):
        share = 1.0
        if skind == LATLONG:
            share = math.cos(math.pi * (j + b / ny) / sh) - math.cos(
                math.pi * (j + (b + 1) / ny) / sh
            )
        fb = (b + 0.5) / ny - 0.5
        for a in range(nx):
            fa = (a + 0.5) / nx - 0.5
            px, py = cx + fa * ex0 + fb * ey0, cy + fa * ex1 + fb * ey1
            for c in range(wx):
                col[c] = _overlap(px, hx, x0 + c)
            for r in range(wy):
                wr = share * _overlap(py, hy, y0 + r)
                if wr > 0:
                    for c in range(wx):
                        window[r, c] += wr * col[c]
    total = window.sum()
    n = 0
    for r in range(wy):
        for c in range(wx):
            if window[r, c] > 0:
                taps[o + n] = base + r * dw + c
                weights[o + n] = om * window[r, c] / total
                n += 1
    return n


@_jit
def _part_taps(skind: int, sh: int, sw: int, f: int, i: int, j: int, trig: ndarray, rot: ndarray,
               dkind: int, dh: int, dw: int, nx: int, ny: int, om_texel: float, o: int,
               taps: ndarray, weights: ndarray) -> int:  # fmt: skip
    """Source texel (f, i, j)'s merged taps at ``o`` onwards, part by part: each part projected
    (a latlong's parts centred on their centroids, with their exact solid angles) and deposited
    into the 3 x 3 destination texels around it, across seams."""
    wx = np.empty(3)
    wy = np.empty(3)
    e = o
    cut_latlong = skind == LATLONG and nx * ny > 1
    if cut_latlong:
        # the parts' edges are equally spaced in longitude (dp apart, centres at odd
        # multiples) and colatitude (dt): their sines and cosines are stepped from the
        # texel's corner by the angle-sum identities, one sine and cosine per texel and
        # step, one per row of parts for its centroid
        dt, dp = math.pi / (sh * ny), math.pi / (sw * nx)
        sdt, cdt = math.sin(dt), math.cos(dt)
        sht, cht = math.sin(dt / 2), math.cos(dt / 2)
        sdp, cdp = math.sin(dp), math.cos(dp)
        s1, c1 = trig[2, 2 * j], trig[3, 2 * j]
    for b in range(ny):
        if cut_latlong:
            # each part centred on its centroid, with its exact solid angle
            s0, c0 = s1, c1
            s1, c1 = s0 * cdt + c0 * sdt, c0 * cdt - s0 * sdt
            theta, band = _band_centroid_of(math.pi * (j + b / ny) / sh,
                                            math.pi * (j + (b + 1) / ny) / sh, s0, c0, s1,
                                            c1)  # fmt: skip
            st, ct = math.sin(theta), math.cos(theta)
            st2, ct2 = st * cht + ct * sht, ct * cht - st * sht
            se, ce = trig[0, 2 * i], trig[1, 2 * i]  # the texel's left edge
        for a in range(nx):
            if nx * ny == 1:
                df, cx, cy, hx, hy, _, _, _ = _footprint(
                    skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw
                )
                om = 1.0
            elif skind == LATLONG:
                # the part's centre and the midpoint of its right edge
                sp, cp = se * cdp + ce * sdp, ce * cdp - se * sdp
                sp2, cp2 = sp * cdp + cp * sdp, cp * cdp - sp * sdp
                se, ce = sp2, cp2
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
    return _merge_taps(taps, weights, o, e, om_texel)


@_jit
def _merge_taps(taps: ndarray, weights: ndarray, o: int, e: int, om: float) -> int:
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
def compact_exceptions(at: ndarray, counts: ndarray, taps: ndarray, weights: ndarray, ends: ndarray,
                       out_taps: ndarray, out_weights: ndarray) -> None:  # fmt: skip
    """Copy texel k's ``counts[k]`` merged entries from ``at[k]`` in ``taps``/``weights`` (the
    buffers :func:`splat_exceptions` filled) to ``ends[k] - counts[k]`` in the outputs."""
    for k in numba.prange(counts.shape[0]):
        src = at[k]
        dst = ends[k] - counts[k]
        for m in range(counts[k]):
            out_taps[dst + m] = taps[src + m]
            out_weights[dst + m] = weights[src + m]


@_jit
def _deposit_exception(acc: ndarray, t: int, offsets: ndarray, taps: ndarray, weights: ndarray,
                       k: int, values: ndarray) -> None:  # fmt: skip
    for m in range(offsets[k], offsets[k + 1]):
        q = taps[m]
        w = weights[m]
        for c in range(values.shape[0]):
            acc[t, q, c] += w * values[c]


@_jit
def deposit_exceptions(where: ndarray, offsets: ndarray, taps: ndarray, weights: ndarray,
                       width: ndarray, acc: ndarray) -> None:  # fmt: skip
    """Add the EXCEPTION texels' weights and weighted widths to ``acc[0, q, :2]``."""
    values = np.ones(2)
    for k in range(where.shape[0]):
        values[1] = width[where[k]]
        _deposit_exception(acc, 0, offsets, taps, weights, k, values)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def area_alpha(acc: ndarray, omega: ndarray, alpha: ndarray, inverse: ndarray) -> None:
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
