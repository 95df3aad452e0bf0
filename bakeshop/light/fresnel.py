"""Fresnel reflectance of a dielectric and the fresnel bake of an environment for flat water.

A flat reflector (a calm water plane) under an infinitely distant environment sees each
direction d of the environment under exactly one angle of incidence: the mirror reflection that
fetches d has cos(theta_i) = d . up. So the reflectance can be multiplied into the environment
once (:func:`bake_fresnel`) and the shader does a plain lookup; after exposure the baked map fits
in 8 bits because fresnel dims the bright zenith. :mod:`bakeshop.light.fresnel_report` measures
how well that holds.

References
----------
M. Born and E. Wolf, *Principles of Optics*, 7th ed., section 1.5.2 (the Fresnel equations).
C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer Graphics Forum
13(3), 1994, doi:10.1111/1467-8659.1330233.
"""

from __future__ import annotations

import numpy as np

from bakeshop.errors import ArgumentError

#: Index of refraction of water at visible wavelengths (about 20 C, 589 nm).
WATER_IOR = 1.333

#: What a bake writes for directions below the reflecting plane.
BELOW_MODES = ("zero", "mirror")


def _check_ior(ior: float) -> float:
    ior = float(ior)
    if not (np.isfinite(ior) and ior > 0):
        raise ArgumentError(f"index of refraction must be a positive finite number, got {ior}")
    return ior


def _cosines(cos_i) -> np.ndarray:
    a = np.asarray(cos_i)
    if a.dtype not in (np.float32, np.float64):
        a = a.astype(np.float64)
    return np.clip(a, 0, 1)  # NaN stays NaN


def fresnel_dielectric(cos_i, ior: float = WATER_IOR) -> np.ndarray:
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
    out_dtype = c.dtype
    c = c.astype(np.float64)
    g2 = n * n - 1.0 + c * c
    with np.errstate(invalid="ignore", divide="ignore"):
        g = np.sqrt(np.maximum(g2, 0.0))
        a = (g - c) / (g + c)
        b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
        r = 0.5 * a * a * (1.0 + b * b)
    r = np.where(g2 <= 0.0, 1.0, r)  # total internal reflection (only possible for n < 1)
    return r.astype(out_dtype, copy=False)


def fresnel_schlick(cos_i, ior: float = WATER_IOR) -> np.ndarray:
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
