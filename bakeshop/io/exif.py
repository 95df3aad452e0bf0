"""The exposure a photograph was taken at, from its EXIF tags (JPEG, TIFF, PNG eXIf).

Read through Pillow, which parses the tags without decoding the pixels. Tags used (EXIF 2.32,
CIPA DC-008): ExposureTime (0x829A, seconds), FNumber (0x829D), PhotographicSensitivity
(0x8827, the ISO speed), ExposureBiasValue (0x9204, EV, reported only), Make and Model.
"""

from __future__ import annotations

import math
import os
import warnings
from typing import Any

from bakeshop.errors import BakeshopError, FormatError

__all__ = ["read_exposure"]

_EXIF_IFD = 0x8769
_TAGS = {
    0x829A: "exposure_time",
    0x829D: "f_number",
    0x8827: "iso",
    0x9204: "exposure_bias",
}


def _number(value: Any) -> float | None:
    """An EXIF rational, integer or tuple of them -> a finite positive float, or None."""
    if isinstance(value, (tuple, list)):
        value = value[0] if value else None
    try:
        number = float(value)
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    return number if math.isfinite(number) else None


def read_exposure(path: str | os.PathLike) -> dict:
    """The exposure settings recorded in a photograph's EXIF.

    Parameters
    ----------
    path : path-like
        A JPEG, TIFF or PNG file.

    Returns
    -------
    dict
        ``exposure_time`` (s), ``f_number``, ``iso`` and ``exposure_bias`` (EV) for each tag
        present with a finite value (exposure time, f-number and ISO only when positive), plus
        ``make`` and ``model`` when recorded. Empty when the file has no EXIF.

    Raises
    ------
    bakeshop.errors.FormatError
        The file is not an image Pillow can open.
    """
    from PIL import Image

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with Image.open(path) as image:
                exif = image.getexif()
                tags = dict(exif.get_ifd(_EXIF_IFD))
                tags.update({k: v for k, v in exif.items() if k in _TAGS})
                make, model = exif.get(0x010F), exif.get(0x0110)
    except OSError as e:
        if isinstance(e, FileNotFoundError):
            raise BakeshopError(e.strerror or str(e), path) from None
        raise FormatError(f"cannot read its EXIF: {e}", path) from None
    except Exception as e:  # Pillow raises many kinds on damaged metadata
        raise FormatError(f"damaged EXIF: {e}", path) from None
    out: dict = {}
    for tag, name in _TAGS.items():
        number = _number(tags.get(tag))
        if number is not None and (number > 0 or name == "exposure_bias"):
            out[name] = number
    for name, value in (("make", make), ("model", model)):
        if isinstance(value, str) and value.strip("\x00 "):
            out[name] = value.strip("\x00 ")
    return out
