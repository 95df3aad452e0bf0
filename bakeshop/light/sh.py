"""Real spherical harmonics: basis, projection, evaluation, zonal convolution, export, blending.

Convention (DESIGN.md): real, orthonormal on the unit sphere, graphics order. Coefficient
``k = l * (l + 1) + m`` holds ``Y(l, m)``, m = -l..l, so an expansion to order ``L`` has
``(L + 1)**2`` coefficients. The polar axis is +Z and the azimuth is measured from +X towards
+Y, without the Condon-Shortley phase, so ``Y(1, -1) = c*y``, ``Y(1, 0) = c*z``,
``Y(1, 1) = c*x`` with ``c = sqrt(3 / (4 pi))`` in bakeshop's world frame (+Y up, -Z forward).
These are the signs of Ramamoorthi and Hanrahan (2001) and of Sloan's "Stupid SH tricks" with
the phase dropped:

    Y(l, 0)  = N(l, 0) P(l, 0)(z)
    Y(l, m)  = sqrt(2) N(l, m) P(l, m)(z) cos(m phi)      m > 0
    Y(l, -m) = sqrt(2) N(l, m) P(l, m)(z) sin(m phi)      m > 0
    N(l, m)  = sqrt((2l + 1) / (4 pi) * (l - m)! / (l + m)!)

An environment's coefficient array is ``(n_coeffs, C)`` float64 (C colour channels); a
convolution kernel is a per-degree array of ``L + 1`` factors (the Funk-Hecke eigenvalues).

References
----------
R. Ramamoorthi and P. Hanrahan, "An efficient representation for irradiance environment maps",
SIGGRAPH 2001, doi:10.1145/383259.383317.
P.-P. Sloan, "Stupid spherical harmonics (SH) tricks", GDC 2008.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from bakeshop.errors import ArgumentError, FormatError, validate_choice

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


def _check_order(order) -> int:
    if isinstance(order, bool) or not float(order).is_integer():
        raise ArgumentError(f"SH order must be an integer, got {order!r}")
    order = int(order)
    if not 0 <= order <= MAX_ORDER:
        raise ArgumentError(f"SH order must be in 0..{MAX_ORDER}, got {order}")
    return order


def basis(directions, order: int) -> np.ndarray:
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
    _basis_rows(flat, order, out)
    return out.reshape(d.shape[:-1] + (out.shape[-1],))


@numba.njit(cache=True)
def _basis_into(x, y, z, order, out):  # pragma: no cover - compiled
    # Y(l, m) at one direction into out[l * (l + 1) + m]: the fully normalised associated
    # Legendre recurrence in z, and (cm, sm) = Re, Im of (x + iy)^m = sin^m (cos m phi, sin m phi).
    cm, sm = 1.0, 0.0
    pmm = 0.5 / math.sqrt(math.pi)  # normalised P(m, m) / sin^m
    root2 = math.sqrt(2.0)
    for m in range(order + 1):
        if m > 0:
            cm, sm = cm * x - sm * y, cm * y + sm * x
            pmm *= math.sqrt((2 * m + 1) / (2 * m))
        p_prev, p = 0.0, pmm  # P(l - 1, m), P(l, m) for l = m
        for l in range(m, order + 1):
            if l == m + 1:
                p_prev, p = p, math.sqrt(2 * m + 3) * z * p
            elif l > m + 1:
                a = math.sqrt((4 * l * l - 1) / (l * l - m * m))
                b = math.sqrt(((l - 1) ** 2 - m * m) / (4 * (l - 1) ** 2 - 1))
                p_prev, p = p, a * (z * p - b * p_prev)
            if m == 0:
                out[l * (l + 1)] = p
            else:
                out[l * (l + 1) + m] = root2 * p * cm
                out[l * (l + 1) - m] = root2 * p * sm


@numba.njit(parallel=True, cache=True)
def _basis_rows(dirs, order, out):  # pragma: no cover - compiled
    for i in numba.prange(dirs.shape[0]):
        _basis_into(dirs[i, 0], dirs[i, 1], dirs[i, 2], order, out[i])


@numba.njit(parallel=True, cache=True)
def _project(values, dirs, weights, order, chunks):  # pragma: no cover - compiled
    # sum_i values[i] * weights[i] * Y(d_i), in parallel chunks, without a basis array.
    n = (order + 1) ** 2
    channels = values.shape[1]
    partial = np.zeros((chunks, n, channels))
    step = (dirs.shape[0] + chunks - 1) // chunks
    for c in numba.prange(chunks):
        y = np.empty(n)
        for i in range(c * step, min(dirs.shape[0], (c + 1) * step)):
            w = weights[i]
            if w == 0.0:
                continue
            _basis_into(dirs[i, 0], dirs[i, 1], dirs[i, 2], order, y)
            for k in range(n):
                yw = y[k] * w
                for ch in range(channels):
                    partial[c, k, ch] += yw * values[i, ch]
    return partial.sum(axis=0)


def project(values, directions, weights, *, order: int = 2) -> np.ndarray:
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
    chunks = min(4 * numba.get_num_threads(), max(1, w.size // 16384))
    coeffs = _project(f, d, w, order, chunks)
    return coeffs[:, 0] if scalar else coeffs


def evaluate(coeffs, directions) -> np.ndarray:
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


def convolve(coeffs, kernel) -> np.ndarray:
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


def irradiance_coefficients(coeffs) -> np.ndarray:
    """SH coefficients of the DIM, ``E / pi``, from the radiance coefficients ``coeffs``."""
    c = np.asarray(coeffs, dtype=np.float64)
    return convolve(c, clamped_cosine(order_of(c.shape[0])) / math.pi)


def blend(coeffs, weights) -> np.ndarray:
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


def inverse_distance_weights(position, probe_positions, *, power: float = 2.0) -> np.ndarray:
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


def irradiance_matrices(coeffs) -> np.ndarray:
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


def to_document(coeffs, *, kind: str = "radiance", irradiance: IrradianceSH | None = None) -> dict:
    """SH coefficients as a JSON document (order, convention and ``[[r, g, b], ...]``), as
    ``sh.json`` holds them (:func:`bakeshop.io.write_json` writes it).

    ``kind`` says what the coefficients expand: ``"radiance"`` (the environment) or
    ``"irradiance"`` (the DIM, E / pi). ``irradiance`` (from :func:`windowed_irradiance`)
    adds the DIM's windowed coefficients as shown and exported, under ``"irradiance"``: the
    window, its per-degree factors, and the fraction of the sphere where the DIM is negative
    with and without it. ``"coefficients"`` stay the raw ones.
    """
    validate_choice(kind, ("radiance", "irradiance"), "SH coefficient kind")
    c = np.asarray(coeffs, dtype=np.float64)
    if c.ndim == 1:
        c = c[:, None]
    order = order_of(c.shape[0])
    doc = {
        "kind": kind,
        "order": order,
        "convention": (
            "real orthonormal SH, index l*(l+1)+m; Y(1,-1)~y, Y(1,0)~z, Y(1,1)~x in the "
            "frame +Y up, -Z forward, +X right; no Condon-Shortley phase"
        ),
        "coefficients": [[float(v) for v in row] for row in c],
    }
    if irradiance is not None:
        w = irradiance.window
        doc["irradiance"] = {
            "meaning": "E/pi (the DIM) = sum of coefficients * Y(l, m)(n); the radiance "
            "coefficients above, convolved with the clamped cosine / pi and the window",
            "window": w.name,
            "window_parameter": w.parameter,
            "window_factors": [float(v) for v in w.factors],
            "negative_fraction": irradiance.negative,
            "negative_fraction_unwindowed": irradiance.negative_raw,
            "coefficients": [[float(v) for v in row] for row in irradiance.coefficients],
        }
    return doc


def from_document(doc, path=None) -> np.ndarray:
    """The ``(N, C)`` float64 coefficients of a :func:`to_document` document (as
    :func:`bakeshop.io.read_json` reads it); ``path`` is named in errors."""
    try:
        c = np.asarray(doc["coefficients"], dtype=np.float64)
    except (ValueError, KeyError, TypeError) as e:
        raise FormatError(f"not a bakeshop SH JSON document ({e})", path) from None
    if c.ndim != 2 or not np.isfinite(c).all():
        raise FormatError("SH coefficients must be a finite list of [r, g, b] rows", path)
    order_of(c.shape[0])
    return c


def shader_snippet(coeffs, *, language: str = "glsl", window: str = "minimal") -> str:
    """A GLSL or HLSL function returning the DIM value ``E(n) / pi`` for a unit normal.

    Uses Ramamoorthi and Hanrahan's quadratic form (order 2, 9 coefficients per channel);
    the matrices are symmetric, so row- and column-major packing agree. The order-2
    coefficients are windowed first (``window``, see :func:`windowed_irradiance`; the default
    "minimal" windows just enough that the function is nowhere negative, so the shader's
    ``max(..., 0)`` never has to cut a dark ring opposite the sun); a comment names the window.
    """
    language = language.lower()
    if language not in ("glsl", "hlsl"):
        raise ArgumentError(f"unknown shader language {language!r}; choose glsl or hlsl")
    validate_choice(window, WINDOWS, "SH window")
    c = np.asarray(coeffs, dtype=np.float64)
    c = c[:, None] if c.ndim == 1 else c
    if c.ndim != 2 or c.shape[0] < 9:
        raise ArgumentError(f"need at least 9 SH coefficients (order 2), got shape {c.shape}")
    c = c[:9]
    w = minimal_window(c) if window == "minimal" else window_factors(2, window)
    mats = irradiance_matrices(convolve(c, w.factors))
    if mats.shape[0] == 1:
        mats = np.repeat(mats, 3, axis=0)
    if mats.shape[0] < 3:
        raise ArgumentError("the snippet needs 1 or 3 (or more) channels")
    glsl = language == "glsl"
    mat, vec, v4 = ("mat4", "vec3", "vec4") if glsl else ("float4x4", "float3", "float4")
    const = "const" if glsl else "static const"
    lines = [
        "// Diffuse irradiance / pi (the DIM value) from 9 SH coefficients per channel:",
        "// Ramamoorthi & Hanrahan 2001 (doi:10.1145/383259.383317), E/pi = n^T M n, n=(x,y,z,1).",
        "// World frame: +Y up, -Z forward, +X right. Generated by bakeshop.",
        f"// Against ringing: {w.describe()}, per-degree factors "
        + ", ".join(f"{v:.6g}" for v in w.factors)
        + ".",
    ]
    for name, m in zip("RGB", mats[:3], strict=True):
        vals = ", ".join(f"{v:.9g}" for v in m.reshape(-1))
        lines.append(f"{const} {mat} BAKESHOP_SH_M{name} = {mat}({vals});")
    quad = [
        f"dot(p, BAKESHOP_SH_M{c} * p)" if glsl else f"dot(p, mul(BAKESHOP_SH_M{c}, p))"
        for c in "RGB"
    ]
    lines += [
        f"{vec} bakeshop_irradiance({vec} n) {{",
        f"    {v4} p = {v4}(n, 1.0);",
        f"    return max({vec}({', '.join(quad)}), 0.0);",
        "}",
    ]
    return "\n".join(lines) + "\n"


# -- windowing ------------------------------------------------------------------------------------

#: Windows :func:`window_factors` knows; "minimal" (the least squared-Laplacian window that makes
#: a function non-negative) depends on the function: see :func:`minimal_window`.
WINDOWS = ("none", "hanning", "lanczos", "laplacian", "minimal")

#: Directions per unit of (L + 1)**2 in the search for a function's minimum on the sphere (a
#: Fibonacci set, then local refinement of the lowest candidates).
_MIN_SEARCH_POINTS = 1024
#: Relative precision of the minimal window's lambda (bisection in log lambda).
_LAMBDA_RTOL = 1e-4
#: Latlong height of the grid on which :func:`negative_fraction` integrates.
NEGATIVE_GRID = 256


class Window(NamedTuple):
    """A per-degree window applied to SH coefficients (what :func:`window_factors` and
    :func:`minimal_window` return)."""

    #: "none", "hanning", "lanczos", "laplacian" or "minimal".
    name: str
    #: (L + 1,) float64: the factor of each degree l (1 at l = 0).
    factors: np.ndarray
    #: the window's parameter: the width w (hanning, lanczos) or lambda (laplacian, minimal);
    #: None for "none".
    parameter: float | None

    def describe(self) -> str:
        """``'Hanning, width 3'``, ``'minimal (lambda 0.0123)'``, ...: for summaries."""
        if self.name == "none":
            return "no window"
        if self.name in ("hanning", "lanczos"):
            return f"{self.name.capitalize()} window, width {self.parameter:g}"
        if self.name == "minimal" and self.parameter == 0:
            return "minimal window (none needed)"
        label = "minimal window" if self.name == "minimal" else "squared-Laplacian window"
        return f"{label}, lambda {self.parameter:.4g}"


def window_factors(order: int, kind: str = "hanning", *, width=None, strength=None) -> Window:
    """Per-degree factors of a window that tames the ringing of a truncated SH expansion.

    Multiplying the degree-l coefficients by ``w_l`` (:func:`convolve` with the factors) is a
    zonal convolution with a smooth kernel: the reconstruction rings less, at the cost of some
    blur. With ``w`` the width (default ``L + 1``, so the first degree left out would get 0):

    - ``hanning``: ``w_l = (1 + cos(pi l / w)) / 2`` for l < w, else 0;
    - ``lanczos``: Lanczos' sigma factors ``w_l = sinc(l / w) = sin(pi l / w) / (pi l / w)``;
    - ``laplacian``: ``w_l = 1 / (1 + lambda l^2 (l + 1)^2)`` with lambda = ``strength``: the
      coefficients that minimise ``|f - g|^2 + lambda |Laplacian f|^2`` (Sloan 2008, "Stupid
      SH Tricks", section on windowing and appendix A7);
    - ``none``: every factor 1.

    No fixed window guarantees a non-negative result (Hanning of width 3 still leaves a delta
    light's irradiance negative opposite the light): :func:`minimal_window` finds the least
    ``laplacian`` window that does.

    Parameters
    ----------
    order : int
        Highest degree L.
    kind : {"none", "hanning", "lanczos", "laplacian"}
    width : float > 0, optional
        Window width of hanning and lanczos (default L + 1).
    strength : float >= 0
        Lambda of the laplacian window (required for it).

    Returns
    -------
    Window

    References
    ----------
    P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008.
    C. Lanczos, "Applied Analysis", 1956 (sigma factors).
    """
    order = _check_order(order)
    validate_choice(kind, WINDOWS[:4], "SH window")
    l = np.arange(order + 1, dtype=np.float64)
    if kind == "none":
        return Window("none", np.ones(order + 1), None)
    if kind == "laplacian":
        lam = float("nan") if strength is None else float(strength)
        if not (math.isfinite(lam) and lam >= 0):
            raise ArgumentError(f"the laplacian window needs a strength >= 0, got {strength!r}")
        return Window("laplacian", _laplacian_factors(order, lam), lam)
    w = float(order + 1 if width is None else width)
    if not (math.isfinite(w) and w > 0):
        raise ArgumentError(f"window width must be positive and finite, got {width!r}")
    if kind == "hanning":
        factors = np.where(l < w, 0.5 * (1 + np.cos(np.pi * np.minimum(l / w, 1))), 0.0)
    else:
        factors = np.sinc(l / w)
    return Window(kind, factors, w)


def _laplacian_factors(order: int, lam: float) -> np.ndarray:
    l = np.arange(order + 1, dtype=np.float64)
    return 1.0 / (1.0 + lam * (l * (l + 1)) ** 2)


def _fibonacci_sphere(n: int) -> np.ndarray:
    """``n`` directions spread evenly over the sphere (a Fibonacci spiral)."""
    k = np.arange(n) + 0.5
    z = 1 - 2 * k / n
    r = np.sqrt(np.maximum(0, 1 - z * z))
    phi = np.pi * (3 - math.sqrt(5)) * k
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


def _degree_parts(coeffs: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """``g[i, l, c] = sum_m coeffs[l, m, c] Y(l, m)(dirs[i])``: each degree's part at each
    direction, so that any window's reconstruction is ``einsum("nlc,l->nc", g, factors)``."""
    order = order_of(coeffs.shape[0])
    y = basis(dirs, order)
    parts = np.empty((dirs.shape[0], order + 1, coeffs.shape[1]))
    for l in range(order + 1):
        s = slice(l * l, (l + 1) ** 2)
        parts[:, l] = y[:, s] @ coeffs[s]
    return parts


def _refine_minimum(coeffs: np.ndarray, start: np.ndarray, step: float):
    """Local minimum of the scalar expansion ``coeffs`` (N,) near the unit direction ``start``:
    Nelder-Mead over the tangent plane at ``start`` (d = normalise(start + u e1 + v e2)), which
    has no coordinate singularity near the start; ``step`` is the initial simplex's size."""
    from scipy.optimize import minimize

    order = order_of(coeffs.shape[0])
    e1 = np.cross(start, [1.0, 0.0, 0.0] if abs(start[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(start, e1)

    def direction(uv):
        d = start + uv[0] * e1 + uv[1] * e2
        return d / np.linalg.norm(d)

    def value(uv):
        return float(basis(direction(uv), order) @ coeffs)

    simplex = np.array([[0.0, 0.0], [step, 0.0], [0.0, step]])
    options = {"xatol": 1e-9, "fatol": 1e-14, "maxiter": 400, "initial_simplex": simplex}
    result = minimize(value, [0.0, 0.0], method="Nelder-Mead", options=options)
    return float(result.fun), direction(result.x)


def minimum(coeffs) -> tuple[np.ndarray, np.ndarray]:
    """The minimum of an SH expansion over the sphere, per channel, and where it is.

    A dense Fibonacci set of ``1024 (L + 1)^2`` directions finds the basin of the minimum, and
    a local search (Nelder-Mead on the tangent plane) from the lowest few directions finds its
    bottom.

    Parameters
    ----------
    coeffs : ((L + 1)**2, C) or ((L + 1)**2,) array_like

    Returns
    -------
    values : (C,) float64, or a float for 1-D ``coeffs``
    directions : (C, 3) float64, or (3,)
    """
    c = np.asarray(coeffs, dtype=np.float64)
    scalar = c.ndim == 1
    c = c[:, None] if scalar else c
    order = order_of(c.shape[0])
    dirs = _fibonacci_sphere(_MIN_SEARCH_POINTS * (order + 1) ** 2)
    step = math.sqrt(4 * math.pi / dirs.shape[0])  # the set's spacing
    f = evaluate(c, dirs)
    values, where = np.empty(c.shape[1]), np.empty((c.shape[1], 3))
    for ch in range(c.shape[1]):
        best = (math.inf, None)
        for i in np.argsort(f[:, ch])[:4]:
            found = _refine_minimum(c[:, ch], dirs[i], step)
            best = min(best, found, key=lambda r: r[0])
        values[ch], where[ch] = best
    return (float(values[0]), where[0]) if scalar else (values, where)


def negative_fraction(coeffs, *, height: int = NEGATIVE_GRID) -> float:
    """Fraction of the sphere, by solid angle, where the expansion is negative in any channel.

    Integrated on a latlong grid of ``height`` rows with exact texel solid angles (the grid's
    resolution error is below 1 / height).
    """
    from bakeshop.sphere import layout

    lay = layout("latlong")
    shape = lay.shape(height)
    dirs, _ = lay.directions(shape)
    omega = lay.solid_angles(shape)
    c = np.asarray(coeffs, dtype=np.float64)
    values = evaluate(c if c.ndim == 2 else c[:, None], dirs)
    negative = (values < 0).any(axis=-1)
    return float(omega[negative].sum() / (4 * math.pi))


def minimal_window(coeffs, *, kernel=None) -> Window:
    """The least squared-Laplacian window that makes ``convolve(coeffs, kernel)`` non-negative.

    Sloan (2008) proposes to window just enough: among the windows
    ``w_l = 1 / (1 + lambda l^2 (l + 1)^2)`` (:func:`window_factors`, ``"laplacian"``), take the
    smallest lambda for which the windowed function has no negative value. Every factor falls
    as lambda grows and lambda -> infinity leaves the mean alone, so for a function of
    non-negative mean such a lambda exists; it is 0 (no window) when the function is already
    non-negative. One lambda serves every channel (the largest any channel needs), so the
    channels are blurred alike and hues stay put.

    The search: the function's degree parts at a dense set of directions, a bracket by
    doubling, bisection in log lambda to 1e-4, and a check of the result's continuous minimum
    (:func:`minimum`) that tightens lambda if the sampled set missed a negative dip.

    Parameters
    ----------
    coeffs : ((L + 1)**2, C) or ((L + 1)**2,) array_like
        Radiance coefficients (or any function's).
    kernel : (K >= L + 1,) array_like, optional
        A zonal kernel applied before the window, e.g. ``clamped_cosine(L) / pi`` for the DIM
        (the default: irradiance is what is shown). Pass ``np.ones(L + 1)`` to make the
        radiance itself non-negative.

    Returns
    -------
    Window
        ``name="minimal"``, its factors and lambda.

    References
    ----------
    P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008 (windowing; appendix A7).
    """
    c = np.asarray(coeffs, dtype=np.float64)
    c = c[:, None] if c.ndim == 1 else c
    order = order_of(c.shape[0])
    if kernel is None:
        kernel = clamped_cosine(order) / math.pi
    f = convolve(c, kernel)
    if not np.isfinite(f).all():
        raise ArgumentError("SH coefficients must be finite")
    if (f[0] < 0).any():
        raise ArgumentError("the function's mean is negative: no window can make it non-negative")
    dirs = _fibonacci_sphere(_MIN_SEARCH_POINTS * (order + 1) ** 2)
    parts = _degree_parts(f, dirs)

    def sampled_min(lam):
        return float(np.einsum("nlc,l->nc", parts, _laplacian_factors(order, lam)).min())

    lam = 0.0
    for _ in range(8):  # each round only tightens lambda where the continuous check finds a dip
        if sampled_min(lam) < 0:
            lo, hi = lam, max(4 * lam, 1e-4)
            while sampled_min(hi) < 0:
                lo, hi = hi, 4 * hi
                if hi > 1e12:
                    raise ArgumentError("no window makes this function non-negative")
            while hi - lo > _LAMBDA_RTOL * hi:
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if sampled_min(mid) >= 0 else (mid, hi)
            lam = hi
        values, where = minimum(convolve(f, _laplacian_factors(order, lam)))
        low = values < 0
        if not low.any():
            return Window("minimal", _laplacian_factors(order, lam), lam)
        # the continuous minimum lies between samples: add it to the set and search again
        dirs = np.concatenate([dirs, where[low]])
        parts = _degree_parts(f, dirs)
    return Window("minimal", _laplacian_factors(order, lam), lam)


class IrradianceSH(NamedTuple):
    """What :func:`windowed_irradiance` returns: the DIM's SH coefficients as shown and
    exported, with what the window did."""

    #: ((L + 1)**2, C) float64: windowed coefficients of E / pi.
    coefficients: np.ndarray
    #: the window applied (to the radiance coefficients, degree by degree).
    window: Window
    #: fraction of the sphere (solid angle) where the windowed DIM is negative in any channel.
    negative: float
    #: the same for the unwindowed DIM.
    negative_raw: float

    def describe(self) -> str:
        """One line: the window and the negative fractions before and after."""
        return (
            f"{self.window.describe()}; negative over {100 * self.negative:.2f}% of the sphere "
            f"(unwindowed {100 * self.negative_raw:.2f}%)"
        )


def windowed_irradiance(coeffs, *, window: str = "minimal", width=None, strength=None):
    """The DIM's SH coefficients (``E / pi``) with a window against ringing.

    Parameters
    ----------
    coeffs : ((L + 1)**2, C) array_like
        Radiance coefficients (kept as they are: the window is applied to a copy).
    window : {"minimal", "hanning", "lanczos", "laplacian", "none"}
        "minimal" (the default) windows just enough to make the DIM non-negative everywhere
        (:func:`minimal_window`); it leaves a DIM that is already non-negative untouched. The
        others are :func:`window_factors`' fixed windows.
    width, strength : float, optional
        The window's parameter (see :func:`window_factors`).

    Returns
    -------
    IrradianceSH
    """
    validate_choice(window, WINDOWS, "SH window")
    c = np.asarray(coeffs, dtype=np.float64)
    c = c[:, None] if c.ndim == 1 else c
    order = order_of(c.shape[0])
    if window == "minimal":
        w = minimal_window(c)
    else:
        w = window_factors(order, window, width=width, strength=strength)
    raw = irradiance_coefficients(c)
    windowed = convolve(raw, w.factors)
    return IrradianceSH(windowed, w, negative_fraction(windowed), negative_fraction(raw))
