"""Nearest and bilinear remap plans: which source texels, with which weights, make each output
texel. Built by the compiled kernels of ``src/sphere/gather.hpp``, cached per (source layout and
shape, destination layout and shape, filter, rotation), applied as one parallel gather."""

from __future__ import annotations

import functools

import numpy as np

from bakeshop.sphere import _native
from bakeshop.sphere._cache import ByteBoundedCache
from bakeshop.sphere.cube import cube_to_view
from bakeshop.sphere.layouts import layout
from bakeshop.sphere.rotation import key_matrix

#: memory for cached remap plans (12 bytes per output texel: six of 6 x 1024^2 faces).
PLAN_BYTES = 1 << 29
#: a plan larger than this (a 6 x 2048^2 cube's takes 300 MB) is applied as it is built, in
#: parts of :data:`PART_BYTES`, and not kept: the output alone is then the remap's memory.
KEEP_PLAN_BYTES = 1 << 27
PART_BYTES = 1 << 24

_NO_IMAGE = np.empty((0, 1), np.float32)

#: a remap plan: ``(base, frac, taps)`` (see :func:`build`).
Plan = tuple[np.ndarray, np.ndarray, np.ndarray]

#: cached plans, by (source, source shape, destination, shape, filter, rotation key).
plans = ByteBoundedCache("remap plans", PLAN_BYTES)


def build(
    src: str,
    src_shape: tuple[int, ...],
    dst: str,
    dst_shape: tuple[int, ...],
    filter: str,
    rotation: bytes | None,
    image: np.ndarray | None = None,
    out: np.ndarray | None = None,
    rows: tuple[int, int] | None = None,
) -> Plan:
    """The remap plan of every output texel (read-only arrays), see ``plan`` in ``gather.hpp``:
    ``(base, frac, taps)``. Nearest: int32 (m,) source texels, no fractions or taps. Bilinear:
    int32 (m,) base indices of 2x2 blocks, float32 (m, 2) fractions and int32 (k, 4) explicit
    taps of the k output texels whose taps cross a seam: 12 bytes per output texel plus 16 per
    seam texel. With a flat ``image`` and an ``out`` (m, C), the plan is applied on the way.
    ``rows`` (first, stop): the plan of those output rows only (faces stacked), ``out`` theirs."""
    s, d = layout(src), layout(dst)
    sh, sw, _ = s.grid(src_shape)
    dh, dw, faces = d.grid(dst_shape)
    first, stop = (0, faces * dh) if rows is None else rows
    m = (stop - first) * dw
    nearest = filter == "nearest"
    rot = key_matrix(rotation)
    if out is None:
        image = out = _NO_IMAGE
    assert image is not None, "a plan is applied to an image"
    base = np.empty(m, np.int32)
    frac = np.empty((0, 2) if nearest else (m, 2), np.float32)
    _native.plan(s.kind, sh, sw, d.kind, dh, dw, faces, rot, nearest, base, frac, image, out,
                 first)  # fmt: skip
    where = np.flatnonzero(base == _native.EXCEPTION)
    taps = np.empty((len(where), 4), np.int32)
    if len(where):
        _native.plan_exceptions(s.kind, sh, sw, d.kind, dh, dw, rot, where + first * dw, taps)
        base[where] = _native.EXCEPTION - np.arange(len(where), dtype=np.int32)
        if len(out):
            _native.gather_at(image, sw, base, frac, taps, where, out)
    for a in (base, frac, taps):
        a.setflags(write=False)
    return base, frac, taps


def plan_bytes(dst: str, dst_shape: tuple[int, ...], filter: str) -> int:
    """Bytes of a remap plan into ``dst`` (seam texels aside): 12 per output texel for
    bilinear, 4 for nearest."""
    dh, dw, faces = layout(dst).grid(dst_shape)
    return faces * dh * dw * (4 if filter == "nearest" else 12)


def apply_in_parts(
    src: str,
    src_shape: tuple[int, ...],
    dst: str,
    dst_shape: tuple[int, ...],
    filter: str,
    rotation: bytes | None,
    image: np.ndarray,
    out: np.ndarray,
) -> None:
    """Remap the flat ``image`` into ``out`` (m, C) by building the plan a part of
    :data:`PART_BYTES` at a time and applying it on the way, keeping none of it."""
    dh, dw, faces = layout(dst).grid(dst_shape)
    step = max(1, PART_BYTES // (12 * dw))
    for first in range(0, faces * dh, step):
        stop = min(first + step, faces * dh)
        build(src, src_shape, dst, dst_shape, filter, rotation, image, out[first * dw : stop * dw],
              (first, stop))  # fmt: skip


def cached(
    src: str,
    src_shape: tuple[int, ...],
    dst: str,
    dst_shape: tuple[int, ...],
    filter: str,
    rotation: bytes | None,
) -> Plan:
    """The cached plan of a conversion (built when missing)."""
    key = (src, src_shape, dst, dst_shape, filter, rotation)
    return plans.cached(key, lambda: build(*key))


def apply(flat_src: np.ndarray, plan: Plan, row: int) -> np.ndarray:
    """A plan applied to a flat (n, C) source whose rows are ``row`` texels long: (m, C)."""
    base, frac, taps = plan
    out = np.empty((base.shape[0], flat_src.shape[1]), flat_src.dtype)
    if len(frac) == 0:
        _native.gather_nearest(flat_src, base[:, None], out)
    else:
        _native.gather_plan(flat_src, row, base, frac, taps, out)
    return out


@functools.lru_cache(maxsize=4)
def view_order(view: str, cube_shape: tuple[int, ...]) -> np.ndarray:
    """Per texel of the picture ``view`` of a cube of ``cube_shape``: the flat index of the
    cube texel it shows, -1 in the unused squares (int32, read-only)."""
    order: np.ndarray = np.arange(int(np.prod(cube_shape)), dtype=np.int32).reshape(cube_shape)
    order = cube_to_view(order, view, fill=-1).reshape(-1)
    order.setflags(write=False)
    return order


def view_plan(plan: Plan, view: str, cube_shape: tuple[int, ...]) -> Plan:
    """A cube's plan rearranged for its picture ``view``: the unused squares get -1 (zero)."""
    base, frac, taps = plan
    order = view_order(view, cube_shape)
    view_base = np.empty(order.size, np.int32)
    view_frac = np.empty((order.size if len(frac) else 0, 2), np.float32)
    _native.reorder_plan(base, frac, order, view_base, view_frac)
    for a in (view_base, view_frac):
        a.setflags(write=False)
    return view_base, view_frac, taps
