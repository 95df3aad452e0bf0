"""Exposure, display encoding and tone mapping of linear HDR images.

The order of a display pipeline is: scale the scene by the exposure (:func:`exposure`), compress
the range with a tone operator, clamp to [0, 1], encode for the display (:func:`srgb_encode`),
quantise to 8 bits.

Values are linear and relative (the file's units); ``exposure`` is in photographic stops (EV):
+1 EV doubles every value. Metering and automatic exposure are in
:mod:`bakeshop.image.metering`, the whole display rule in :mod:`bakeshop.image.picture`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.image import _native
from bakeshop.image.statistics import luminance

#: IEC 61966-2-1 sRGB transfer function constants: the linear segment's end in linear light,
#: its slope, and the power segment's offset and exponent.
SRGB_LINEAR_LIMIT = 0.0031308
SRGB_SLOPE = 12.92
SRGB_OFFSET = 0.055
SRGB_GAMMA = 2.4
#: End of the linear segment in encoded values (12.92 * 0.0031308 rounded as the standard does).
SRGB_ENCODED_LIMIT = 0.04045


def _float_array(values: ArrayLike) -> np.ndarray:
    """``values`` as a float array: float32/float64 kept, everything else becomes float32."""
    a = np.asarray(values)
    if a.dtype not in (np.float32, np.float64):
        a = a.astype(np.float32)
    return a


def exposure(image: ArrayLike, ev: float) -> np.ndarray:
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


def srgb_encode(linear: ArrayLike) -> np.ndarray:
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
    out = np.empty(a.shape, a.dtype)
    _apply(_ENCODE, a, out)
    return out


def srgb_decode(encoded: ArrayLike) -> np.ndarray:
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
    out = np.empty(a.shape, a.dtype)
    _apply(_DECODE, a, out)
    return out


_ENCODE, _DECODE = 0, 1


def _apply(which: int, a: np.ndarray, out: np.ndarray) -> None:
    """Run a curve over any-shaped ``a`` into ``out`` (same shape, C order), in float64
    arithmetic (``src/image/display.hpp``)."""
    _native.srgb_apply(np.ascontiguousarray(a).reshape(-1), which == _DECODE, out.reshape(-1))


def _colour_channels(image: ArrayLike) -> tuple[np.ndarray, int]:
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


def reinhard(image: ArrayLike, *, white: float | None = None) -> np.ndarray:
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


def aces_filmic(image: ArrayLike, *, fit: str = "hill") -> np.ndarray:
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


def tonemap(
    image: ArrayLike, *, ev: float = 0.0, operator: str = "none", white: float | None = None
) -> np.ndarray:
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


def to_srgb8(linear: ArrayLike, *, dither: str = "none", seed: int = 0) -> np.ndarray:
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
    _native.srgb8(
        np.ascontiguousarray(a).reshape(-1, channels),
        max(colour, 1),
        dither == "triangular",
        int(seed) & 0xFFFFFFFF,
        out.reshape(-1, channels),
    )
    return out
