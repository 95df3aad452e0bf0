"""The environment contract, and an environment's texels as flat arrays.

Every spherical function of bakeshop (remap, sample, SH, irradiance, the sun, the DIM pair,
prefiltering, fresnel bakes, the probe bake) takes ``(image, layout)`` and checks it with
:func:`check_environment`, so one rule answers for all of them:

- **Shape**: ``(H, W, C)`` for flat layouts, ``(6, S, S, C)`` for the cube, the spatial shape
  valid for the layout (a latlong is any ``(H, W)``, an angular map square, ...). A 2-D image
  (``(H, W)`` or ``(6, S, S)``) is one channel; results that are images come back 2-D too.
- **Channels**: 1 to 4, all carried. Every operation here is linear per channel, so a fourth
  (alpha) channel is resampled, integrated and filtered like the colour channels and comes
  out beside them; where an operation looks at colour only (finding the sun measures the
  luminance of the first three; a fresnel bake multiplies colour by reflectance), alpha
  passes through unchanged.
- **Values**: finite. NaN or infinite texels are refused, counted, with the first one's place:
  a NaN would spread silently through every filter and integral.
- **Types**: float32 stays float32, float64 stays float64, anything else becomes float32.
- **Memory**: a C-contiguous array is used as it is (never copied); any other is copied once.

:func:`texels` flattens an environment into (values, directions, solid angles) for everything
that integrates over the sphere; the directions and solid angles depend only on the layout and
shape and are cached (:func:`bakeshop.sphere.clear_caches` frees them).
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from typing import Literal, NamedTuple, overload

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, with_article
from bakeshop.sphere import _native
from bakeshop.sphere._cache import ByteBoundedCache
from bakeshop.sphere._kinds import CUBE, LATLONG
from bakeshop.sphere.cube import cube_to_view
from bakeshop.sphere.layouts import Layout, layout
from bakeshop.sphere.layouts.cubemap import _cube_face_solid_angles

#: the most channels an environment may have (RGB and alpha).
MAX_CHANNELS = 4


class Environment(NamedTuple):
    """An environment checked by :func:`check_environment`."""

    #: spatial shape + (C,): float32 (or float64), finite.
    image: np.ndarray
    #: its layout.
    layout: Layout
    #: True when the input was 2-D (one channel without a channel axis).
    squeezed: bool

    def shaped(self, result: np.ndarray) -> np.ndarray:
        """``result`` (..., C) without its channel axis when the input had none."""
        return result[..., 0] if self.squeezed else result


def check_environment(image: ArrayLike, layout_name: str | Layout) -> Environment:
    """Check ``(image, layout)`` against the environment contract (see the module docstring).

    Parameters
    ----------
    image : array_like
        ``(H, W[, C])``, or ``(6, S, S[, C])`` for the cube; C in 1..4.
    layout_name : str or Layout

    Returns
    -------
    Environment
        ``(image with a channel axis, layout, squeezed)``.

    Raises
    ------
    ArgumentError
        A bad layout name, shape, channel count, type, or a NaN or infinite value.
    """
    lay = layout(layout_name)
    a = np.asarray(image)
    if a.dtype.kind not in "fiub":
        raise ArgumentError(f"an environment must hold numbers; got {a.dtype}")
    spatial = 3 if lay.cubic else 2
    if a.ndim not in (spatial, spatial + 1):
        want = "(6, S, S) or (6, S, S, C)" if lay.cubic else "(H, W) or (H, W, C)"
        raise ArgumentError(f"{with_article(lay.name)} image must be {want}; got shape {a.shape}")
    squeezed = a.ndim == spatial
    if squeezed:
        a = a[..., None]
    if not 1 <= a.shape[-1] <= MAX_CHANNELS:
        raise ArgumentError(
            f"an environment has 1 to {MAX_CHANNELS} channels; got {a.shape[-1]} (shape {a.shape})"
        )
    lay.check_shape(a.shape[:-1])
    if a.dtype != np.float64:
        a = a.astype(np.float32, copy=False)
    # every step reads the texels as one flat (N, C) array: a strided view (a PFM's memory map
    # holds its rows bottom-up) is copied here once, not by each step
    a = np.ascontiguousarray(a)
    _check_finite(a)
    return Environment(a, lay, squeezed)


def _check_finite(a: np.ndarray) -> None:
    nan, inf, first = _native.count_nonfinite(a.reshape(-1))
    if nan or inf:
        where = np.unravel_index(first // a.shape[-1], a.shape[:-1])
        place = ", ".join(f"{n} {i}" for n, i in zip(_AXES[-len(where) :], where, strict=True))
        what = " and ".join(f"{n} {kind}" for n, kind in ((nan, "NaN"), (inf, "infinite")) if n)
        raise ArgumentError(
            f"the environment has {what} value(s) (the first at {place}); replace them first "
            "(bakeshop convert --nonfinite zero)"
        )


_AXES = ("face", "row", "column")


class Texels(NamedTuple):
    """An environment as flat arrays (see :func:`texels`)."""

    #: (N, C) float32 or float64: the radiance of each texel (a view of the image when possible).
    values: np.ndarray
    #: (N, 3) float64, read-only: unit direction of each texel centre.
    dirs: np.ndarray
    #: (N,) float64, read-only: solid angle of each texel, 0 where the layout has none.
    omega: np.ndarray
    #: the checked environment (its image, layout and whether it was 2-D); None for texels
    #: gathered from windows of a file (:mod:`bakeshop.huge`).
    environment: Environment | None


def texels(image: ArrayLike, layout_name: str | Layout) -> Texels:
    """An environment's texels as flat arrays, for everything that integrates over it.

    ``sum(values * omega[:, None])`` is the integral of radiance over the sphere (W m^-2 for
    radiance in W m^-2 sr^-1).

    Parameters
    ----------
    image : array_like
        The environment in ``layout_name`` (checked by :func:`check_environment`).
    layout_name : str or Layout

    Returns
    -------
    Texels
        ``(values, dirs, omega, environment)``.
    """
    env = check_environment(image, layout_name)
    spatial = env.image.shape[:-1]
    dirs, omega = texel_geometry(env.layout, spatial)
    return Texels(env.image.reshape(len(omega), -1), dirs, omega, env)


#: the texel geometry of the last layout and shape used (a 12.6 MP probe's is 400 MB), so that
#: the several passes of a probe bake compute it once.
_geometry = ByteBoundedCache("texel directions and solid angles", 0)


def texel_geometry(
    layout_name: str | Layout, shape: Sequence[int]
) -> tuple[np.ndarray, np.ndarray]:
    """Flat texel directions ``(N, 3)`` and solid angles ``(N,)`` (0 where invalid) of a
    layout's image of spatial ``shape``; float64, read-only, cached (the last one)."""
    lay = layout(layout_name)
    shape = lay.check_shape(shape)

    def build() -> tuple[np.ndarray, np.ndarray]:
        dirs, valid = lay.directions(shape)
        omega = np.where(valid, lay.solid_angles(shape), 0.0).reshape(-1)
        dirs = dirs.reshape(-1, 3)
        dirs.setflags(write=False)
        omega.setflags(write=False)
        return dirs, omega

    return _geometry.cached((lay.name, shape), build)


#: texels per strip of :func:`texel_strips`: a strip's directions and solid angles take 32 MB
#: (a whole 8192 x 4096 latlong's would take 1.07 GB).
STRIP_TEXELS = 1 << 20


def texel_rows(layout_name: str | Layout, shape: tuple[int, ...]) -> tuple[int, int]:
    """``(rows, texels per row)`` of a layout's flat texels (the order of :func:`texels`): a
    flat layout's H rows of W texels, the cube's faces stacked, 6 S rows of S."""
    lay = layout(layout_name)
    h, w, faces = lay.grid(lay.check_shape(shape))
    return faces * h, w


@overload
def texel_strips(
    layout_name: str | Layout,
    shape: tuple[int, ...],
    *,
    rows: tuple[int, int] | None = None,
    texels: int = STRIP_TEXELS,
    directions: Literal[True] = True,
) -> Iterator[tuple[int, int, np.ndarray, np.ndarray]]: ...
@overload
def texel_strips(
    layout_name: str | Layout,
    shape: tuple[int, ...],
    *,
    rows: tuple[int, int] | None = None,
    texels: int = STRIP_TEXELS,
    directions: bool,
) -> Iterator[tuple[int, int, np.ndarray | None, np.ndarray]]: ...
def texel_strips(
    layout_name: str | Layout,
    shape: tuple[int, ...],
    *,
    rows: tuple[int, int] | None = None,
    texels: int = STRIP_TEXELS,
    directions: bool = True,
) -> Iterator[tuple[int, int, np.ndarray | None, np.ndarray]]:
    """The texel geometry of :func:`texel_geometry` in strips of whole rows, never the whole
    layout's at once: for everything that sums over an environment's texels.

    Parameters
    ----------
    layout_name : str or Layout
    shape : tuple of int
        Spatial shape of the layout's image.
    rows : (int, int), optional
        ``(top, bottom)``: only these rows (of :func:`texel_rows`; default all).
    texels : int
        About as many texels per strip (at least one row).
    directions : bool
        False: solid angles only (``dirs`` is None).

    Yields
    ------
    start, stop : int
        The strip's flat texels ``[start, stop)`` (row-major, as :func:`texels` flattens).
    dirs : (stop - start, 3) float64 or None
    omega : (stop - start,) float64
        The same numbers, bit for bit, as those texels of :func:`texel_geometry`.
    """
    lay = layout(layout_name)
    shape = lay.check_shape(shape)
    n_rows, width = texel_rows(lay, shape)
    top, bottom = (0, n_rows) if rows is None else (max(0, rows[0]), min(n_rows, rows[1]))
    geometry = _RowGeometry(lay, shape)
    step = max(1, int(texels) // width)
    for r0 in range(top, bottom, step):
        r1 = min(r0 + step, bottom)
        dirs = geometry.directions(r0, r1) if directions else None
        yield r0 * width, r1 * width, dirs, geometry.solid_angles(r0, r1)


def texels_at(
    layout_name: str | Layout, shape: tuple[int, ...], index: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Directions ``(n, 3)`` and solid angles ``(n,)`` (float64) of the flat texels ``index``
    of a layout's image of spatial ``shape``: the same numbers as ``texel_geometry(...)[k][index]``
    without building the whole layout's."""
    lay = layout(layout_name)
    shape = lay.check_shape(shape)
    n_rows, width = texel_rows(lay, shape)
    index = np.asarray(index, dtype=np.int64).reshape(-1)
    if index.size and (index.min() < 0 or index.max() >= n_rows * width):
        raise ArgumentError(
            f"texel indices outside {with_article(lay.name)} image of shape {shape}"
        )
    return _RowGeometry(lay, shape).at(index)


class _RowGeometry:
    """Directions and solid angles of rows (or single texels) of one layout and shape."""

    def __init__(self, lay: Layout, shape: tuple):
        self.lay, self.shape = lay, shape
        self.h, self.w, self.faces = lay.grid(shape)
        self.kind = lay.kind
        self.trig = _NO_TRIG
        if self.kind == LATLONG:
            self.trig = np.empty((4, max(self.h, self.w)))
            _native.latlong_trig(self.h, self.w, self.trig)
        self._full: np.ndarray | None = None
        if self.kind == LATLONG:
            # the bands of LatLong.solid_angles, computed whole so that they are the same numbers
            c = np.cos(np.pi * np.arange(self.h + 1) / self.h)
            self._band = (c[:-1] - c[1:]) * (2 * np.pi / self.w)
        elif self.kind == CUBE and lay.base is lay:
            # a face's table is cached (8 bytes a texel): large faces are computed as needed
            self._face = _cube_face_solid_angles(self.h) if self.h <= 1024 else None

    def _full_omega(self) -> np.ndarray:
        if self._full is None:
            self._full = np.asarray(self.lay.solid_angles(self.shape)).reshape(-1)
        return self._full

    def solid_angles(self, r0: int, r1: int) -> np.ndarray:
        if self.kind == LATLONG:
            return np.repeat(self._band[r0:r1], self.w)
        if self.kind == CUBE and self.lay.base is self.lay:
            if self._face is None:
                return _cube_rows_solid_angles(self.h, r0, r1).reshape(-1)
            return self._face[np.arange(r0, r1) % self.h].reshape(-1)
        return self._full_omega()[r0 * self.w : r1 * self.w].copy()

    def directions(self, r0: int, r1: int) -> np.ndarray:
        out = np.empty(((r1 - r0) * self.w, 3))
        if self.lay.base is self.lay:
            _native.row_directions(self.kind, self.h, self.w, r0, r1, self.trig, out)
            return out
        return self._view_directions(np.arange(r0 * self.w, r1 * self.w))

    def _view_directions(self, index: np.ndarray) -> np.ndarray:
        j, i = np.divmod(index, self.w)
        coords = np.stack([i + 0.5, j + 0.5], axis=-1)
        return self.lay.directions_at(coords, self.shape)

    def at(self, index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if self.lay.base is self.lay:
            dirs = np.empty((len(index), 3))
            _native.index_directions(self.kind, self.h, self.w, index, self.trig, dirs)
        else:
            dirs = self._view_directions(index)
        if self.kind == LATLONG:
            omega = self._band[index // self.w]
        elif self.kind == CUBE and self.lay.base is self.lay:
            if self._face is None:
                j, i = np.divmod(index % (self.h * self.w), self.w)
                omega = _cube_texel_solid_angles(self.h, j, i)
            else:
                omega = self._face.reshape(-1)[index % (self.h * self.w)]
        else:
            omega = self._full_omega()[index]
        return dirs, omega


_NO_TRIG = np.zeros((4, 1))


def _cube_rows_solid_angles(s: int, r0: int, r1: int) -> np.ndarray:
    """Solid angles (r1 - r0, s) of rows r0..r1 of a cube's stacked faces (6 s rows): the
    corner differences of ``layouts.cubemap._cube_face_solid_angles``, one corner per texel."""
    e = 2 * np.arange(s + 1) / s - 1
    out = np.empty((r1 - r0, s))
    r = r0
    while r < r1:
        j0 = r % s
        j1 = min(s, j0 + r1 - r, j0 + 256)  # blocks of rows: small temporaries
        y, x = e[j0 : j1 + 1, None], e[None, :]
        c = np.arctan2(x * y, np.sqrt(x * x + y * y + 1))
        out[r - r0 : r - r0 + j1 - j0] = c[1:, 1:] - c[:-1, 1:] - c[1:, :-1] + c[:-1, :-1]
        r += j1 - j0
    return out


def cube_face_solid_angles(s: int) -> np.ndarray:
    """The (s, s) solid angles of a cube face's texels (the same on every face): cached up to
    1024 texels a side, computed by blocks of rows beyond (never a temporary of more than a
    few rows)."""
    return _cube_face_solid_angles(s) if s <= 1024 else _cube_rows_solid_angles(s, 0, s)


def _cube_texel_solid_angles(s: int, j: np.ndarray, i: np.ndarray) -> np.ndarray:
    """Solid angles of texels (row j, column i) of a cube face of s texels, broadcast: the
    corner differences of ``layouts.cubemap._cube_face_solid_angles`` (the same numbers), per
    texel."""
    e = 2 * np.arange(s + 1) / s - 1

    def corner(y: np.ndarray, x: np.ndarray) -> np.ndarray:
        return np.arctan2(x * y, np.sqrt(x * x + y * y + 1))

    j, i = np.asarray(j), np.asarray(i)
    y0, y1, x0, x1 = e[j], e[j + 1], e[i], e[i + 1]
    return corner(y1, x1) - corner(y0, x1) - corner(y1, x0) + corner(y0, x0)


#: cosines of recent (layout, shape, axis): a fresnel bake and its exposure share them.
_cosines = ByteBoundedCache("texel cosines", 1 << 28)


def texel_cosines(
    layout_name: str | Layout, shape: Sequence[int], axis: ArrayLike = (0.0, 1.0, 0.0)
) -> np.ndarray:
    """Cosine between each texel centre's direction and ``axis`` (normalised here).

    Computed from the layout's own scalar maps in one kernel, without building a direction
    array (a cross or strip is computed as its cube), and cached.

    Parameters
    ----------
    layout_name : str or Layout
    shape : tuple of int
        Spatial shape of the layout's image (``(H, W)``, or ``(6, S, S)`` for the cube).
    axis : 3-vector
        Non-zero and finite.

    Returns
    -------
    float64 array of ``shape``, read-only
        d . axis in [-1, 1]; NaN where the texel is invalid (outside a disk, unused cross
        squares).
    """
    lay = layout(layout_name)
    shape = lay.check_shape(shape)
    u = np.asarray(axis, dtype=np.float64).reshape(-1)
    norm = np.linalg.norm(u) if u.size == 3 else 0.0
    if not (np.isfinite(norm) and norm > 0):
        raise ArgumentError(f"the axis must be a non-zero finite 3-vector, got {axis!r}")
    up = tuple(u / norm)
    return _cosines.cached((lay.name, shape, up), lambda: (_texel_cosines(lay, shape, up),))[0]


def _texel_cosines(lay: Layout, shape: tuple, up: tuple) -> np.ndarray:
    if lay.base is not lay:
        cube = _texel_cosines(lay.base, lay.base_shape(shape), up)
        out = cube_to_view(cube, lay.name, fill=np.nan)
    else:
        h, w, faces = lay.grid(shape)
        out = np.empty(shape)
        _native.texel_cosines(lay.kind, faces, h, w, np.array(up), out.reshape(-1))
    out.setflags(write=False)
    return out


#: Largest shape whose valid texels are counted one by one (a float64 array of solid angles).
COUNTED_TEXELS = 1 << 22


def valid_texels(lay: str | Layout, shape: Sequence[int]) -> int:
    """How many texels of a ``shape`` image in layout ``lay`` hold a direction (a disk's
    inside, a cross's six cells). Counted exactly up to :data:`COUNTED_TEXELS` texels; past
    that, the layout's valid fraction measured on a small image of it, so that a size is
    judged (``auto`` filter, default sizes, cost estimates) without allocating its picture."""
    lay = layout(lay)
    shape = tuple(int(n) for n in shape)
    total = math.prod(shape)
    if total <= COUNTED_TEXELS:
        return int(np.count_nonzero(lay.solid_angles(shape)))
    small = lay.shape(lay.default_size(1 << 16))
    fraction = np.count_nonzero(lay.solid_angles(small)) / math.prod(small)
    return int(round(fraction * total))
