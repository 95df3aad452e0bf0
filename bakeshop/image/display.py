"""Exposure, display encoding and tone mapping of linear HDR images.

The order of a display pipeline is: scale the scene by the exposure (:func:`exposure`), compress
the range with a tone operator, clamp to [0, 1], encode for the display (:func:`srgb_encode`),
quantise to 8 bits.

Values are linear and relative (the file's units); ``exposure`` is in photographic stops (EV):
+1 EV doubles every value.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.image.statistics import luminance

#: IEC 61966-2-1 sRGB transfer function constants: the linear segment's end in linear light,
#: its slope, and the power segment's offset and exponent.
SRGB_LINEAR_LIMIT = 0.0031308
SRGB_SLOPE = 12.92
SRGB_OFFSET = 0.055
SRGB_GAMMA = 2.4
#: End of the linear segment in encoded values (12.92 * 0.0031308 rounded as the standard does).
SRGB_ENCODED_LIMIT = 0.04045


def _float_array(values) -> np.ndarray:
    """``values`` as a float array: float32/float64 kept, everything else becomes float32."""
    a = np.asarray(values)
    if a.dtype not in (np.float32, np.float64):
        a = a.astype(np.float32)
    return a


def exposure(image, ev: float) -> np.ndarray:
    """Scale linear values by ``2**ev`` (photographic exposure in stops).

    Parameters
    ----------
    image : (..., C) or any shape, float
        Linear values. Integer and float16 input becomes float32; float32 stays float32.
    ev : float
        Exposure in stops (EV). 0 leaves the image unchanged, +1 doubles it, -1 halves it.

    Returns
    -------
    ndarray, same shape
        ``image * 2**ev``. NaN and infinities propagate (inf stays inf, NaN stays NaN).
    """
    ev = float(ev)
    if not math.isfinite(ev):
        raise ArgumentError(f"exposure must be a finite number of stops, got {ev}")
    a = _float_array(image)
    return a * a.dtype.type(2.0**ev)


def srgb_encode(linear) -> np.ndarray:
    """Encode linear light with the sRGB transfer function (IEC 61966-2-1).

    ``V = 12.92 L`` for ``L <= 0.0031308``, else ``V = 1.055 L**(1/2.4) - 0.055``.

    Parameters
    ----------
    linear : array_like, float
        Linear values; 1 is display white. Float32 stays float32 (float64 stays float64);
        anything else becomes float32.

    Returns
    -------
    ndarray, same shape
        Encoded values. Nothing is clamped: values above 1 continue the power segment, so clamp
        (``np.clip(..., 0, 1)``) before quantising to 8 bits. Negative values are encoded as
        the odd extension of the curve, ``V(-L) = -V(L)`` (the "extended sRGB" convention of
        scRGB and CSS Color 4), which keeps :func:`srgb_decode` an exact inverse on the whole
        real line. NaN stays NaN, +-inf stays +-inf.

    References
    ----------
    IEC 61966-2-1:1999, Multimedia systems and equipment - Colour measurement and management -
    Part 2-1: Default RGB colour space - sRGB.
    """
    a = _float_array(linear)
    out = np.empty_like(a)
    _apply(_ENCODE, a, out)
    return out


def srgb_decode(encoded) -> np.ndarray:
    """Decode sRGB-encoded values to linear light (inverse of :func:`srgb_encode`).

    ``L = V / 12.92`` for ``V <= 0.04045``, else ``L = ((V + 0.055) / 1.055)**2.4``.

    Parameters
    ----------
    encoded : array_like, float
        Encoded values (8-bit code values must first be divided by 255). Float32 stays
        float32 (float64 stays float64); anything else becomes float32.

    Returns
    -------
    ndarray, same shape
        Linear values. Not clamped; negative values decode as the odd extension
        ``L(-V) = -L(V)``; NaN stays NaN, +-inf stays +-inf.

    References
    ----------
    IEC 61966-2-1:1999 (see :func:`srgb_encode`).
    """
    a = _float_array(encoded)
    out = np.empty_like(a)
    _apply(_DECODE, a, out)
    return out


_ENCODE, _DECODE = 0, 1


@numba.njit(cache=True, inline="always")
def _srgb_encode1(x: float) -> float:
    """The IEC 61966-2-1 encoding of one value, odd-extended to negatives; NaN stays NaN."""
    m = abs(x)
    if m <= SRGB_LINEAR_LIMIT:
        v = SRGB_SLOPE * m
    else:
        v = (1.0 + SRGB_OFFSET) * m ** (1.0 / SRGB_GAMMA) - SRGB_OFFSET
    return -v if x < 0 else v


@numba.njit(cache=True, inline="always")
def _srgb_decode1(x: float) -> float:
    m = abs(x)
    if m <= SRGB_ENCODED_LIMIT:
        v = m / SRGB_SLOPE
    else:
        v = ((m + SRGB_OFFSET) / (1.0 + SRGB_OFFSET)) ** SRGB_GAMMA
    return -v if x < 0 else v


@numba.njit(cache=True, parallel=True)
def _apply_flat(which, a, out):
    for i in numba.prange(a.size):
        x = np.float64(a[i])
        out[i] = _srgb_encode1(x) if which == _ENCODE else _srgb_decode1(x)


def _apply(which: int, a: np.ndarray, out: np.ndarray) -> None:
    """Run a curve over any-shaped ``a`` into ``out`` (same shape), in float64 arithmetic."""
    _apply_flat(which, np.ascontiguousarray(a).reshape(-1), out.reshape(-1))


def _colour_channels(image) -> tuple[np.ndarray, int]:
    """``image`` as a float array and the number of its leading colour channels (alpha excluded).

    (H, W) is one grey channel; (..., C) with C in {1, 3} is all colour; C = 4 keeps its last
    channel as alpha, untouched by tone operators and encoding.
    """
    a = _float_array(image)
    if a.ndim == 2:
        return a, 0  # 0: the whole array is one grey channel
    if a.ndim < 2 or a.shape[-1] not in (1, 3, 4):
        raise ArgumentError(f"an image must be (H, W) or (..., C) with C in 1, 3, 4; got {a.shape}")
    return a, min(a.shape[-1], 3)


def _luminance(a: np.ndarray, colour: int) -> np.ndarray:
    if colour == 0:
        return a
    return luminance(a[..., :colour])


def reinhard(image, *, white: float | None = None) -> np.ndarray:
    """Reinhard's global operator with a white point, applied to luminance, hue preserved.

    With L the luminance of a pixel (Rec. 709 weights) and L_white the smallest luminance that
    maps to white (Reinhard et al. 2002, eq. 4)::

        L_d = L (1 + L / L_white^2) / (1 + L)

    and every colour channel is scaled by L_d / L, so the ratios between R, G and B (hue and
    saturation) are kept. ``white=None`` is L_white -> infinity, eq. 3: L_d = L / (1 + L).
    The scene scaling of eq. 2 (key a over the log-average luminance) is the exposure step
    before the operator: see :func:`auto_exposure`.

    Parameters
    ----------
    image : (H, W) or (..., C) float, C in {1, 3, 4}
        Linear, exposed values. Alpha (C = 4) passes through.
    white : float or None
        L_white, in the units of ``image`` after exposure (> 0).

    Returns
    -------
    ndarray, shape and float dtype of ``image``
        Display-referred linear values. Luminance is in [0, 1) (reaches 1 at L = L_white and
        exceeds it above); a saturated colour can have one channel above 1 while its luminance
        is below, so clamp before encoding. Pixels of luminance <= 0 are left unchanged; NaN
        and infinite luminance give NaN.

    References
    ----------
    E. Reinhard, M. Stark, P. Shirley and J. Ferwerda, "Photographic Tone Reproduction for
    Digital Images", ACM TOG 21(3) (SIGGRAPH 2002), doi:10.1145/566654.566575.
    """
    a, colour = _colour_channels(image)
    t = a.dtype.type
    lum = np.maximum(_luminance(a, colour), t(0))
    if white is None:
        scale = t(1) / (t(1) + lum)
    else:
        white = float(white)
        if not (np.isfinite(white) and white > 0):
            raise ArgumentError(f"Reinhard white point must be positive and finite, got {white}")
        with np.errstate(invalid="ignore"):
            scale = (t(1) + lum / t(white * white)) / (t(1) + lum)
    out = a.copy()
    if colour == 0:
        out *= scale
    else:
        out[..., :colour] *= scale[..., None]
    return out


#: Narkowicz's fit of the ACES RRT+ODT (sRGB, 1000 nit) curve: x (a x + b) / (x (c x + d) + e).
NARKOWICZ = (2.51, 0.03, 2.43, 0.59, 0.14)
#: Hill's fit: linear sRGB -> ACES AP1 with the RRT's saturation (rows sum to 1) ...
HILL_INPUT = np.array(
    [[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]]
)
#: ... and back, with the ODT's desaturation.
HILL_OUTPUT = np.array(
    [[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605], [-0.00327, -0.07276, 1.07602]]
)

ACES_FITS = ("hill", "narkowicz")


def aces_filmic(image, *, fit: str = "hill") -> np.ndarray:
    """ACES-fitted filmic tone curve: a cheap fit of the ACES RRT + sRGB ODT.

    ``fit="hill"`` (default) is Stephen Hill's fit (BakingLab, 2016): the colour is taken to
    ACES AP1 with the RRT saturation (matrix :data:`HILL_INPUT`), each channel goes through::

        f(v) = (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.4329510) + 0.238081)

    and it comes back with the ODT desaturation (:data:`HILL_OUTPUT`). It follows the reference
    transform closely, including its hue and saturation shifts.
    ``fit="narkowicz"`` is Krzysztof Narkowicz's per-channel curve (2016)::

        f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)

    which matches the luminance curve only (it over-saturates bright colours).

    Parameters
    ----------
    image : (H, W) or (..., C) float, C in {1, 3, 4}
        Linear scene values after exposure (mid grey near 0.18). Grey images (C = 1) go through
        the curve alone (both matrices map grey to grey). Alpha passes through.
    fit : {"hill", "narkowicz"}

    Returns
    -------
    ndarray, shape and float dtype of ``image``
        Display-referred linear values clamped to [0, 1] (both fits saturate as published);
        encode with :func:`srgb_encode`. NaN stays NaN.

    References
    ----------
    Academy Color Encoding System, RRT and ODT (Academy S-2014-004).
    K. Narkowicz, "ACES Filmic Tone Mapping Curve", 2016,
    https://knarkowicz.wordpress.com/2016/01/06/aces-filmic-tone-mapping-curve/.
    S. Hill, BakingLab ``ACES.hlsl``, 2016, https://github.com/TheRealMJP/BakingLab.
    """
    validate_choice(fit, ACES_FITS, "ACES fit")
    a, colour = _colour_channels(image)
    out = a.copy()
    x = (out if colour == 0 else out[..., :colour]).astype(np.float64)
    with np.errstate(invalid="ignore", over="ignore"):
        if fit == "narkowicz":
            pa, pb, pc, pd, pe = NARKOWICZ
            y = x * (pa * x + pb) / (x * (pc * x + pd) + pe)
        else:
            if colour == 3:
                x = x @ HILL_INPUT.T
            y = (x * (x + 0.0245786) - 0.000090537) / (x * (0.983729 * x + 0.4329510) + 0.238081)
            if colour == 3:
                y = y @ HILL_OUTPUT.T
    y = np.clip(y, 0.0, 1.0)
    if colour == 0:
        out[...] = y
    else:
        out[..., :colour] = y
    return out


TONE_OPERATORS = ("none", "reinhard", "aces")


def tonemap(image, *, ev: float = 0.0, operator: str = "none", white: float | None = None):
    """Exposure, then a tone operator, then clamping: display-referred linear values in [0, 1].

    Parameters
    ----------
    image : (H, W) or (..., C) float, C in {1, 3, 4}
        Linear scene values.
    ev : float
        Exposure in stops, applied first (:func:`exposure`).
    operator : {"none", "reinhard", "aces"}
        "none" only clamps; "reinhard" is :func:`reinhard` with ``white``; "aces" is
        :func:`aces_filmic` with Hill's fit.
    white : float or None
        Reinhard's white point (after exposure); ignored by the other operators.

    Returns
    -------
    ndarray, shape of ``image``
        Values in [0, 1] (NaN becomes 0), ready for :func:`to_srgb8`. Alpha is clamped only.
    """
    validate_choice(operator, TONE_OPERATORS, "tone operator")
    a = exposure(image, ev)
    if operator == "reinhard":
        a = reinhard(a, white=white)
    elif operator == "aces":
        a = aces_filmic(a)
    return np.clip(np.nan_to_num(a, nan=0.0), 0, 1)


DITHERS = ("none", "triangular")


def to_srgb8(linear, *, dither: str = "none", seed: int = 0) -> np.ndarray:
    """Display-referred linear values -> 8-bit sRGB code values (uint8), with optional dither.

    Colour channels are clamped to [0, 1], encoded with :func:`srgb_encode` and rounded to
    ``round(255 V)``; alpha (C = 4) is clamped and quantised without encoding. NaN becomes 0.

    ``dither="triangular"`` adds, before rounding, noise with a triangular distribution on
    (-1, 1) code values (the sum of two uniform variables, TPDF), which makes the expected
    quantised value equal the unquantised one and turns banding in smooth gradients into
    fine grain; values that clip (linear <= 0 or >= 1) are left undithered so black and
    blown-out white stay clean. The noise is seeded (``seed``), so a bake is reproducible.
    The rounding error is then up to one code value instead of half.

    Returns
    -------
    ndarray of uint8, shape of ``linear``
    """
    validate_choice(dither, DITHERS, "dither")
    a, colour = _colour_channels(linear)
    channels = 1 if colour == 0 else a.shape[-1]
    out = np.empty(a.shape, np.uint8)
    _srgb8(
        np.ascontiguousarray(a).reshape(-1, channels),
        max(colour, 1),
        dither == "triangular",
        np.uint64(seed & 0xFFFFFFFF),
        out.reshape(-1, channels),
    )
    return out


@numba.njit(cache=True, inline="always")
def _uniform(key):
    """A uniform number in [0, 1) from a 64-bit key (SplitMix64's finaliser): counter-based, so
    the dither is the same whatever the number of threads."""
    z = key + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return np.float64(z >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@numba.njit(cache=True, parallel=True)
def _srgb8(a, colour, dither, seed, out):
    channels = a.shape[1]
    base = seed << np.uint64(34)
    for p in numba.prange(a.shape[0]):
        for k in range(channels):
            x = np.float64(a[p, k])
            x = 0.0 if x != x else min(max(x, 0.0), 1.0)
            q = 255.0 * (_srgb_encode1(x) if k < colour else x)
            if dither and k < colour and 0.0 < x < 1.0:
                key = base + np.uint64(2 * (p * channels + k))
                q += _uniform(key) - _uniform(key + np.uint64(1))
            out[p, k] = np.uint8(min(max(np.rint(q), 0.0), 255.0))


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


def _metering(shape, center_weight) -> tuple[float, np.ndarray, np.ndarray]:
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
    image, *, center_weight: float = 0.75, delta: float = 1e-4, weights=None
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

    def weighted_sum(values):  # sum of w * values without building w: the spot is separable
        return (1.0 - w_c) / values.size * values.sum() + w_c * (spot_y @ values @ spot_x)

    total = weighted_sum(mask)
    if not total > 0:
        raise ArgumentError("cannot meter a frame without finite pixels")
    return float(np.exp(weighted_sum(logs) / total))


def _check_weights(weights, shape) -> np.ndarray:
    w = np.asarray(weights, dtype=np.float64)
    if w.shape != tuple(shape):
        raise ArgumentError(f"metering weights of shape {w.shape} for an image of {tuple(shape)}")
    if not (np.isfinite(w).all() and (w >= 0).all()):
        raise ArgumentError("metering weights must be finite and non-negative")
    return w


#: Reinhard's "middle grey" key: the exposed log-average luminance of a normal-key scene.
MIDDLE_GREY = 0.18


def auto_exposure(
    image,
    *,
    center_weight: float = 0.75,
    key: float = MIDDLE_GREY,
    delta: float = 1e-4,
    weights=None,
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
    targets,
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
    ev = t[0] if (start is None and t.size) else start
    for k, target in enumerate(t):
        gain = gain_brighter if target < ev else gain_darker
        ev = ev + (target - ev) * gain
        out[k] = ev
    return out


# -- the display rule: HDR data to a picture ------------------------------------------------------

#: How a picture's colour channels are encoded: sRGB (IEC 61966-2-1) or linear values.
ENCODINGS = ("srgb", "linear")
#: Exposure modes besides a number of stops: "auto" maps the metered log-average luminance to
#: the key (middle grey), "fit" lets only the brightest CLIP_FRACTION of the metered texels clip.
EXPOSURE_MODES = ("auto", "fit")
#: The largest exposure, in stops, accepted anywhere (2^64: beyond any float32 scene's range).
MAX_EV = 64.0
#: Fraction of the metered weight (an environment's solid angle) that ``fit`` exposure clips.
CLIP_FRACTION = 1e-3
#: Sample depths a picture can have.
PICTURE_BITS = (8, 16)


def check_ev(ev) -> float:
    """``ev`` as a float, refused unless finite and within +-:data:`MAX_EV` stops."""
    try:
        value = float(ev)
    except (TypeError, ValueError):
        value = float("nan")
    if not (math.isfinite(value) and abs(value) <= MAX_EV):
        raise ArgumentError(
            f"exposure must be a number of stops in [-{MAX_EV:g}, {MAX_EV:g}], got {ev!r}"
        )
    return value


def fit_exposure(image, *, weights=None, clip_fraction: float = CLIP_FRACTION) -> float:
    """Exposure (EV) after which only the brightest ``clip_fraction`` of the image exceeds 1.

    Returns ``-log2(q)`` with q the weighted (1 - ``clip_fraction``) quantile of each texel's
    largest colour channel: after ``exposure(image, ev)`` everything but the brightest
    ``clip_fraction`` of the weight is <= 1. With an environment's solid angles as ``weights``
    the default 0.1% (12.6 msr of the sphere) is a few dozen sun discs: a sun clips, the sky
    does not. The exposure that stores HDR data in a picture with the least clipping.

    Parameters
    ----------
    image : (H, W) or (..., C) float, C in {1, 3, 4}
    weights : array of the image's spatial shape, optional
        Non-negative weight of each texel (solid angles; 0 for texels that do not count); None
        weighs every texel alike.
    clip_fraction : float in (0, 1)

    Returns
    -------
    float, stops
    """
    if not 0.0 < clip_fraction < 1.0:
        raise ArgumentError(f"clip fraction must be in (0, 1), got {clip_fraction}")
    a, colour = _colour_channels(image)
    peak = a if colour == 0 else np.max(a[..., :colour], axis=-1)
    w = np.ones(peak.shape) if weights is None else _check_weights(weights, peak.shape)
    keep = (w > 0) & np.isfinite(peak)
    peak, w = peak[keep].astype(np.float64), w[keep]
    if peak.size == 0 or not np.any(peak > 0):
        raise ArgumentError("the image is black where it is metered: no exposure fits it")
    order = np.argsort(peak)
    cdf = np.cumsum(w[order])
    q = peak[order][min(np.searchsorted(cdf, (1.0 - clip_fraction) * cdf[-1]), peak.size - 1)]
    if not q > 0:
        q = peak[peak > 0].min()
    return check_ev(-np.log2(q))


def encode_picture(
    linear, *, bits: int = 8, encoding: str = "srgb", dither: str = "none", seed: int = 0
) -> np.ndarray:
    """Display-referred linear values -> 8- or 16-bit code values.

    Colour channels are clamped to [0, 1] (NaN -> 0), sRGB-encoded unless
    ``encoding="linear"``, and rounded to ``round((2^bits - 1) V)``; alpha is clamped and
    quantised without encoding. ``dither`` applies at 8 bits (:func:`to_srgb8`); 16 bits need
    none.

    Returns
    -------
    uint8 or uint16 array, shape of ``linear``
    """
    validate_choice(encoding, ENCODINGS, "picture encoding")
    if bits not in PICTURE_BITS:
        raise ArgumentError(f"a picture has 8 or 16 bits per sample, not {bits!r}")
    if bits == 8 and encoding == "srgb":
        return to_srgb8(linear, dither=dither, seed=seed)
    validate_choice(dither, DITHERS, "dither")
    a, colour = _colour_channels(linear)
    v = np.clip(np.nan_to_num(a.astype(np.float64), nan=0.0), 0.0, 1.0)
    if encoding == "srgb":
        if colour == 0:
            v = srgb_encode(v)
        else:
            v[..., :colour] = srgb_encode(v[..., :colour])
    top = (1 << bits) - 1
    if bits == 8 and dither == "triangular":
        rng = np.random.default_rng(seed)
        noise = rng.random(v.shape) - rng.random(v.shape)
        inside = (v > 0) & (v < 1)
        if colour:
            inside[..., colour:] = False
        q = v * top + np.where(inside, noise, 0.0)
    else:
        q = v * top
    return np.clip(np.rint(q), 0, top).astype(np.uint8 if bits == 8 else np.uint16)


class Picture(NamedTuple):
    """What :func:`to_picture` returns: the code values and what was done to make them."""

    #: uint8 or uint16 code values, the input's shape.
    pixels: np.ndarray
    #: the exposure applied, in stops.
    ev: float
    #: how it was chosen: "fixed", "auto" or "fit".
    exposure_mode: str
    #: "none" (clamp only), "reinhard" or "aces".
    operator: str
    #: "srgb" or "linear".
    encoding: str
    #: 8 or 16.
    bits: int
    #: fraction of the metered texels (by weight) whose colour reached 1 and clipped.
    clipped: float
    #: fraction of the texels that the exposure was metered over (1 for a fixed exposure).
    metered: float
    #: dither applied ("none" or "triangular").
    dither: str

    def describe(self) -> str:
        """The rule in one line, e.g. ``exposure -3.21 EV (auto over 50% of texels), ACES,
        clamped (0.8% clip), sRGB, 8-bit``."""
        how = {"fixed": "", "auto": "auto", "fit": "fit"}[self.exposure_mode]
        if how and self.metered < 1:
            how += f" over {_percent(self.metered)} of texels"
        tone = {"none": "", "reinhard": "Reinhard, ", "aces": "ACES, "}[self.operator]
        encoding = "sRGB" if self.encoding == "srgb" else "linear (not sRGB-encoded)"
        dither = ", dithered" if self.dither != "none" else ""
        return (
            f"exposure {self.ev:+.2f} EV" + (f" ({how})" if how else "") + f", {tone}clamped "
            f"({_percent(self.clipped)} clip), {encoding}, {self.bits}-bit{dither}"
        )

    def metadata(self) -> str:
        """The line a picture file records (``description``), with the exposure to 4 decimals."""
        return f"bakeshop display: exposure {self.ev:+.4f} EV; " + self.describe()


def _percent(fraction: float) -> str:
    if fraction == 0:
        return "0%"
    if fraction < 1e-3:
        return "<0.1%"
    return f"{100 * fraction:.1f}%"


def _metered_weights(image, weights, center_weight) -> np.ndarray:
    """The weights auto and fit exposure meter with: ``weights`` (an environment's solid
    angles) or the centre-weighted frame weights, with texels that are exactly black in every
    colour channel left out (no data: a cross's empty cells, outside a probe's disk, a fresnel
    bake's lower half), unless every texel is."""
    a, colour = _colour_channels(image)
    lum_shape = a.shape if colour == 0 else a.shape[:-1]
    if weights is None:
        if len(lum_shape) != 2:
            raise ArgumentError(f"metering needs weights for an image of shape {a.shape}")
        w = metering_weights(lum_shape, center_weight=center_weight)
    else:
        w = _check_weights(weights, lum_shape)
    lit = (a != 0) if colour == 0 else (a[..., :colour] != 0).any(axis=-1)
    return np.where(lit, w, 0.0) if (lit & (w > 0)).any() else w


class Exposure(NamedTuple):
    """What :func:`choose_exposure` returns."""

    #: stops.
    ev: float
    #: "fixed", "auto" or "fit".
    mode: str
    #: fraction of the texels metered (1 for a fixed exposure).
    metered: float
    #: the metering weights (spatial shape), or None for a fixed exposure.
    weights: np.ndarray | None


def choose_exposure(
    image,
    ev=0.0,
    *,
    weights=None,
    key: float = MIDDLE_GREY,
    center_weight: float = 0.75,
    clip_fraction: float = CLIP_FRACTION,
) -> Exposure:
    """The exposure of the display rule (:func:`to_picture`): ``ev`` stops, or metered.

    ``"auto"`` is :func:`auto_exposure` (log-average luminance to ``key``), ``"fit"`` is
    :func:`fit_exposure` (only ``clip_fraction`` clips), both over ``weights`` (or the
    centre-weighted frame) without the texels that are exactly black in every channel.
    """
    if not isinstance(ev, str):
        return Exposure(check_ev(ev), "fixed", 1.0, None)
    validate_choice(ev, EXPOSURE_MODES, "exposure mode")
    w = _metered_weights(image, weights, center_weight)
    if ev == "auto":
        value = check_ev(auto_exposure(image, key=key, weights=w))
    else:
        value = fit_exposure(image, weights=w, clip_fraction=clip_fraction)
    return Exposure(value, ev, float(np.count_nonzero(w) / w.size), w)


def to_picture(
    image,
    *,
    ev=0.0,
    operator: str = "none",
    white: float | None = None,
    encoding: str = "srgb",
    bits: int = 8,
    dither: str = "none",
    seed: int = 0,
    weights=None,
    key: float = MIDDLE_GREY,
    center_weight: float = 0.75,
    clip_fraction: float = CLIP_FRACTION,
) -> Picture:
    """HDR (linear) values -> a picture's code values, by the one display rule of bakeshop.

    exposure (a number of stops, or metered: ``"auto"``, ``"fit"``) -> tone operator ("none"
    clamps, "reinhard", "aces") -> clamp to [0, 1] -> sRGB encoding (or ``"linear"``) ->
    rounding to ``bits``. Every command that writes a picture from HDR data goes through here,
    and :meth:`Picture.describe` says what was done in one line.

    Metering (``"auto"``: :func:`auto_exposure`, the log-average luminance mapped to ``key``;
    ``"fit"``: :func:`fit_exposure`, only ``clip_fraction`` clips) uses ``weights`` when given
    (an environment's texel solid angles, 0 outside a layout's valid texels or below a
    horizon), else the centre-weighted frame weights; either way texels that are exactly black
    in every channel are left out (they hold no light: the empty cells of a cross, the outside
    of a light-probe disk, a fresnel bake's lower half), so they cannot drag the exposure up.

    Parameters
    ----------
    image : (H, W) or (..., C) float, C in {1, 3, 4}
        Linear values (a cube's ``(6, S, S, C)`` too, with ``weights``).
    ev : float or {"auto", "fit"}
    operator : {"none", "reinhard", "aces"}
    white : float, optional
        Reinhard's white point.
    encoding : {"srgb", "linear"}
    bits : {8, 16}
    dither : {"none", "triangular"}
        At 8 bits (:func:`to_srgb8`).
    seed : int
    weights : array of the spatial shape, optional
    key, center_weight, clip_fraction : float
        Metering parameters.

    Returns
    -------
    Picture
    """
    validate_choice(operator, TONE_OPERATORS, "tone operator")
    validate_choice(encoding, ENCODINGS, "picture encoding")
    a, colour = _colour_channels(image)
    chosen = choose_exposure(
        a,
        ev,
        weights=weights,
        key=key,
        center_weight=center_weight,
        clip_fraction=clip_fraction,
    )
    value, mode, metered, w = chosen.ev, chosen.mode, chosen.metered, chosen.weights
    exposed = exposure(a, value)
    if operator == "reinhard":
        exposed = reinhard(exposed, white=white)
    elif operator == "aces":
        exposed = aces_filmic(exposed)
    colours = exposed if colour == 0 else exposed[..., :colour]
    over = colours >= 1 if colour == 0 else (colours >= 1).any(axis=-1)
    if w is None:
        w = np.ones(over.shape) if weights is None else _check_weights(weights, over.shape)
    total = float(w.sum())
    clipped = float(w[over].sum() / total) if total > 0 else 0.0
    pixels = encode_picture(exposed, bits=bits, encoding=encoding, dither=dither, seed=seed)
    dither = dither if bits == 8 else "none"
    return Picture(pixels, value, mode, operator, encoding, bits, clipped, metered, dither)
