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

from typing import TYPE_CHECKING

from bakeshop._lazy import export_lazily

# names load from their module when first read (scipy and the kernels only with resize and display)
export_lazily(
    __name__,
    {
        "ACES_FITS": "display",
        "DITHERS": "display",
        "TONE_OPERATORS": "display",
        "aces_filmic": "display",
        "exposure": "display",
        "reinhard": "display",
        "srgb_decode": "display",
        "srgb_encode": "display",
        "to_srgb8": "display",
        "tonemap": "display",
        "MIDDLE_GREY": "metering",
        "adapt_exposure": "metering",
        "auto_exposure": "metering",
        "log_average_luminance": "metering",
        "metering_weights": "metering",
        "CLIP_FRACTION": "picture",
        "ENCODINGS": "picture",
        "EXPOSURE_MODES": "picture",
        "MAX_EV": "picture",
        "Exposure": "picture",
        "Picture": "picture",
        "check_ev": "picture",
        "choose_exposure": "picture",
        "encode_picture": "picture",
        "fit_exposure": "picture",
        "to_picture": "picture",
        "area_footprint": "resize",
        "area_weights": "resize",
        "resample_separable": "resize",
        "resize_area": "resize",
        "resize_area_cost": "resize",
        "resize_area_part": "resize",
        "LUMINANCE_WEIGHTS": "statistics",
        "describe": "statistics",
        "luminance": "statistics",
    },
)

if TYPE_CHECKING:  # what the table loads, for type checkers (tests/test_lazy.py)
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
    from bakeshop.image.statistics import (
        LUMINANCE_WEIGHTS,
        describe,
        luminance,
    )

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
