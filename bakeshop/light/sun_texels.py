"""The texels the sun's search reads (:mod:`bakeshop.light.sun`): held as arrays
(:class:`TexelArrays`), an environment's image with its geometry computed strip by strip where
it is looked at (:class:`ImageTexels`), or a file's windows read piece by piece
(:mod:`bakeshop.huge.light`). Each answers the search's three questions
(:class:`TexelSource`): the brightest texel outside a cap, the texels of a cap piece by piece in
index order, and the values and geometry of given texels."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Protocol

import numpy as np

from bakeshop.image import LUMINANCE_WEIGHTS
from bakeshop.light import _native
from bakeshop.sphere import Environment, texel_rows, texel_strips, texels_at

#: some texels: flat indices (n,), colour values (n, colour), directions (n, 3), solid angles (n,).
Piece = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def luminance_weights(values: np.ndarray) -> np.ndarray:
    """The luminance weights in the values' type."""
    return np.asarray(LUMINANCE_WEIGHTS, dtype=values.dtype)


def texel_luminance(values: np.ndarray) -> np.ndarray:
    """BT.709 luminance of (n, colour) values (:func:`bakeshop.image.luminance`), texel by texel
    in the values' type, so that it is the same number whichever texels are looked at together."""
    if values.shape[1] < 3:
        return values[:, 0]
    r, g, b = (values.dtype.type(w) for w in LUMINANCE_WEIGHTS)
    return values[:, 0] * r + values[:, 1] * g + values[:, 2] * b


class TexelSource(Protocol):
    """What the sun's search asks of texels (:class:`TexelArrays` over arrays), with flat
    indices of the source's own."""

    def brightest(self, centre: np.ndarray, cos_limit: float) -> int:
        """The texel of largest luminance farther than ``acos(cos_limit)`` from ``centre``
        (``cos_limit`` > 1: of all), the first on a tie; -1 when none is positive."""
        ...

    def caps(self, centre: np.ndarray, cos_limit: float) -> Iterator[Piece]:
        """The texels within ``acos(cos_limit)`` of ``centre`` (and perhaps a few more), piece
        by piece in ascending order of index: a source never holds a whole cap."""
        ...

    def gather(self, index: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Colour values (n, colour), directions (n, 3) and solid angles (n,) of texels."""
        ...


class TexelArrays:
    """Texels held as arrays (an environment's, or a piece of a chunked job's windows): what
    the sun's search asks of texels, ``brightest``, ``caps`` and ``gather``, with indices into
    these arrays (a :class:`TexelSource`; a chunked job's reads its texels from a file where
    they are looked at)."""

    def __init__(self, values: np.ndarray, dirs: np.ndarray, omega: np.ndarray) -> None:
        self.values, self.dirs, self.omega = values, dirs, omega

    def brightest(self, centre: np.ndarray, cos_limit: float) -> int:
        """As :meth:`TexelSource.brightest`."""
        weights = luminance_weights(self.values)
        return _brightest(self.values, weights, self.omega, self.dirs, centre, cos_limit)

    def cap(self, centre: np.ndarray, cos_limit: float) -> np.ndarray:
        """The indices of the texels within ``acos(cos_limit)`` of ``centre``, ascending."""
        return _cap(self.dirs, self.omega, centre, cos_limit)

    def caps(self, centre: np.ndarray, cos_limit: float) -> Iterator[Piece]:
        """As :meth:`TexelSource.caps`: one piece."""
        index = self.cap(centre, cos_limit)
        yield index, self.values[index], self.dirs[index], self.omega[index]

    def gather(self, index: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """As :meth:`TexelSource.gather`."""
        return self.values[index], self.dirs[index], self.omega[index]


class ImageTexels:
    """An environment's texels read from its image, their geometry computed strip by strip
    (:func:`bakeshop.sphere.texel_strips`): no per-texel array of the whole layout."""

    def __init__(self, env: Environment, colour: int):
        self.values = env.image.reshape(-1, env.image.shape[-1])
        self.colour, self.layout, self.shape = colour, env.layout, env.image.shape[:-1]

    def brightest(self, centre: np.ndarray, cos_limit: float) -> int:
        """As :meth:`TexelSource.brightest`, strip by strip."""
        whole = cos_limit > 1.0
        best, top = -1, 0.0
        for start, stop, dirs, omega in texel_strips(self.layout, self.shape, directions=not whole):
            values = self.values[start:stop, : self.colour]
            weights = luminance_weights(values)
            k = _brightest(values, weights, omega, _NO_DIRS if whole else dirs, centre, cos_limit)
            lum = texel_luminance(values[k : k + 1])[0] if k >= 0 else 0.0
            if lum > top:
                best, top = start + k, lum
        return best

    def caps(self, centre: np.ndarray, cos_limit: float) -> Iterator[Piece]:
        """As :meth:`TexelSource.caps`: a piece per strip of the rows the cap may reach."""
        rows = self._rows(centre, cos_limit)
        for start, _, dirs, omega in texel_strips(self.layout, self.shape, rows=rows):
            local = _cap(dirs, omega, centre, cos_limit)
            yield (
                start + local,
                self.values[start + local, : self.colour],
                dirs[local],
                omega[local],
            )

    def _rows(self, centre: np.ndarray, cos_limit: float) -> tuple[int, int]:
        """Rows that may hold texels within the cap: a latlong's band of colatitudes."""
        n_rows, _ = texel_rows(self.layout, self.shape)
        if self.layout.name != "latlong" or cos_limit <= -1.0:
            return 0, n_rows
        theta = math.acos(min(1.0, max(-1.0, float(centre[1]))))
        reach = math.acos(min(1.0, cos_limit))
        pitch = math.pi / n_rows
        return (
            max(0, math.floor((theta - reach) / pitch) - 1),
            min(n_rows, math.ceil((theta + reach) / pitch) + 1),
        )

    def gather(self, index: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """As :meth:`TexelSource.gather`."""
        dirs, omega = texels_at(self.layout, self.shape, index)
        return self.values[index, : self.colour], dirs, omega


_NO_DIRS = np.zeros((0, 3))


def _cap(dirs: np.ndarray, omega: np.ndarray, centre: np.ndarray, cos_limit: float) -> np.ndarray:
    """Indices (ascending) of the texels with a solid angle within ``acos(cos_limit)`` of
    ``centre`` (``src/light/sun_texels.hpp``)."""
    return _native.cap(dirs, omega, np.asarray(centre, np.float64).reshape(-1), cos_limit)


def _brightest(
    values: np.ndarray,
    weights: np.ndarray,
    omega: np.ndarray,
    dirs: np.ndarray | None,
    centre: np.ndarray,
    cos_limit: float,
) -> int:
    """The texel of largest luminance (in the values' type, ``weights`` the luminance weights
    in it) among those with a solid angle and at more than ``acos(cos_limit)`` from ``centre``
    (``cos_limit`` > 1: all of them, ``dirs`` unread, None allowed); -1 if none is positive;
    the first on a tie. 64 chunks whatever the thread count (``src/light/sun_texels.hpp``)."""
    if values.dtype not in (np.float32, np.float64):
        values = values.astype(np.float64)
    weights = np.asarray(weights, values.dtype)
    if dirs is None:
        dirs = _NO_DIRS
    return int(
        _native.brightest(
            values, weights, omega, dirs, np.asarray(centre, np.float64).reshape(-1), cos_limit
        )
    )
