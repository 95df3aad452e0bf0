"""The display rule: HDR data to a picture (exposure chosen, tone mapped, encoded, quantised),
with a record of what was done."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.image.display import (
    DITHERS,
    TONE_OPERATORS,
    _colour_channels,
    aces_filmic,
    exposure,
    reinhard,
    srgb_encode,
    to_srgb8,
)
from bakeshop.image.metering import MIDDLE_GREY, _check_weights, auto_exposure, metering_weights

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


def check_ev(ev: float | str) -> float:
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


def fit_exposure(
    image: ArrayLike, *, weights: ArrayLike | None = None, clip_fraction: float = CLIP_FRACTION
) -> float:
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
    linear: ArrayLike, *, bits: int = 8, encoding: str = "srgb", dither: str = "none", seed: int = 0
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


def _metered_weights(
    image: ArrayLike, weights: ArrayLike | None, center_weight: float
) -> np.ndarray:
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
    image: ArrayLike,
    ev: float | str = 0.0,
    *,
    weights: ArrayLike | None = None,
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
    image: ArrayLike,
    *,
    ev: float | str = 0.0,
    operator: str = "none",
    white: float | None = None,
    encoding: str = "srgb",
    bits: int = 8,
    dither: str = "none",
    seed: int = 0,
    weights: ArrayLike | None = None,
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
