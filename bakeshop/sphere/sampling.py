"""Sampling environments at directions and remapping any layout to any layout.

Filters:

- ``nearest``: the texel containing the direction.
- ``bilinear``: the four texels around the direction, weighted by the fractional position,
  across seams: latlong wraps in longitude and continues across a pole on the opposite
  meridian; a cube face takes the texel across an edge at the same place along it and a cube
  corner's missing fourth texel is the mean of the other three (OpenGL's seamless cube map
  filtering); an octahedral map folds back over its edges; angular and paraboloid maps
  continue through their rims, and a mirror ball's rim texel stands in for what lies beyond
  (so the rim never fades to black).
- ``area``: an energy-preserving antialiasing filter for downsampling, see :func:`remap`.

Geometry is computed once per (source layout and shape, destination layout and shape,
rotation, filter) and cached: the texel indices and weights of every output texel (and, for the
area filter, of every source texel). Applying a cached plan is one numba-parallel gather over
the output.
"""

from __future__ import annotations

import collections
import functools

import numba
import numpy as np

from bakeshop import progress
from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.sphere import _maps
from bakeshop.sphere.cube import cube_to_view
from bakeshop.sphere.layouts import Layout, layout

FILTERS = ("nearest", "bilinear", "area")

#: largest memory for the area filter's per-thread accumulation buffers (fewer threads above).
AREA_BUFFER_BYTES = 1 << 29

#: memory for cached remap plans (12 bytes per output texel: six of 6 x 1024^2 faces).
PLAN_CACHE_BYTES = 1 << 29
#: memory for cached area filter plans (~48 bytes per output texel where the output is as
#: fine as the source: the plan of 4096 x 2048 latlong -> 6 x 1024^2 cube, 320 MB, fits).
AREA_PLAN_CACHE_BYTES = 1 << 29

#: the area filter's balancing (see ``_balance``): iterations at most, and the relative
#: error of every column's energy at which it stops.
AREA_BALANCE_ITERATIONS = 30
AREA_BALANCE_RTOL = 1e-4

_NO_FRAC = np.empty((0, 2), np.float32)
_NO_IMAGE = np.empty((0, 1), np.float32)


# --- rotation -----------------------------------------------------------------------------------


def rotation_matrix(yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0) -> np.ndarray:
    """The 3x3 rotation ``R = R_y(yaw) R_x(pitch) R_z(roll)``, angles in degrees.

    Each factor is a right-handed (counter-clockwise seen from the axis' tip) rotation about a
    world axis: yaw about +Y (up), pitch about +X (right), roll about +Z (backward). Roll is
    applied first, yaw last. Rotating an environment by ``R`` moves what was seen in direction
    ``d`` to direction ``R d``: ``yaw=90`` brings the forward view (-Z) to the left (-X),
    ``pitch=90`` brings the forward view up (+Y).
    """
    y, p, r = np.radians([yaw, pitch, roll])
    cy, sy, cp, sp, cr, sr = np.cos(y), np.sin(y), np.cos(p), np.sin(p), np.cos(r), np.sin(r)
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    rz = np.array([[cr, -sr, 0], [sr, cr, 0], [0, 0, 1]])
    return ry @ rx @ rz


def as_rotation(rotation) -> np.ndarray | None:
    """``rotation`` as an orthogonal 3x3 float64 matrix, or None for no rotation.

    Accepts None, a ``(yaw, pitch, roll)`` triple in degrees (see :func:`rotation_matrix`) or a
    3x3 orthogonal matrix (a reflection, determinant -1, is accepted: it mirrors the world).
    """
    if rotation is None:
        return None
    m = np.asarray(rotation, dtype=np.float64)
    if m.shape == (3,):
        m = rotation_matrix(*m)
    if m.shape != (3, 3) or not np.all(np.isfinite(m)):
        raise ArgumentError(
            f"rotation must be (yaw, pitch, roll) in degrees or a 3x3 matrix; got shape {m.shape}"
        )
    if not np.allclose(m @ m.T, np.eye(3), atol=1e-6):
        raise ArgumentError("a rotation matrix must be orthogonal (R @ R.T == I within 1e-6)")
    if np.allclose(m, np.eye(3), rtol=0, atol=1e-15):
        return None
    return m


# --- images -------------------------------------------------------------------------------------


def _as_environment(image, lay: Layout):
    """(float image with a channel axis, spatial shape, True if the channel axis was added)."""
    a = np.asarray(image)
    spatial = 3 if lay.cubic else 2
    if a.ndim not in (spatial, spatial + 1):
        want = "(6, S, S) or (6, S, S, C)" if lay.cubic else "(H, W) or (H, W, C)"
        raise ArgumentError(f"a {lay.name} image must be {want}; got shape {a.shape}")
    squeeze = a.ndim == spatial
    if squeeze:
        a = a[..., None]
    if a.shape[-1] < 1:
        raise ArgumentError(f"an image needs at least one channel; got shape {a.shape}")
    lay.check_shape(a.shape[:-1])
    if a.dtype != np.float64:
        a = a.astype(np.float32, copy=False)
    return a, a.shape[:-1], squeeze


def _apply(flat_src, index, frac):
    out = np.empty((index.shape[0], flat_src.shape[1]), flat_src.dtype)
    if frac is None:
        _maps.gather_nearest(flat_src, index, out)
    else:
        _maps.gather_bilinear(flat_src, index, frac.astype(flat_src.dtype, copy=False), out)
    return out


def sample(image, layout_name, dirs, *, filter: str = "bilinear") -> np.ndarray:
    """Values of an environment at directions.

    Parameters
    ----------
    image : array
        The environment in layout ``layout_name``: ``(H, W[, C])``, or ``(6, S, S[, C])`` for a
        cube; float32 (other types are converted) or float64, linear radiance.
    layout_name : str or Layout
        One of :data:`~bakeshop.sphere.layouts.LAYOUT_NAMES`.
    dirs : (..., 3) array
        Directions in the world frame (need not be normalised).
    filter : {"nearest", "bilinear"}

    Returns
    -------
    (..., C) array (``(...)`` for a single-channel image given without channel axis)
        float32 (float64 for float64 images). NaN or Inf in a texel spreads to the samples that
        use it; a direction with a NaN or infinite component gives NaN.
    """
    validate_choice(filter, ("nearest", "bilinear"), "sampling filter")
    lay = layout(layout_name)
    img, _, squeeze = _as_environment(image, lay)
    base = lay.base
    img = base_img = lay.prepare(img)
    d = np.asarray(dirs, dtype=np.float64)
    if d.ndim < 1 or d.shape[-1] != 3:
        raise ArgumentError(f"directions must be an array of shape (..., 3); got {d.shape}")
    h, w, _ = base._hw(base_img.shape[:-1])
    flat = np.ascontiguousarray(d.reshape(-1, 3))
    nearest = filter == "nearest"
    index = np.empty((len(flat), 1 if nearest else 4), np.int32)
    frac = None if nearest else np.empty((len(flat), 2), np.float32)
    _maps.taps_of(base.kind, h, w, flat, nearest, index, frac if frac is not None else _NO_FRAC)
    out = _apply(np.ascontiguousarray(img.reshape(-1, img.shape[-1])), index, frac)
    out[~np.isfinite(flat).all(axis=1)] = np.nan
    out = out.reshape(d.shape[:-1] + (img.shape[-1],))
    return out[..., 0] if squeeze else out


# --- remap --------------------------------------------------------------------------------------


class _ByteBoundedCache:
    """Least-recently-used results of ``fn`` (tuples of arrays) holding at most ``budget``
    bytes in all; the newest result is kept whatever its size."""

    def __init__(self, fn, budget: int):
        self.fn, self.budget = fn, budget
        self.entries: collections.OrderedDict = collections.OrderedDict()
        self.hits = self.misses = 0
        functools.update_wrapper(self, fn)

    def __call__(self, *key):
        value = self.get(key)
        return self.put(key, self.fn(*key)) if value is None else value

    def get(self, key):
        """The cached result for ``key`` (now the most recent), or None."""
        if key not in self.entries:
            self.misses += 1
            return None
        self.hits += 1
        self.entries.move_to_end(key)
        return self.entries[key]

    def put(self, key, value):
        """Cache ``value`` for ``key``, dropping the least recent beyond the budget."""
        self.entries[key] = value
        while len(self.entries) > 1 and self.nbytes() > self.budget:
            self.entries.popitem(last=False)
        return value

    def nbytes(self) -> int:
        return sum(a.nbytes for value in self.entries.values() for a in value)

    def cache_clear(self) -> None:
        self.entries.clear()


def _build_plan(src: str, src_shape, dst: str, dst_shape, filter: str, rotation, image=None,
                out=None):  # fmt: skip
    """The remap plan of every output texel (read-only arrays), see ``_maps.plan``:
    ``(base, frac, taps)``. Nearest: int32 (m,) source texels, no fractions or taps. Bilinear:
    int32 (m,) base indices of 2x2 blocks, float32 (m, 2) fractions and int32 (k, 4) explicit
    taps of the k output texels whose taps cross a seam: 12 bytes per output texel plus 16 per
    seam texel. With a flat ``image`` and an ``out`` (m, C), the plan is applied on the way."""
    s, d = layout(src), layout(dst)
    sh, sw, _ = s._hw(src_shape)
    dh, dw, faces = d._hw(dst_shape)
    m = faces * dh * dw
    nearest = filter == "nearest"
    rot = _matrix(rotation)
    if out is None:
        image = out = _NO_IMAGE
    base = np.empty(m, np.int32)
    frac = np.empty((0, 2) if nearest else (m, 2), np.float32)
    _maps.plan(s.kind, sh, sw, d.kind, dh, dw, faces, rot, nearest, base, frac, image, out)
    where = np.flatnonzero(base == _maps.EXCEPTION)
    taps = np.empty((len(where), 4), np.int32)
    if len(where):
        _maps.plan_exceptions(s.kind, sh, sw, d.kind, dh, dw, rot, where, taps)
        base[where] = _maps.EXCEPTION - np.arange(len(where), dtype=np.int32)
        if len(out):
            _maps.gather_at(image, sw, base, frac, taps, where, out)
    for a in (base, frac, taps):
        a.setflags(write=False)
    return base, frac, taps


#: cached remap plans, by (source, source shape, destination, shape, filter, rotation).
_plan = _ByteBoundedCache(_build_plan, PLAN_CACHE_BYTES)


def _apply_plan(flat_src, plan, row: int):
    """A cached plan applied to a flat (n, C) source whose rows are ``row`` texels long."""
    base, frac, taps = plan
    out = np.empty((base.shape[0], flat_src.shape[1]), flat_src.dtype)
    if len(frac) == 0:
        _maps.gather_nearest(flat_src, base[:, None], out)
    else:
        _maps.gather_plan(flat_src, row, base, frac, taps, out)
    return out


@functools.lru_cache(maxsize=4)
def _view_order(view: str, cube_shape) -> np.ndarray:
    """Per texel of the picture ``view`` of a cube of ``cube_shape``: the flat index of the
    cube texel it shows, -1 in the unused squares (int32, read-only)."""
    order = np.arange(int(np.prod(cube_shape)), dtype=np.int32).reshape(cube_shape)
    order = cube_to_view(order, view, fill=-1).reshape(-1)
    order.setflags(write=False)
    return order


def _view_plan(plan, view: str, cube_shape):
    """A cube's remap plan rearranged for its picture ``view``: the unused squares get -1
    (zero)."""
    base, frac, taps = plan
    order = _view_order(view, cube_shape)
    view_base = np.empty(order.size, np.int32)
    view_frac = np.empty((order.size if len(frac) else 0, 2), np.float32)
    _maps.reorder_plan(base, frac, order, view_base, view_frac)
    for a in (view_base, view_frac):
        a.setflags(write=False)
    return view_base, view_frac, taps


def _matrix(rotation: bytes | None) -> np.ndarray:
    return np.eye(3) if rotation is None else np.frombuffer(rotation).reshape(3, 3)


def _accumulators(m: int, channels: int) -> np.ndarray:
    """Zeroed float64 (chunks, m, channels) partial sums for a parallel splat: one per thread,
    as many as fit in AREA_BUFFER_BYTES (at least one)."""
    fit = AREA_BUFFER_BYTES // (m * channels * 8)
    return np.zeros((max(1, min(numba.get_num_threads(), fit)), m, channels))


def _build_area_plan(src: str, src_shape, dst: str, dst_shape, rotation: bytes | None):
    """The area filter's cached geometry: the sparse matrix from source to output texels
    (read-only CSR arrays: int64 row starts, int32 source texels, float32 weights; about 5
    entries per output texel where the output is as fine as the source, ~48 bytes). Built
    from the per-source-texel splat (``_maps.splat_plan``, ``_maps.splat_exceptions``),
    transposed into rows (``_maps.splat_rows``), with the bilinear taps where the splat does
    not cover (``_maps.bilinear_rows``), then balanced (:func:`_balance`). Empty arrays when
    the filter is bilinear everywhere."""
    s, d = layout(src), layout(dst)
    sh, sw, sfaces = s._hw(src_shape)
    dh, dw, faces = d._hw(dst_shape)
    n, m = sfaces * sh * sw, faces * dh * dw
    omega = s.solid_angles(src_shape).reshape(-1)
    rot = _matrix(rotation)
    anchor = np.empty(n, np.int32)
    wq = np.empty((n, 4), np.float32)
    scale = np.zeros(n, np.float32)
    width = np.zeros(n, np.float32)
    parts = np.ones((n, 2), np.int32)
    # the blend between splat and bilinear depends on the geometry only: sums of the weights
    # and of the weighted footprint widths
    acc = _accumulators(m, 2)
    _maps.splat_plan(s.kind, sh, sw, sfaces, omega, d.kind, dh, dw, rot, anchor, wq, scale,
                     width, parts, acc)  # fmt: skip
    if not np.any((parts.min(axis=1) <= 2) & (omega > 0)):
        # magnifying everywhere (every source texel over 4/3 destination texels long along both
        # of its axes): the area filter is bilinear (an empty plan)
        return np.empty(0, np.int64), np.empty(0, np.int32), np.empty(0, np.float32)
    where = np.flatnonzero(anchor == _maps.EXCEPTION)
    offsets = np.zeros(len(where) + 1, np.int64)
    # the merged entries, written straight into arrays grown as needed (fresh pages are what
    # costs here: nothing is allocated twice); the spare end is never touched
    kept, filled = (np.empty(0, np.int32), np.empty(0, np.float32)), 0
    if len(where):
        # in chunks, so that the unmerged taps (at most 4 per part: a part's box is at most one
        # destination texel wide; 8 bytes each) stay within AREA_BUFFER_BYTES / 16 (or one
        # texel's)
        cut = np.take(parts, where, axis=0)
        room = 4 * cut[:, 0].astype(np.int64) * cut[:, 1]
        del cut
        ends = np.cumsum(room)
        start = 0
        # one pair of buffers for every chunk: fresh pages cost more than the copying
        room_bytes = AREA_BUFFER_BYTES // 16
        buffers = (
            np.empty(room_bytes // 8 + int(room.max()), np.int32),
            np.empty(room_bytes // 8 + int(room.max()), np.float32),
        )
        while start < len(where):
            stop = max(
                start + 1,
                int(
                    np.searchsorted(ends, ends[start] - room[start] + room_bytes // 8, side="right")
                ),
            )
            chunk, chunk_room = where[start:stop], room[start:stop]
            at = np.zeros(len(chunk) + 1, np.int64)
            np.cumsum(chunk_room, out=at[1:])
            taps, weights = buffers[0][: at[-1]], buffers[1][: at[-1]]
            counts = offsets[start + 1 : stop + 1]
            _maps.splat_exceptions(s.kind, sh, sw, omega, d.kind, dh, dw, rot, chunk, parts,
                                   at, taps, weights, counts)  # fmt: skip
            # keep each texel's merged entries only
            kept_ends = np.cumsum(counts) + filled
            if kept_ends[-1] > len(kept[0]):
                # room for all at this chunk's merged share of the unmerged entries, + 1/16
                share = kept_ends[-1] / ends[stop - 1]
                cap = max(int(kept_ends[-1]), int(share * ends[-1] * 17 / 16) + 1024)
                grown = (np.empty(cap, np.int32), np.empty(cap, np.float32))
                grown[0][:filled], grown[1][:filled] = kept[0][:filled], kept[1][:filled]
                kept = grown
            _maps.compact_exceptions(at, counts, taps, weights, kept_ends, *kept)
            filled = int(kept_ends[-1])
            start = stop
        np.cumsum(offsets, out=offsets)
        del buffers
    taps, weights = kept[0][:filled], kept[1][:filled]
    if len(where):
        _maps.deposit_exceptions(where, offsets, taps, weights, width, acc)
        anchor[where] = _maps.EXCEPTION - np.arange(len(where), dtype=np.int32)
    alpha = np.empty(m, np.float32)
    inverse = np.empty(m, np.float32)
    omega_out = d.solid_angles(dst_shape).reshape(-1)
    _maps.area_alpha(acc, omega_out, alpha, inverse)
    del acc
    # one row of (source texel, weight) per output texel: the splat transposed (a cached call
    # is then a parallel gather), then the bilinear taps where alpha < 1
    cursor = np.zeros((numba.get_num_threads(), m), np.int64)
    none = (np.empty(0, np.int32), np.empty(0, np.float32))
    _maps.splat_rows(anchor, wq, scale, dw, offsets, taps, weights, alpha, inverse, cursor,
                     False, *none)  # fmt: skip
    bilinear = _plan(src, src_shape, dst, dst_shape, "bilinear", rotation)
    counts = np.zeros(m, np.int64)
    _maps.bilinear_rows(alpha, sw, *bilinear, counts, counts, False, *none)
    indptr = np.zeros(m + 1, np.int64)
    _maps.row_starts(cursor, counts, indptr)
    rows = (np.empty(indptr[-1], np.int32), np.empty(indptr[-1], np.float32))
    _maps.splat_rows(anchor, wq, scale, dw, offsets, taps, weights, alpha, inverse, cursor,
                     True, *rows)  # fmt: skip
    del anchor, wq, scale, offsets, taps, weights, cursor
    _maps.bilinear_rows(alpha, sw, *bilinear, indptr, counts, True, *rows)
    sums = np.zeros((numba.get_num_threads(), n))
    _balance(indptr, *rows, omega_out, omega, sums)
    plan = (indptr, *rows)
    for a in plan:
        a.setflags(write=False)
    return plan


def _balance(indptr, indices, values, omega_out, omega_in, sums):
    """Scale the rows and columns of the sparse matrix M (CSR, nonnegative float32 ``values``,
    in place) towards every nonempty row summing to 1 (a constant stays constant) and every
    column p carrying its source texel's solid angle, sum_q omega_out[q] M[q, p] = omega_in[p]
    (radiance x solid angle is preserved): Sinkhorn's alternating normalisation (Sinkhorn &
    Knopp 1967) of the energy transport omega_out[q] M[q, p], on the scale vectors (one pass
    over M per iteration), its column steps over-relaxed (Thibault et al. 2017) and with
    momentum (the slow, smooth imbalances around a latlong's poles converge ~3x sooner),
    ending on the rows (exact). Stops when every column is within AREA_BALANCE_RTOL or after
    AREA_BALANCE_ITERATIONS; returns the largest relative column error left. ``sums``:
    zeroed scratch, (chunks, n)."""
    col = np.ones(len(omega_in))
    step = np.ones(len(omega_in))
    err = np.inf
    for _ in range(AREA_BALANCE_ITERATIONS):
        _maps.balance_rows(indptr, indices, values, omega_out, col, sums)
        err = _maps.balance_columns(sums, omega_in, col, step)
        if err <= AREA_BALANCE_RTOL:
            break
    _maps.scale_rows(indptr, indices, values, col)
    return err


def _area_plan(src: str, src_shape, dst: str, dst_shape, rotation: bytes | None):
    """:func:`_build_area_plan` into layout ``dst``; for a cube picture, the cube's with its
    rows reordered into the picture's (the unused squares' rows are empty)."""
    d = layout(dst)
    if d.base is d:
        return _build_area_plan(src, src_shape, dst, dst_shape, rotation)
    cube_shape = d.base.shape(d.face_size(dst_shape))
    indptr, indices, values = _build_area_plan(src, src_shape, d.base.name, cube_shape, rotation)
    if len(indptr) == 0:
        return indptr, indices, values
    order = _view_order(dst, cube_shape)
    lengths = np.zeros(order.size + 1, np.int64)
    used = order >= 0
    lengths[1:][used] = np.diff(indptr)[order[used]]
    view_indptr = np.cumsum(lengths)
    view_rows = (np.empty_like(indices), np.empty_like(values))
    _maps.reorder_rows(indptr, indices, values, order, view_indptr, *view_rows)
    plan = (view_indptr, *view_rows)
    for a in plan:
        a.setflags(write=False)
    return plan


_area_plan = _ByteBoundedCache(_area_plan, AREA_PLAN_CACHE_BYTES)


def _area(flat, s: Layout, src_shape, d: Layout, dst_shape, key):
    """The area filter into ``d`` (a cube picture: gathered straight into it); None where it
    is bilinear (magnifying everywhere)."""
    with progress.step(f"area filter {s.name} -> {d.name}"):
        indptr, indices, values = _area_plan(s.name, src_shape, d.name, dst_shape, key)
        if len(indptr) == 0:
            return None
        out = np.empty(dst_shape + (flat.shape[1],), flat.dtype)
        _maps.area_gather(flat, indptr, indices, values, out.reshape(-1, flat.shape[1]))
    return out


def remap(image, src, dst, size=None, *, filter: str = "bilinear", rotation=None) -> np.ndarray:
    """Convert an environment from layout ``src`` to layout ``dst``.

    Parameters
    ----------
    image : array
        ``(H, W[, C])``, or ``(6, S, S[, C])`` when ``src`` is ``"cube"``; linear values.
    src, dst : str
        Layout names (:data:`~bakeshop.sphere.layouts.LAYOUT_NAMES`).
    size : int or (int, int), optional
        Output size as for :meth:`Layout.shape`: a latlong's height or ``(width, height)``, a
        square layout's edge, a cube's (or cross's) face edge. Default: about as many valid
        texels as the source has.
    filter : {"bilinear", "nearest", "area"}
        ``area`` is for downsampling (see Notes).
    rotation : (yaw, pitch, roll) degrees or (3, 3) array, optional
        Rotate the environment: what the input shows in direction ``d`` appears in the output
        at ``R d`` (see :func:`rotation_matrix`).

    Returns
    -------
    array
        ``dst``'s shape plus the channel axis (none if the input had none); float32 (float64
        for float64 input). Texels outside a disk layout's disk, and the unused squares of a
        cross, are 0 in every channel (alpha too).

    Notes
    -----
    ``nearest`` and ``bilinear`` look every output texel centre's direction up in the source;
    the geometry (which source texels, which weights) is cached per
    (src, source shape, dst, output shape, filter, rotation), so converting many images of
    one size costs one gather each.

    ``area`` averages: every source texel deposits its solid angle into the output texels
    that its footprint (the box bounding its locally affine image) overlaps, in proportion to
    the overlap; an output texel is the deposits' weighted mean of radiance. A source texel
    more than 2/3 of an output texel long (where the output is locally finer) is cut into
    parts that short, each depositing its own solid angle the same way, so its energy is
    shared among every output texel it covers (boxy, as an area average of a coarser source
    is); where the deposits cover less than 3/4 of an output texel it blends towards bilinear.
    The resulting matrix of weights is then balanced (Sinkhorn & Knopp 1967): rows are scaled
    to sum 1, so a constant stays exactly constant, and columns so that each source texel
    sends out its solid angle, so radiance x solid angle is preserved (to 5e-5 on the default
    probe with its one-texel sun, 4.4e-4 for a sun at a latlong's zenith; docs/panoramas.md).
    Only when every source texel is over 4/3 output texels long along both its axes
    (magnifying everywhere) is the filter plain bilinear. Its geometry is cached too: 8 bytes
    per weight, about 5 per output texel, and 8 for its row's start; a cached call is one
    parallel gather over the output.
    """
    validate_choice(filter, FILTERS, "filter")
    s, d = layout(src), layout(dst)
    img, _, squeeze = _as_environment(image, s)
    img = s.prepare(img)
    src_shape = img.shape[:-1]
    if size is None:
        size = d.default_size(int(np.count_nonzero(s.base.solid_angles(src_shape))))
    dst_shape = d.shape(size)
    base_shape = dst_shape if d.base is d else d.base.shape(d.face_size(dst_shape))
    rot = as_rotation(rotation)
    key = None if rot is None else rot.tobytes()
    flat = np.ascontiguousarray(img.reshape(-1, img.shape[-1]))
    channels = img.shape[-1]
    if filter == "area":
        out = _area(flat, s.base, src_shape, d, dst_shape, key)
        if out is not None:
            return _shaped(out, squeeze)
        filter = "bilinear"
    # a cube picture (cross, strip) gets a plan of its own, the cube's reordered, the first
    # time the cube's plan is reused: a cached call then gathers straight into the picture
    key_of = (s.base.name, src_shape, d.base.name, base_shape, filter, key)
    view_key = (s.base.name, src_shape, d.name, dst_shape, filter, key)
    plan = _plan.get(view_key)
    if plan is None and d.base is not d and key_of in _plan.entries:
        plan = _plan.put(view_key, _view_plan(_plan.get(key_of), d.name, base_shape))
    if plan is not None:
        out = _apply_plan(flat, plan, s.base._hw(src_shape)[1])
        return _shaped(out.reshape(dst_shape + (channels,)), squeeze)
    # a first conversion applies the plan while building it
    out = np.empty((int(np.prod(base_shape)), channels), flat.dtype)
    _plan.put(key_of, _build_plan(*key_of, flat, out))
    out = out.reshape(base_shape + (channels,))
    return _shaped(out if d.base is d else cube_to_view(out, d.name), squeeze)


def _shaped(out, squeeze: bool):
    """``out`` without its channel axis where the input had none."""
    return out[..., 0] if squeeze else out
