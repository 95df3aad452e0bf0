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

:func:`texels` flattens an environment into (values, directions, solid angles) for everything
that integrates over the sphere; the directions and solid angles depend only on the layout and
shape and are cached (:func:`bakeshop.sphere.clear_caches` frees them).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from bakeshop.errors import ArgumentError
from bakeshop.sphere import _maps
from bakeshop.sphere._cache import ByteBoundedCache
from bakeshop.sphere.cube import cube_to_view
from bakeshop.sphere.layouts import Layout, layout

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


def check_environment(image, layout_name: str | Layout) -> Environment:
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
        raise ArgumentError(f"a {lay.name} image must be {want}; got shape {a.shape}")
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
    _check_finite(a)
    return Environment(a, lay, squeezed)


def _check_finite(a: np.ndarray) -> None:
    flat = a.reshape(-1)
    nan, inf, first = _count_nonfinite(flat if flat.flags.c_contiguous else a.ravel())
    if nan or inf:
        where = np.unravel_index(first // a.shape[-1], a.shape[:-1])
        place = ", ".join(f"{n} {i}" for n, i in zip(_AXES[-len(where) :], where, strict=True))
        what = " and ".join(f"{n} {kind}" for n, kind in ((nan, "NaN"), (inf, "infinite")) if n)
        raise ArgumentError(
            f"the environment has {what} value(s) (the first at {place}); replace them first "
            "(bakeshop convert --nonfinite zero)"
        )


_AXES = ("face", "row", "column")


@numba.njit(parallel=True, cache=True)
def _count_nonfinite(flat):  # pragma: no cover - compiled
    """(NaNs, infinities, flat index of the first non-finite value or -1)."""
    chunks = 64
    n = flat.shape[0]
    nans = np.zeros(chunks, np.int64)
    infs = np.zeros(chunks, np.int64)
    firsts = np.full(chunks, -1, np.int64)
    for c in numba.prange(chunks):
        for k in range(c * n // chunks, (c + 1) * n // chunks):
            v = flat[k]
            if not np.isfinite(v):
                if v != v:
                    nans[c] += 1
                else:
                    infs[c] += 1
                if firsts[c] < 0:
                    firsts[c] = k
    first = -1
    for c in range(chunks):
        if firsts[c] >= 0:
            first = firsts[c]
            break
    return nans.sum(), infs.sum(), first


class Texels(NamedTuple):
    """An environment as flat arrays (see :func:`texels`)."""

    #: (N, C) float32 or float64: the radiance of each texel (a view of the image when possible).
    values: np.ndarray
    #: (N, 3) float64, read-only: unit direction of each texel centre.
    dirs: np.ndarray
    #: (N,) float64, read-only: solid angle of each texel, 0 where the layout has none.
    omega: np.ndarray
    #: the checked environment (its image, layout and whether it was 2-D).
    environment: Environment


def texels(image, layout_name: str | Layout) -> Texels:
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


def texel_geometry(layout_name: str | Layout, shape) -> tuple[np.ndarray, np.ndarray]:
    """Flat texel directions ``(N, 3)`` and solid angles ``(N,)`` (0 where invalid) of a
    layout's image of spatial ``shape``; float64, read-only, cached (the last one)."""
    lay = layout(layout_name)
    shape = lay.check_shape(shape)

    def build():
        dirs, valid = lay.directions(shape)
        omega = np.where(valid, lay.solid_angles(shape), 0.0).reshape(-1)
        dirs = dirs.reshape(-1, 3)
        dirs.setflags(write=False)
        omega.setflags(write=False)
        return dirs, omega

    return _geometry.cached((lay.name, shape), build)


#: cosines of recent (layout, shape, axis): a fresnel bake and its exposure share them.
_cosines = ByteBoundedCache("texel cosines", 1 << 28)


def texel_cosines(layout_name: str | Layout, shape, axis=(0.0, 1.0, 0.0)) -> np.ndarray:
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
        s = lay.face_size(shape)
        cube = _texel_cosines(lay.base, (6, s, s), up)
        out = cube_to_view(cube, lay.name, fill=np.nan)
    else:
        h, w, faces = lay.grid(shape)
        out = np.empty(shape)
        _cosine_kernel(lay.kind, faces, h, w, np.array(up), out.reshape(-1))
    out.setflags(write=False)
    return out


@numba.njit(cache=True, parallel=True)
def _cosine_kernel(kind, faces, h, w, up, out):  # pragma: no cover - compiled
    for row in numba.prange(faces * h):
        f, j = divmod(row, h)
        for i in range(w):
            if _maps.valid(kind, h, w, f, i, j):
                dx, dy, dz = _maps.direction(kind, h, w, f, i + 0.5, j + 0.5)
                out[row * w + i] = dx * up[0] + dy * up[1] + dz * up[2]
            else:
                out[row * w + i] = np.nan
