"""Planar operations on ``(H, W, C)`` images: energy-preserving resize, statistics, and the
display transforms (exposure, sRGB, tone mapping, metering and adaptation).

>>> from bakeshop.image import resize_area, tonemap, to_srgb8
>>> small = resize_area(image, (512, 256))            # (width, height); the mean is kept
>>> picture = to_srgb8(tonemap(small, ev=-1.0, operator="aces"))
"""

from bakeshop.image.display import (
    ACES_FITS,
    DITHERS,
    MIDDLE_GREY,
    TONE_OPERATORS,
    aces_filmic,
    adapt_exposure,
    auto_exposure,
    exposure,
    log_average_luminance,
    metering_weights,
    reinhard,
    srgb_decode,
    srgb_encode,
    to_srgb8,
    tonemap,
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
    "DITHERS",
    "LUMINANCE_WEIGHTS",
    "MIDDLE_GREY",
    "TONE_OPERATORS",
    "aces_filmic",
    "adapt_exposure",
    "area_footprint",
    "area_weights",
    "auto_exposure",
    "describe",
    "exposure",
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
    "to_srgb8",
    "tonemap",
]
