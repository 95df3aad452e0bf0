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
- ``area``: an energy-preserving antialiasing filter for downsampling
  (:mod:`bakeshop.sphere.area`).
- ``auto``: ``area`` where the output holds at most half as many directions as the input (a
  real downsampling, where a point filter aliases), else ``bilinear`` (see :func:`auto_filter`).

Geometry is computed once per (source layout and shape, destination layout and shape,
rotation, filter) and cached (:mod:`bakeshop.sphere._plans`, :mod:`bakeshop.sphere.area`):
applying a cached plan is one parallel gather over the output.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop._typing import Filter
from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.resources import Cost, require
from bakeshop.sphere import _native, _plans
from bakeshop.sphere.area import SUPERSAMPLE_PART, area_remap, supersample, supersampling
from bakeshop.sphere.cube import cube_to_view
from bakeshop.sphere.layouts import Layout, layout
from bakeshop.sphere.reductions import area_exact
from bakeshop.sphere.rotation import rotation_key
from bakeshop.sphere.texels import STRIP_TEXELS, check_environment, valid_texels

#: the remap filters, ``auto`` the policy between ``area`` and ``bilinear``.
FILTERS = ("nearest", "bilinear", "area", "auto")

#: bytes per output texel of a nearest and a bilinear plan (int32 source texels; bilinear adds
#: two float32 fractions), see :mod:`bakeshop.sphere._plans`.
PLAN_BYTES = {"nearest": 4, "bilinear": 12}
#: peak bytes of building the area filter's matrix, per source and per output texel (measured
#: at 60-65 and 140-150 on latlong, cube and disk conversions, tests/test_resources.py; with a
#: margin).
AREA_SOURCE_BYTES = 80
AREA_OUTPUT_BYTES = 180
#: bytes any remap may hold besides (geometry tables, the kernels' scratch).
REMAP_OVERHEAD = 16 << 20
#: what a supersampled area remap (large sources, :func:`bakeshop.sphere.area.supersample`)
#: holds besides its output: a part's samples (taps, fractions, values, weights: ~96 bytes
#: each) and a strip's solid angles and peaks in the bright texels' pass.
SUPERSAMPLE_BYTES = 96 * SUPERSAMPLE_PART + 32 * STRIP_TEXELS

_NO_FRAC = np.empty((0, 2), np.float32)


def sample(
    image: ArrayLike, layout_name: str | Layout, dirs: ArrayLike, *, filter: str = "bilinear"
) -> np.ndarray:
    """Values of an environment at directions.

    Parameters
    ----------
    image : array
        The environment in layout ``layout_name``: ``(H, W[, C])``, or ``(6, S, S[, C])`` for a
        cube; linear radiance (see :func:`~bakeshop.sphere.check_environment`).
    layout_name : str or Layout
        One of :data:`~bakeshop.sphere.LAYOUT_NAMES`.
    dirs : (..., 3) array
        Directions in the world frame (need not be normalised).
    filter : {"nearest", "bilinear"}

    Returns
    -------
    (..., C) array (``(...)`` for a single-channel image given without channel axis)
        float32 (float64 for float64 images); a direction with a NaN or infinite component
        gives NaN.
    """
    validate_choice(filter, ("nearest", "bilinear"), "sampling filter")
    env = check_environment(image, layout_name)
    base = env.layout.base
    img = env.layout.prepare(env.image)
    d = np.asarray(dirs, dtype=np.float64)
    if d.ndim < 1 or d.shape[-1] != 3:
        raise ArgumentError(f"directions must be an array of shape (..., 3); got {d.shape}")
    h, w, _ = base.grid(img.shape[:-1])
    flat = np.ascontiguousarray(d.reshape(-1, 3))
    nearest = filter == "nearest"
    index = np.empty((len(flat), 1 if nearest else 4), np.int32)
    frac = _NO_FRAC if nearest else np.empty((len(flat), 2), np.float32)
    _native.taps_of(base.kind, h, w, flat, nearest, index, frac)
    src = np.ascontiguousarray(img.reshape(-1, img.shape[-1]))
    out = np.empty((index.shape[0], src.shape[1]), src.dtype)
    if nearest:
        _native.gather_nearest(src, index, out)
    else:
        _native.gather_bilinear(src, index, frac.astype(src.dtype, copy=False), out)
    out[~np.isfinite(flat).all(axis=1)] = np.nan
    return env.shaped(out.reshape(d.shape[:-1] + (img.shape[-1],)))


def auto_filter(
    src: str | Layout, src_shape: Sequence[int], dst: str | Layout, dst_shape: Sequence[int]
) -> Filter:
    """The filter ``"auto"`` means for a conversion: ``"area"`` (the energy-preserving
    average) when the output holds at most half as many valid texels as the input (a real
    downsampling, where a point filter aliases), else ``"bilinear"``.

    Near the input's size the area filter must cut source texels into parts, which costs
    seconds and about a gigabyte on a first 4096x2048 <-> 6x1024^2 call (a single command
    does not reuse the matrix), while bilinear moves the total energy by ~0.2-1% only for a
    one-texel sun (docs/panoramas.md)."""
    s, d = layout(src), layout(dst)
    in_texels = valid_texels(s, src_shape)
    out_texels = valid_texels(d, dst_shape)
    return "area" if 2 * out_texels <= in_texels else "bilinear"


def remap_shape(
    src: str | Layout,
    src_shape: Sequence[int],
    dst: str | Layout,
    size: int | tuple[int, int] | None = None,
) -> tuple[int, ...]:
    """The spatial shape :func:`remap` gives an image of spatial ``src_shape`` in layout
    ``src`` converted to ``dst`` at ``size`` (None: about as many valid texels as the
    source has; a power-of-two face edge for cubes, crosses and strips)."""
    s, d = layout(src), layout(dst)
    if size is None:
        size = d.default_size(valid_texels(s, src_shape))
    return d.shape(size)


def shape_text(shape: Sequence[int]) -> str:
    """``'1024x512'`` for an (H, W) layout, ``'6x256x256'`` for a cube."""
    return "x".join(map(str, shape)) if len(shape) == 3 else f"{shape[1]}x{shape[0]}"


def remap_cost(
    src: str | Layout,
    src_shape: Sequence[int],
    dst: str | Layout,
    size: int | tuple[int, int] | None = None,
    *,
    filter: str = "bilinear",
    channels: int = 3,
    itemsize: int = 4,
) -> Cost:
    """What :func:`remap` of an image of spatial ``src_shape`` (as given: a cross's picture
    shape) will hold at its peak, before it starts (:mod:`bakeshop.resources`).

    The output (``dst``'s shape times ``channels`` times ``itemsize``; a cube picture is
    gathered as a cube first), the plan (:data:`PLAN_BYTES` per output texel; the area
    filter's construction :data:`AREA_SOURCE_BYTES` per source texel and
    :data:`AREA_OUTPUT_BYTES` per output texel), a cube of a cross or strip given as the
    source, and :data:`REMAP_OVERHEAD`. A plan already cached costs less; the estimate does not
    count on it. ``work`` is in texels (output, plus the source's for the area filter).
    """
    validate_choice(filter, FILTERS, "filter")
    s, d = layout(src), layout(dst)
    src_shape = tuple(int(n) for n in src_shape)
    base_src = s.base_shape(src_shape)
    dst_shape = remap_shape(s.base, base_src, d, size)
    if filter == "auto":
        filter = auto_filter(s.base, base_src, d, dst_shape)
    return _remap_cost(s, src_shape, d, dst_shape, filter, channels * itemsize)


def _remap_cost(
    s: Layout,
    src_shape: Sequence[int],
    d: Layout,
    dst_shape: Sequence[int],
    filter: str,
    texel: int,
) -> Cost:
    """:func:`remap_cost` of resolved shapes and filter (``texel``: bytes per texel)."""
    base_src = s.base_shape(src_shape)
    n_src, n_out = math.prod(base_src), math.prod(dst_shape)
    memory = n_out * texel + REMAP_OVERHEAD
    if d.base is not d:  # gathered as a cube, then laid out as the picture
        memory += math.prod(d.base_shape(dst_shape)) * texel
    if s.base is not s:  # the cube of the source picture
        memory += n_src * texel
    if filter == "area" and supersampling(s.base, base_src, d.base, d.base_shape(dst_shape)):
        memory += SUPERSAMPLE_BYTES  # parts of bounded size, the bright texels' strips
        work = n_src + n_out
    elif filter == "area":
        memory += AREA_SOURCE_BYTES * n_src + AREA_OUTPUT_BYTES * n_out
        work = n_src + n_out
    else:
        memory += PLAN_BYTES[filter] * n_out
        work = n_out
    what = (
        f"remapping {s.name} {shape_text(src_shape)} to {d.name} {shape_text(dst_shape)} ({filter})"
    )
    return Cost(int(memory), int(work), what)


def remap(
    image: ArrayLike,
    src: str | Layout,
    dst: str | Layout,
    size: int | tuple[int, int] | None = None,
    *,
    filter: str = "bilinear",
    rotation: ArrayLike | None = None,
) -> np.ndarray:
    """Convert an environment from layout ``src`` to layout ``dst``.

    Parameters
    ----------
    image : array
        ``(H, W[, C])``, or ``(6, S, S[, C])`` when ``src`` is ``"cube"``; linear values (see
        :func:`~bakeshop.sphere.check_environment`).
    src, dst : str or Layout
        Layout names (:data:`~bakeshop.sphere.LAYOUT_NAMES`).
    size : int or (int, int), optional
        Output size as for :meth:`Layout.shape`: a latlong's height or ``(width, height)``, a
        square layout's edge, a cube's (or cross's) face edge. Default: about as many valid
        texels as the source has (a cube's face edge: the nearest power of two).
    filter : {"bilinear", "nearest", "area", "auto"}
        ``area`` is for downsampling (see Notes); ``auto`` chooses (:func:`auto_filter`).
    rotation : (yaw, pitch, roll) degrees or (3, 3) array, optional
        Rotate the environment: what the input shows in direction ``d`` appears in the output
        at ``R d`` (see :func:`~bakeshop.sphere.rotation_matrix`).

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

    The memory it needs is checked first (:func:`remap_cost`,
    :func:`bakeshop.resources.require`): a conversion that cannot fit is refused, saying how
    much it needs.

    ``area`` averages: every source texel deposits its solid angle into the output texels
    that its footprint (the box bounding its locally affine image) overlaps, in proportion to
    the overlap; an output texel is the deposits' weighted mean of radiance. A source texel
    more than 2/3 of an output texel long (where the output is locally finer) is cut into
    parts that short, each depositing its own solid angle the same way, so its energy is
    shared among every output texel it covers (boxy, as an area average of a coarser source
    is); where the deposits cover less than 3/4 of an output texel it blends towards bilinear.
    The resulting matrix of weights is then balanced (Sinkhorn & Knopp 1967): rows are scaled
    to sum 1, so a constant stays exactly constant, and columns so that each source texel
    sends out its solid angle, so radiance x solid angle is preserved (measured in
    docs/panoramas.md). Only when every source texel is over 4/3 output texels long along both
    its axes (magnifying everywhere) is the filter plain bilinear. Its geometry is cached too:
    8 bytes per weight, about 5 per output texel, and 8 for its row's start; a cached call is
    one parallel gather over the output.
    """
    validate_choice(filter, FILTERS, "filter")
    env = check_environment(image, src)
    s, d = env.layout, layout(dst)
    given = env.image.shape[:-1]
    src_shape = s.base_shape(given)
    dst_shape = remap_shape(s.base, src_shape, d, size)
    if filter == "auto":
        filter = auto_filter(s.base, src_shape, d, dst_shape)
    texel = env.image.itemsize * env.image.shape[-1]
    require(_remap_cost(s, given, d, dst_shape, filter, texel))
    img = s.prepare(env.image)
    base_shape = d.base_shape(dst_shape)
    key = rotation_key(rotation)
    channels = img.shape[-1]
    flat = np.ascontiguousarray(img.reshape(-1, channels))
    if filter == "area":
        out = area_exact(img, s.base, d, dst_shape, key)
        k = 0 if out is not None else supersampling(s.base, src_shape, d.base, base_shape)
        if k:
            out = supersample(flat, s.base, src_shape, d.base, base_shape, key, k)
            out = out if d.base is d else cube_to_view(out, d.name)
        elif out is None:
            out = area_remap(flat, s.base, src_shape, d, dst_shape, key)
        if out is not None:
            return env.shaped(out)
        filter = "bilinear"
    # a cube picture (cross, strip) gets a plan of its own, the cube's reordered, the first
    # time the cube's plan is reused: a cached call then gathers straight into the picture
    key_of = (s.base.name, src_shape, d.base.name, base_shape, filter, key)
    view_key = (s.base.name, src_shape, d.name, dst_shape, filter, key)
    plans = _plans.plans
    plan = plans.get(view_key)
    if plan is None and d.base is not d and key_of in plans.entries:
        cube_plan = plans.get(key_of)
        if cube_plan is not None:
            plan = plans.put(view_key, _plans.view_plan(cube_plan, d.name, base_shape))
    if plan is not None:
        out = _plans.apply(flat, plan, s.base.grid(src_shape)[1])
        return env.shaped(out.reshape(dst_shape + (channels,)))
    # a first conversion applies the plan while building it; a large one keeps none of it
    out = np.empty((int(np.prod(base_shape)), channels), flat.dtype)
    if _plans.plan_bytes(d.base.name, base_shape, filter) > _plans.KEEP_PLAN_BYTES:
        _plans.apply_in_parts(*key_of, flat, out)
    else:
        plans.put(key_of, _plans.build(*key_of, flat, out))
    out = out.reshape(base_shape + (channels,))
    return env.shaped(out if d.base is d else cube_to_view(out, d.name))
