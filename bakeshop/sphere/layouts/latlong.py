"""The latitude-longitude (equirectangular) layout."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from bakeshop.errors import ArgumentError
from bakeshop.sphere import _kinds
from bakeshop.sphere.layouts.base import (
    Layout,
)


class LatLong(Layout):
    """Equirectangular: ``phi = 2 pi (u - 0.5)``, ``theta = pi v``,
    ``d = (sin theta sin phi, cos theta, -sin theta cos phi)``; centre column -Z, top row +Y.

    Any (H, W) is accepted (2:1 is usual). Filtering across a pole uses the texel half a turn
    away in the same row, exact for even widths (odd widths round it to the nearest column).
    """

    name = "latlong"
    kind = _kinds.LATLONG

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, 2 * n))

    def _check(self, shape: tuple[int, ...]) -> None:
        if len(shape) != 2:
            raise ArgumentError(f"a latlong image is (H, W); got spatial shape {shape}")

    def default_size(self, texels: int) -> int:
        return max(1, round(np.sqrt(texels / 2)))

    def directions(self, shape: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        # separable: W + H sines and cosines, then products (docs/BENCHMARKS.md, irradiance;
        # bit-identical to the general path: the same trigonometry as remap's plans)
        shape = self.check_shape(shape)
        dirs = np.empty(shape + (3,))
        from bakeshop.sphere import _native

        _native.latlong_directions(dirs)
        return dirs, self._valid(shape)

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        h, w = self.check_shape(shape)
        # exact: the band between theta_j and theta_j+1 covers 2 pi (cos theta_j - cos theta_j+1)
        c = np.cos(np.pi * np.arange(h + 1) / h)
        band = (c[:-1] - c[1:]) * (2 * np.pi / w)
        return np.repeat(band[:, None], w, axis=1)
