"""Metering and automatic exposure of linear HDR images: centre-weighted weights, the
log-average luminance, the exposure that maps it to middle grey, and adaptation over frames."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError
from bakeshop.image.display import _colour_channels, _luminance

#: Standard deviation of the centre component of the metering weight, in short sides of the frame.
CENTER_SIGMA = 1 / 6


def metering_weights(shape: tuple[int, int], *, center_weight: float = 0.75) -> np.ndarray:
    """Centre-weighted metering weights of an (H, W) frame, summing to 1.

    ``w = (1 - W) / (H W) + W g / sum(g)`` with ``g = exp(-r^2 / (2 sigma^2))``, r the distance
    of a pixel centre from the frame centre and sigma = 1/6 of the frame's short side
    (:data:`CENTER_SIGMA`): a fraction W of the total weight lies in a smooth centre spot (86%
    of it within the central disc whose diameter is 2/3 of the short side), the rest is spread
    evenly over the frame, as a camera's centre-weighted average metering does (which gives the
    centre 60 to 80 percent). W = 0 is the plain average over the frame; W = 1 meters the
    centre spot only. The spot is smooth so that a bright object crossing it changes the
    exposure gradually.

    Parameters
    ----------
    shape : (H, W)
    center_weight : float in [0, 1]
        W, the fraction of the total weight given to the centre spot.

    Returns
    -------
    (H, W) float64, sums to 1
    """
    w_c, spot_y, spot_x = _metering(shape, center_weight)
    h, w = spot_y.size, spot_x.size
    return (1.0 - w_c) / (h * w) + w_c * np.outer(spot_y, spot_x)


def _metering(shape: Sequence[int], center_weight: float) -> tuple[float, np.ndarray, np.ndarray]:
    """(W, g_y, g_x): the centre spot is the outer product of two normalised 1-D Gaussians."""
    w_c = float(center_weight)
    if not 0.0 <= w_c <= 1.0:
        raise ArgumentError(f"centre weight must be in [0, 1], got {center_weight}")
    h, w = (int(s) for s in shape[:2])
    if h < 1 or w < 1:
        raise ArgumentError(f"cannot meter an empty frame of shape {shape}")
    sigma = CENTER_SIGMA * min(h, w)
    profiles = []
    for n in (h, w):
        g = np.exp(-((np.arange(n) + 0.5 - n / 2) ** 2) / (2 * sigma * sigma))
        profiles.append(g / g.sum())
    return w_c, profiles[0], profiles[1]


def log_average_luminance(
    image: ArrayLike,
    *,
    center_weight: float = 0.75,
    delta: float = 1e-4,
    weights: ArrayLike | None = None,
) -> float:
    """Weighted log-average luminance ``exp(sum w log(delta + L) / sum w)`` of a frame.

    Reinhard et al. 2002, eq. 1 (the scene's "key"), with the centre-weighted ``w`` of
    :func:`metering_weights` instead of a plain average, or the ``weights`` given. Pixels whose
    luminance is not finite are left out (their weight too); negative luminance counts as 0.
    ``delta`` (in the image's units) keeps black pixels from sending the logarithm to -infinity.

    Parameters
    ----------
    image : (H, W) or (..., C) float, C in {1, 3, 4}
        One frame; with ``weights`` any spatial shape (a cube's (6, S, S, C) too).
    center_weight : float in [0, 1]
        Used when ``weights`` is None.
    delta : float > 0
    weights : array of the image's spatial shape, optional
        Non-negative metering weight of each texel, replacing the centre-weighted frame
        weights: an environment's texel solid angles (0 outside a layout's valid texels), a
        mask of the texels that hold data.

    Returns
    -------
    float, in the units of ``image``
    """
    a, colour = _colour_channels(image)
    if not delta > 0:
        raise ArgumentError(f"delta must be positive, got {delta}")
    lum = _luminance(a, colour)
    ok = np.isfinite(lum)
    logs = np.where(ok, np.log(delta + np.maximum(np.where(ok, lum, 0), 0), dtype=np.float64), 0)
    if weights is not None:
        w = _check_weights(weights, lum.shape)
        w = np.where(ok, w, 0.0)
        total = float(w.sum())
        if not total > 0:
            raise ArgumentError("cannot meter a frame without finite pixels of positive weight")
        return float(np.exp(float((w * logs).sum()) / total))
    if a.ndim not in (2, 3):
        raise ArgumentError(f"metering needs one (H, W) or (H, W, C) frame; got {a.shape}")
    w_c, spot_y, spot_x = _metering(lum.shape, center_weight)
    mask = ok.astype(np.float64)

    # sum of w * values without building w: the spot is separable
    def weighted_sum(values: np.ndarray) -> float:
        return (1.0 - w_c) / values.size * values.sum() + w_c * (spot_y @ values @ spot_x)

    total = weighted_sum(mask)
    if not total > 0:
        raise ArgumentError("cannot meter a frame without finite pixels")
    return float(np.exp(weighted_sum(logs) / total))


def _check_weights(weights: ArrayLike, shape: Sequence[int]) -> np.ndarray:
    w = np.asarray(weights, dtype=np.float64)
    if w.shape != tuple(shape):
        raise ArgumentError(f"metering weights of shape {w.shape} for an image of {tuple(shape)}")
    if not (np.isfinite(w).all() and (w >= 0).all()):
        raise ArgumentError("metering weights must be finite and non-negative")
    return w


#: Reinhard's "middle grey" key: the exposed log-average luminance of a normal-key scene.
MIDDLE_GREY = 0.18


def auto_exposure(
    image: ArrayLike,
    *,
    center_weight: float = 0.75,
    key: float = MIDDLE_GREY,
    delta: float = 1e-4,
    weights: ArrayLike | None = None,
) -> float:
    """Exposure in EV that maps the centre-weighted log-average luminance to ``key``.

    ``ev = log2(key / L_avg)`` with L_avg from :func:`log_average_luminance`: after
    ``exposure(image, ev)`` the frame's metered log-average is ``key`` (Reinhard et al. 2002,
    eq. 2, with a = ``key``; 0.18 is middle grey, lower keys for dark scenes). ``weights``
    meters an environment or a masked frame instead (see :func:`log_average_luminance`).

    Returns
    -------
    float, stops
    """
    if not key > 0:
        raise ArgumentError(f"key must be positive, got {key}")
    avg = log_average_luminance(image, center_weight=center_weight, delta=delta, weights=weights)
    return float(np.log2(key / avg))


def adapt_exposure(
    targets: ArrayLike,
    *,
    frame_time: float,
    tau_brighter: float = 0.5,
    tau_darker: float = 2.0,
    start: float | None = None,
) -> np.ndarray:
    """Temporal adaptation of exposure over a sequence of frames, as an eye or camera adapts.

    The adapted exposure follows each frame's target (for example :func:`auto_exposure`) with
    a first-order exponential lag in stops::

        ev[k] = ev[k-1] + (target[k] - ev[k-1]) (1 - exp(-frame_time / tau))

    with tau = ``tau_brighter`` when the scene got brighter than the eye is adapted to
    (target < ev[k-1]: less exposure is needed) and ``tau_darker`` otherwise; eyes adapt to
    light faster than to dark. The update is the exact solution of
    d ev / dt = (target - ev) / tau over one frame, so a step in the target is followed by
    1 - exp(-t / tau) of the step after time t: 63.2% after one time constant, whatever the
    frame rate.

    Parameters
    ----------
    targets : (N,) float
        Target exposure of each frame, stops.
    frame_time : float
        Seconds between frames (1 / fps), > 0.
    tau_brighter, tau_darker : float
        Time constants in seconds (> 0).
    start : float or None
        Exposure the eye is adapted to before the first frame; None starts adapted to the
        first frame's target.

    Returns
    -------
    (N,) float64
        Adapted exposure of each frame, stops.
    """
    t = np.asarray(targets, dtype=np.float64).reshape(-1)
    checks = {"frame_time": frame_time, "tau_brighter": tau_brighter, "tau_darker": tau_darker}
    for name, value in checks.items():
        if not (np.isfinite(value) and value > 0):
            raise ArgumentError(f"{name} must be positive and finite, got {value}")
    if not np.isfinite(t).all():
        raise ArgumentError("target exposures must be finite")
    gain_brighter = -np.expm1(-frame_time / tau_brighter)
    gain_darker = -np.expm1(-frame_time / tau_darker)
    out = np.empty_like(t)
    if start is None and not t.size:
        return out
    ev = t[0] if start is None else start
    for k, target in enumerate(t):
        gain = gain_brighter if target < ev else gain_darker
        ev = ev + (target - ev) * gain
        out[k] = ev
    return out
