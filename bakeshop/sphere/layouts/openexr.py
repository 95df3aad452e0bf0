"""OpenEXR's environment maps (``ImfEnvmap.h``): its latlong and its cube."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError
from bakeshop.sphere import _kinds
from bakeshop.sphere.layouts.base import (
    Layout,
    _dirs_array,
)
from bakeshop.sphere.layouts.cubemap import _cube_corner


def _centre_aligned_edges(n: int) -> np.ndarray:
    """The cell edges, in [-1, 1], of ``n`` samples whose first and last lie on -1 and 1: the
    midpoints between samples, and the ends (the end samples' cells are half as wide)."""
    e = (2 * np.arange(n + 1) - 1) / (n - 1) - 1
    e[0], e[-1] = -1.0, 1.0
    return e


class OpenEXRLatLong(Layout):
    """OpenEXR's latitude-longitude environment (``envmap = latlong``, ``ImfEnvmap.h``).

    Texel centres, not edges, reach the ends: column ``i`` of ``W`` has longitude
    ``lon = pi (1 - 2 i / (W - 1))`` (+pi to -pi) and row ``j`` of ``H`` latitude
    ``lat = pi (1/2 - j / (H - 1))`` (+pi/2 to -pi/2); ``d = (sin lon cos lat, sin lat,
    cos lon cos lat)``: longitude 0 is +Z (the centre column), pi/2 is +X (a quarter to the
    left of the centre), the first and last rows are the poles and the first and last columns
    the same meridian (-Z). It is bakeshop's latlong turned half a turn, on a texel grid half
    a texel off both ways (a resampling, never a reordering).

    Each texel covers the part of the sphere nearer to its centre than to its neighbours'
    along each axis (its cell between midpoints), so the pole rows and the two seam columns are
    half cells: solid angles are exact and sum to 4*pi. Sizes are at least 2 x 2.
    """

    name = "openexr-latlong"
    kind = _kinds.OPENEXR_LATLONG

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, 2 * n))

    def _check(self, shape: tuple[int, ...]) -> None:
        if len(shape) != 2 or min(shape) < 2:
            raise ArgumentError(
                "an openexr-latlong image is (H, W) with H, W >= 2 (its first and last rows "
                f"are the poles); got spatial shape {shape}"
            )

    def default_size(self, texels: int) -> int:
        return max(2, round(np.sqrt(texels / 2)))

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        h, w = self.check_shape(shape)
        colatitude = np.pi * (_centre_aligned_edges(h) + 1) / 2
        c = np.cos(colatitude)
        band = c[:-1] - c[1:]
        width = np.pi * np.diff(_centre_aligned_edges(w))
        return band[:, None] * width[None, :]


class OpenEXRCube(Layout):
    """OpenEXR's cube environment (``envmap = cube``, ``ImfEnvmap.h``): six ``S x S`` faces
    stacked top to bottom in the order +X, -X, +Y, -Y, +Z, -Z, an ``(6 S, S)`` picture.

    Each face is the world seen from inside the cube, unmirrored (right-handed): +X has +Y up
    and +Z right, -X +Y up and -Z right, +Y +Z up and +X right, -Y -Z up and +X right, +Z +Y up
    and -X right, -Z +Y up and +X right (:data:`~bakeshop.sphere.cube.OPENEXR_FACE_BASES`).
    Texel centres reach the cube's edges: texel ``i`` of a face is at face coordinate
    ``2 i / (S - 1) - 1``, so neighbouring faces both hold the samples along their shared edge
    (each texel's solid angle is its cell's on its own face: exact, summing to 4*pi).
    Coordinates are ``(x, y)`` in the stacked picture; the scalar maps see six faces
    (:meth:`grid` is ``(S, S, 6)``). Faces are at least 2 x 2.
    """

    name = "openexr-cube"
    kind = _kinds.OPENEXR_CUBE

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        if isinstance(size, (tuple, list)):
            w, h = size
            if h != 6 * w:
                raise ArgumentError(
                    f"an openexr-cube is six square faces stacked (height 6 x width); got size "
                    f"{w}x{h}"
                )
            size = w
        n = int(size)
        return self.check_shape((6 * n, n))

    def _check(self, shape: tuple[int, ...]) -> None:
        if len(shape) != 2 or shape[0] != 6 * shape[1] or shape[1] < 2:
            raise ArgumentError(
                "an openexr-cube image is six square faces stacked top to bottom, (H, W) = "
                f"(6 S, S) with S >= 2; got (H, W) = {shape}"
            )

    def default_size(self, texels: int) -> int:
        return max(2, round(np.sqrt(texels / 6)))

    def grid(self, shape: Sequence[int]) -> tuple[int, int, int]:
        _, s = self.check_shape(shape)
        return s, s, 6

    def face_size(self, shape: Sequence[int]) -> int:
        return self.check_shape(shape)[1]

    def directions_at(self, coords: ArrayLike, shape: Sequence[int]) -> np.ndarray:
        s = self.face_size(shape)
        c = np.asarray(coords, dtype=np.float64)
        if c.shape[-1] != 2:
            raise ArgumentError(f"{self.name} coordinates must be (..., 2)")
        face = np.clip(np.floor(c[..., 1] / s), 0, 5)
        fxy = np.stack([face, c[..., 0], c[..., 1] - face * s], axis=-1).reshape(-1, 3)
        out = np.empty((len(fxy), 3))
        from bakeshop.sphere import _native

        _native.directions_at(self.kind, s, s, np.ascontiguousarray(fxy), out)
        return out.reshape(c.shape[:-1] + (3,))

    def coordinates(self, dirs: ArrayLike, shape: Sequence[int]) -> np.ndarray:
        s = self.face_size(shape)
        d = _dirs_array(dirs)
        out = np.empty((d.size // 3, 3))
        from bakeshop.sphere import _native

        _native.coordinates_of(self.kind, s, s, np.ascontiguousarray(d.reshape(-1, 3)), out)
        fxy = out.reshape(d.shape[:-1] + (3,))
        return np.stack([fxy[..., 1], fxy[..., 0] * s + fxy[..., 2]], axis=-1)

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        s = self.face_size(shape)
        e = _centre_aligned_edges(s)
        c = _cube_corner(e[None, :], e[:, None])
        face = c[1:, 1:] - c[:-1, 1:] - c[1:, :-1] + c[:-1, :-1]
        return np.tile(face, (6, 1))
