"""Real spherical harmonics: the basis, projection, evaluation, zonal convolution (Funk-Hecke
kernels), irradiance matrices and blending between probes. The convention is in
:mod:`bakeshop.light.sh`."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import threads
from bakeshop.errors import ArgumentError
from bakeshop.light import _native

#: the highest order the module accepts (a guard against absurd allocations).
MAX_ORDER = 256

#: basis values per chunk in evaluation (bounds the temporary basis array to
#: 128 MB whatever the order).
_CHUNK_VALUES = 1 << 24


def _chunk(order: int) -> int:
    return max(1, _CHUNK_VALUES // (order + 1) ** 2)


def n_coefficients(order: int) -> int:
    """Number of coefficients of an expansion to ``order``: ``(order + 1)**2``."""
    return (_check_order(order) + 1) ** 2


def order_of(n_coeffs: int) -> int:
    """The order ``L`` of an expansion with ``n_coeffs`` coefficients (a perfect square)."""
    order = math.isqrt(int(n_coeffs)) - 1
    if order < 0 or (order + 1) ** 2 != n_coeffs:
        raise ArgumentError(f"{n_coeffs} is not a number of SH coefficients ((L+1)^2)")
    return order


def index(l: int, m: int) -> int:
    """The position of ``Y(l, m)`` in a coefficient array: ``l * (l + 1) + m``."""
    if l < 0 or abs(m) > l:
        raise ArgumentError(f"no spherical harmonic Y({l}, {m}): need l >= 0 and |m| <= l")
    return l * (l + 1) + m


def _check_order(order: float) -> int:
    if isinstance(order, bool) or not float(order).is_integer():
        raise ArgumentError(f"SH order must be an integer, got {order!r}")
    order = int(order)
    if not 0 <= order <= MAX_ORDER:
        raise ArgumentError(f"SH order must be in 0..{MAX_ORDER}, got {order}")
    return order


def basis(directions: ArrayLike, order: int) -> np.ndarray:
    """Evaluate every real SH basis function up to ``order`` at unit directions.

    Parameters
    ----------
    directions : (..., 3) array_like
        Unit vectors (x, y, z) in bakeshop's world frame. They are not renormalised.
    order : int
        Highest degree L (0..MAX_ORDER).

    Returns
    -------
    (..., (L + 1)**2) float64
        ``Y(l, m)(d)`` at index ``l * (l + 1) + m``.

    Notes
    -----
    The associated Legendre functions are computed in fully normalised form with the
    three-term recurrence in ``z`` (stable to high degree), and ``sin(theta)**m cos(m phi)``,
    ``sin(theta)**m sin(m phi)`` as the real and imaginary parts of ``(x + i y)**m``, so no
    trigonometric function and no division by ``sin(theta)`` is evaluated.
    """
    order = _check_order(order)
    d = np.asarray(directions, dtype=np.float64)
    if d.shape[-1:] != (3,):
        raise ArgumentError(f"directions must have shape (..., 3), got {d.shape}")
    flat = np.ascontiguousarray(d.reshape(-1, 3))
    out = np.empty((flat.shape[0], (order + 1) ** 2), dtype=np.float64)
    _native.basis_rows(flat, order, out)
    return out.reshape(d.shape[:-1] + (out.shape[-1],))


def project(
    values: ArrayLike, directions: ArrayLike, weights: ArrayLike, *, order: int = 2
) -> np.ndarray:
    """Project samples of a function on the sphere to real SH coefficients.

    ``c(l, m) = sum_i f(d_i) Y(l, m)(d_i) w_i``: a quadrature of the projection integral with
    the texels' solid angles as weights, so an environment in any layout projects the same.

    Parameters
    ----------
    values : (..., C) or (...) array_like
        Samples (radiance); NaN and Inf are refused. A layout's spatial shape ``...`` matches
        ``directions`` and ``weights``.
    directions : (..., 3) array_like
        Unit direction of each sample (``layout.directions(shape)[0]``).
    weights : (...) array_like
        Solid angle of each sample in steradians (``layout.solid_angles(shape)``; 0 for texels
        outside a disk layout's disk).
    order : int
        Highest degree L.

    Returns
    -------
    ((L + 1)**2, C) float64, or ((L + 1)**2,) for scalar samples.
    """
    order = _check_order(order)
    w = np.asarray(weights, dtype=np.float64)
    d = np.asarray(directions)
    f = np.asarray(values)
    scalar = f.shape == w.shape
    if scalar:
        f = f[..., None]
    if d.shape != w.shape + (3,) or f.shape[:-1] != w.shape:
        raise ArgumentError(
            f"values {np.shape(values)}, directions {d.shape} and weights {w.shape} "
            "do not describe the same texels"
        )
    d = np.ascontiguousarray(d.reshape(-1, 3), dtype=np.float64)
    w, f = w.reshape(-1), f.reshape(w.size, -1)
    if not np.isfinite(f).all():
        raise ArgumentError("the environment has NaN or infinite values; fix or clamp them first")
    if f.dtype not in (np.float32, np.float64):
        f = f.astype(np.float64)
    # parallel partial sums, added in order; order 2 has its nine polynomials written out
    # (~3x fewer operations than the recurrence, the same sums to rounding)
    chunks = min(4 * threads.count(), max(1, w.size // 16384))
    coeffs = np.empty(((order + 1) ** 2, f.shape[1]))
    if order == 2:
        _native.project_order2(f, d, w, chunks, coeffs)
    else:
        _native.project(f, d, w, order, chunks, coeffs)
    return coeffs[:, 0] if scalar else coeffs


def evaluate(coeffs: ArrayLike, directions: ArrayLike) -> np.ndarray:
    """Evaluate an SH expansion at directions.

    Parameters
    ----------
    coeffs : ((L + 1)**2, C) or ((L + 1)**2,) array_like
    directions : (..., 3) array_like
        Unit vectors.

    Returns
    -------
    (..., C) float64, or (...) for a 1-D ``coeffs``.
    """
    c = np.asarray(coeffs, dtype=np.float64)
    order = order_of(c.shape[0])
    d = np.asarray(directions, dtype=np.float64)
    if d.shape[-1:] != (3,):
        raise ArgumentError(f"directions must have shape (..., 3), got {d.shape}")
    flat = d.reshape(-1, 3)
    out = np.empty((flat.shape[0],) + c.shape[1:])
    chunk = _chunk(order)
    for start in range(0, flat.shape[0], chunk):
        sl = slice(start, start + chunk)
        out[sl] = basis(flat[sl], order) @ c
    return out.reshape(d.shape[:-1] + c.shape[1:])


def cosine_power_kernel(order: int, exponent: float = 1.0) -> np.ndarray:
    """Funk-Hecke factors of the clamped cosine power ``max(0, cos t)**a``.

    ``k_l = 2 pi integral_0^1 t**a P_l(t) dt``: convolving a function with the kernel
    multiplies its degree-l coefficients by ``k_l``. For ``a = 1`` these are Ramamoorthi and
    Hanrahan's ``A_l`` (pi, 2 pi / 3, pi / 4, 0, -pi / 24, ...), which turn radiance into
    irradiance. Computed with the exact recurrence
    ``I_l = (a - l + 2) / (a + l + 1) I_(l-2)``, ``I_0 = 1 / (a + 1)``, ``I_1 = 1 / (a + 2)``.

    Parameters
    ----------
    order : int
        Highest degree L.
    exponent : float
        The power ``a >= 0``.

    Returns
    -------
    (L + 1,) float64
    """
    order = _check_order(order)
    a = float(exponent)
    if not (math.isfinite(a) and a >= 0):
        raise ArgumentError(f"cosine exponent must be finite and >= 0, got {exponent!r}")
    integral = np.zeros(order + 1)
    integral[0] = 1 / (a + 1)
    if order >= 1:
        integral[1] = 1 / (a + 2)
    for l in range(2, order + 1):
        integral[l] = (a - l + 2) / (a + l + 1) * integral[l - 2]
    return 2 * math.pi * integral


def clamped_cosine(order: int) -> np.ndarray:
    """The irradiance kernel ``A_l`` (clamped cosine ``max(0, n.w)``) up to ``order``.

    ``E(n) = sum_lm A_l L_lm Y_lm(n)``; ``A_l`` falls off as ``l**-2.5`` for even l and is 0 for
    odd ``l > 1``. See :func:`cosine_power_kernel`.
    """
    return cosine_power_kernel(order, 1.0)


def phong_kernel(order: int, exponent: float) -> np.ndarray:
    """Funk-Hecke factors of the normalised Phong lobe ``(a + 1) / (2 pi) max(0, cos t)**a``.

    The lobe integrates to 1 over the sphere, so ``k_0 = 1``; convolution gives HDRShop's
    Phong-prefiltered environment (a = 1 is the diffuse convolution divided by pi).
    """
    return (exponent + 1) / (2 * math.pi) * cosine_power_kernel(order, exponent)


def convolve(coeffs: ArrayLike, kernel: ArrayLike) -> np.ndarray:
    """Convolve an SH expansion with a zonal kernel given by its per-degree factors.

    Parameters
    ----------
    coeffs : ((L + 1)**2, ...) array_like
    kernel : (K,) array_like with K >= L + 1
        Factor of each degree, e.g. :func:`clamped_cosine` (irradiance) or :func:`phong_kernel`.

    Returns
    -------
    ((L + 1)**2, ...) float64
    """
    c = np.asarray(coeffs, dtype=np.float64)
    order = order_of(c.shape[0])
    k = np.asarray(kernel, dtype=np.float64).reshape(-1)
    if k.size < order + 1:
        raise ArgumentError(f"kernel has {k.size} degrees; the coefficients need {order + 1}")
    per_coeff = np.repeat(k[: order + 1], 2 * np.arange(order + 1) + 1)
    return c * per_coeff.reshape((-1,) + (1,) * (c.ndim - 1))


def irradiance_coefficients(coeffs: ArrayLike) -> np.ndarray:
    """SH coefficients of the DIM, ``E / pi``, from the radiance coefficients ``coeffs``."""
    c = np.asarray(coeffs, dtype=np.float64)
    return convolve(c, clamped_cosine(order_of(c.shape[0])) / math.pi)


def blend(coeffs: ArrayLike, weights: ArrayLike) -> np.ndarray:
    """Blend the SH coefficients of several probes: ``sum_p w_p c_p / sum_p w_p``.

    Irradiance is linear in the environment, so blending coefficients is blending the probes'
    irradiance (and their radiance up to the same order), without the snapping that switching
    between cube maps gives when an object moves from one probe's zone to the next.

    Parameters
    ----------
    coeffs : (P, N, ...) array_like
        Coefficients of P probes, all of one order (N = (L + 1)**2).
    weights : (P,) or (Q, P) array_like
        Non-negative weights (normalised here); Q sets of weights give Q blends.

    Returns
    -------
    (N, ...) or (Q, N, ...) float64
    """
    c = np.asarray(coeffs, dtype=np.float64)
    w = np.asarray(weights, dtype=np.float64)
    if c.ndim < 2 or w.ndim not in (1, 2) or w.shape[-1] != c.shape[0]:
        raise ArgumentError(
            f"weights {w.shape} do not match {c.shape[0] if c.ndim else 0} probes' "
            f"coefficients {c.shape}"
        )
    order_of(c.shape[1])
    total = w.sum(axis=-1, keepdims=True)
    if not np.isfinite(w).all() or (w < 0).any() or (total <= 0).any():
        raise ArgumentError("blend weights must be finite, non-negative and not all zero")
    return np.tensordot(w / total, c, axes=(-1, 0))


def inverse_distance_weights(
    position: ArrayLike, probe_positions: ArrayLike, *, power: float = 2.0
) -> np.ndarray:
    """Weights of probes for a point: ``1 / distance**power``, normalised; exact at a probe.

    Parameters
    ----------
    position : (3,) or (Q, 3) array_like
        Points where irradiance is wanted.
    probe_positions : (P, 3) array_like
        Where each probe was captured.
    power : float
        Falloff exponent (> 0).

    Returns
    -------
    (P,) or (Q, P) float64, rows summing to 1 (for :func:`blend`).
    """
    q = np.asarray(position, dtype=np.float64)
    p = np.asarray(probe_positions, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3 or q.shape[-1:] != (3,) or q.ndim > 2 or len(p) == 0:
        raise ArgumentError("positions must be (3,) or (Q, 3) and probe positions (P, 3)")
    if not (power > 0):
        raise ArgumentError(f"power must be > 0, got {power!r}")
    dist = np.linalg.norm(q[..., None, :] - p, axis=-1)
    at_probe = dist == 0
    with np.errstate(divide="ignore"):
        w = np.where(at_probe.any(axis=-1, keepdims=True), at_probe, dist**-power)
    return w / w.sum(axis=-1, keepdims=True)


# -- export -----------------------------------------------------------------------------------

#: Ramamoorthi and Hanrahan's constants of the quadratic form (their equation 12).
RH_C1, RH_C2, RH_C3, RH_C4, RH_C5 = 0.429043, 0.511664, 0.743125, 0.886227, 0.247708


def irradiance_matrices(coeffs: ArrayLike) -> np.ndarray:
    """Ramamoorthi and Hanrahan's 4x4 matrices M with ``E(n) / pi = n^T M n``, n = (x, y, z, 1).

    Parameters
    ----------
    coeffs : (N >= 9, C) array_like
        Radiance SH coefficients (only degrees 0..2 are used).

    Returns
    -------
    (C, 4, 4) float64, symmetric
        One matrix per channel, already divided by pi so that ``n^T M n`` is the DIM value
        (the radiance an albedo-1 Lambertian surface reflects).

    References
    ----------
    Ramamoorthi and Hanrahan 2001, equation 12, doi:10.1145/383259.383317.
    """
    c = np.asarray(coeffs, dtype=np.float64)
    if c.ndim == 1:
        c = c[:, None]
    if c.ndim != 2 or c.shape[0] < 9:
        raise ArgumentError(f"need at least 9 SH coefficients (order 2), got shape {c.shape}")
    L00, L1m1, L10, L11, L2m2, L2m1, L20, L21, L22 = c[:9]
    c1, c2, c3, c4, c5 = RH_C1, RH_C2, RH_C3, RH_C4, RH_C5
    m = np.array(
        [
            [c1 * L22, c1 * L2m2, c1 * L21, c2 * L11],
            [c1 * L2m2, -c1 * L22, c1 * L2m1, c2 * L1m1],
            [c1 * L21, c1 * L2m1, c3 * L20, c2 * L10],
            [c2 * L11, c2 * L1m1, c2 * L10, c4 * L00 - c5 * L20],
        ]
    )
    return np.moveaxis(m, -1, 0) / math.pi
