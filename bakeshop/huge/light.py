"""Spherical harmonics, the DIM pair and the sun of latlong panoramas larger than memory.

Everything here is a sum over texels, so each strip of rows gives a partial sum that dask adds
up (:meth:`bakeshop.huge.engine.Engine.reduce`); directions and solid angles are computed per
strip (:func:`bakeshop.sphere.windows.latlong_window_geometry`), never for the whole layout.

Two passes over the file:

1. per strip: its brightest texel, its SH projection, and its DIM (the cosine sum of the
   strip's texels for ``exact``; for ``auto``, of the strip's moment-preserving bins,
   :func:`bakeshop.light.diffuse.compress`, split against the strip's own energy, so at least as
   finely as the in-memory ``auto`` splits them): only the (M, C) sums are kept, never the
   sources of every strip;
2. per strip: the brightest texel outside caps of :data:`RIVAL_RADII` around the brightest one
   (the sun's possible rivals).

The strips' partial results are added by the engine as they come (a DIM partial is as large
as the output: one per strip at once would grow with the image). The sun is then found and
measured at full resolution by :func:`bakeshop.light.sun.split_texels` among the texels within
:data:`SUN_REACH` of the brightest texel and within :data:`RIVAL_REACH` of each rival (what its
measurements read), read piece by piece where the search looks: a light's measurement holds
the luminance and angle of the texels it examines (~8 degrees around it: 0.5 % of the image,
4.4 % at a pole, where its cap spans every column;
:data:`bakeshop.light.sun.EXAMINED_BYTES` each), never their directions nor the windows
whole, and the job says before pass 1 if that cannot fit its bound. The fill, a few thousand
texels at most, is subtracted exactly: the shadow DIM is the DIM of the
probe less the DIM of what the fill removes (linear, so exactly the DIM of the painted probe
for ``exact`` and ``sh``), the sun DIM adds it back, as :func:`bakeshop.light.dim_pair` does.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Iterator
from typing import Any, NamedTuple

import numpy as np

from bakeshop.errors import UnsupportedError, validate_choice
from bakeshop.huge.engine import Engine
from bakeshop.huge.memory import refuse
from bakeshop.huge.resize import Source, as_reader
from bakeshop.image import luminance
from bakeshop.io.stream import Reader
from bakeshop.light import sh
from bakeshop.light.diffuse import METHODS, compress, cosine_sum, dim_normals
from bakeshop.light.sun import EXAMINED_BYTES, REACH_DEG, Sampler, Sun, split_texels
from bakeshop.light.sun_texels import Piece, TexelArrays
from bakeshop.sphere import texels_at
from bakeshop.sphere.windows import (
    gather_taps,
    latlong_window_geometry,
    localise_taps,
    sample_taps,
    taps_window,
)

#: texels within this angle of the brightest one are read to find and measure the sun (its
#: measurement reaches 8 degrees for any sun up to 1.3 degrees in radius).
SUN_REACH = math.radians(12.0)
#: ... and within this angle of each rival (a rival's core is at most 10 degrees).
RIVAL_REACH = math.radians(10.0)
#: radii of the caps around the brightest texel outside which the brightest texel is a rival
#: (the sun's exclusion radius is max(3 mask radii, 4 degrees)).
RIVAL_RADII = tuple(math.radians(r) for r in (4, 6, 8, 12, 16, 24, 32, 48))
#: bytes per texel of a strip's task besides 8 per channel: its values (read, copied),
#: directions, solid angles, luminance, the bins' indices (measured with tracemalloc on a
#: 3-channel strip: 148 in all).
_TEXEL_BYTES = 130
#: bytes per texel of a piece of the sun's windows while it is looked at (values read and
#: sliced, directions, solid angles, indices).
_PIECE_BYTES = 80
#: the largest strip task: larger ones save nothing (the work is per texel) and would add
#: their size, times the tasks running at once, to the process's peak.
STRIP_BYTES = 64 << 20


class HugeDimPair(NamedTuple):
    """What :func:`dim_pair` returns (the shadow probe is not held: see
    :func:`write_shadow_probe`)."""

    #: (..., C) float32: the DIM of the probe as photographed.
    sun_dim: np.ndarray
    #: (..., C) float32: the DIM without the sun.
    shadow_dim: np.ndarray
    #: the sun, or None.
    sun: Sun | None
    #: ((order + 1)^2, C) float64: SH radiance coefficients of the probe as photographed.
    sh: np.ndarray
    #: (n,) int64 flat texel indices of the sun's fill, and (n, colour) their new values.
    fill_index: np.ndarray
    fill_values: np.ndarray


def _check(reader: Reader, layout: str) -> tuple[int, int, int]:
    if layout != "latlong":
        raise UnsupportedError(
            f"chunked spherical integrals read latlong panoramas, not {layout}; convert it first "
            "(bakeshop remap), or use bakeshop.light in memory"
        )
    h, w, c = reader.shape
    from bakeshop.sphere import layout as get_layout

    get_layout("latlong").check_shape((h, w))
    return h, w, c


def _strips(reader: Reader, engine: Engine, fixed: int, what: str) -> list[tuple[int, int]]:
    """Strips of rows whose tasks fit their share of the bound, at most :data:`STRIP_BYTES`
    each (the interpreter, numpy and dask already hold ~300 MB outside the bound)."""
    h, w, c = reader.shape
    row = w * (_TEXEL_BYTES + 8 * c)
    per_task = min(engine.per_task(fixed, reader), STRIP_BYTES)
    if fixed + engine.workers * row > engine.memory:
        raise refuse(what, fixed + engine.workers * row, engine.memory)
    rows = max(1, per_task // row)
    rows = min(rows, max(1, math.ceil(h / (4 * engine.total_workers))))
    return [(top, min(top + rows, h)) for top in range(0, h, rows)]


class _Brightest:
    """A strip's brightest texel (luminance, flat index); the sum of two is the brighter (the
    later on a tie), so that :meth:`Engine.reduce` adds the strips' partial results."""

    def __init__(self, luminance: float, index: int):
        self.key = (luminance, index)

    def __add__(self, other: _Brightest) -> _Brightest:
        return max(self, other, key=lambda b: b.key)


def _strip(
    rows: tuple[int, int], reader: Reader, order: int, method: str, normals: np.ndarray
) -> tuple[_Brightest, np.ndarray, np.ndarray | None]:
    """Pass 1 on one strip: its brightest texel (:class:`_Brightest`), SH and DIM partials (the
    irradiance at ``normals``, not over pi; None for ``sh``), summed over the strips by the
    engine as they come (a DIM partial is (M, C) float64: never one per strip at once)."""
    h, w, c = reader.shape
    values = reader.read(rows).reshape(-1, c)
    dirs, omega = latlong_window_geometry((h, w), rows)
    colour = min(3, c)
    lum = luminance(values[:, :colour])
    k = int(np.argmax(lum))
    brightest = _Brightest(float(lum[k]), rows[0] * w + k)
    coeffs = sh.project(values, dirs, omega, order=order)
    if method == "exact":
        return brightest, coeffs, cosine_sum(normals, dirs, values * omega[:, None])
    if method == "auto":  # the strip's sources summed here: only (M, C) per strip is kept
        return brightest, coeffs, cosine_sum(normals, *compress(values, dirs, omega))
    return brightest, coeffs, None


def _rivals(rows: tuple[int, int], reader: Reader, centre: np.ndarray) -> list[tuple[float, int]]:
    """Pass 2 on one strip: per radius of RIVAL_RADII, the brightest texel outside that cap
    around ``centre`` (luminance, flat index; -1 when none)."""
    h, w, c = reader.shape
    values = reader.read(rows).reshape(-1, c)
    dirs, _ = latlong_window_geometry((h, w), rows)
    lum = luminance(values[:, : min(3, c)])
    cos = dirs @ centre
    out = []
    for r in RIVAL_RADII:
        masked = np.where(cos < math.cos(r), lum, -np.inf)
        k = int(np.argmax(masked))
        out.append((float(masked[k]), rows[0] * w + k) if np.isfinite(masked[k]) else (-1.0, -1))
    return out


def _cap_window(
    h: int, w: int, index: int, reach: float
) -> tuple[tuple[int, int], list[tuple[int, int]]]:
    """Rows and column ranges of a latlong holding every texel within ``reach`` of texel
    ``index`` (all columns when the cap holds a pole or is wide)."""
    j, i = divmod(index, w)
    theta = math.pi * (j + 0.5) / h
    pitch = math.pi / h
    top = max(0, math.floor((theta - reach - pitch) / pitch))
    bottom = min(h, math.ceil((theta + reach + pitch) / pitch) + 1)
    low = math.sin(min(max(theta - reach, 0.0), math.pi))
    high = math.sin(min(theta + reach, math.pi))
    s = min(low, high) if theta - reach > 0 and theta + reach < math.pi else 0.0
    if s <= math.sin(reach) * 1.0001:
        return (top, bottom), [(0, w)]
    half = math.asin(min(1.0, math.sin(reach) / s)) + 2 * math.pi / w
    span = math.ceil(half / (2 * math.pi) * w) + 1
    if 2 * span + 1 >= w:
        return (top, bottom), [(0, w)]
    a, b = i - span, i + span + 1
    if a < 0:
        return (top, bottom), [(a + w, w), (0, b)]
    if b > w:
        return (top, bottom), [(a, w), (0, b - w)]
    return (top, bottom), [(a, b)]


def _pieces(
    windows: list[tuple[tuple[int, int], list[tuple[int, int]]]], w: int, texels: int
) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """Disjoint rectangles ``(rows, (left, right))`` covering the union of ``windows`` (each
    ``(rows, column ranges)``), of at most ``texels`` texels (or one row) each, in ascending
    order of their texels' flat indices (a band of rows with two column ranges, a window
    across the seam, is cut row by row)."""
    cuts = sorted({r for rows, _ in windows for r in rows})
    out = []
    for top, bottom in itertools.pairwise(cuts):
        ranges = sorted(
            r for rows, rs in windows if rows[0] <= top and bottom <= rows[1] for r in rs
        )
        merged: list[list[int]] = []
        for a, b in ranges:
            if merged and a <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], b)
            else:
                merged.append([a, b])
        step = max(1, texels // sum(b - a for a, b in merged)) if len(merged) == 1 else 1
        for y in range(top, bottom, step):
            out += [((y, min(y + step, bottom)), (a, b)) for a, b in merged]
    return out


#: the values a cap search does not read.
_NO_VALUES = np.empty((0, 1), np.float32)


class _WindowTexels:
    """The texels of the union of some windows of a latlong file, as the sun's search asks for
    them (:class:`bakeshop.light.sun_texels.TexelSource`, flat indices of the whole image): read and
    given their geometry piece by piece where they are looked at, so that only the texels of
    one cap (the sun's measurement, 8 degrees or so) are ever held, never the windows whole."""

    def __init__(
        self,
        reader: Reader,
        windows: list[tuple[tuple[int, int], list[tuple[int, int]]]],
        texels: int,
    ) -> None:
        self.reader = reader
        self.h, self.w, _ = reader.shape
        self.colour = min(3, reader.shape[2])
        self.pieces = _pieces(windows, self.w, texels)
        self.texels = texels

    def _values(self, rows: tuple[int, int], cols: tuple[int, int]) -> np.ndarray:
        return self.reader.read(rows, cols).reshape(-1, self.reader.shape[2])[:, : self.colour]

    def _geometry(
        self, rows: tuple[int, int], cols: tuple[int, int]
    ) -> tuple[np.ndarray, np.ndarray]:
        return latlong_window_geometry((self.h, self.w), rows, cols)

    def _index(self, rows: tuple[int, int], cols: tuple[int, int], local: Any) -> Any:
        j, i = np.divmod(local, cols[1] - cols[0])
        return (j + rows[0]) * self.w + i + cols[0]

    def brightest(self, centre: np.ndarray, cos_limit: float) -> int:
        best = []  # each piece's brightest: the pieces' order is not the texels'
        for rows, cols in self.pieces:
            values = self._values(rows, cols)
            dirs, omega = self._geometry(rows, cols)
            k = TexelArrays(values, dirs, omega).brightest(centre, cos_limit)
            if k >= 0:
                # copies: a row of the piece's arrays would keep them whole, every piece's
                best.append(
                    (int(self._index(rows, cols, k)), *(a[k].copy() for a in (values, dirs, omega)))
                )
        if not best:
            return -1
        best.sort(key=lambda b: b[0])  # ties go to the first texel, as over all of them
        values, dirs, omega = (np.stack([b[n] for b in best]) for n in (1, 2, 3))
        return best[TexelArrays(values, dirs, omega).brightest(centre, cos_limit)][0]

    def caps(self, centre: np.ndarray, cos_limit: float) -> Iterator[Piece]:
        theta = math.acos(min(1.0, max(-1.0, float(centre[1]))))
        reach = math.acos(min(1.0, max(-1.0, cos_limit)))
        pitch = math.pi / self.h
        low, high = (theta - reach) / pitch - 1, (theta + reach) / pitch + 1
        for rows, cols in self.pieces:
            if rows[1] < low or rows[0] > high:
                continue
            dirs, omega = self._geometry(rows, cols)
            local = TexelArrays(_NO_VALUES, dirs, omega).cap(centre, cos_limit)
            if not local.size:
                continue
            values = self._values(rows, cols)[local]
            yield self._index(rows, cols, local), values, dirs[local], omega[local]

    def gather(self, index: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        index = np.asarray(index, np.int64)
        c = self.reader.shape[2]
        order = np.argsort(index, kind="stable")
        rows = index[order] // self.w
        per_read = max(1, self.texels // self.w)
        parts = []
        start = 0
        while start < len(order):  # bands of rows, each read once (its columns' span)
            stop = int(np.searchsorted(rows, rows[start] + per_read))
            take = order[start:stop]
            j, i = np.divmod(index[take], self.w)
            top, left = int(j[0]), int(i.min())
            window = self.reader.read((top, int(j[-1]) + 1), (left, int(i.max()) + 1))
            parts.append(window.reshape(-1, c)[(j - top) * (window.shape[1]) + i - left])
            start = stop
        values = np.empty((len(index), self.colour), parts[0].dtype if parts else np.float32)
        if parts:
            values[order] = np.concatenate(parts)[:, : self.colour]
        dirs, omega = texels_at("latlong", (self.h, self.w), index)
        return values, dirs, omega


def _sampler(reader: Reader, colour: int) -> Sampler:
    """Bilinear samples of the colour channels at directions, read from their own window."""
    h, w, c = reader.shape

    def sample(dirs: np.ndarray) -> np.ndarray:
        d = np.asarray(dirs, dtype=np.float64)
        taps, frac = sample_taps("latlong", (h, w), d.reshape(-1, 3))
        rows, ranges = taps_window(taps, w)
        window = np.concatenate([reader.read(rows, r) for r in ranges], axis=1)
        local = localise_taps(taps, w, rows, ranges)
        values = gather_taps(window.reshape(-1, c)[:, :colour], local, frac)
        return values.reshape(d.shape[:-1] + (colour,))

    return sample


def _find_sun(
    reader: Reader, brightest: int, rivals: list[int], texels: int
) -> tuple[Sun | None, np.ndarray, np.ndarray, tuple | None]:
    """The sun's split (:func:`bakeshop.light.sun.split_texels`) among the texels of the windows
    around the brightest texel and the rivals (read where they are looked at, ``texels`` at a
    time), with global texel indices."""
    h, w, c = reader.shape
    windows = [_cap_window(h, w, brightest, SUN_REACH)]
    windows += [_cap_window(h, w, k, RIVAL_REACH) for k in rivals]
    source = _WindowTexels(reader, windows, texels)
    removal = split_texels(source, sampler=_sampler(reader, min(3, c)))
    if removal is None:
        return None, np.empty(0, np.int64), np.empty((0, min(3, c)), np.float32), None
    return removal.sun, removal.index, removal.filled, source.gather(removal.index)


def dim_pair(
    source: Source,
    layout: str = "latlong",
    *,
    to: str = "latlong",
    size: int | tuple[int, int] = (360, 180),
    method: str = "auto",
    order: int = 2,
    window: str = "minimal",
    engine: Engine | None = None,
) -> HugeDimPair:
    """The DIM pair, the sun and the SH coefficients of a panorama of any size, in two passes
    over it within the engine's memory bound (see the module docstring).

    Parameters
    ----------
    source : Reader, path or (H, W, C) array
        A latlong panorama.
    layout : str
        ``"latlong"`` (the only chunked source layout).
    to, size, method, order, window
        As for :func:`bakeshop.light.dim_pair`.
    engine : Engine, optional

    Returns
    -------
    HugeDimPair
        The DIMs equal :func:`bakeshop.light.dim_pair`'s to rounding for ``exact`` and ``sh``
        (the sun is found and filled identically), and within ``auto``'s own tolerance of
        them for ``auto``.
    """
    validate_choice(method, METHODS, "irradiance method")
    engine = Engine() if engine is None else engine
    reader = as_reader(source)
    engine.check_source(reader)
    h, w, c = _check(reader, layout)
    shape, normals, valid = dim_normals(to, size)
    flat_normals = normals.reshape(-1, 3)
    out_bytes = 4 * flat_normals.shape[0] * c * 8
    what = f"DIM pair of latlong {w}x{h}"
    strips = _strips(reader, engine, out_bytes, what)
    # the sun's search, after the passes, holds a light's examined cap (at a pole it spans
    # every column; a light whose core needs a wider reach, up to SUN_REACH, needs up to 1.5
    # times this) beside the output, and reads pieces of at least a row into what is left
    cap_rows = min(h, math.ceil(REACH_DEG / 180 * h) + 2)
    search = out_bytes + EXAMINED_BYTES * w * cap_rows
    if search + _PIECE_BYTES * w > engine.memory:
        raise refuse(f"{what}: the sun's search", search + _PIECE_BYTES * w, engine.memory)
    texels = max(w, min(engine.per_task(search, reader), STRIP_BYTES) // _PIECE_BYTES)
    top, coeffs, e = engine.reduce(
        _strip, [(r, reader, order, method, flat_normals) for r in strips], f"{what}: pass 1 of 2"
    )
    lum, brightest = top.key
    j, i = divmod(brightest, w)
    centre = latlong_window_geometry((h, w), (j, j + 1), (i, i + 1))[0][0]
    rival_parts = engine.gather(
        _rivals, [(r, reader, centre) for r in strips], f"{what}: pass 2 of 2"
    )
    rivals = sorted({max(p[k] for p in rival_parts)[1] for k in range(len(RIVAL_RADII))} - {-1})
    sun, fill_index, found = None, np.empty(0, np.int64), None
    fill_values = np.empty((0, min(3, c)), np.float32)
    if lum > 0:
        sun, fill_index, fill_values, found = _find_sun(reader, brightest, rivals, texels)
    if method == "sh":
        lit = sh.evaluate(sh.windowed_irradiance(coeffs, window=window).coefficients, normals)
    else:
        assert e is not None  # the exact and auto strips sum their DIMs
        lit = e.reshape(normals.shape[:-1] + (-1,)) / math.pi
    shadow = lit.copy()
    if found is not None:
        values, dirs, omega = found  # the fill's texels
        colour = fill_values.shape[1]
        excess = np.zeros((len(values), c))
        excess[:, :colour] = values[:, :colour].astype(np.float64) - fill_values
        removed = cosine_sum(flat_normals, dirs, excess * omega[:, None])
        removed = removed.reshape(lit.shape) / math.pi
        if method == "sh":  # as bakeshop.light.dim_pair: SH of the painted probe + the exact sun
            painted = coeffs - sh.project(excess, dirs, omega, order=order)
            shadow = sh.evaluate(
                sh.windowed_irradiance(painted, window=window).coefficients, normals
            )
            lit = shadow + removed
        else:
            shadow = lit - removed
    lit[~valid] = 0
    shadow[~valid] = 0
    return HugeDimPair(
        lit.astype(np.float32), shadow.astype(np.float32), sun, coeffs, fill_index, fill_values
    )


def sh_coefficients(
    source: Source, layout: str = "latlong", *, order: int = 2, engine: Engine | None = None
) -> np.ndarray:
    """SH radiance coefficients of a panorama of any size: per-strip projections summed
    (equal to :func:`bakeshop.light.sh_coefficients` to rounding); ((order+1)^2, C) float64."""
    engine = Engine() if engine is None else engine
    reader = as_reader(source)
    engine.check_source(reader)
    h, w, c = _check(reader, layout)
    strips = _strips(reader, engine, 0, f"SH projection of latlong {w}x{h}")
    return engine.reduce(
        _project, [(r, reader, order) for r in strips], f"SH projection of latlong {w}x{h}"
    )


def _project(rows: tuple[int, int], reader: Reader, order: int) -> np.ndarray:
    h, w, c = reader.shape
    dirs, omega = latlong_window_geometry((h, w), rows)
    return sh.project(reader.read(rows).reshape(-1, c), dirs, omega, order=order)


def find_sun(
    source: Source, layout: str = "latlong", *, engine: Engine | None = None
) -> Sun | None:
    """The sun of a panorama of any size, found and measured at full resolution (as
    :func:`bakeshop.light.find_sun`)."""
    return dim_pair(source, layout, size=(4, 2), method="sh", order=0, engine=engine).sun


def write_shadow_probe(
    source: Source,
    target: str | os.PathLike,
    pair: HugeDimPair,
    *,
    engine: Engine | None = None,
    **options: Any,
) -> None:
    """Write the probe with its sun painted out (``pair``'s fill) to ``target`` by strips."""
    from bakeshop.io.stream import write_strips

    engine = Engine() if engine is None else engine
    reader = as_reader(source)
    h, w, c = reader.shape
    rows = max(1, min(h, engine.memory // 4 // (w * c * 4)))

    def strips() -> Iterator[np.ndarray]:
        for top in range(0, h, rows):
            bottom = min(top + rows, h)
            block = np.array(reader.read((top, bottom)))  # a copy: the fill is written in it
            inside = (pair.fill_index >= top * w) & (pair.fill_index < bottom * w)
            flat = block.reshape(-1, c)
            colour = pair.fill_values.shape[1]
            flat[pair.fill_index[inside] - top * w, :colour] = pair.fill_values[inside]
            yield block

    write_strips(target, (h, w, c), strips(), **options)
