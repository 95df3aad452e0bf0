"""The base class of every panorama layout, and the limits on layout sizes.

The layouts' formulas are the compiled maps of :mod:`bakeshop.sphere._native`
(``src/sphere/maps.hpp``), imported by the methods that run them: naming a layout (a command's
``--help``, its options) loads no extension."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError

#: largest accepted edge length of any layout, in texels.
MAX_EDGE = 1 << 16
#: largest accepted number of texels of one layout (a 32768 x 16384 latlong, 6 x 8192^2 cube).
MAX_TEXELS = 1 << 29

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(24)


def _dirs_array(dirs: ArrayLike) -> np.ndarray:
    d = np.asarray(dirs, dtype=np.float64)
    if d.ndim < 1 or d.shape[-1] != 3:
        raise ArgumentError(f"directions must be an array of shape (..., 3); got {d.shape}")
    return d


def power_of_two_edge(area: float) -> int:
    """The power of two nearest (in log scale) to ``sqrt(area)``: the default edge of cube faces,
    so that a cube's texels number about ``6 * area`` and every mip level halves exactly
    (296 texels becomes 256, 326 becomes 256, 400 becomes 512)."""
    edge = float(np.sqrt(max(float(area), 1.0)))
    return int(2 ** round(np.log2(edge)))


class Layout:
    """A panorama layout. Get one with :func:`layout` (``layout("latlong")``)."""

    #: the layout's name, as given to :func:`layout`.
    name: str = ""
    #: True when the image array has a face axis first (``(6, S, S, C)``).
    cubic = False

    def __repr__(self) -> str:
        return f"layout({self.name!r})"

    # -- shapes --------------------------------------------------------------------------------

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        """The spatial array shape for a user ``size``: an int, or ``(width, height)``."""
        raise NotImplementedError

    def check_shape(self, shape: Sequence[int]) -> tuple[int, ...]:
        """Return ``shape`` as a tuple of ints if it is a valid array shape of this layout, else
        raise :class:`~bakeshop.errors.ArgumentError`."""
        shape = tuple(int(n) for n in shape)
        self._check(shape)
        if min(shape) < 1 or max(shape) > MAX_EDGE or int(np.prod(shape)) > MAX_TEXELS:
            raise ArgumentError(
                f"{self.name} shape {shape} is out of range (edges 1..{MAX_EDGE}, "
                f"at most {MAX_TEXELS} texels)"
            )
        return shape

    def _check(self, shape: tuple[int, ...]) -> None:
        raise NotImplementedError

    def default_size(self, texels: int) -> int:
        """The size (for :meth:`shape`) whose valid texels number about ``texels`` (for cubes,
        crosses and strips: the nearest power-of-two face edge, :func:`power_of_two_edge`)."""
        raise NotImplementedError

    # -- the three operations --------------------------------------------------------------------

    #: kind number of the layout in the scalar maps (``src/sphere/maps.hpp``).
    kind = -1

    def grid(self, shape: Sequence[int]) -> tuple[int, int, int]:
        """``(h, w, faces)`` of a spatial shape, as the scalar maps take them
        (``src/sphere/maps.hpp``): a flat layout's ``(H, W, 1)``, the cube's
        ``(S, S, 6)``."""
        h, w = self.check_shape(shape)
        return h, w, 1

    def directions(self, shape: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        """Unit directions of the texel centres and the validity mask.

        Parameters
        ----------
        shape : tuple of int
            Spatial array shape, as returned by :meth:`shape`.

        Returns
        -------
        dirs : shape + (3,) float64
            Unit vectors (x, y, z) in the world frame. Invalid texels hold a unit vector too
            (the nearest meaningful one), never NaN.
        valid : shape bool
        """
        shape = self.check_shape(shape)
        return self.directions_at(self._centres(shape), shape), self._valid(shape)

    def _valid(self, shape: tuple[int, ...]) -> np.ndarray:
        return np.ones(shape, bool)

    def directions_at(self, coords: ArrayLike, shape: Sequence[int]) -> np.ndarray:
        """Unit directions at continuous texel coordinates: the inverse of :meth:`coordinates`.

        ``coords`` is ``(..., 2)`` ``(x, y)`` (``(..., 3)`` ``(face, x, y)`` for the cube);
        returns ``(..., 3)`` float64. Points outside a disk give the direction of the disk's
        nearest point.
        """
        h, w, _ = self.grid(shape)
        c = np.asarray(coords, dtype=np.float64)
        if c.shape[-1] != (3 if self.cubic else 2):
            raise ArgumentError(f"{self.name} coordinates must be (..., {3 if self.cubic else 2})")
        flat = c.reshape(-1, c.shape[-1])
        if not self.cubic:
            flat = np.concatenate([np.zeros((len(flat), 1)), flat], axis=1)
        out = np.empty((len(flat), 3))
        from bakeshop.sphere import _native

        _native.directions_at(self.kind, h, w, np.ascontiguousarray(flat), out)
        return out.reshape(c.shape[:-1] + (3,))

    def _centres(self, shape: tuple[int, ...]) -> np.ndarray:
        h, w = shape[-2:]
        x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
        c = np.stack([x, y], axis=-1)
        if self.cubic:
            f = np.broadcast_to(np.arange(6.0)[:, None, None, None], (6, h, w, 1))
            c = np.concatenate([f, np.broadcast_to(c, (6, h, w, 2))], axis=-1)
        return c

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        """Solid angle of each texel in steradians, float64 ``shape``; 0 where invalid.

        Exact (closed forms, or integrals evaluated to float64 precision); the whole layout
        sums to 4*pi.
        """
        raise NotImplementedError

    def coordinates(self, dirs: ArrayLike, shape: Sequence[int]) -> np.ndarray:
        """Continuous texel coordinates of directions.

        Parameters
        ----------
        dirs : (..., 3) array
            Directions (need not be normalised; a zero vector gives an arbitrary texel).
        shape : tuple of int

        Returns
        -------
        (..., 2) float64
            ``(x, y)``: column and row coordinates, texel ``i``'s centre at ``i + 0.5``, in
            ``[0, W] x [0, H]``. Cube layouts return ``(..., 3)``: ``(face, x, y)``.
        """
        h, w, _ = self.grid(shape)
        d = _dirs_array(dirs)
        out = np.empty((d.size // 3, 3))
        from bakeshop.sphere import _native

        _native.coordinates_of(self.kind, h, w, np.ascontiguousarray(d.reshape(-1, 3)), out)
        coords = out.reshape(d.shape[:-1] + (3,))
        return coords if self.cubic else coords[..., 1:]

    # -- cube views ----------------------------------------------------------------------------

    @property
    def base(self) -> Layout:
        """The layout images of this one are sampled in (the cube for crosses and strips)."""
        return self

    def prepare(self, image: np.ndarray) -> np.ndarray:
        """``image`` in :attr:`base` form: the image itself, or the cube of a cross or strip."""
        return image

    def base_shape(self, shape: Sequence[int]) -> tuple[int, ...]:
        """The spatial shape of :attr:`base` for this layout's ``shape``: the shape itself, or
        the ``(6, S, S)`` of a cross's or strip's cube."""
        return tuple(shape)
