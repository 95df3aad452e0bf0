"""Planar operations on ``(H, W, C)`` images: energy-preserving resize, statistics, and the
display transforms (exposure, sRGB, tone mapping, metering and adaptation).

>>> from bakeshop.image import resize_area, tonemap, to_srgb8
>>> small = resize_area(image, (512, 256))            # (width, height); the mean is kept
>>> picture = to_srgb8(tonemap(small, ev=-1.0, operator="aces"))
>>> shown = to_picture(small, ev="auto", operator="aces")   # the display rule, in one call
>>> shown.pixels, shown.describe()                         # uint8 codes, what was done

Modules: :mod:`~bakeshop.image.resize`, :mod:`~bakeshop.image.statistics`,
:mod:`~bakeshop.image.display` (sRGB, exposure, tone operators, 8-bit quantisation),
:mod:`~bakeshop.image.metering` (metering, automatic exposure, adaptation) and
:mod:`~bakeshop.image.picture` (the display rule: HDR data to a picture).
"""

from bakeshop.image.display import (
    ACES_FITS,
    DITHERS,
    TONE_OPERATORS,
    aces_filmic,
    exposure,
    reinhard,
    srgb_decode,
    srgb_encode,
    to_srgb8,
    tonemap,
)
from bakeshop.image.metering import (
    MIDDLE_GREY,
    adapt_exposure,
    auto_exposure,
    log_average_luminance,
    metering_weights,
)
from bakeshop.image.picture import (
    CLIP_FRACTION,
    ENCODINGS,
    EXPOSURE_MODES,
    MAX_EV,
    Exposure,
    Picture,
    check_ev,
    choose_exposure,
    encode_picture,
    fit_exposure,
    to_picture,
)
from bakeshop.image.resize import (
    area_footprint,
    area_weights,
    resample_separable,
    resize_area,
    resize_area_cost,
    resize_area_part,
)
from bakeshop.image.statistics import LUMINANCE_WEIGHTS, describe, luminance

__all__ = [
    "ACES_FITS",
    "CLIP_FRACTION",
    "DITHERS",
    "ENCODINGS",
    "EXPOSURE_MODES",
    "LUMINANCE_WEIGHTS",
    "MAX_EV",
    "Exposure",
    "MIDDLE_GREY",
    "TONE_OPERATORS",
    "Picture",
    "aces_filmic",
    "adapt_exposure",
    "area_footprint",
    "area_weights",
    "auto_exposure",
    "check_ev",
    "choose_exposure",
    "describe",
    "encode_picture",
    "exposure",
    "fit_exposure",
    "log_average_luminance",
    "luminance",
    "metering_weights",
    "reinhard",
    "resample_separable",
    "resize_area",
    "resize_area_cost",
    "resize_area_part",
    "srgb_decode",
    "srgb_encode",
    "to_picture",
    "to_srgb8",
    "tonemap",
]
