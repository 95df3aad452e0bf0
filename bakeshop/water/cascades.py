"""Cascades: several patches of different sizes that split one spectrum between them.

One patch of N texels covers wavelengths from its size down to two texels; a sea needs more
decades than one texture holds, and a single patch repeats visibly at its own period. Cascades
(as Crest, Unity HDRP and UE Water run them) lay several patches of sizes L_0 > L_1 > ... over
the same water, each keeping only the wave numbers of its band, so the bands add up to the whole
spectrum with no wave counted twice. A shader samples each cascade at its own scale and sums
them. Sizes whose ratios are not close to ratios of small integers do not realign for a long
distance: :func:`repeat_distance` measures how long. Every cascade uses the same loop period, so
the sum loops too.

Band split: cascade c keeps k in [k_c, k_{c+1}) with k_0 = 0, and the boundary between c - 1 and
c at the wave number whose wavelength spans ``split_texels`` texels of cascade c - 1 (8 by
default: every wave in the larger cascade is sampled by at least 8 texels), and the last cascade
up to its own Nyquist limit.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError
from bakeshop.water import _native
from bakeshop.water.ocean import Ocean, ocean
from bakeshop.water.spectra import Spectrum

#: Default ratio between successive cascade sizes: e (2.718...) is far from every ratio of small
#: integers, so the patterns of two cascades do not realign within many patch lengths.
DEFAULT_RATIO = math.e


def cascade_sizes(largest: float, count: int, *, ratio: float = DEFAULT_RATIO) -> list[float]:
    """``count`` patch sizes, m, from ``largest`` down by ``ratio`` each (> 1)."""
    if not (isinstance(count, (int, np.integer)) and 1 <= count <= 8):
        raise ArgumentError(f"cascade count must be 1 to 8, got {count!r}")
    if not (math.isfinite(largest) and largest > 0):
        raise ArgumentError(f"the largest cascade size must be > 0 m, got {largest!r}")
    if not (math.isfinite(ratio) and ratio > 1):
        raise ArgumentError(f"the cascade size ratio must be > 1, got {ratio!r}")
    return [largest / ratio**c for c in range(count)]


def repeat_distance(size_a: float, size_b: float, tolerance: float) -> float:
    """The shortest distance D, m, after which two patterns of periods ``size_a`` and
    ``size_b`` realign within ``tolerance`` metres: D = p a with |p a - q b| <= tolerance for
    integers p, q. Found from the continued-fraction convergents of a / b (the best rational
    approximations). A commensurate pair (b = a / 4) realigns after a itself."""
    if not (size_a > 0 and size_b > 0 and tolerance > 0):
        raise ArgumentError("sizes and tolerance must be positive")
    a, b = max(size_a, size_b), min(size_a, size_b)
    x = a / b
    h0, h1, k0, k1 = 1, 0, 0, 1  # convergents h/k of x: p b ~ q a with q = k, p = h
    rest = x
    for _ in range(64):
        digit = math.floor(rest)
        h0, h1 = digit * h0 + h1, h0
        k0, k1 = digit * k0 + k1, k0
        # k0 periods of a against h0 periods of b
        if abs(k0 * a - h0 * b) <= tolerance:
            return k0 * a
        frac = rest - digit
        if frac < 1e-15:
            break
        rest = 1 / frac
    return math.inf


def _cascade_seed(seed: int, index: int) -> int:
    return _native.splitmix64(int(np.uint64(seed) ^ np.uint64(0x6A09E667F3BCC908 + index))) >> 1


def cascades(
    spectrum: Spectrum,
    sizes: Sequence[float],
    *,
    resolution: int,
    seed: int = 0,
    loop_period: float | None = None,
    frozen: str = "keep",
    split_texels: float = 8.0,
) -> list[Ocean]:
    """One :class:`Ocean` per size (largest first), splitting ``spectrum`` into bands.

    Each cascade's report gains ``band`` (k_min, k_max in rad/m) and ``repeat_distance`` (m:
    how far until it realigns with the next larger cascade within one of its texels).
    """
    sizes = [float(s) for s in sizes]
    if not sizes or any(not (math.isfinite(s) and s > 0) for s in sizes):
        raise ArgumentError(f"cascade sizes must be positive, got {sizes!r}")
    if any(b >= a for a, b in zip(sizes[:-1], sizes[1:], strict=False)):
        raise ArgumentError(f"cascade sizes must decrease, got {sizes!r}")
    if not (math.isfinite(split_texels) and split_texels >= 2):
        raise ArgumentError(f"split_texels must be >= 2, got {split_texels!r}")
    bounds = [0.0]
    for c in range(1, len(sizes)):
        k_split = 2 * math.pi / (split_texels * sizes[c - 1] / resolution)
        if k_split <= 2 * math.pi / sizes[c]:
            raise ArgumentError(
                f"cascade {c} ({sizes[c]:g} m) is too small for its band: the split at "
                f"wavelength {2 * math.pi / k_split:g} m is longer than the patch; use larger "
                "sizes, a smaller ratio or a higher resolution"
            )
        bounds.append(k_split)
    bounds.append(math.inf)
    out = []
    for c, size in enumerate(sizes):
        o = ocean(
            spectrum,
            size=size,
            resolution=resolution,
            seed=_cascade_seed(seed, c),
            loop_period=loop_period,
            frozen=frozen,
            k_range=(bounds[c], bounds[c + 1]),
        )
        o.report["band"] = (bounds[c], bounds[c + 1] if math.isfinite(bounds[c + 1]) else None)
        if c:
            o.report["repeat_distance"] = repeat_distance(sizes[c - 1], size, size / resolution)
        out.append(o)
    return out


def sample_periodic(field: ArrayLike, size: float, x: ArrayLike, y: ArrayLike) -> np.ndarray:
    """Bilinear, wrapping lookup of a patch field at world points, as a GPU's REPEAT sampler
    does. ``field`` (N, N) or (N, N, C); x, y in metres (y up the picture). Returns (..., C) or
    (...) float64 (NaN at points that are not finite). The kernel: ``src/water/cascades.hpp``."""
    f = np.asarray(field, dtype=np.float64)
    scalar = f.ndim == 2
    if scalar:
        f = f[..., None]
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    shape = np.broadcast(x, y).shape
    out: np.ndarray = np.zeros((int(np.prod(shape)), f.shape[2]))
    _native.sample_add(
        np.ascontiguousarray(f),
        float(size),
        np.ascontiguousarray(np.broadcast_to(x, shape)).ravel(),
        np.ascontiguousarray(np.broadcast_to(y, shape)).ravel(),
        1.0,
        out,
    )
    out = out.reshape(shape + (f.shape[2],))
    return out[..., 0] if scalar else out


def sum_cascades(
    fields: Sequence[np.ndarray], sizes: Sequence[float], x: ArrayLike, y: ArrayLike
) -> np.ndarray:
    """The sum of each cascade's field (heights or slopes, ``(N, N[, C])``) sampled at world
    points with :func:`sample_periodic`: what a shader that layers the cascades computes."""
    if len(fields) != len(sizes):
        raise ArgumentError("one field per cascade size")
    if not fields:
        raise ArgumentError("sum_cascades needs at least one cascade")
    total = sample_periodic(fields[0], sizes[0], x, y)
    for f, s in zip(fields[1:], sizes[1:], strict=True):
        total = total + sample_periodic(f, s, x, y)
    return total
