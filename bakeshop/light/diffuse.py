"""Diffuse irradiance maps (DIMs): exact, spherical-harmonic and fast exact ("auto") convolution.

The irradiance at a surface with unit normal n lit by an environment of radiance L is

    E(n) = integral over the sphere of L(w) max(0, n . w) dw,

and a DIM stores ``E / pi``: the radiance an albedo-1 Lambertian surface reflects, so a uniform
environment of 1 gives a DIM of 1 (DESIGN.md). Everything here works on the directions and
solid angles of the sphere layouts (:mod:`bakeshop.sphere`), so any input layout gives any
output layout.

Methods
-------
``exact``
    The quadrature over every source texel for every output texel (HDRShop's diffuse
    convolution): ``E(n_i) = sum_j L_j omega_j max(0, n_i . w_j)``; the reference. Summed by
    cones (:func:`cosine_sum`): the same sum at O(N_out N_in**(2/3)) instead of O(N_out N_in).
``sh``
    Projection on real spherical harmonics to an order L and convolution with the clamped
    cosine's ``A_l`` (Ramamoorthi and Hanrahan 2001; L = 2 is their 9-coefficient form).
    Smooth and cheap, but not exact: at L = 2, 1-8 % RMS on real probes, and several times
    off at normals facing away from a sun.
``auto`` (default)
    The exact quadrature over a compressed source (:func:`compress`): texels are grouped into
    cube-face bins and each bin becomes one source carrying the bin's total energy
    ``sum L omega`` (per channel), placed at the energy-weighted centroid of its texels'
    directions, so the zeroth and first moments of every bin are kept and the error is of
    second order in the bin's angular size, except at normals whose horizon crosses the bin,
    where it is of the order of the bin's energy times its size. Bins where that product
    exceeds :data:`HOT_FRACTION` of the environment's energy (a sun, a lamp, a window) are
    split into four finer bins, recursively, down to single texels. The result agrees with
    ``exact`` within 0.1 % RMS and 0.5 % maximum relative error on real probes
    (tests/light/test_irradiance.py measures it: at most 3e-5 RMS and 2e-3 max) at a cost that
    no longer depends on the input's resolution beyond one pass over its texels.

References
----------
R. Ramamoorthi and P. Hanrahan, "An efficient representation for irradiance environment maps",
SIGGRAPH 2001, doi:10.1145/383259.383317.
G. Miller and C. R. Hoffman, "Illumination and reflection maps: simulated objects in simulated
and real environments", SIGGRAPH 1984 course notes (the diffuse convolution).
"""

from __future__ import annotations

import functools
import math
import operator
from collections.abc import Iterable, Iterator, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress, threads
from bakeshop.errors import ArgumentError, validate_choice, with_article
from bakeshop.light import _native, sh
from bakeshop.resources import Cost, require, seconds_of
from bakeshop.sphere import STRIP_TEXELS, Environment, Layout, check_environment, texel_strips
from bakeshop.sphere import layout as get_layout

#: the irradiance methods, the default first.
METHODS = ("auto", "exact", "sh")

#: edge of the coarsest bin grid of ``auto``: 6 * 32**2 = 6144 bins of at most 3.6 degrees.
BASE_BINS = 32

#: ``auto`` splits a bin whose energy times its size (relative to the coarsest bins) exceeds
#: this fraction of the environment's energy: the error a bin can make at a normal whose
#: horizon crosses it scales with both. Chosen from the measured errors on the shared probes
#: (tests/light/test_irradiance.py) with a margin of ~3 on the 0.5 % bound.
HOT_FRACTION = 1e-4

#: the largest DIM accepted, in texels (4096 x 4096: far more than a DIM ever needs).
MAX_OUTPUT_TEXELS = 1 << 24

#: the finest bin grid's edge (2**20 bins per face edge: far below any texel).
_MAX_BINS = 1 << 20

#: output texels per block of the exact kernel (progress granularity).
_BLOCK = 4096

#: peak bytes per texel of the environment, by method: its texels' directions, solid angles and
#: float64 values, and each method's work arrays (measured on RGB latlongs at 86, 184 and 41,
#: tests/test_resources.py), and per texel of the DIM (normals, float64 sums, the float32 DIM:
#: measured at 80). The SH projection's basis adds at most 128 MB (it goes by chunks). The
#: texels are read by strips (:func:`bakeshop.sphere.texel_strips`), so these count for one
#: strip's texels at most.
INPUT_BYTES = {"auto": 100, "exact": 200, "sh": 48}
OUTPUT_BYTES = 96
#: bytes per texel of the environment that ``auto`` keeps from every strip: its bins' sources
#: (48 bytes each; measured at one bin per ~180 texels of a real probe, counted at one per 64).
SOURCE_BYTES = 1
#: terms per second per core: ``exact`` sums one cosine term per (DIM texel, environment texel),
#: ``sh`` one basis value per (environment texel, coefficient); measured at 1.4e7 and 5e6 on a
#: loaded machine (the sh run with its report), docs/hostile-input.md.
TERMS_PER_SECOND = {"exact": 1.4e7, "sh": 5e6}


def irradiance_cost(
    shape: Sequence[int],
    layout: str,
    *,
    to: str = "latlong",
    size: int | tuple[int, int] = (360, 180),
    method: str = "auto",
    order: int = 2,
    extra: int = 0,
) -> Cost:
    """What :func:`irradiance` of an environment of ``shape`` in ``layout`` holds at its peak:
    :data:`INPUT_BYTES` per texel of one strip (:data:`bakeshop.sphere.STRIP_TEXELS` at most),
    ``extra`` per texel of the environment (and :data:`SOURCE_BYTES` for ``auto``),
    :data:`OUTPUT_BYTES` per texel of the DIM. ``work`` is in DIM texels (the unit of the
    progress shown); ``seconds`` counts :data:`TERMS_PER_SECOND` (``auto`` opens only the
    cones a normal's horizon crosses: not estimated)."""
    validate_choice(method, METHODS, "irradiance method")
    lay = get_layout(layout)
    n = math.prod(shape[: 3 if lay.cubic else 2])
    m = math.prod(get_layout(to).shape(size))
    strip = min(n, STRIP_TEXELS)
    kept = (extra + SOURCE_BYTES * (method == "auto")) * n
    memory = INPUT_BYTES[method] * strip + kept + OUTPUT_BYTES * m + (128 << 20) * (method == "sh")
    terms = {"exact": n * m, "sh": n * (order + 1) ** 2}.get(method, 0)
    seconds = seconds_of(terms, TERMS_PER_SECOND[method]) if terms else 0.0
    what = f"the {to} DIM of {with_article(lay.name)} environment of {n} texels ({method})"
    return Cost(memory, m, what, seconds)


def _cones(
    d: np.ndarray, e: np.ndarray, starts: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Axis, sin(half-angle) and linear sum of the cones of sorted sources ``d`` split at
    ``starts`` (a half-angle of 90 degrees or more gets sin 2: never decided whole)."""
    counts = np.diff(starts)
    axes = np.add.reduceat(d, starts[:-1], axis=0)
    norm = np.linalg.norm(axes, axis=1, keepdims=True)
    axes = np.divide(axes, norm, out=np.tile([1.0, 0.0, 0.0], (len(axes), 1)), where=norm > 0)
    cos_min = np.minimum.reduceat(
        np.einsum("ij,ij->i", d, np.repeat(axes, counts, axis=0)), starts[:-1]
    )
    sin_half = np.where(cos_min > 0, np.sqrt(np.clip(1 - cos_min**2, 0, 1)), 2.0)
    linear = np.empty((len(counts), 3, 3))
    for c in range(3):
        for k in range(3):
            linear[:, c, k] = np.add.reduceat(e[:, c] * d[:, k], starts[:-1])
    return axes, sin_half, linear


#: a large cone holds (GROUP_RATIO x GROUP_RATIO) small cones' worth of cube-face bins.
_GROUP_RATIO = 8


def _groups(
    dirs: np.ndarray, energy: np.ndarray
) -> tuple[
    np.ndarray,
    np.ndarray,
    tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
]:
    """Sort sources into two levels of cone-bounded groups for the cosine sum kernel
    (``src/light/diffuse.hpp``).

    Small cones of angular size h ~ (8 pi / N)**(1/3), nested in cones 8 times larger:
    per normal, every large cone is tested, the small cones of the ~2 pi / (8 h) large ones
    its horizon crosses, and the ~N h sources of the small ones it crosses.
    """
    n = dirs.shape[0]
    h = (8 * math.pi / max(n, 1)) ** (1 / 3)
    coarse = max(1, round(2 / h / _GROUP_RATIO))
    fine = coarse * _GROUP_RATIO  # fine bins nest in coarse ones
    none = np.empty(0, np.int64)
    key = _bins(dirs, none, coarse) * (6 * fine * fine) + _bins(dirs, none, fine)
    order = np.argsort(key, kind="stable")
    key = key[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1], True])
    group_coarse = key[starts[:-1]] // (6 * fine * fine)
    super_starts = np.flatnonzero(np.r_[True, group_coarse[1:] != group_coarse[:-1], True])
    d = dirs[order]
    e = np.zeros((n, 3))
    e[:, : energy.shape[1]] = energy[order]
    g_axes, g_sin, g_linear = _cones(d, e, starts)
    s_axes, s_sin, s_linear = _cones(d, e, starts[super_starts])
    return (
        np.ascontiguousarray(d.T),
        np.ascontiguousarray(e.T),
        (starts, g_axes, g_sin, g_linear),
        (super_starts, s_axes, s_sin, s_linear),
    )


def cosine_sum(
    normals: ArrayLike,
    directions: ArrayLike,
    energy: ArrayLike,
    *,
    description: str = "irradiance",
) -> np.ndarray:
    """Irradiance of a set of point sources: ``E_i = sum_j e_j max(0, n_i . w_j)``.

    The exact kernel behind every method: a discretised environment is a set of sources, one per
    texel, each with direction ``w_j`` and energy ``e_j = L_j omega_j``. Sources are grouped in
    small cones; a cone wholly above a normal's horizon contributes the exact linear sum
    ``n . sum_j e_j w_j`` and one wholly below contributes nothing, so only the cones the
    horizon crosses are summed source by source. The result is the full sum (to rounding) at
    O(M N**(2/3)) instead of O(M N).

    Parameters
    ----------
    normals : (M, 3) array_like
        Unit surface normals.
    directions : (N, 3) array_like
        Unit directions towards the sources.
    energy : (N, C) array_like
        Radiance times solid angle of each source (W m^-2 for radiance in W m^-2 sr^-1); any
        number of channels (the kernel sums three at a time).

    Returns
    -------
    (M, C) float64
        Irradiance (not divided by pi).
    """
    n = np.ascontiguousarray(np.asarray(normals, dtype=np.float64).reshape(-1, 3))
    w = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    e = np.asarray(energy, dtype=np.float64)
    e = e.reshape(e.shape[0], -1) if e.size else e.reshape(e.shape[0], e.shape[-1])
    channels = e.shape[1]
    if e.shape[0] != w.shape[0]:
        raise ArgumentError(f"energy {e.shape} does not match {w.shape[0]} source directions")
    if channels > 3:
        parts = [e[:, c : c + 3] for c in range(0, channels, 3)]
        return np.concatenate(
            [cosine_sum(n, w, part, description=description) for part in parts], 1
        )
    out = np.zeros((n.shape[0], 3))
    if w.shape[0] == 0:
        return out[:, :channels]
    if w.shape[0] > 2_000_000:  # sorting millions of texels takes a second or more
        with progress.step("sorting the texels into cones"):
            grouped = _groups(w, e)
    else:
        grouped = _groups(w, e)
    blocks: Iterable[int] = range(0, n.shape[0], _BLOCK)
    if n.shape[0] * w.shape[0] ** (2 / 3) > 1e8:  # about a second of work or more
        blocks = progress.track(blocks, description)
    for start in blocks:
        d, e, groups, supers = grouped
        _native.cosine_sum(
            n[start : start + _BLOCK], d, e, *groups, *supers, out[start : start + _BLOCK]
        )
    return out[:, :channels]


def _bins(dirs: np.ndarray, subset: np.ndarray, size: int) -> np.ndarray:
    """The cube-face bin at ``size`` of each texel (of all, or of those listed in ``subset``):
    a private spatial hash of directions whose bins nest (``src/light/diffuse.hpp``)."""
    out = np.empty(len(subset) if len(subset) else len(dirs), np.int64)
    _native.bins(dirs, subset, size, out)
    return out


def _accumulate(
    values: np.ndarray,
    dirs: np.ndarray,
    omega: np.ndarray,
    subset: np.ndarray,
    index: np.ndarray,
    n_bins: int,
    chunks: int,
    size: int,
    colour: int,
) -> np.ndarray:
    """Row b sums, over the texels k (of all, or of those listed in ``subset``) with
    ``index[k] == b``: their energy per channel, weight (the sum over the first ``colour``
    channels of ``|energy|``: alpha is carried, but it is no light), weight * direction and
    count, in ``chunks`` parallel partial sums. With ``size`` > 0, ``index[k]`` is first set
    to the texel's bin at that size."""
    sums = np.empty((n_bins, values.shape[1] + 5))
    _native.accumulate(values, dirs, omega, subset, index, n_bins, chunks, size, colour, sums)
    return sums


def _select(
    index: np.ndarray, subset: np.ndarray, rank: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The texels (of all, or of ``subset``) whose bin has a rank >= 0, and that rank."""
    r = rank[index]
    keep = r >= 0
    return (subset[keep] if len(subset) else np.flatnonzero(keep)), r[keep]


def compress(
    values: np.ndarray,
    dirs: np.ndarray,
    omega: np.ndarray,
    *,
    base: int = BASE_BINS,
    hot_fraction: float = HOT_FRACTION,
    total: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Group an environment's texels into moment-preserving bins, finer where energy gathers.

    Each bin becomes one source with the bin's energy ``sum L omega`` per channel, at the
    weighted centroid of its texels' directions (weight: the energy summed over the colour
    channels), so
    every bin keeps its zeroth and first moments and replacing it by a point source errs only
    to second order in its angular size (first order, times its energy, at a normal whose
    horizon crosses it). Bins whose energy times angular size (relative to the coarsest bins)
    exceeds ``hot_fraction`` of the total energy are split in four, recursively, down to
    single texels.

    Parameters
    ----------
    values : (N, C) float array
        Radiance of each texel.
    dirs : (N, 3) float64
        Unit texel directions.
    omega : (N,) float64
        Texel solid angles (0 for no texel).
    base : int
        Edge of the coarsest bin grid: ``6 * base**2`` cube-face bins.
    hot_fraction : float
        Split threshold as a fraction of the total energy.
    total : float, optional
        The total energy that ``hot_fraction`` is a fraction of (summed over the colour
        channels of ``|L| omega``). Default: these texels'. An environment compressed in parts
        (strips of rows) passes the whole environment's, so that each part's bins are split
        as the whole's would be: a bin that a strip boundary cuts is two sources, each
        moment-preserving.

    Returns
    -------
    dirs : (K, 3) float64
    energy : (K, C) float64
        The sources; ``energy`` sums to the environment's ``sum L omega``.
    """
    channels = values.shape[1]
    colour = min(channels, 3)
    size = base
    subset = np.empty(0, np.int64)  # empty: every texel
    index = parent = None
    n_parents = 0
    out_dirs, out_energy = [], []
    threshold = None
    while True:
        if parent is None:  # every texel: the bins are found while summing
            index, n_bins, fused = np.empty(len(omega), np.int64), 6 * size * size, size
        else:
            # the four children of each split bin, numbered after their parent's rank: bin
            # (face, j, i) at this size has the parity (j % 2, i % 2) in its parent (size even)
            bins = _bins(dirs, subset, size)
            index = 4 * parent + 2 * (bins // size % 2) + bins % 2
            n_bins, fused = 4 * n_parents, 0
        chunks = min(4 * threads.count(), max(1, len(index) // 65536))
        sums = _accumulate(values, dirs, omega, subset, index, n_bins, chunks, fused, colour)
        weight = sums[:, channels]
        if threshold is None:
            threshold = hot_fraction * (weight.sum() if total is None else total)
        # split a bin that holds too much energy, unless it is a single texel
        hot = (weight * (base / size) > threshold) & (sums[:, channels + 4] > 1)
        if size >= _MAX_BINS:
            hot[:] = False
        moment = sums[:, channels + 1 : channels + 4]
        norm = np.linalg.norm(moment, axis=1)
        emit = ~hot & (norm > 0)
        out_dirs.append(moment[emit] / norm[emit, None])
        out_energy.append(sums[emit, :channels])
        if not hot.any():
            break
        rank = np.where(hot, np.cumsum(hot) - 1, -1)
        subset, parent = _select(index, subset, rank)
        n_parents = int(np.count_nonzero(hot))
        size *= 2
    return np.concatenate(out_dirs), np.concatenate(out_energy)


def dim_normals(to: str, size: int | tuple[int, int]) -> tuple[tuple, np.ndarray, np.ndarray]:
    """The output layout's ``(shape, texel normals, valid mask)`` for a DIM, checked against
    :data:`MAX_OUTPUT_TEXELS`."""
    from bakeshop.sphere import layout

    lay = layout(to)
    shape = lay.shape(size)
    if math.prod(shape) > MAX_OUTPUT_TEXELS:
        raise ArgumentError(
            f"{with_article(to)} DIM of shape {shape} has more than {MAX_OUTPUT_TEXELS} texels; "
            "a DIM is "
            "smooth: 360x180 is plenty"
        )
    dirs, valid = lay.directions(shape)
    return shape, dirs, valid


def sh_coefficients(image: ArrayLike, layout: str | Layout, *, order: int = 2) -> np.ndarray:
    """Project an environment on real SH to ``order``, weighting texels by their solid angles.

    Returns
    -------
    ((order + 1)**2, C) float64
        Radiance coefficients (see :mod:`bakeshop.light.sh`; ``sh.irradiance_coefficients``
        turns them into the DIM's).
    """
    env = check_environment(image, layout)
    with progress.step(f"projecting on spherical harmonics to order {order}"):
        return integrate(env, "sh", order=order)


def irradiance(
    image: ArrayLike,
    layout: str,
    *,
    to: str = "latlong",
    size: int | tuple[int, int] = (360, 180),
    method: str = "auto",
    order: int = 2,
    window: str = "minimal",
) -> np.ndarray:
    """The DIM (``E / pi``) of an environment, in any layout and size.

    Parameters
    ----------
    image : (..., C) array_like
        The environment's radiance in ``layout``: ``(H, W, C)`` for flat layouts,
        ``(6, S, S, C)`` for a cube; C in {1, 3, 4} (alpha is dropped). NaN and Inf are refused.
    layout : str
        The input's layout name (see :func:`bakeshop.sphere.layout`).
    to : str
        The output layout.
    size : int or (int, int)
        The output size as the layout reads it (``(W, H)`` for latlong; default 360x180).
    method : {"auto", "exact", "sh"}
        See the module docstring. ``auto`` is exact within 0.1 % RMS / 0.5 % max.
    order : int
        SH order for ``method="sh"`` (2: the classic 9 coefficients per channel).
    window : {"minimal", "hanning", "lanczos", "none"}
        The window of ``method="sh"`` against ringing
        (:func:`bakeshop.light.sh.windowed_irradiance`): by default the least one that makes
        the DIM nowhere negative.

    Returns
    -------
    (..., C') float32
        ``E / pi`` per output texel (0 outside a disk layout's disk); C' = 3 for RGBA input.
    """
    validate_choice(method, METHODS, "irradiance method")
    require(irradiance_cost(np.shape(image), layout, to=to, size=size, method=method))
    env = check_environment(image, layout)
    shape, normals, valid = dim_normals(to, size)
    dim = dim_of_environment(env, normals, method, order=order, window=window)
    dim[~valid] = 0
    return env.shaped(dim.astype(np.float32))


def dim_of_environment(env: Environment, normals: np.ndarray, method: str, *, order: int = 2,
                       window: str = "minimal", fill: Any = None) -> np.ndarray:  # fmt: skip
    """E / pi at ``normals`` (..., 3) of a checked environment by ``method``, in one pass over
    its texels (:func:`integrate`); ``fill`` (a :class:`bakeshop.light.sun.Removal`) paints
    the sun out first; ``window`` is the SH method's
    (:func:`bakeshop.light.sh.windowed_irradiance`)."""
    if method == "sh":
        coeffs = integrate(env, "sh", order=order, fill=fill)
        return sh.evaluate(sh.windowed_irradiance(coeffs, window=window).coefficients, normals)
    e = integrate(env, method, normals=normals.reshape(-1, 3), fill=fill)
    return e.reshape(normals.shape[:-1] + (-1,)) / math.pi


def integrate(
    env: Environment,
    method: str,
    *,
    order: int = 2,
    normals: np.ndarray | None = None,
    fill: Any = None,
) -> np.ndarray:
    """One pass over an environment's texels in strips of rows
    (:func:`bakeshop.sphere.texel_strips`): the directions and solid angles of one strip at a
    time, never the whole layout's.

    Parameters
    ----------
    env : Environment
        A checked environment (:func:`bakeshop.sphere.check_environment`).
    method : {"sh", "exact", "auto"}
        ``sh``: the SH projection to ``order`` (sums of each strip's). ``exact``: the
        irradiance (not over pi) at ``normals`` (M, 3), sums of each strip's
        :func:`cosine_sum`. ``auto``: each strip compressed (:func:`compress`, split against
        the whole environment's energy), then one :func:`cosine_sum` of all the sources.
    fill : Removal, optional
        Texels to read with other values (a sun painted out), without copying the image.

    Returns
    -------
    ((order + 1)**2, C) float64 for ``sh``; (M, C) float64 irradiance otherwise.
    """
    flat = env.image.reshape(-1, env.image.shape[-1])
    shape = env.image.shape[:-1]

    def strips() -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        for start, stop, dirs, omega in texel_strips(env.layout, shape):
            yield _painted(flat, start, stop, fill), dirs, omega

    if method == "sh":
        return functools.reduce(
            operator.add, (sh.project(v, d, w, order=order) for v, d, w in strips())
        )
    if normals is None:
        raise ArgumentError(f"the {method} method integrates at normals: give them")
    if method == "exact":
        return functools.reduce(
            operator.add, (cosine_sum(normals, d, v * w[:, None]) for v, d, w in strips())
        )
    colour = min(3, flat.shape[1])
    total = sum(
        _energy(_painted(flat, start, stop, fill), w, colour)
        for start, stop, _, w in texel_strips(env.layout, shape, directions=False)
    )
    with progress.step("grouping the environment's texels"):
        sources = [compress(v, d, w, total=total) for v, d, w in strips()]
    dirs = np.concatenate([d for d, _ in sources])
    energy = np.concatenate([e for _, e in sources])
    return cosine_sum(normals, dirs, energy)


def _energy(values: np.ndarray, omega: np.ndarray, colour: int) -> float:
    """Sum over texels and the colour channels of ``|L omega|``: :func:`compress`'s measure of
    energy (16 partial sums, added in order)."""
    return float(_native.energy(values, omega, colour))


def _painted(flat: np.ndarray, start: int, stop: int, fill: Any) -> np.ndarray:
    """Texels ``[start, stop)`` of the flat image, with the fill's values where it has any (a
    copy of the strip then)."""
    values = flat[start:stop]
    if fill is None:
        return values
    lo, hi = np.searchsorted(fill.index, (start, stop))
    if hi > lo:
        values = values.copy()
        values[fill.index[lo:hi] - start, : fill.filled.shape[1]] = fill.filled[lo:hi]
    return values
