"""Probe transitions: blending baked probes along a camera path instead of snapping between them.

A bake is linear in radiance except where it looks at the probe to decide: the environment
cube, every level of the GGX chain, the radiance SH and the sun DIM (the irradiance of the whole
probe) of a weighted sum of probes are the same weighted sum of the probes' bakes, so blending
the bakes is exact and costs nothing at run time (``tests/preview/test_transitions.py`` bakes
both ways: equal to 1e-6 of the peak radiance). Two outputs are not: the shadow DIM is the
irradiance of the probe without *its* sun, and two probes with different suns have no common sun
to remove; and the exported SH irradiance is windowed with a window chosen per probe (Sloan's
minimal non-negative window). Their blends are the blends of each probe's own, which is what an
engine blending the pair does.

Weights are either inverse-distance (:func:`bakeshop.light.sh.inverse_distance_weights`) or
influence volumes as engines place them (a sphere per probe with a blend distance inside its
edge, and a priority: higher-priority probes take their share first, lower ones the rest).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice

if TYPE_CHECKING:
    from bakeshop.preview.bake import Bake

__all__ = ["WEIGHT_METHODS", "Walk", "blend_bakes", "influence_weights", "path_weights", "walk"]

WeightMethod = Literal["inverse-distance", "volumes"]
#: How a point's probe weights are found.
WEIGHT_METHODS = ("inverse-distance", "volumes")


def influence_weights(
    points: ArrayLike,
    centres: ArrayLike,
    radii: ArrayLike,
    *,
    blend_distance: ArrayLike,
    priority: ArrayLike | None = None,
) -> np.ndarray:
    """Probe weights from influence volumes, summing to 1 at every point.

    A probe's raw weight at x is ``clamp((R - |x - c|) / b, 0, 1)``: 1 deeper than the blend
    distance b inside its sphere of radius R, falling linearly to 0 at the sphere's edge.
    Probes are taken by descending ``priority``, a priority level at a time (the accumulation of
    HDRP's and Unreal's reflection probes): a level whose raw weights sum to S takes
    ``min(S, 1)`` of what the levels before it left, shared among its probes in proportion to
    their raw weights (so probes of one level blend symmetrically, with no jump where they
    overlap); the result is normalised to sum 1.
    A point outside every volume takes the nearest probe alone.

    Parameters
    ----------
    points : (Q, 3) float
        Where weights are wanted (metres).
    centres : (P, 3) float
        Each probe's position.
    radii : (P,) float
        Each volume's radius (> 0).
    blend_distance : float or (P,) float
        The fade inside each volume's edge (> 0, at most the radius).
    priority : (P,) int, optional
        Higher first; default all equal.

    Returns
    -------
    (Q, P) float64
        Rows summing to 1, continuous along a path inside the union of the volumes.
    """
    x = np.atleast_2d(np.asarray(points, np.float64))
    c = np.asarray(centres, np.float64)
    r = np.broadcast_to(np.asarray(radii, np.float64), (len(c),))
    b = np.broadcast_to(np.asarray(blend_distance, np.float64), (len(c),))
    pr = np.zeros(len(c)) if priority is None else np.asarray(priority, np.float64)
    if c.ndim != 2 or c.shape[1] != 3 or x.shape[1] != 3 or pr.shape != (len(c),):
        raise ArgumentError("points must be (Q, 3), centres (P, 3), radii and priority (P,)")
    if not (np.isfinite(r).all() and (r > 0).all() and (b > 0).all() and (b <= r).all()):
        raise ArgumentError("influence radii must be > 0 and blend distances in (0, radius]")
    dist = np.linalg.norm(x[:, None, :] - c[None], axis=-1)
    raw = np.clip((r - dist) / b, 0.0, 1.0)
    # priority groups, highest first: a group takes min(1, its raw sum) of what is left, shared
    # in proportion to its members' raw weights (within a group no order, so no jump)
    w = np.zeros_like(raw)
    left = np.ones(len(x))
    for level in np.unique(pr)[::-1]:
        members = pr == level
        group = raw[:, members]
        total = group.sum(axis=-1)
        share = np.minimum(total, 1.0) * left
        w[:, members] = group * (share / np.where(total > 0, total, 1.0))[:, None]
        left = left - share
    total = w.sum(axis=-1, keepdims=True)
    nearest = np.eye(len(c))[dist.argmin(axis=-1)]
    return np.where(total > 0, w / np.where(total > 0, total, 1.0), nearest)


def path_weights(
    points: ArrayLike,
    positions: ArrayLike,
    *,
    method: WeightMethod = "inverse-distance",
    power: float = 2.0,
    radii: ArrayLike | None = None,
    blend_distance: ArrayLike | None = None,
    priority: ArrayLike | None = None,
) -> np.ndarray:
    """(Q, P) probe weights at ``points`` by ``method`` (:data:`WEIGHT_METHODS`): inverse
    distance to the ``power``, or :func:`influence_weights` with ``radii``, ``blend_distance``
    and ``priority``."""
    validate_choice(method, WEIGHT_METHODS, "probe weighting")
    if method == "inverse-distance":
        from bakeshop.light.sh import inverse_distance_weights

        return np.atleast_2d(inverse_distance_weights(points, positions, power=power))
    if radii is None or blend_distance is None:
        raise ArgumentError("influence volumes need radii and a blend distance")
    return influence_weights(points, positions, radii, blend_distance=blend_distance,
                             priority=priority)  # fmt: skip


def blend_bakes(bakes: Sequence[Bake], weights: ArrayLike) -> Bake:
    """The weighted sum of bakes of one shape: every radiance array (the cube, each level of the
    chain, the sun and shadow DIMs) and the SH; the DFG table (the same for every bake) and the
    sun of the most heavily weighted bake are kept.

    Parameters
    ----------
    bakes : list of Bake
    weights : (P,) float
        Non-negative, not all zero (normalised here).

    Returns
    -------
    Bake
    """
    w = np.asarray(weights, np.float64)
    if w.shape != (len(bakes),) or not np.isfinite(w).all() or (w < 0).any() or w.sum() <= 0:
        raise ArgumentError(f"need {len(bakes)} finite non-negative weights, not all zero")
    w = w / w.sum()
    first = bakes[0]
    for bake in bakes[1:]:
        shapes = [a.shape for a in (bake.cube, bake.sun_dim, bake.shadow_dim, *bake.specular)]
        if shapes != [a.shape for a in (first.cube, first.sun_dim, first.shadow_dim,
                                        *first.specular)]:  # fmt: skip
            raise ArgumentError("bakes to blend must have the same sizes and levels")

    def mix(get: Callable[..., np.ndarray]) -> np.ndarray:
        total = sum(wi * np.asarray(get(b), np.float64) for wi, b in zip(w, bakes, strict=True))
        return np.asarray(total, np.float32)

    return first._replace(
        cube=mix(lambda b: b.cube),
        specular=[mix(lambda b, m=m: b.specular[m]) for m in range(len(first.specular))],
        sun_dim=mix(lambda b: b.sun_dim),
        shadow_dim=mix(lambda b: b.shadow_dim),
        sh=np.asarray(sum(wi * b.sh for wi, b in zip(w, bakes, strict=True)), np.float64),
        sun=bakes[int(np.argmax(w))].sun,
        folder=None,
        files=None,
    )


class Walk(NamedTuple):
    """What :func:`walk` measures along a path."""

    #: (F, P) the probes' weights at each frame.
    weights: np.ndarray
    #: (F, 3) irradiance (E/pi, the sun DIM) at the reference normal, blended.
    blended: np.ndarray
    #: (F, 3) the same, snapping to the nearest probe.
    snapped: np.ndarray
    #: the largest frame-to-frame change of the blended luminance, and of the snapped one.
    worst_step: float
    worst_snap_step: float


def walk(
    bakes: Sequence[Bake],
    positions: ArrayLike,
    path: ArrayLike,
    *,
    normal: ArrayLike = (0.0, 1.0, 0.0),
    **weighting: Any,
) -> Walk:
    """Blend bakes along a camera path and measure the transition at a reference normal.

    Parameters
    ----------
    bakes : list of Bake
        P bakes.
    positions : (P, 3) float
        Where each was captured (metres).
    path : (F, 3) float
        The camera's positions, frame by frame.
    normal : (3,) float
        The reference normal whose irradiance is followed (default up).
    **weighting
        :func:`path_weights` options.

    Returns
    -------
    Walk
        The blended irradiance is ``weights @ E_p``, each probe's sun DIM at ``normal``: the
        sun DIM of the blended bake (it is linear), and the luminance steps use Rec. 709.
    """
    from bakeshop.preview.reference import latlong_bilinear

    positions = np.asarray(positions, np.float64)
    path = np.atleast_2d(np.asarray(path, np.float64))
    if len(bakes) != len(positions) or len(bakes) == 0:
        raise ArgumentError(f"{len(bakes)} bakes but {len(positions)} positions")
    n = np.asarray(normal, np.float64)
    if n.shape != (3,) or not np.isfinite(n).all() or not np.linalg.norm(n) > 0:
        raise ArgumentError("the reference normal must be 3 finite numbers, not zero")
    n = n / np.linalg.norm(n)
    e = np.stack([latlong_bilinear(b.sun_dim, n[None])[0] for b in bakes])
    weights = path_weights(path, positions, **weighting)
    nearest = np.linalg.norm(path[:, None] - positions[None], axis=-1).argmin(axis=-1)
    blended, snapped = weights @ e, e[nearest]
    lum = np.array([0.2126, 0.7152, 0.0722])

    def worst(values: np.ndarray) -> float:
        return float(np.abs(np.diff(values @ lum)).max()) if len(values) > 1 else 0.0

    return Walk(weights, blended, snapped, worst(blended), worst(snapped))
