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

The sun is then found and measured at full resolution by :func:`bakeshop.light.sun.split_texels`
on the windows of texels within :data:`SUN_REACH` of the brightest texel and within
:data:`RIVAL_REACH` of each rival (what its measurements read), and its fill, a few thousand
texels at most, is subtracted exactly: the shadow DIM is the DIM of the probe less the DIM of
what the fill removes (linear, so exactly the DIM of the painted probe for ``exact`` and
``sh``), the sun DIM adds it back, as :func:`bakeshop.light.dim_pair` does.
"""

from __future__ import annotations

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
from bakeshop.light.sun import Sampler, Sun, split_texels
from bakeshop.sphere import Texels
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
#: bytes per texel of a strip's task: its values (read, copied), directions, solid angles,
#: luminance, energies and the SH basis of a block.
_TEXEL_BYTES = 120
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
    each (the interpreter, numpy, numba and dask already hold ~300 MB outside the bound)."""
    h, w, c = reader.shape
    row = w * (_TEXEL_BYTES + 8 * c)
    per_task = min(engine.per_task(fixed), STRIP_BYTES)
    if fixed + engine.workers * row > engine.memory:
        raise refuse(what, fixed + engine.workers * row, engine.memory)
    rows = max(1, per_task // row)
    rows = min(rows, max(1, math.ceil(h / (4 * engine.total_workers))))
    return [(top, min(top + rows, h)) for top in range(0, h, rows)]


def _strip(
    rows: tuple[int, int], reader: Reader, order: int, method: str, normals: np.ndarray
) -> tuple[tuple[float, int], np.ndarray, np.ndarray | None]:
    """Pass 1 on one strip: (brightest luminance, its flat index), SH and DIM partials (the
    irradiance at ``normals``, not over pi; None for ``sh``)."""
    h, w, c = reader.shape
    values = reader.read(rows).reshape(-1, c)
    dirs, omega = latlong_window_geometry((h, w), rows)
    colour = min(3, c)
    lum = luminance(values[:, :colour])
    k = int(np.argmax(lum))
    brightest = (float(lum[k]), rows[0] * w + k)
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


def _window_texels(
    reader: Reader, rows: tuple[int, int], ranges: list[tuple[int, int]]
) -> tuple[np.ndarray, ...]:
    """Flat values, directions, solid angles and global indices of a window."""
    h, w, c = reader.shape
    parts = []
    for a, b in ranges:
        values = reader.read(rows, (a, b)).reshape(-1, c)
        dirs, omega = latlong_window_geometry((h, w), rows, (a, b))
        jj, ii = np.divmod(np.arange(len(omega)), b - a)
        parts.append((values, dirs, omega, (jj + rows[0]) * w + ii + a))
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(4))


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
    reader: Reader, brightest: int, rivals: list[int]
) -> tuple[Sun | None, np.ndarray, np.ndarray, tuple | None]:
    """The sun's split (:func:`bakeshop.light.sun.split_texels`) from the windows around the
    brightest texel and the rivals, with global texel indices."""
    h, w, c = reader.shape
    windows = [_cap_window(h, w, brightest, SUN_REACH)]
    windows += [_cap_window(h, w, k, RIVAL_REACH) for k in rivals]
    gathered = [_window_texels(reader, rows, ranges) for rows, ranges in windows]
    values, dirs, omega, index = (np.concatenate([g[k] for g in gathered]) for k in range(4))
    index, first = np.unique(index, return_index=True)  # windows may overlap; keep file order
    values, dirs, omega = values[first], dirs[first], omega[first]
    t = Texels(values, dirs, omega, None)
    removal = split_texels(t, sampler=_sampler(reader, min(3, c)))
    if removal is None:
        return None, np.empty(0, np.int64), np.empty((0, min(3, c)), np.float32), None
    return removal.sun, index[removal.index], removal.filled, (values, dirs, omega, removal.index)


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
    parts = engine.gather(
        _strip, [(r, reader, order, method, flat_normals) for r in strips], f"{what}: pass 1 of 2"
    )
    lum, brightest = max(p[0] for p in parts)
    coeffs = sum(p[1] for p in parts)
    j, i = divmod(brightest, w)
    centre = latlong_window_geometry((h, w), (j, j + 1), (i, i + 1))[0][0]
    rival_parts = engine.gather(
        _rivals, [(r, reader, centre) for r in strips], f"{what}: pass 2 of 2"
    )
    rivals = sorted({max(p[k] for p in rival_parts)[1] for k in range(len(RIVAL_RADII))} - {-1})
    sun, fill_index, found = None, np.empty(0, np.int64), None
    fill_values = np.empty((0, min(3, c)), np.float32)
    if lum > 0:
        sun, fill_index, fill_values, found = _find_sun(reader, brightest, rivals)
    if method != "sh":
        e = sum(p[2] for p in parts)
    if method == "sh":
        lit = sh.evaluate(sh.windowed_irradiance(coeffs, window=window).coefficients, normals)
    else:
        lit = e.reshape(normals.shape[:-1] + (-1,)) / math.pi
    shadow = lit.copy()
    if found is not None:
        values, dirs, omega, k = found
        colour = fill_values.shape[1]
        excess = np.zeros((len(k), c))
        excess[:, :colour] = values[k, :colour].astype(np.float64) - fill_values
        removed = cosine_sum(flat_normals, dirs[k], excess * omega[k, None])
        removed = removed.reshape(lit.shape) / math.pi
        if method == "sh":  # as bakeshop.light.dim_pair: SH of the painted probe + the exact sun
            painted = coeffs - sh.project(excess, dirs[k], omega[k], order=order)
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
