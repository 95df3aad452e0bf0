"""Fresnel reflectance of a dielectric and the fresnel bake of an environment for flat water.

A flat reflector (a calm water plane) under an infinitely distant environment sees each
direction d of the environment under exactly one angle of incidence: the mirror reflection that
fetches d has cos(theta_i) = d . up. So the reflectance can be multiplied into the environment
once (:func:`bake_fresnel`) and the shader does a plain lookup; after exposure the baked map fits
in 8 bits because fresnel dims the bright zenith. :func:`flat_water_error` and
:func:`normal_mapped_error` measure how well that holds.

References
----------
M. Born and E. Wolf, *Principles of Optics*, 7th ed., section 1.5.2 (the Fresnel equations).
C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer Graphics Forum
13(3), 1994, doi:10.1111/1467-8659.1330233.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress, sphere
from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.image import CLIP_FRACTION, exposure, fit_exposure, srgb_decode, to_srgb8
from bakeshop.light import _native
from bakeshop.sphere import check_environment, texel_cosines

#: Index of refraction of water at visible wavelengths (about 20 C, 589 nm).
WATER_IOR = 1.333

#: What a bake writes for directions below the reflecting plane.
BELOW_MODES = ("zero", "mirror")


def _check_ior(ior: float) -> float:
    ior = float(ior)
    if not (np.isfinite(ior) and ior > 0):
        raise ArgumentError(f"index of refraction must be a positive finite number, got {ior}")
    return ior


def _cosines(cos_i: ArrayLike) -> np.ndarray:
    a = np.asarray(cos_i)
    if a.dtype not in (np.float32, np.float64):
        a = a.astype(np.float64)
    return np.clip(a, 0, 1)  # NaN stays NaN


def fresnel_dielectric(cos_i: ArrayLike, ior: float = WATER_IOR) -> np.ndarray:
    """Exact unpolarised Fresnel reflectance at a smooth interface between two dielectrics.

    With c = cos(theta_i), n = ior (relative index: transmitted side over incident side) and
    g = sqrt(n^2 - 1 + c^2)::

        R = 1/2 (g - c)^2 / (g + c)^2 * (1 + ((c (g + c) - 1) / (c (g - c) + 1))^2)

    which is (R_s + R_p) / 2 of the Fresnel equations written without the refraction angle
    (Cook and Torrance 1982, eq. 8 notation), accurate to rounding for every c in [0, 1]
    (no cancellation at grazing incidence: the denominators are >= the numerators).

    Parameters
    ----------
    cos_i : array_like, float
        Cosine of the angle of incidence, measured from the surface normal on the incident
        side. Domain [0, 1]: 1 is normal incidence, 0 grazing. Values outside are clipped to
        [0, 1] (a value a hair above 1 comes from rounding of unit vectors; a negative cosine is
        a ray arriving from the other side, which is outside this function's domain and is
        given the grazing limit R = 1). NaN stays NaN.
    ior : float
        Relative index of refraction n2 / n1 (> 0); 1.333 is air to water. For n < 1 (looking
        up from under water) directions beyond the critical angle, c < sqrt(1 - n^2), are
        totally reflected (R = 1).

    Returns
    -------
    ndarray, shape of ``cos_i``
        Reflectance in [0, 1] (dimensionless). Float32 input gives float32 (computed in
        float64), anything else float64.

    Notes
    -----
    At normal incidence R = ((n - 1) / (n + 1))^2 (0.0204 for water); R -> 1 at grazing.

    References
    ----------
    M. Born and E. Wolf, *Principles of Optics*, 7th ed., section 1.5.2.
    R. L. Cook and K. E. Torrance, "A Reflectance Model for Computer Graphics", ACM TOG 1(1),
    1982, doi:10.1145/357290.357293.
    """
    n = _check_ior(ior)
    c = _cosines(cos_i)
    out = np.empty(c.shape, np.float64)
    _native.reflectance(np.ascontiguousarray(c, dtype=np.float64).reshape(-1), n, out.reshape(-1))
    return out.astype(c.dtype, copy=False)


def fresnel_schlick(cos_i: ArrayLike, ior: float = WATER_IOR) -> np.ndarray:
    """Schlick's approximation R0 + (1 - R0) (1 - c)^5 with R0 = ((n - 1) / (n + 1))^2.

    Same domain, clipping and dtype rules as :func:`fresnel_dielectric`; meant for n > 1 (from
    the optically thinner side). For water (n = 1.333) it is exact at both ends; in between it
    errs by up to +0.059 (at 83.8 degrees incidence) and -0.0094 (at 56.8 degrees); mean
    error over cos_i +0.010 (docs/fresnel.md).

    References
    ----------
    C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer Graphics
    Forum 13(3), 1994, eq. 24, doi:10.1111/1467-8659.1330233.
    """
    n = _check_ior(ior)
    c = _cosines(cos_i)
    r0 = ((n - 1.0) / (n + 1.0)) ** 2
    return (r0 + (1.0 - r0) * (1.0 - c.astype(np.float64)) ** 5).astype(c.dtype, copy=False)


def schlick_error(ior: float = WATER_IOR, *, samples: int = 100001) -> dict:
    """How far Schlick's approximation is from the exact reflectance, over cos_i in [0, 1].

    Returns
    -------
    dict
        ``max`` (largest signed error, Schlick - exact) and ``max_angle_deg`` (its angle of
        incidence), ``min`` and ``min_angle_deg`` likewise, ``mean`` (mean error over cos_i,
        evenly spaced, ``samples`` points).
    """
    c = np.linspace(0.0, 1.0, int(samples))
    err = fresnel_schlick(c, ior) - fresnel_dielectric(c, ior)
    hi, lo = int(np.argmax(err)), int(np.argmin(err))
    return {
        "max": float(err[hi]),
        "max_angle_deg": float(np.degrees(np.arccos(c[hi]))),
        "min": float(err[lo]),
        "min_angle_deg": float(np.degrees(np.arccos(c[lo]))),
        "mean": float(err.mean()),
    }


def _unit_axis(up: ArrayLike) -> np.ndarray:
    u = np.asarray(up, dtype=np.float64).reshape(-1)
    norm = np.linalg.norm(u) if u.size == 3 else 0.0
    if not (np.isfinite(norm) and norm > 0):
        raise ArgumentError(f"the up axis must be a non-zero finite 3-vector, got {up!r}")
    return u / norm


def bake_fresnel(
    image: ArrayLike,
    layout: str,
    *,
    ior: float = WATER_IOR,
    up: ArrayLike = (0.0, 1.0, 0.0),
    below: str = "zero",
) -> np.ndarray:
    """Multiply an environment by the reflectance of a flat dielectric plane (calm water).

    A viewer looking at a horizontal mirror plane sees environment direction d (d . up > 0)
    by the reflection whose angle of incidence has cos(theta_i) = d . up, so each texel is
    multiplied by R(d . up) (:func:`fresnel_dielectric`, evaluated at the texel centre).
    Directions below the plane are never fetched by a flat reflector; ``below`` chooses what
    they hold:

    - ``"zero"``: black. The smallest file, but a bilinear or mip-mapped lookup within half a
      texel of the horizon blends that black in (a thin dark seam at the horizon line).
    - ``"mirror"``: the bake of the mirror direction d - 2 (d . up) up, so the map is symmetric
      about the plane and filtering across the horizon sees the same values on both sides.
      For a latlong with up = +Y this is exactly the upper half flipped; other layouts and
      axes sample the upper half bilinearly.

    Parameters
    ----------
    image : (H, W, C) or, for "cube", (6, S, S, C) float; C in {1, 3, 4}
        Linear radiance in ``layout`` (a grey image may omit C). Alpha passes through.
    layout : str
        Layout name of :func:`bakeshop.sphere.layout` ("latlong", "cube", "angular", ...).
    ior : float
        Index of refraction of the water (air -> water), default 1.333.
    up : 3-vector
        The plane's normal in the world frame (normalised here); default +Y.
    below : {"zero", "mirror"}

    Returns
    -------
    ndarray, shape of ``image``, float32 (float64 stays float64)
        Radiance times reflectance, in the units of ``image``; alpha is kept. Texels outside
        a disk layout's disk, and the unused squares of a cross, are 0 (alpha too).
    """
    validate_choice(below, BELOW_MODES, "below-horizon mode")
    n = _check_ior(ior)
    up = _unit_axis(up)
    env = check_environment(image, layout)
    a, lay = env.image, env.layout
    shape = a.shape[:-1]
    cos = texel_cosines(lay, shape, up)
    out = np.empty(a.shape, a.dtype)  # C order: the kernel writes it through a flat view
    # out = image * R(cos) where cos >= 0, 0 below the plane; alpha kept; NaN cos: all 0
    _native.apply_reflectance(
        cos.reshape(-1),
        n,
        np.ascontiguousarray(a).reshape(-1, a.shape[-1]),
        out.reshape(-1, a.shape[-1]),
        min(a.shape[-1], 3),
    )
    if below == "mirror":
        lower = np.nonzero(cos < 0)
        centres = [i + 0.5 for i in lower[-2:][::-1]]  # (x, y) = (column, row) + 1/2
        if lay.cubic:
            centres.insert(0, lower[0].astype(np.float64))
        dirs = lay.directions_at(np.stack(centres, axis=-1), shape)
        c = cos[lower]
        fetched = sphere.sample(a, layout, dirs - 2.0 * c[:, None] * up, filter="bilinear")
        colour = min(a.shape[-1], 3)
        out[lower + (slice(0, colour),)] = fetched[:, :colour] * fresnel_dielectric(-c, n)[:, None]
    return env.shaped(out)


#: Fraction of the reflected hemisphere's solid angle that the automatic LDR exposure lets clip.
LDR_CLIP_FRACTION = CLIP_FRACTION


def ldr_exposure(
    baked: ArrayLike,
    layout: str,
    *,
    up: ArrayLike = (0.0, 1.0, 0.0),
    clip_fraction: float = LDR_CLIP_FRACTION,
) -> float:
    """Exposure (EV) for storing a fresnel bake in 8 bits: only the brightest spot clips.

    Returns ``-log2(q)`` where q is the solid-angle weighted (1 - ``clip_fraction``) quantile
    of the largest colour channel over the texels above the plane: after exposure everything
    but the brightest ``clip_fraction`` of the reflected hemisphere (by solid angle) is <= 1.
    This is the display rule's ``fit`` exposure (:func:`bakeshop.image.fit_exposure`) metered
    above the horizon.
    The default 0.1% (6.3 msr) is about 90 sun discs: the sun and its aureole clip, the sky
    does not.

    Parameters
    ----------
    baked : environment as for :func:`bake_fresnel` (usually its output)
    layout : str
    up : 3-vector
    clip_fraction : float in (0, 1)

    Returns
    -------
    float, stops
    """
    env = check_environment(baked, layout)
    a, lay = env.image, env.layout
    weights = np.where(texel_cosines(lay, a.shape[:-1], up) > 0, lay.solid_angles(a.shape[:-1]), 0)
    try:
        return fit_exposure(a, weights=weights, clip_fraction=clip_fraction)
    except ArgumentError as e:
        if "clip fraction" in e.reason:
            raise
        raise ArgumentError(
            "the environment is black above the plane: no exposure fits it"
        ) from None


def hemisphere_directions(count: int, up: ArrayLike = (0.0, 1.0, 0.0)) -> np.ndarray:
    """``count`` directions spread evenly (equal solid angle each) over the hemisphere ``up``.

    A Fibonacci spiral: cos(theta) = (k + 1/2) / count and phi = 2 pi k / golden ratio, which
    covers the hemisphere uniformly in solid angle with no clumping (deterministic, no seed).

    Returns
    -------
    (count, 3) float64 unit vectors with d . up > 0.
    """
    count = int(count)
    if count < 1:
        raise ArgumentError(f"need at least one direction, got {count}")
    k = np.arange(count, dtype=np.float64)
    c = (k + 0.5) / count
    s = np.sqrt(1.0 - c * c)
    phi = 2.0 * np.pi * k * (2.0 / (1.0 + np.sqrt(5.0)))
    up = _unit_axis(up)
    helper = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    t1 = np.cross(up, helper)
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(up, t1)
    return (s * np.cos(phi))[:, None] * t1 + (s * np.sin(phi))[:, None] * t2 + c[:, None] * up


def flat_water_error(
    image: ArrayLike,
    layout: str,
    *,
    ev: float,
    ior: float = WATER_IOR,
    up: ArrayLike = (0.0, 1.0, 0.0),
    below: str = "zero",
    filter: str = "bilinear",
    dither: str = "none",
    seed: int = 0,
    samples: int = 1 << 20,
) -> dict:
    """How far the baked 8-bit lookup is from the runtime fresnel path, for flat water.

    For ``samples`` reflected directions r spread evenly over the upper hemisphere (every view
    direction of a flat mirror, :func:`hemisphere_directions`), both paths give an 8-bit sRGB
    pixel:

    - runtime: ``E = lookup(image, r) * R(r . up) * 2**ev``, clamped, sRGB-encoded, rounded;
    - baked: the bake of ``image`` (:func:`bake_fresnel`), exposed and stored as 8-bit sRGB
      (:func:`~bakeshop.image.to_srgb8`, with ``dither``), decoded to linear as an
      sRGB texture is by the GPU before filtering, looked up at r, then encoded and rounded.

    ``filter`` is the texture filter of both lookups. With "nearest" a lookup returns one
    texel and the paths differ by the 8-bit rounding of the stored texel and by R varying
    across the texel (the bake evaluates R at texel centres). With "bilinear" the baked path
    interpolates R L while the runtime multiplies the interpolated L by R at r exactly; their
    difference is about t (1 - t) dR dL for neighbouring texels differing by dR and dL, which
    matters only near the horizon, where R changes fastest. Two kinds of lookups are set apart
    because the paths there see different data:

    - *footprint clipped*: a texel of the filter footprint clipped in the bake (the sun), so
      the baked path interpolates a clipped value and is darker than the runtime, even where
      the runtime result is not clipped;
    - *horizon*: the footprint reaches a texel below the plane, which the runtime fetches from
      the HDR environment (the real ground, times R ~ 1) and the bake holds as zero or the
      mirrored sky (``below``); a band half a texel high.

    Returns
    -------
    dict
        Errors |baked - runtime| in 8-bit steps over (direction, colour channel) pairs:
        ``max``/``mean`` over all pairs; ``max_unclipped``/``mean_unclipped`` where the
        runtime value is not clipped (exposed value in [0, 1)); ``max_clean``/``mean_clean``/
        ``over_one_clean`` (fraction above 1 step) over the unclipped pairs that are neither
        footprint-clipped nor horizon lookups; fractions of all pairs ``clipped``,
        ``footprint_clipped`` and ``horizon``; ``worst_elevation_deg``, elevation of r above
        the plane at the worst clean pair; and ``samples``, ``ev``, ``filter``, ``below``,
        ``dither``.
    """
    validate_choice(filter, ("nearest", "bilinear"), "filter")
    with progress.step("flat water: baked 8-bit lookups vs the runtime path"):
        return _flat_water_error(image, layout, ev, ior, up, below, filter, dither, seed, samples)


def _flat_water_error(
    image: ArrayLike,
    layout: str,
    ev: float,
    ior: float,
    up: ArrayLike,
    below: str,
    filter: str,
    dither: str,
    seed: int,
    samples: int,
) -> dict:
    a = check_environment(image, layout).image
    a = a[..., : min(a.shape[-1], 3)]
    up = _unit_axis(up)
    r = hemisphere_directions(samples, up)
    cos = r @ up

    def lookup(texture: np.ndarray) -> np.ndarray:
        return sphere.sample(texture, layout, r, filter=filter)

    exposed_bake = exposure(bake_fresnel(a, layout, ior=ior, up=up, below=below), ev)
    codes = to_srgb8(exposed_bake, dither=dither, seed=seed)
    texture = srgb_decode(codes.astype(np.float32) / np.float32(255))
    baked = to_srgb8(lookup(texture)).astype(np.int16)
    runtime_linear = lookup(a).astype(np.float64) * fresnel_dielectric(cos, ior)[:, None] * 2.0**ev
    runtime = to_srgb8(runtime_linear).astype(np.int16)
    err = np.abs(baked - runtime)

    footprint = lookup((exposed_bake >= 1).astype(np.float32)) > 0
    horizon = lookup((texel_cosines(layout, a.shape[:-1], up) < 0).astype(np.float32)) > 0
    unclipped = (runtime_linear >= 0) & (runtime_linear < 1)
    clean = unclipped & ~footprint & ~horizon[:, None]
    worst = np.unravel_index(np.argmax(np.where(clean, err, -1)), err.shape)[0]

    def stats(mask: np.ndarray) -> tuple[int, float]:
        e = err[mask]
        return (int(e.max()), float(e.mean())) if e.size else (0, 0.0)

    max_all, mean_all = stats(np.ones_like(err, bool))
    max_u, mean_u = stats(unclipped)
    max_c, mean_c = stats(clean)
    return {
        "samples": int(samples),
        "ev": float(ev),
        "filter": filter,
        "below": below,
        "dither": dither,
        "max": max_all,
        "mean": mean_all,
        "max_unclipped": max_u,
        "mean_unclipped": mean_u,
        "max_clean": max_c,
        "mean_clean": mean_c,
        "over_one_clean": float(np.mean(err[clean] > 1)) if clean.any() else 0.0,
        "clipped": float(np.mean(~unclipped)),
        "footprint_clipped": float(np.mean(unclipped & footprint)),
        "horizon": float(np.mean(horizon)),
        "worst_elevation_deg": float(np.degrees(np.arcsin(np.clip(cos[worst], 0, 1)))),
    }


#: RMS slopes of the normal-mapped water table (calm to wind-roughened).
RMS_SLOPES = (0.02, 0.05, 0.1, 0.2, 0.3)


def slope_normals(count: int, rms_slope: float, *, seed: int = 0) -> np.ndarray:
    """Shading normals of a water normal map with isotropic Gaussian slopes (Cox and Munk).

    The slopes along x and z are independent N(0, s^2 / 2), so the mean square of the slope
    magnitude is s^2 (s = ``rms_slope``), and n = normalise(-s_x, 1, -s_z) (+Y up).

    Returns
    -------
    (count, 3) float64 unit normals.

    References
    ----------
    C. Cox and W. Munk, "Measurement of the Roughness of the Sea Surface from Photographs of
    the Sun's Glitter", JOSA 44(11), 1954, doi:10.1364/JOSA.44.000838.
    """
    s = float(rms_slope)
    if not (np.isfinite(s) and s >= 0):
        raise ArgumentError(f"RMS slope must be finite and >= 0, got {rms_slope}")
    count = int(count)
    if count < 1:
        raise ArgumentError("need at least one sample")
    slopes = np.random.default_rng(seed).normal(0.0, s / np.sqrt(2.0), size=(count, 2))
    n = np.stack([-slopes[:, 0], np.ones(count), -slopes[:, 1]], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def baked_fresnel_error(
    eye: ArrayLike, normals: ArrayLike, *, ior: float = WATER_IOR, up: ArrayLike = (0.0, 1.0, 0.0)
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reflectance error of a flat-plane fresnel bake fetched with a perturbed normal.

    For the direction e towards the eye and a shading normal n, the shader reflects
    r = 2 (e . n) n - e and fetches the bake at r, getting L(r) R(r . up); the true value is
    L(r) R(e . n). The radiance factor is the same, so the error is that of the reflectance.

    Parameters
    ----------
    eye : (N, 3) unit vectors towards the eye (e . up > 0)
    normals : (N, 3) unit shading normals
    ior : float
    up : 3-vector

    Returns
    -------
    absolute : (M,) float64
        R(r . up) - R(e . n) over the M usable pairs.
    relative : (M,) float64
        R(r . up) / R(e . n) - 1.
    usable : (N,) bool
        e . n > 0 (the normal faces the eye) and r . up > 0 (r is above the plane, where the
        bake holds the flat reflectance).
    """
    e = np.asarray(eye, dtype=np.float64)
    n = np.asarray(normals, dtype=np.float64)
    cos_true = np.einsum("ij,ij->i", e, n)
    cos_baked = (2.0 * cos_true[:, None] * n - e) @ _unit_axis(up)
    usable = (cos_true > 0) & (cos_baked > 0)
    true = fresnel_dielectric(cos_true[usable], ior)
    absolute = fresnel_dielectric(cos_baked[usable], ior) - true
    return absolute, absolute / true, usable


def normal_mapped_error(
    rms_slope: float,
    *,
    ior: float = WATER_IOR,
    samples: int = 1 << 20,
    seed: int = 0,
    elevations: ArrayLike | None = None,
) -> dict:
    """Error of the baked fresnel on normal-mapped water, for normals of a given RMS slope.

    The water is a flat plane (up = +Y) shaded with a normal map whose normals have RMS slope
    s (:func:`slope_normals`); every normal-map texel weighs the same (the surface is flat, so
    each covers the same area). For each direction e towards the eye the shader reflects about
    the shading normal and fetches the flat-plane bake there, getting the right radiance times
    the wrong reflectance R(r . up) instead of R(e . n) (:func:`baked_fresnel_error`). The
    errors compared are those of the reflectance factor, which do not depend on the
    environment::

        absolute: R(r . up) - R(e . n)     relative: R(r . up) / R(e . n) - 1

    Eye directions are spread evenly over the hemisphere (:func:`hemisphere_directions`), one
    normal each. Pairs whose normal faces away from the eye (near grazing) and pairs whose r
    points below the plane (the bake has no flat-plane value there: zero or the mirror, see
    :func:`bake_fresnel`) are counted and left out of the statistics.

    Parameters
    ----------
    rms_slope : float
        s (0.02 is glassy water, 0.2 to 0.3 wind-roughened; Cox and Munk measured
        s^2 = 0.003 + 0.00512 U for wind speed U in m/s).
    ior : float
    samples : int
        Number of eye directions (= normals).
    seed : int
        Seed of the slope draws.
    elevations : sequence of float, optional
        Bin edges in degrees of the eye's elevation above the plane; with them the result has
        per-bin statistics in ``by_elevation``.

    Returns
    -------
    dict
        ``rms_slope``; ``mean_abs``, ``p99_abs`` of |absolute error|; ``mean_rel``, ``p99_rel``
        of |relative error|; ``bias_rel``, the mean signed relative error; ``back_facing`` and
        ``below_horizon``, the fractions left out; with ``elevations``, ``by_elevation``: a
        list of dicts with ``low``, ``high`` and the four statistics.
    """
    up = np.array([0.0, 1.0, 0.0])
    e = hemisphere_directions(samples, up)
    n = slope_normals(samples, rms_slope, seed=seed)
    absolute, relative, usable = baked_fresnel_error(e, n, ior=ior, up=up)
    facing = np.einsum("ij,ij->i", e, n) > 0
    elevation = np.degrees(np.arcsin(e[usable, 1]))

    def summary(mask: np.ndarray | None = None) -> dict[str, float]:
        a = np.abs(absolute if mask is None else absolute[mask])
        rel = np.abs(relative if mask is None else relative[mask])
        if a.size == 0:
            return {"mean_abs": np.nan, "p99_abs": np.nan, "mean_rel": np.nan, "p99_rel": np.nan}
        return {
            "mean_abs": float(a.mean()),
            "p99_abs": float(np.percentile(a, 99)),
            "mean_rel": float(rel.mean()),
            "p99_rel": float(np.percentile(rel, 99)),
        }

    result: dict[str, object] = {"rms_slope": float(rms_slope), **summary()}
    result["bias_rel"] = float(relative.mean()) if relative.size else np.nan
    result["back_facing"] = float(np.mean(~facing))
    result["below_horizon"] = float(np.mean(facing & ~usable))
    if elevations is not None:
        edges = np.asarray(elevations, dtype=np.float64)
        result["by_elevation"] = [
            {"low": float(lo), "high": float(hi), **summary((elevation >= lo) & (elevation < hi))}
            for lo, hi in zip(edges[:-1], edges[1:], strict=True)
        ]
    return result
