"""The split-sum DFG lookup table: the environment BRDF's scale and bias on F0.

The split-sum approximation (Karis 2013) writes the specular image-based lighting integral as the
prefiltered environment (:mod:`bakeshop.light.specular`) times the directional albedo of the
specular BRDF, which depends on F0 linearly through Schlick's Fresnel
F = F0 + (1 - F0) (1 - v.h)^5::

    integral of f(l, v) (n.l) dl = F0 * A(n.v, roughness) + B(n.v, roughness)

    A = integral of (1 - Fc) D(h) V(l, v) (n.l) dl,    B = integral of Fc D(h) V(l, v) (n.l) dl,
    Fc = (1 - v.h)^5

with the GGX distribution D and the Smith visibility V = G / (4 (n.l) (n.v)). The table stores A
("scale") and B ("bias"); a shader computes ``specular = prefiltered * (F0 * A + B)``.

Conventions
-----------
- roughness is the artist's "perceptual" roughness r in [0, 1]; GGX's alpha = r^2 (Burley 2012,
  as UE4).
- columns are n.v, rows are roughness, both sampled at texel centres ((i + 0.5) / size), row 0
  is the smoothest. Uploaded row 0 first (as every bakeshop writer stores it), a shader reads it
  with ``texture(dfg, vec2(NdotV, roughness)).rg``.
- the default visibility is Smith's height-correlated masking-shadowing for GGX (Heitz 2014),
  the physically exact one, as Frostbite and Filament use. ``visibility="schlick"`` gives UE4's
  table: separable Schlick-Smith with k = alpha / 2 (Karis 2013), which Karis' and Lazarov's
  analytic fits approximate.

References
----------
B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course Physically Based Shading in
Theory and Practice. https://blog.selfshadow.com/publications/s2013-shading-course/
E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2),
2014. https://jcgt.org/published/0003/02/03/
D. Lazarov, "Getting More Physical in Call of Duty: Black Ops II", SIGGRAPH 2013 course.
B. Karis, "Physically Based Shading on Mobile", 2014 (the analytic fit of UE4's table).
https://www.unrealengine.com/blog/physically-based-shading-on-mobile
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.errors import ArgumentError, validate_choice, with_article
from bakeshop.light import _native
from bakeshop.light.specular import BLOCK_LOOKUPS, hammersley
from bakeshop.resources import Cost, require, seconds_of

VISIBILITIES = ("height-correlated", "schlick")

#: Largest table side accepted (a 4096x4096 table is already far past any use).
MAX_SIZE = 4096

#: Peak bytes per texel of a table: the n.v and roughness grids, the float64 terms and the
#: float32 table.
TABLE_BYTES = 56
#: Importance samples per second per core: measured at 6.4e7 (a loaded machine),
#: docs/hostile-input.md.
SAMPLES_PER_SECOND = 6e7

__all__ = ["VISIBILITIES", "dfg_terms", "dfg_table", "dfg_table_cost", "dfg_approximation"]


def dfg_terms(
    n_dot_v: ArrayLike,
    roughness: ArrayLike,
    *,
    samples: int = 4096,
    visibility: str = "height-correlated",
) -> np.ndarray:
    """The split-sum environment BRDF terms (A, B) at given n.v and roughness.

    Integrated by importance sampling GGX's distribution of normals with a Hammersley point set
    (Karis 2013): deterministic; with the default 4096 samples within 4e-3 of brute-force
    quadrature everywhere, and within 1e-3 away from grazing angles (n.v > 0.2).

    Parameters
    ----------
    n_dot_v : array_like of float
        Cosine of the view angle, in [0, 1] (clamped to at least 1e-6).
    roughness : array_like of float
        Perceptual roughness in [0, 1]; alpha = roughness^2. Broadcast against ``n_dot_v``.
    samples : int
        Number of importance samples per point.
    visibility : {"height-correlated", "schlick"}
        Smith height-correlated GGX visibility (Heitz 2014), or UE4's separable Schlick-Smith
        approximation with k = alpha / 2.

    Returns
    -------
    terms : (..., 2) float64
        ``[..., 0]`` is the scale A on F0 and ``[..., 1]`` the bias B:
        the specular albedo is ``F0 * A + B``.
    """
    validate_choice(visibility, VISIBILITIES, "visibility")
    if not 1 <= samples <= 1 << 20:
        raise ArgumentError(f"samples must be in 1..{1 << 20}, got {samples}")
    nv, r = np.broadcast_arrays(np.asarray(n_dot_v, float), np.asarray(roughness, float))
    if not (np.all(np.isfinite(nv)) and np.all(np.isfinite(r))):
        raise ArgumentError("n_dot_v and roughness must be finite")
    if nv.size and (nv.min() < 0 or nv.max() > 1 or r.min() < 0 or r.max() > 1):
        raise ArgumentError("n_dot_v and roughness must lie in [0, 1]")
    out = np.empty((nv.size, 2))
    flat_nv, flat_r = np.ascontiguousarray(nv.ravel()), np.ascontiguousarray(r.ravel())
    xi, schlick = hammersley(samples), visibility == "schlick"
    # in blocks of points, so that progress (and a signal) is seen between them
    step = max(1, BLOCK_LOOKUPS // samples)
    with progress.task("DFG table", total=nv.size * samples) as task:
        for a in range(0, nv.size, step):
            b = min(nv.size, a + step)
            _native.dfg_terms(flat_nv[a:b], flat_r[a:b], xi, schlick, out[a:b])
            task.advance((b - a) * samples)
    return out.reshape(nv.shape + (2,))


def dfg_table_cost(size: int = 128, *, samples: int = 4096) -> Cost:
    """What :func:`dfg_table` holds at its peak (:data:`TABLE_BYTES` per texel) and the work
    it does (``size^2 samples`` importance samples, at :data:`SAMPLES_PER_SECOND`)."""
    return Cost(
        TABLE_BYTES * size * size,
        size * size * samples,
        f"{with_article(size)}x{size} DFG table of {samples} samples per texel",
        seconds_of(size * size * samples, SAMPLES_PER_SECOND),
    )


def dfg_table(
    size: int = 128, *, samples: int = 4096, visibility: str = "height-correlated"
) -> np.ndarray:
    """The DFG lookup texture: ``(size, size, 2)`` float32, columns n.v, rows roughness.

    Texel (i, j) holds :func:`dfg_terms` at n.v = (i + 0.5) / size and
    roughness = (j + 0.5) / size; row 0 is the smoothest (read it with
    ``texture(dfg, vec2(NdotV, roughness)).rg`` when uploaded row 0 first).

    Parameters
    ----------
    size : int
        Side of the square table (UE4 uses 128; 32 is enough for bilinear lookups to stay within
        1e-3 away from grazing angles).
    samples, visibility
        As :func:`dfg_terms`.

    Returns
    -------
    table : (size, size, 2) float32
        Channel 0 is the scale A on F0, channel 1 the bias B.
    """
    if not 1 <= size <= MAX_SIZE:
        raise ArgumentError(f"the DFG table size must be in 1..{MAX_SIZE}, got {size}")
    validate_choice(visibility, VISIBILITIES, "visibility")
    if not 1 <= samples <= 1 << 20:
        raise ArgumentError(f"samples must be in 1..{1 << 20}, got {samples}")
    require(dfg_table_cost(size, samples=samples))
    centres = (np.arange(size) + 0.5) / size
    out = np.empty((size * size, 2))
    # each row's half vectors are drawn once and reused along it (the same numbers as
    # dfg_terms, a fraction of the work)
    _native.dfg_grid(centres, centres, hammersley(samples), visibility == "schlick", out)
    return out.reshape(size, size, 2).astype(np.float32)


def dfg_approximation(n_dot_v: ArrayLike, roughness: ArrayLike) -> np.ndarray:
    """Karis' analytic fit of UE4's DFG table (after Lazarov 2013), for comparison and mobile.

    ``r = roughness * c0 + c1``, ``a = min(r0^2, 2^(-9.28 n.v)) r0 + r1``,
    ``(A, B) = (-1.04, 1.04) a + (r2, r3)`` with c0 = (-1, -0.0275, -0.572, 0.022) and
    c1 = (1, 0.0425, 1.04, -0.04) (Karis 2014, "Physically Based Shading on Mobile").

    Returns
    -------
    terms : (..., 2) float64
        (A, B) as :func:`dfg_terms`.
    """
    nv, r = np.broadcast_arrays(np.asarray(n_dot_v, float), np.asarray(roughness, float))
    c0 = np.array([-1.0, -0.0275, -0.572, 0.022])
    c1 = np.array([1.0, 0.0425, 1.04, -0.04])
    k = r[..., None] * c0 + c1
    a = np.minimum(k[..., 0] ** 2, np.exp2(-9.28 * nv)) * k[..., 0] + k[..., 1]
    return np.stack([-1.04 * a + k[..., 2], 1.04 * a + k[..., 3]], axis=-1)
