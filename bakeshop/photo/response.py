"""Camera response curves: which linear exposure each pixel code stands for.

A camera maps the light it collected in a frame, ``X = E t`` (scene radiance times exposure),
through its response ``Z = f(X)`` to codes ``Z``; merging needs the inverse, written here as the
per-channel table :attr:`CameraResponse.linear` (``X`` at each of ``K`` code knots). Three ways
to get it:

- :func:`known_response`: a curve you know: ``srgb`` (the IEC 61966-2-1 EOTF, right for most
  camera JPEGs to within their tone curve), ``gamma`` (``X = Z**gamma``) or ``linear``
  (raw-developed, linear TIFFs);
- :func:`recover_response` with ``method="debevec"``: Debevec and Malik's least squares on
  ``g = ln f^-1``, a smoothness term on ``g''``, hat weights zero at the clipped ends (Debevec &
  Malik 1997, doi:10.1145/258734.258884), solved exactly through the Schur complement of the
  per-pixel unknowns (a ``K x K`` system whatever the sample count);
- ``method="robertson"``: Robertson, Borman and Stevenson's alternating maximum-likelihood
  estimate (Robertson et al. 2003, doi:10.1117/1.1557695) on the same samples.

Samples are chosen by :func:`select_samples`: a fixed number of candidates spread over a
jittered grid of the frame (so the choice does not change with the image size), kept where the
picture is locally flat, then stratified by value so that every part of the code range is
represented (not a few dozen random pixels, whose curve wanders with the draw).

Gauge: ``g`` is known up to a constant per channel. Each channel is shifted so that its mean
over the middle half of the codes equals the sRGB curve's mean there: the channels agree on a
neutral grey, and a recovered curve has the scale of the sRGB one (code 118 of 255 is about
0.18).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, FormatError, validate_choice

__all__ = [
    "CameraResponse",
    "KNOWN_CURVES",
    "RESPONSE_METHODS",
    "known_response",
    "recover_response",
    "select_samples",
]

KnownCurve = Literal["srgb", "gamma", "linear"]
ResponseMethod = Literal["debevec", "robertson"]
KNOWN_CURVES: tuple[KnownCurve, ...] = ("srgb", "gamma", "linear")
RESPONSE_METHODS: tuple[ResponseMethod, ...] = ("debevec", "robertson")

#: knots of a recovered curve for 16-bit input (8-bit input uses its 256 codes); a 16-bit
#: sample reads the curve between knots by linear interpolation.
KNOTS_16 = 256
#: default weight of Debevec's smoothness term, relative to the data term (scale-free: see
#: :func:`recover_response`).
SMOOTHNESS = 50.0
#: sample pixels per channel selected for recovery.
SAMPLES = 1500
#: most sample pixels per channel.
MAX_SAMPLES = 100000
#: candidates examined (a jittered grid over the frame).
CANDIDATES = 1 << 15
#: version of the saved JSON document.
FORMAT_VERSION = 1


@dataclass(frozen=True)
class CameraResponse:
    """A camera's inverse response, per channel.

    Attributes
    ----------
    linear : (K, C) float64
        Relative linear exposure ``X`` at code knots ``z_k = k / (K - 1)`` of full scale,
        non-decreasing in ``k``, positive except possibly at ``k = 0``.
    method : str
        ``srgb``, ``gamma``, ``linear``, ``debevec``, ``robertson`` or ``file``.
    fit_error_stops : (C,) float64
        RMS residual of the recovery's data term, in stops (log2 units); 0 for known curves.
    samples : int
        Sample pixels used per channel (0 for known curves).
    gamma : float or None
        The exponent of a ``gamma`` curve (known curves are evaluated from their formula at
        every code, not from the table).
    """

    linear: np.ndarray
    method: str
    fit_error_stops: np.ndarray = field(default_factory=lambda: np.zeros(0))
    samples: int = 0
    gamma: float | None = None

    def __post_init__(self) -> None:
        lin = np.asarray(self.linear, dtype=np.float64)
        if lin.ndim == 1:
            lin = lin[:, None]
        if lin.ndim != 2 or lin.shape[0] < 2 or lin.shape[1] not in (1, 3):
            raise ArgumentError(f"a response is a (K, 1) or (K, 3) table, not {lin.shape}")
        if not np.isfinite(lin).all() or (lin < 0).any() or (np.diff(lin, axis=0) < 0).any():
            raise ArgumentError("a response must be finite, non-negative and non-decreasing")
        if (lin[1:] <= 0).any():
            raise ArgumentError("a response must be positive above its lowest code")
        object.__setattr__(self, "linear", lin)
        fit = np.asarray(self.fit_error_stops, dtype=np.float64).reshape(-1)
        object.__setattr__(self, "fit_error_stops", fit if fit.size else np.zeros(lin.shape[1]))

    @property
    def channels(self) -> int:
        """Number of colour channels of the curve."""
        return self.linear.shape[1]

    def table(self, bits: int, channels: int) -> np.ndarray:
        """Linear exposure of every code of a ``bits``-bit image: ``(2**bits, channels)``
        float64. Between knots, ``ln X`` is interpolated linearly in ``ln Z`` (a power law,
        the toe of most curves, is then exact), and ``X`` linearly below the first knot."""
        codes = np.arange(1 << bits) / ((1 << bits) - 1)
        if self.method in KNOWN_CURVES:
            return np.repeat(_known(self.method, codes, self.gamma)[:, None], channels, axis=1)
        knots = np.linspace(0.0, 1.0, self.linear.shape[0])
        out = np.empty((codes.size, channels))
        above = codes >= knots[1]
        for c in range(channels):
            lin = self.linear[:, min(c, self.channels - 1)]
            out[above, c] = np.exp(
                np.interp(np.log(codes[above]), np.log(knots[1:]), np.log(lin[1:]))
            )
            out[~above, c] = np.interp(codes[~above], knots[:2], lin[:2])
        return out

    def to_dict(self) -> dict:
        """The saved document (``bakeshop merge --save-response``): plain lists and numbers;
        a known curve is saved by name."""
        if self.method in KNOWN_CURVES:
            doc: dict[str, object] = {
                "bakeshop_camera_response": FORMAT_VERSION,
                "method": self.method,
            }
            if self.gamma is not None:
                doc["gamma"] = float(self.gamma)
            doc["channels"] = int(self.channels)
            return doc
        return {
            "bakeshop_camera_response": FORMAT_VERSION,
            "method": self.method,
            "knots": int(self.linear.shape[0]),
            "channels": int(self.channels),
            "linear": [[float(v) for v in row] for row in self.linear],
            "fit_error_stops": [float(v) for v in self.fit_error_stops],
            "samples": int(self.samples),
        }

    @classmethod
    def from_dict(cls, doc: dict, path: str | os.PathLike | None = None) -> CameraResponse:
        """Read what :meth:`to_dict` wrote; :class:`FormatError` naming what is wrong."""
        if doc.get("bakeshop_camera_response") != FORMAT_VERSION:
            raise FormatError("not a bakeshop camera response (version 1)", path)
        if doc.get("method") in KNOWN_CURVES:
            try:
                return known_response(
                    doc["method"], gamma=float(doc.get("gamma", 2.2)),
                    channels=int(doc.get("channels", 3)),
                )  # fmt: skip
            except (ArgumentError, TypeError, ValueError, OverflowError) as e:
                raise FormatError(f"damaged camera response: {e}", path) from None
        try:  # JSON holds integers of any size and Infinity: float() and int() overflow
            linear = np.asarray(doc["linear"], dtype=np.float64)
            fit = np.asarray(doc.get("fit_error_stops", []), dtype=np.float64)
            samples = int(doc.get("samples", 0))
        except (KeyError, TypeError, ValueError, OverflowError) as e:
            raise FormatError(f"damaged camera response: {e}", path) from None
        if not (np.isfinite(fit).all() and (fit >= 0).all() and 0 <= samples <= MAX_SAMPLES):
            raise FormatError(
                f"damaged camera response: its fit errors must be finite and non-negative and "
                f"its sample count within 0-{MAX_SAMPLES}",
                path,
            )
        try:
            return cls(linear, "file", fit, samples)
        except ArgumentError as e:
            raise FormatError(e.reason, path) from None


def known_response(curve: KnownCurve, *, gamma: float = 2.2, channels: int = 3) -> CameraResponse:
    """A response from a known transfer curve.

    Parameters
    ----------
    curve : {"srgb", "gamma", "linear"}
        ``srgb``: ``X = Z / 12.92`` for ``Z <= 0.04045``, else ``((Z + 0.055) / 1.055)**2.4``
        (IEC 61966-2-1); ``gamma``: ``X = Z**gamma``; ``linear``: ``X = Z``, with ``Z`` the code
        as a fraction of full scale.
    gamma : float
        Exponent of ``gamma`` (0.2-5).
    channels : {1, 3}
    """
    validate_choice(curve, KNOWN_CURVES, "response curve")
    if not (math.isfinite(gamma) and 0.2 <= gamma <= 5):
        raise ArgumentError(f"gamma must be within 0.2-5, not {gamma!r}")
    if channels not in (1, 3):
        raise ArgumentError(f"a response has 1 or 3 channels, not {channels}")
    g = gamma if curve == "gamma" else None
    z = np.linspace(0.0, 1.0, 1 << 12)
    return CameraResponse(np.repeat(_known(curve, z, g)[:, None], channels, axis=1), curve, gamma=g)


def _known(curve: str, z: np.ndarray, gamma: float | None) -> np.ndarray:
    if curve == "srgb":
        return np.where(z <= 0.04045, z / 12.92, ((z + 0.055) / 1.055) ** 2.4)
    if curve == "gamma":
        return z**gamma
    return z.copy()


# --- samples -------------------------------------------------------------------------------------


def _clipped_any(values: np.ndarray, low: int, high: int) -> np.ndarray | np.bool_:
    """(..., C) codes -> (...) bool: some channel at or beyond a clipped end."""
    return ((values <= low) | (values >= high)).any(axis=-1)


def select_samples(
    codes: np.ndarray,
    *,
    count: int = SAMPLES,
    shifts: ArrayLike | None = None,
    seed: int = 0,
) -> np.ndarray:
    """Pixel positions for response recovery, stable across image sizes.

    ``CANDIDATES`` positions are drawn on a jittered grid over the frame; those whose 3x3
    neighbourhood varies by more than 2 % of full scale in the middle frame are dropped (edges
    blur differently in each frame and misalign); each channel's key, the sum of its codes over
    the frames (monotonic in the scene's radiance), is split into ``count`` equal bins and the
    flattest candidate of each bin is kept. Up to ``count`` positions per channel, merged.

    Parameters
    ----------
    codes : (P, H, W, C) uint8 or uint16
        The stack's codes, frames in order of exposure.
    count : int
        Samples per channel (16-100000).
    shifts : (P, 2) float, optional
        Each frame's offset ``(dy, dx)`` from :func:`bakeshop.photo.align_stack`: frame ``j``
        is read at ``(y + dy, x + dx)`` (rounded).
    seed : int

    Returns
    -------
    (N, 2) int64
        ``(row, column)`` positions in the first frame's grid.
    """
    codes = np.asarray(codes)
    if not 16 <= count <= MAX_SAMPLES:
        raise ArgumentError(f"sample count must be within 16-{MAX_SAMPLES}, not {count}")
    p, h, w, channels = codes.shape
    offsets = _integer_shifts(shifts, p)
    margin_y = int(np.abs(offsets[:, 0]).max()) + 1
    margin_x = int(np.abs(offsets[:, 1]).max()) + 1
    if h <= 2 * margin_y + 2 or w <= 2 * margin_x + 2:
        raise ArgumentError(f"the frames ({w}x{h}) are too small to sample")
    rng = np.random.default_rng(seed)
    side = max(1, int(math.sqrt(CANDIDATES * h / w)))
    cols = max(1, CANDIDATES // side)
    gy, gx = np.meshgrid(np.arange(side), np.arange(cols), indexing="ij")
    lo_y, span_y = margin_y, h - 2 * margin_y
    lo_x, span_x = margin_x, w - 2 * margin_x
    ys = lo_y + ((gy + rng.random(gy.shape)) * span_y / side).astype(np.int64).ravel()
    xs = lo_x + ((gx + rng.random(gx.shape)) * span_x / cols).astype(np.int64).ravel()
    ys = np.clip(ys, lo_y, lo_y + span_y - 1)
    xs = np.clip(xs, lo_x, lo_x + span_x - 1)
    top = float(np.iinfo(codes.dtype).max)
    mid = codes[p // 2]
    spread = np.zeros(ys.size)
    centre = mid[ys, xs].astype(np.float64)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy or dx:
                other = mid[ys + dy, xs + dx].astype(np.float64)
                spread = np.maximum(spread, np.abs(other - centre).max(axis=-1))
    flat = spread <= 0.02 * top
    if np.count_nonzero(flat) < 4 * count:  # a busy picture: the flattest quarter
        flat = spread <= np.quantile(spread, 0.25)
    ys, xs, spread = ys[flat], xs[flat], spread[flat]
    key = np.zeros((ys.size, channels))
    for j in range(p):
        key += codes[j, ys + offsets[j, 0], xs + offsets[j, 1]]
    chosen = set()
    for c in range(channels):
        k = key[:, c]
        lo, hi = k.min(), k.max()
        if hi <= lo:
            continue
        bins = np.minimum(((k - lo) / (hi - lo) * count).astype(np.int64), count - 1)
        order = np.lexsort((spread, bins))  # by bin, flattest first
        first = np.ones(order.size, bool)
        first[1:] = bins[order][1:] != bins[order][:-1]
        chosen.update(order[first].tolist())
    index = np.fromiter(sorted(chosen), np.int64)
    return np.stack([ys[index], xs[index]], axis=1)


def _integer_shifts(shifts: ArrayLike | None, p: int) -> np.ndarray:
    if shifts is None:
        return np.zeros((p, 2), np.int64)
    s = np.asarray(shifts, dtype=np.float64)
    if s.shape != (p, 2) or not np.isfinite(s).all():
        raise ArgumentError(f"shifts must be a finite ({p}, 2) array, got {s.shape}")
    return np.rint(s).astype(np.int64)


def _gather(codes: np.ndarray, positions: np.ndarray, shifts: ArrayLike | None) -> np.ndarray:
    """Codes of the sample positions in each frame: (N, P, C)."""
    p = codes.shape[0]
    offsets = _integer_shifts(shifts, p)
    ys, xs = positions[:, 0], positions[:, 1]
    return np.stack([codes[j, ys + offsets[j, 0], xs + offsets[j, 1]] for j in range(p)], axis=1)


# --- recovery ------------------------------------------------------------------------------------


def _hat(knots: int) -> np.ndarray:
    """Debevec's hat over knot indices: 0 at both ends, peak at the middle."""
    z = np.arange(knots, dtype=np.float64)
    return np.minimum(z, knots - 1 - z)


def _anchor(g: np.ndarray) -> np.ndarray:
    """Shift every channel's ln X so that its mean over the middle half of the codes equals the
    sRGB curve's mean there (channels agree on a neutral grey; the scale is sRGB's)."""
    z = np.linspace(0.0, 1.0, g.shape[0])
    middle = (z >= 0.25) & (z <= 0.75)
    target = np.log(((z[middle] + 0.055) / 1.055) ** 2.4).mean()
    return g - g[middle].mean(axis=0) + target


def _isotonic(y: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Weighted least-squares non-decreasing fit (pool adjacent violators)."""
    values, weights, sizes = [], [], []
    for yi, wi in zip(y, np.maximum(w, 1e-12), strict=True):
        values.append(yi)
        weights.append(wi)
        sizes.append(1)
        while len(values) > 1 and values[-2] > values[-1]:
            v2, w2, s2 = values.pop(), weights.pop(), sizes.pop()
            v1, w1, s1 = values.pop(), weights.pop(), sizes.pop()
            values.append((v1 * w1 + v2 * w2) / (w1 + w2))
            weights.append(w1 + w2)
            sizes.append(s1 + s2)
    return np.repeat(values, sizes)


def _strictly_increasing(g: np.ndarray) -> np.ndarray:
    """Non-decreasing ln X made strictly increasing by the least lift (1e-6 per knot)."""
    ramp = 1e-6 * np.arange(g.size)
    return np.maximum.accumulate(g - ramp) + ramp


def _debevec_channel(
    zf: np.ndarray, lnt: np.ndarray, valid: np.ndarray, knots: int, smoothness: float
) -> tuple[np.ndarray, float]:
    """Solve Debevec-Malik for one channel; returns (g (knots,), fit RMS in ln units).

    ``zf`` (N, P) are the samples' positions in knot units: a sample between two knots reads
    the curve there by linear interpolation (exact for 8-bit codes on 256 knots)."""
    from scipy import sparse

    n, p = zf.shape
    hat = _hat(knots)
    k0 = np.minimum(np.floor(zf).astype(np.int64), knots - 2)
    a = zf - k0
    w = np.where(valid, (1 - a) * hat[k0] + a * hat[k0 + 1], 0.0)
    w2 = w * w
    keep = w2.sum(axis=1) > 0
    k0, a, w2 = k0[keep], a[keep], w2[keep]
    n = k0.shape[0]
    if n < 2:
        raise ArgumentError("too few unclipped samples to recover a response")
    # normal equations of sum w^2 (c . g - lnE - lnt)^2 + lam^2 sum (hat(z) g''(z))^2, with
    # c = (1 - a) at knot k0 and a at k0 + 1
    c0, c1 = (1 - a).ravel(), a.ravel()
    kk0, kk1 = k0.ravel(), k0.ravel() + 1
    data = w2.ravel()
    lnt_obs = np.tile(lnt, n)
    hgg = np.zeros((knots, knots))
    np.add.at(hgg, (kk0, kk0), data * c0 * c0)
    np.add.at(hgg, (kk1, kk1), data * c1 * c1)
    np.add.at(hgg, (kk0, kk1), data * c0 * c1)
    np.add.at(hgg, (kk1, kk0), data * c0 * c1)
    bg = np.bincount(kk0, data * c0 * lnt_obs, minlength=knots) + np.bincount(
        kk1, data * c1 * lnt_obs, minlength=knots
    )
    d = w2.sum(axis=1)
    be = -(w2 * lnt).sum(axis=1)
    cols = np.repeat(np.arange(n), p)
    hge = sparse.csr_matrix(
        (
            -np.concatenate([data * c0, data * c1]),
            (np.concatenate([kk0, kk1]), np.concatenate([cols, cols])),
        ),
        shape=(knots, n),
    )
    schur = hgg - (hge @ sparse.diags(1.0 / d) @ hge.T).toarray()
    rhs = bg - hge @ (be / d)
    lam2 = _penalty(smoothness, data.sum(), knots)
    weighted = _curvature_rows(knots)
    schur += lam2 * weighted.T @ weighted
    mid = (knots - 1) // 2
    free = np.arange(knots) != mid
    g = np.zeros(knots)
    g[free] = np.linalg.solve(schur[np.ix_(free, free)], rhs[free])
    at = (1 - a) * g[k0] + a * g[k0 + 1]
    lne = (w2 * (at - lnt)).sum(axis=1) / d
    residual = at - lne[:, None] - lnt
    rms = math.sqrt(float((w2 * residual**2).sum() / data.sum()))
    weight_of_knot = np.diag(hgg) + 1e-9
    return _strictly_increasing(_isotonic(g, weight_of_knot)), rms


CURVATURE = "linear"


def _curvature_rows(knots: int) -> np.ndarray:
    """Rows of the weighted curvature penalty on ``g``: ``(K - 2, K)``.

    The curvature of ``g = ln X`` is taken against ``ln z`` below the middle code (a power law,
    the toe of nearly every camera curve, has none there, where its curvature against ``z``
    grows as ``1/z^2`` and a penalty on it bends the toe away from the data), scaled to match
    ``g''(z)`` at the middle, and against ``z`` above it, weighted by Debevec's hat.
    """
    hat = _hat(knots)
    mid = (knots - 1) / 2
    rows = np.zeros((knots - 2, knots))
    for r, k in enumerate(range(1, knots - 1)):
        if CURVATURE == "loglog" and k < mid:
            u0, u1, u2 = np.log([max(k - 1, 0.5), k, k + 1])
            h1, h2 = u1 - u0, u2 - u1
            coef = 2 / (h1 + h2) * np.array([1 / h1, -(1 / h1 + 1 / h2), 1 / h2])
            rows[r, k - 1 : k + 2] = coef / mid**2 * hat[int(round(mid))]
        else:
            rows[r, k - 1 : k + 2] = np.array([1.0, -2.0, 1.0]) * hat[k]
    return rows


def _penalty(smoothness: float, total: float, knots: int) -> float:
    """``lam^2`` of the ``g''`` penalty: ``smoothness * total / K / max(hat)^2`` at 256 knots,
    scaled so that the penalty on the curve as a function of the code's fraction of full scale
    (not of the knot index) is the same for any number of knots."""
    top = (knots - 1) / 2
    return smoothness * total / knots / top**2 * (127.5 / top) ** 2 * ((knots - 1) / 255) ** 4


def _smooth(g: np.ndarray, counts: np.ndarray, smoothness: float) -> np.ndarray:
    """Penalised fit: minimise ``sum n_z (h_z - g_z)^2 + lam^2 sum (hat(z) h''_z)^2`` with the
    same scale-free ``lam`` as Debevec's (``n_z``: observations of code ``z``); the normal
    equations are pentadiagonal, solved banded."""
    from scipy.linalg import solveh_banded

    knots = g.size
    hat = _hat(knots)
    lam2 = _penalty(smoothness, counts.sum(), knots)
    h2 = lam2 * hat[1:-1] ** 2  # weight of the second difference centred on knot k + 1
    bands = np.zeros((3, knots))  # upper form: row 2 diagonal, 1 first, 0 second superdiagonal
    bands[2] = counts + 1e-9
    for offset, coef in ((0, 1.0), (1, -2.0), (2, 1.0)):
        bands[2, offset : offset + knots - 2] += h2 * coef * coef
    bands[1, 1 : knots - 1] += h2 * -2.0  # (k, k + 1)
    bands[1, 2:knots] += h2 * -2.0  # (k + 1, k + 2)
    bands[0, 2:knots] += h2  # (k, k + 2)
    return solveh_banded(bands, (counts + 1e-9) * g)


def _robertson_channel(
    z: np.ndarray,
    exposure: np.ndarray,
    valid: np.ndarray,
    knots: int,
    smoothness: float,
    iterations: int = 60,
    tol: float = 1e-5,
) -> tuple[np.ndarray, float]:
    """Robertson's alternating estimate for one channel; returns (g, fit RMS in ln units)."""
    n, p = z.shape
    hat = _hat(knots)
    mid = (knots - 1) // 2
    weight = np.exp(-4.0 * (np.arange(knots) - mid) ** 2 / mid**2) * (hat > 0)
    w = np.where(valid, weight[z], 0.0)
    keep = w.sum(axis=1) > 0
    z, w = z[keep], w[keep]
    t = np.broadcast_to(exposure, z.shape)
    # start from the sRGB curve: from a linear start, brackets two stops apart converge to a
    # curve rippled by 10 % (the iteration has such fixed points); from sRGB, within 1.5 %
    inv = _known("srgb", np.linspace(0.0, 1.0, knots), None)
    counts = np.bincount(z.ravel(), minlength=knots)
    seen = counts > 0
    for _ in range(iterations):
        e = (w * t * inv[z]).sum(axis=1) / (w * t * t).sum(axis=1)
        sums = np.bincount(z.ravel(), (e[:, None] * t).ravel(), minlength=knots)
        new = np.interp(np.arange(knots), np.flatnonzero(seen), sums[seen] / counts[seen])
        # each update smoothed: with exposures a power of two apart, a ripple of period one
        # stop in ln X is barely observable and the plain iteration drifts into it
        positive = new > 0
        new[positive] = np.exp(_smooth(np.log(new[positive]), counts[positive] * 1.0, smoothness))
        new /= new[mid]
        change = float(np.abs(new - inv).max())
        inv = new
        if change < tol:
            break
    e = (w * t * inv[z]).sum(axis=1) / (w * t * t).sum(axis=1)
    positive = inv > 0
    g = np.full(knots, np.nan)
    g[positive] = np.log(inv[positive])
    g = np.where(np.isnan(g), np.nanmin(g) - 1.0, g)
    residual = g[z] - np.log(np.maximum(e, 1e-300))[:, None] - np.log(t)
    rms = math.sqrt(float((w * residual**2).sum() / w.sum()))
    return _strictly_increasing(_isotonic(g, counts + 1e-9)), rms


def recover_response(
    codes: np.ndarray,
    exposures: ArrayLike,
    *,
    method: ResponseMethod = "debevec",
    smoothness: float = SMOOTHNESS,
    samples: int = SAMPLES,
    shifts: ArrayLike | None = None,
    clip_low: float | None = None,
    clip_high: float | None = None,
    seed: int = 0,
) -> CameraResponse:
    """Recover a camera's inverse response from a bracketed stack.

    Parameters
    ----------
    codes : (P, H, W, C) uint8 or uint16
        The frames' codes, P >= 2, in any order.
    exposures : (P,) float
        Each frame's relative exposure (for example its exposure time), positive, not all
        equal.
    method : {"debevec", "robertson"}
        Debevec-Malik minimises ``sum w(Z)^2 (g(Z) - ln E - ln t)^2 + lam^2 sum (w(z) g''(z))^2``
        over ``g`` and the samples' ``ln E``, with the hat weight ``w`` (0 at both ends);
        ``lam^2 = smoothness * sum w^2 / K / max(w)^2``, so ``smoothness`` does not depend on
        the number of samples or frames. Robertson alternates ``E = sum w t X / sum w t^2`` and
        ``X(z) = mean of E t`` over the samples of code ``z`` (Gaussian weights, 0 at the ends),
        smoothing ``ln X`` by the same penalty at each step (with exposures a power of two
        apart, a ripple of one stop's period is barely observable and the plain iteration drifts
        into it by a few per cent), starting from the sRGB curve (from a linear start, brackets
        two stops apart end in a curve rippled by 10 %).
    smoothness : float
        Weight of the ``g''`` penalty (0.001-1000), for either method.
    samples : int
        Pixels per channel (see :func:`select_samples`).
    shifts : (P, 2) float, optional
        Frame offsets from alignment.
    clip_low, clip_high : float, optional
        Codes at or below ``clip_low`` / at or above ``clip_high`` (fractions of full scale) are
        clipped; a sample clipped in any channel of a frame is left out of that frame.
        Defaults: :data:`bakeshop.photo.stack.CLIP_LOW`, :data:`~bakeshop.photo.stack.CLIP_HIGH`.

    Returns
    -------
    CameraResponse
        One curve per channel, strictly increasing, anchored as the module notes say, with the
        fit's RMS residual in stops.
    """
    from bakeshop.photo.stack import clip_codes

    validate_choice(method, RESPONSE_METHODS, "response method")
    codes = np.asarray(codes)
    if codes.ndim != 4 or codes.dtype not in (np.uint8, np.uint16):
        raise ArgumentError("codes must be a (P, H, W, C) uint8 or uint16 stack")
    exposures = np.asarray(exposures, dtype=np.float64)
    if exposures.shape != (codes.shape[0],) or not (np.isfinite(exposures) & (exposures > 0)).all():
        raise ArgumentError("exposures must be one positive finite number per frame")
    if codes.shape[0] < 2 or np.ptp(np.log(exposures)) < 1e-6:
        raise ArgumentError("response recovery needs at least two different exposures")
    if not (math.isfinite(smoothness) and 1e-3 <= smoothness <= 1e3):
        raise ArgumentError(f"smoothness must be within 0.001-1000, not {smoothness!r}")
    bits = 8 if codes.dtype == np.uint8 else 16
    knots = 256 if bits == 8 else KNOTS_16
    low, high = clip_codes(bits, clip_low, clip_high)
    positions = select_samples(codes, count=samples, shifts=shifts, seed=seed)
    values = _gather(codes, positions, shifts)  # (N, P, C)
    valid = np.logical_not(_clipped_any(values, low, high))  # (N, P)
    if np.count_nonzero(valid.sum(axis=1) >= 2) < 2:
        raise ArgumentError(
            "too few samples unclipped in two frames to recover a response: the frames are "
            "black or white almost everywhere; use a known curve (srgb, gamma, linear)"
        )
    zf = values.astype(np.float64) * ((knots - 1) / ((1 << bits) - 1))  # in knot units
    z = np.rint(zf).astype(np.int64)  # Robertson averages per knot
    gs, fits = [], []
    for c in range(codes.shape[3]):
        if method == "debevec":
            g, rms = _debevec_channel(zf[..., c], np.log(exposures), valid, knots, smoothness)
        else:
            g, rms = _robertson_channel(z[..., c], exposures, valid, knots, smoothness)
        gs.append(g)
        fits.append(rms / math.log(2))
    g = _anchor(np.stack(gs, axis=1))
    return CameraResponse(np.exp(g), method, np.asarray(fits), len(positions))
