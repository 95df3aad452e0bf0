"""From photographs to a light probe: bracketed exposures merged to HDR, mirror balls unwrapped.

>>> from bakeshop.photo import read_stack, recover_response, merge_stack
>>> stack = read_stack(["b1.jpg", "b2.jpg", "b3.jpg"])          # exposures from EXIF
>>> response = recover_response(stack.codes, stack.exposures)   # Debevec-Malik
>>> merged = merge_stack(stack, response)                        # radiance + confidence

Modules: ``stack`` (frames and exposures), ``response`` (camera curves), ``merge`` (weighted
merge, clipping, ghosts, confidence), ``align`` (median-threshold bitmaps and sub-pixel
refinement), ``sun`` (a clipped sun recovered from its aureole), ``mirrorball`` (find, unwrap
and merge photographs of a mirror ball), ``quality`` (measures for comparing merges). See
docs/photographs.md.
"""

from bakeshop.photo.align import align_stack
from bakeshop.photo.merge import (
    CLIPPED,
    DARK,
    MEASURED,
    MODELLED,
    Merged,
    confidence_image,
    merge_stack,
)
from bakeshop.photo.mirrorball import (
    Circle,
    best_yaw,
    card_reflectance,
    crop_ball,
    find_ball,
    merge_views,
    unwrap,
)
from bakeshop.photo.quality import log2_rmse, multi_exposure_psnr, relative_scale
from bakeshop.photo.response import (
    KNOWN_CURVES,
    RESPONSE_METHODS,
    CameraResponse,
    known_response,
    recover_response,
    select_samples,
)
from bakeshop.photo.stack import ExposureStack, make_stack, read_stack
from bakeshop.photo.sun import SunRecovery, recover_sun

__all__ = [
    "CLIPPED",
    "DARK",
    "KNOWN_CURVES",
    "MEASURED",
    "MODELLED",
    "RESPONSE_METHODS",
    "CameraResponse",
    "Circle",
    "ExposureStack",
    "Merged",
    "SunRecovery",
    "align_stack",
    "best_yaw",
    "card_reflectance",
    "confidence_image",
    "crop_ball",
    "find_ball",
    "known_response",
    "log2_rmse",
    "make_stack",
    "merge_stack",
    "merge_views",
    "multi_exposure_psnr",
    "read_stack",
    "recover_response",
    "recover_sun",
    "relative_scale",
    "select_samples",
    "unwrap",
]
