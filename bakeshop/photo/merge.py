"""Merging an exposure stack into one HDR image, with a per-pixel confidence map.

Each frame ``j`` that sees pixel ``x`` unclipped estimates its radiance as ``X_j / e_j`` (the
response's linear value of its code over the frame's exposure); the merge is the weighted mean

    E(x) = sum_j w_j(x) X_j(x) / e_j  /  sum_j w_j(x)

with ``w = taper(Z) / g'(Z)^2``: the inverse of the variance that a constant code noise gives
an estimate through the curve ``g = ln X`` (so a frame that sees a pixel brighter, where the
curve is flatter in log terms, counts more), times a taper that is exactly 0 at the clipped
ends and rises to 1 over :data:`TAPER` of full scale (and, for a recovered curve, times a ramp
up to :data:`SUPPORT` of full scale: a recovered curve's darkest codes rest on few samples with
Debevec's smallest weights, and are trusted less). Clipping is judged per pixel across
channels: a frame in which any channel of a pixel is at or beyond ``clip_low`` or ``clip_high``
does not vote for that pixel at all (a red channel clipped in a sunset would otherwise tint the
merge with the other channels' larger values).

Where no frame votes, the merge says why in the *status*: every frame clipped high (the sun,
glints: the value is the darkest frame's, a lower bound), every frame at the dark end (the
brightest frame's, an upper bound), or, rarely, each frame clipped in some channel (then each
channel is merged on its own). :func:`bakeshop.photo.recover_sun` can replace a clipped sun by a
model and marks it ``MODELLED``.

Ghost suppression (``ghost=``): per pixel, the reference is the median of the unclipped
frames' estimates (in log, one vote per frame), and a frame whose estimate differs from it by
more than ``ghost`` (natural log of the ratio) plus three times the noise the two codes allow
is left out. Something that moved through the scene in fewer than half of the frames (a walker,
leaves) is then outvoted by the frames that saw the background, instead of blended in as a
ghost. It tests each pixel alone: a moving object seen at about the brightness of what it
covers passes, and one that stood still in most frames wins.

References: Debevec & Malik 1997 (doi:10.1145/258734.258884); Granados et al. 2010, "Optimal
HDR reconstruction with linear digital cameras" (doi:10.1109/CVPR.2010.5540208) for
inverse-variance weights.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, with_article
from bakeshop.photo import _native
from bakeshop.photo.response import KNOWN_CURVES, CameraResponse
from bakeshop.photo.stack import CLIP_HIGH, CLIP_LOW, LUMINANCE_PER_UNIT, ExposureStack, clip_codes
from bakeshop.resources import Cost, require

__all__ = [
    "CLIP_HIGH",
    "CLIP_LOW",
    "MEASURED",
    "CLIPPED",
    "DARK",
    "MODELLED",
    "Merged",
    "clip_codes",
    "confidence_image",
    "merge_stack",
]

#: the weights rise from 0 at a clipped end to full over this fraction of full scale.
TAPER = 0.06
#: a recovered curve's darkest codes are trusted in proportion up to this fraction of full
#: scale (known curves are trusted everywhere).
SUPPORT = 0.25
#: code noise assumed by the ghost test, as a fraction of full scale.
GHOST_NOISE = 0.005
#: rows merged per call of the kernel (progress granularity).
BAND_ROWS = 256

#: status codes of the confidence map.
MEASURED, CLIPPED, DARK, MODELLED = 0, 1, 2, 3
STATUS_NAMES = {MEASURED: "measured", CLIPPED: "clipped", DARK: "dark", MODELLED: "modelled"}


def _tables(
    response: CameraResponse, bits: int, channels: int, low: int, high: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-code linear value, merge weight and log slope (per full scale): (2**bits, C) each."""
    table = response.table(bits, channels)
    top = (1 << bits) - 1
    codes = np.arange(top + 1)
    logs = np.log(np.maximum(table, 1e-300))
    slope = np.gradient(logs, axis=0) * top  # d ln X / d (code / full scale)
    slope = np.maximum(slope, 1e-3)
    ramp = max(TAPER * top, 1.0)
    taper = np.clip((codes - low) / ramp, 0, 1) * np.clip((high - codes) / ramp, 0, 1)
    weight = taper[:, None] / slope**2
    if response.method not in KNOWN_CURVES:
        # a recovered curve rests on few, low-weighted samples at its darkest codes (Debevec's
        # hat): trust them less, rising to full trust at a quarter of full scale
        weight *= np.clip(codes / (SUPPORT * top), 0, 1)[:, None]
    weight[codes <= low] = 0
    weight[codes >= high] = 0
    weight /= weight.max()
    return table.astype(np.float32), weight.astype(np.float32), slope.astype(np.float32)


@dataclass
class Merged:
    """What :func:`merge_stack` returns.

    Attributes
    ----------
    radiance : (H, W, C) float32
        Linear radiance, relative (or cd/m^2 for an absolute stack: see
        :data:`bakeshop.photo.stack.LUMINANCE_PER_UNIT`).
    votes : (H, W) uint8
        Frames that saw the pixel unclipped (and passed the ghost test).
    weight : (H, W) float32
        Sum of their weights (each at most 1): the effective number of well-exposed frames.
    status : (H, W) uint8
        ``MEASURED`` (0), ``CLIPPED`` (1, every frame saturated: a lower bound), ``DARK`` (2,
        every frame at the dark end: an upper bound), ``MODELLED`` (3, written by a model).
    clipped_high, clipped_low : (P,) float64
        Fraction of each frame's pixels clipped at the bright / dark end (in some channel).
    ghost_rejected : (P,) float64
        Fraction of each frame's pixels left out by the ghost test.
    exposures : (P,) float64
    absolute : bool
    """

    radiance: np.ndarray
    votes: np.ndarray
    weight: np.ndarray
    status: np.ndarray
    clipped_high: np.ndarray
    clipped_low: np.ndarray
    ghost_rejected: np.ndarray
    exposures: np.ndarray
    absolute: bool = False

    def fraction(self, code: int) -> float:
        """Fraction of pixels with status ``code``."""
        return float(np.count_nonzero(self.status == code)) / self.status.size


def merge_stack(
    stack: ExposureStack,
    response: CameraResponse,
    *,
    shifts: ArrayLike | None = None,
    ghost: float | None = None,
    clip_low: float | None = None,
    clip_high: float | None = None,
) -> Merged:
    """Merge a bracketed stack into HDR radiance with its confidence.

    Parameters
    ----------
    stack : ExposureStack
        Frames sorted darkest first (:func:`bakeshop.photo.read_stack`,
        :func:`~bakeshop.photo.make_stack`).
    response : CameraResponse
        The inverse response (one curve, or one per channel).
    shifts : (P, 2) float, optional
        Frame ``j`` is read at ``(y + dy_j, x + dx_j)`` (bilinear; taps that touch a clipped
        code make the frame clipped there), from :func:`bakeshop.photo.align_stack`.
    ghost : float, optional
        Ghost suppression threshold (natural log of the ratio, 0.05-5; 0.25 is about 28 %).
        None: off.
    clip_low, clip_high : float, optional
        Clipped ends as fractions of full scale (defaults :data:`CLIP_LOW`, :data:`CLIP_HIGH`).

    Returns
    -------
    Merged
    """
    from bakeshop import progress

    codes = stack.codes
    p, h, w, channels = codes.shape
    if channels not in (1, 3):
        raise ArgumentError(f"frames must have 1 or 3 channels, not {channels}")
    if response.channels not in (1, channels):
        raise ArgumentError(
            f"{with_article(response.channels)}-channel response cannot merge "
            f"{channels}-channel frames"
        )
    low, high = clip_codes(stack.bits, clip_low, clip_high)
    table, weight, slope = _tables(response, stack.bits, channels, low, high)
    if shifts is None:
        shifts = np.zeros((p, 2))
    shifts = np.asarray(shifts, dtype=np.float64)
    if shifts.shape != (p, 2) or not np.isfinite(shifts).all():
        raise ArgumentError(f"shifts must be a finite ({p}, 2) array")
    if ghost is not None and not (math.isfinite(ghost) and 0.05 <= ghost <= 5):
        raise ArgumentError(f"ghost threshold must be within 0.05-5, not {ghost!r}")
    scale = LUMINANCE_PER_UNIT if stack.absolute else 1.0
    inv_exposure = (scale / stack.exposures).astype(np.float32)
    # the outputs (float32 colour, votes, status, weights) and one row of every frame
    need = h * w * (channels * 4 + 6) + h * p * 12
    require(Cost(need, h * w * p, f"merging {p} frames of {w}x{h}"))
    out = np.empty((h, w, channels), np.float32)
    votes = np.empty((h, w), np.uint8)
    wsum = np.empty((h, w), np.float32)
    status = np.empty((h, w), np.uint8)
    counts = np.zeros((h, p, 3), np.int32)
    bands = range(0, h, BAND_ROWS)
    codes = np.ascontiguousarray(codes)
    for r0 in progress.track(bands, f"merging {p} frames", total=len(bands)):
        _native.merge_rows(  # the kernel: src/photo/merge.hpp
            codes, table, weight, slope, int(low), int(high), inv_exposure, shifts,
            float(ghost or 0.0), GHOST_NOISE, r0, min(h, r0 + BAND_ROWS),
            out, votes, wsum, status, counts,
        )  # fmt: skip
    totals = counts.sum(axis=0, dtype=np.int64) / float(h * w)
    return Merged(
        out, votes, wsum, status, totals[:, 0], totals[:, 1], totals[:, 2],
        stack.exposures.copy(), stack.absolute,
    )  # fmt: skip


def confidence_image(merged: Merged) -> np.ndarray:
    """The confidence map as an image, ``(H, W, 3)`` float32: votes, weight, status.

    Channel 0 (R) is the number of frames that voted, 1 (G) the sum of their weights (the
    effective number of well-exposed frames), 2 (B) the status code (0 measured, 1 clipped in
    every frame, 2 dark in every frame, 3 modelled). Saved beside the HDR by ``bakeshop merge``.
    """
    return np.stack(
        [merged.votes.astype(np.float32), merged.weight, merged.status.astype(np.float32)],
        axis=-1,
    )
