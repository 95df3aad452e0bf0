"""Windows against the ringing of truncated SH expansions, the minimum of an expansion on the
sphere, and the least window that makes the DIM non-negative (:func:`windowed_irradiance`)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.light.sh.harmonics import (
    _check_order,
    _chunk,
    basis,
    clamped_cosine,
    convolve,
    evaluate,
    irradiance_coefficients,
    order_of,
)
from bakeshop.resources import Cost, require, seconds_of

#: a function non-negative) depends on the function: see :func:`minimal_window`.
WINDOWS = ("none", "hanning", "lanczos", "laplacian", "minimal")

#: Directions per unit of (L + 1)**2 in the search for a function's minimum on the sphere (a
#: Fibonacci set, then local refinement of the lowest candidates).
_MIN_SEARCH_POINTS = 1024
#: degree-part values per second per core of the minimal window's search (each read at every
#: lambda tried, with the local refinements): measured at 4.4-5e5 at orders 16 and 24 on a
#: loaded machine, docs/hostile-input.md.
PARTS_PER_SECOND = 5e5
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


def window_factors(
    order: int, kind: str = "hanning", *, width: float | None = None, strength: float | None = None
) -> Window:
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
    direction, so that any window's reconstruction is ``einsum("nlc,l->nc", g, factors)``.
    The basis goes by chunks of directions (:func:`search_cost`)."""
    order = order_of(coeffs.shape[0])
    parts = np.empty((dirs.shape[0], order + 1, coeffs.shape[1]))
    step = _chunk(order)
    for start in range(0, dirs.shape[0], step):
        y = basis(dirs[start : start + step], order)
        for l in range(order + 1):
            s = slice(l * l, (l + 1) ** 2)
            parts[start : start + step, l] = y[:, s] @ coeffs[s]
    return parts


def search_cost(order: int, channels: int) -> Cost:
    """What :func:`minimal_window` of an expansion to ``order`` of ``channels`` channels holds
    at its peak: the degree parts at its ``1024 (L + 1)^2`` directions (float64), the
    directions, and two chunks of the basis (:func:`_degree_parts`, then :func:`minimum`'s
    evaluation); its work is the degree parts' values (read once per lambda tried), at
    :data:`PARTS_PER_SECOND`."""
    n = _MIN_SEARCH_POINTS * (order + 1) ** 2
    chunk = 8 * _chunk(order) * (order + 1) ** 2
    memory = 8 * n * ((order + 1) * channels + 3 + channels) + 2 * chunk
    work = n * (order + 1) * channels
    what = f"the minimal window's search at SH order {order}"
    return Cost(memory, work, what, seconds_of(work, PARTS_PER_SECOND))


def _refine_minimum(coeffs: np.ndarray, start: np.ndarray, step: float) -> tuple[float, np.ndarray]:
    """Local minimum of the scalar expansion ``coeffs`` (N,) near the unit direction ``start``:
    Nelder-Mead over the tangent plane at ``start`` (d = normalise(start + u e1 + v e2)), which
    has no coordinate singularity near the start; ``step`` is the initial simplex's size."""
    from scipy.optimize import minimize

    order = order_of(coeffs.shape[0])
    e1 = np.cross(start, [1.0, 0.0, 0.0] if abs(start[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(start, e1)

    def direction(uv: np.ndarray) -> np.ndarray:
        d = start + uv[0] * e1 + uv[1] * e2
        return d / np.linalg.norm(d)

    def value(uv: np.ndarray) -> float:
        return float(basis(direction(uv), order) @ coeffs)

    simplex = np.array([[0.0, 0.0], [step, 0.0], [0.0, step]])
    options = {"xatol": 1e-9, "fatol": 1e-14, "maxiter": 400, "initial_simplex": simplex}
    result = minimize(value, [0.0, 0.0], method="Nelder-Mead", options=options)
    return float(result.fun), direction(result.x)


def minimum(coeffs: ArrayLike) -> tuple[float | np.ndarray, np.ndarray]:
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
        best: tuple[float, np.ndarray | None] = (math.inf, None)
        for i in np.argsort(f[:, ch])[:4]:
            found = _refine_minimum(c[:, ch], dirs[i], step)
            best = min(best, found, key=lambda r: r[0])
        values[ch], where[ch] = best
    return (float(values[0]), where[0]) if scalar else (values, where)


def negative_fraction(coeffs: ArrayLike, *, height: int = NEGATIVE_GRID) -> float:
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


def minimal_window(coeffs: ArrayLike, *, kernel: ArrayLike | None = None) -> Window:
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
    require(search_cost(order, f.shape[1]))
    dirs = _fibonacci_sphere(_MIN_SEARCH_POINTS * (order + 1) ** 2)
    parts = _degree_parts(f, dirs)

    def sampled_min(lam: float) -> float:
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
        low = np.asarray(values) < 0
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


def windowed_irradiance(
    coeffs: ArrayLike,
    *,
    window: str = "minimal",
    width: float | None = None,
    strength: float | None = None,
) -> IrradianceSH:
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
