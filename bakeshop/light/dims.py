"""The DIM pair: the diffuse irradiance of a probe with its sun (for lit surfaces) and without
it (for surfaces in shadow), composed from :mod:`bakeshop.light.sun` and
:mod:`bakeshop.light.irradiance`.

A renderer that knows from a shadow map whether a fragment sees the sun shades it with the sun
DIM where it does and the shadow DIM where it does not; their difference is the sun's own
contribution, close to ``E_sun max(0, n . s) / pi``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.errors import validate_choice
from bakeshop.light.diffuse import (
    METHODS,
    OUTPUT_BYTES,
    cosine_sum,
    dim_normals,
    dim_of_environment,
    irradiance_cost,
)
from bakeshop.light.sun import COPY_BYTES, Removal, Sun, find_sun_cost, split_environment
from bakeshop.resources import Cost, require
from bakeshop.sphere import Environment, check_environment, texels_at

__all__ = ["DimPair", "dim_pair", "dim_pair_cost", "dim_pair_of"]

#: bytes per texel of the probe that :func:`dim_pair` holds beyond one DIM's work (the painted
#: copy of the probe; measured at 8 + 4 per channel, tests/test_resources.py); the sun's search
#: goes by strips (:func:`bakeshop.light.sun.find_sun_cost`).
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
    shape: Sequence[int],
    layout: str,
    *,
    to: str = "latlong",
    size: int | tuple[int, int] = (360, 180),
    method: str = "auto",
    painted: bool = True,
) -> Cost:
    """What :func:`dim_pair` of a probe of ``shape`` in ``layout`` holds at its peak: one DIM's
    (:func:`bakeshop.light.diffuse.irradiance_cost`), the sun's search
    (:func:`bakeshop.light.sun.find_sun_cost` without its copy), the second DIM, and with
    ``painted`` (not for :func:`dim_pair_of`) :data:`PAIR_BYTES` per probe texel."""
    extra = PAIR_BYTES if painted else 0
    one = irradiance_cost(shape, layout, to=to, size=size, method=method, extra=extra)
    search = find_sun_cost(shape, layout)
    search_memory = search.memory - COPY_BYTES * search.work
    what = "the DIM pair" + one.what.removeprefix(f"the {to} DIM")
    memory = one.memory + search_memory + OUTPUT_BYTES * one.work
    return Cost(memory, one.work, what, 2 * one.seconds)  # two DIMs


def dim_pair(
    image: ArrayLike,
    layout: str,
    *,
    to: str = "latlong",
    size: int | tuple[int, int] = (360, 180),
    method: str = "auto",
    order: int = 2,
    window: str = "minimal",
    copy: bool = True,
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
    copy : bool
        False: the shadow probe is painted into the checked probe itself, which is ``image``
        when it is a writable C-contiguous float32 or float64 array (the command line's own
        decoded probe: a large probe is not copied), else a copy.

    Returns
    -------
    DimPair
        ``(sun_dim, shadow_dim, shadow_probe, sun)``; 2-D results for a 2-D probe.
    """
    validate_choice(method, METHODS, "irradiance method")
    require(dim_pair_cost(np.shape(image), layout, to=to, size=size, method=method))
    env = check_environment(image, layout)
    lit, shadow, removal = dim_pair_of(
        env, to=to, size=size, method=method, order=order, window=window
    )
    # the fill is fractional: a float array
    probe = env.image if not copy and env.image.flags.writeable else env.image.copy()
    if removal is not None:
        removal.paint(probe)
    return DimPair(
        env.shaped(lit),
        env.shaped(shadow),
        env.shaped(probe),
        None if removal is None else removal.sun,
    )


def dim_pair_of(
    env: Environment,
    *,
    to: str = "latlong",
    size: int | tuple[int, int] = (360, 180),
    method: str = "auto",
    order: int = 2,
    window: str = "minimal",
) -> tuple[np.ndarray, np.ndarray, Removal | None]:
    """The DIM pair of a checked environment (:func:`bakeshop.sphere.check_environment`)
    without painting a copy of it: ``(sun DIM, shadow DIM, removal)``, float32 with a channel
    axis, and the sun's :class:`~bakeshop.light.sun.Removal` (None without a sun), whose
    :meth:`~bakeshop.light.sun.Removal.paint` paints the shadow probe into any copy.

    The probe's texels are read in strips with their geometry (no per-texel array of the whole
    layout, no copy of the image): the shadow DIM is the DIM of the texels with the fill read
    in place of the sun's, and the sun DIM adds the exact irradiance of what the fill removes.
    """
    validate_choice(method, METHODS, "irradiance method")
    shape, normals, valid = dim_normals(to, size)
    with progress.step("finding the sun"):
        removal = split_environment(env)
    shadow = dim_of_environment(env, normals, method, order=order, window=window, fill=removal)
    lit = shadow
    if removal is not None:
        i = removal.index
        colour = removal.filled.shape[1]
        flat = env.image.reshape(-1, env.image.shape[-1])
        dirs, omega = texels_at(env.layout, env.image.shape[:-1], i)
        excess = np.zeros((len(i), flat.shape[1]))
        excess[:, :colour] = flat[i, :colour].astype(np.float64) - removal.filled
        e = cosine_sum(normals.reshape(-1, 3), dirs, excess * omega[:, None])
        lit = shadow + e.reshape(shadow.shape) / math.pi
    shadow[~valid] = 0
    lit[~valid] = 0
    return lit.astype(np.float32), shadow.astype(np.float32), removal
