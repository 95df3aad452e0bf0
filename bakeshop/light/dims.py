"""The DIM pair: the diffuse irradiance of a probe with its sun (for lit surfaces) and without
it (for surfaces in shadow), composed from :mod:`bakeshop.light.sun` and
:mod:`bakeshop.light.irradiance`.

A renderer that knows from a shadow map whether a fragment sees the sun shades it with the sun
DIM where it does and the shadow DIM where it does not; their difference is the sun's own
contribution, close to ``E_sun max(0, n . s) / pi``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from bakeshop import progress
from bakeshop.errors import validate_choice
from bakeshop.light import sh
from bakeshop.light.diffuse import (
    METHODS,
    OUTPUT_BYTES,
    cosine_sum,
    dim_normals,
    dim_of,
    irradiance_cost,
)
from bakeshop.light.sun import Sun, split_texels
from bakeshop.resources import Cost, require
from bakeshop.sphere import texels

__all__ = ["DimPair", "dim_pair", "dim_pair_cost"]

#: bytes per texel of the probe that the pair holds beyond one DIM's work (the sun's search and
#: the painted copy of the probe; measured at 8 + 4 per channel, tests/test_resources.py).
PAIR_BYTES = 32


class DimPair(NamedTuple):
    """What :func:`dim_pair` returns."""

    #: (..., C) float32: the DIM of the probe as photographed (lit surfaces).
    sun_dim: np.ndarray
    #: (..., C) float32: the DIM of the probe without its sun (surfaces in shadow).
    shadow_dim: np.ndarray
    #: the probe with its sun painted out, in the input's layout and shape (float32, or
    #: float64 for float64 input; alpha kept).
    shadow_probe: np.ndarray
    #: the sun's measurements, or None when the probe has none (then both DIMs are equal).
    sun: Sun | None


def dim_pair_cost(
    shape, layout: str, *, to: str = "latlong", size=(360, 180), method: str = "auto"
) -> Cost:
    """What :func:`dim_pair` of a probe of ``shape`` in ``layout`` holds at its peak: one DIM's
    (:func:`bakeshop.light.diffuse.irradiance_cost`) plus :data:`PAIR_BYTES` per probe texel
    and the second DIM."""
    one = irradiance_cost(shape, layout, to=to, size=size, method=method, extra=PAIR_BYTES)
    what = "the DIM pair" + one.what.removeprefix(f"the {to} DIM")
    return Cost(one.memory + OUTPUT_BYTES * one.work, one.work, what)


def dim_pair(
    image,
    layout: str,
    *,
    to: str = "latlong",
    size=(360, 180),
    method: str = "auto",
    order: int = 2,
    window: str = "minimal",
) -> DimPair:
    """The sun DIM, the shadow DIM, the sun-removed probe and the sun, from one probe.

    The sun is found and painted out (:mod:`bakeshop.light.sun`); the shadow DIM is the DIM of
    the painted probe (by ``method``), and the sun DIM adds the exact irradiance of what was
    painted out, so ``sun_dim - shadow_dim`` is the sun's own contribution, close to
    ``E_sun max(0, n . s) / pi``.

    Parameters
    ----------
    image : (..., C) array_like
        The probe in ``layout`` (see :func:`bakeshop.sphere.check_environment`).
    layout : str
    to, size, method, order, window
        As for :func:`bakeshop.light.irradiance`.

    Returns
    -------
    DimPair
        ``(sun_dim, shadow_dim, shadow_probe, sun)``; 2-D results for a 2-D probe.
    """
    validate_choice(method, METHODS, "irradiance method")
    require(dim_pair_cost(np.shape(image), layout, to=to, size=size, method=method))
    t = texels(image, layout)
    env = t.environment
    shape, normals, valid = dim_normals(to, size)
    with progress.step("finding the sun"):
        removal = split_texels(t)
    probe = env.image.copy()  # the fill is fractional: a float copy
    values = t.values
    if removal is not None:
        values = probe.reshape(len(t.omega), -1)
        values[removal.index, : removal.filled.shape[1]] = removal.filled
    if method == "sh":
        coeffs = sh.project(values, t.dirs, t.omega, order=order)
        shadow = sh.evaluate(sh.windowed_irradiance(coeffs, window=window).coefficients, normals)
    else:
        shadow = dim_of(values, t.dirs, t.omega, normals, method)
    lit = shadow
    if removal is not None:
        i = removal.index
        colour = removal.filled.shape[1]
        excess = np.zeros((len(i), values.shape[1]))
        excess[:, :colour] = t.values[i, :colour].astype(np.float64) - removal.filled
        e = cosine_sum(normals.reshape(-1, 3), t.dirs[i], excess * t.omega[i, None])
        lit = shadow + e.reshape(shadow.shape) / math.pi
    shadow[~valid] = 0
    lit[~valid] = 0
    return DimPair(
        env.shaped(lit.astype(np.float32)),
        env.shaped(shadow.astype(np.float32)),
        env.shaped(probe),
        None if removal is None else removal.sun,
    )
