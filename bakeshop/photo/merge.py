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

import numba
import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, with_article
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


@numba.njit(parallel=True, cache=True)
def _merge_rows(
    codes: np.ndarray, table: np.ndarray, weight: np.ndarray, slope: np.ndarray,
    low: int, high: int, inv_exposure: np.ndarray, shifts: np.ndarray, ghost: float,
    noise: float, row0: int, row1: int, out: np.ndarray, votes: np.ndarray, wsum: np.ndarray,
    status: np.ndarray, counts: np.ndarray,
) -> None:  # fmt: skip  # pragma: no cover - compiled
    p, h, w, nc = codes.shape
    shift_y = np.floor(shifts[:, 0])
    shift_x = np.floor(shifts[:, 1])
    frac_y = shifts[:, 0] - shift_y
    frac_x = shifts[:, 1] - shift_x
    iys = shift_y.astype(np.int64)
    ixs = shift_x.astype(np.int64)
    whole = True
    for j in range(p):
        if frac_y[j] != 0.0 or frac_x[j] != 0.0:
            whole = False
    lut = np.empty((p, table.shape[0], nc), np.float32)
    for j in range(p):
        for z in range(table.shape[0]):
            for c in range(nc):
                lut[j, z, c] = table[z, c] * inv_exposure[j]
    flag = np.zeros(table.shape[0], np.uint8)
    for z in range(table.shape[0]):
        if z >= high:
            flag[z] = 1
        elif z <= low:
            flag[z] = 2
    for y in numba.prange(row0, row1):
        est = np.empty((p, nc), np.float32)
        wts = np.empty((p, nc), np.float32)
        sig = np.empty(p, np.float32)
        state = np.empty(p, np.int8)
        order_level = np.empty(p, np.float64)
        order_w = np.empty(p, np.float64)
        order_j = np.empty(p, np.int64)
        acc = np.empty(nc, np.float64)
        den = np.empty(nc, np.float64)
        acc_all = np.empty(nc, np.float64)
        den_all = np.empty(nc, np.float64)
        first = np.empty(nc, np.float64)
        last = np.empty(nc, np.float64)
        for x in range(w):
            if ghost == 0.0 and whole:  # no ghost test, whole-pixel shifts: one fused pass
                n = 0
                wsum_total = 0.0
                for c in range(nc):
                    acc[c] = 0.0
                    den[c] = 0.0
                    acc_all[c] = 0.0
                    den_all[c] = 0.0
                first_state = 0
                last_state = 0
                for j in range(p):
                    y0 = min(max(y + iys[j], 0), h - 1)
                    x0 = min(max(x + ixs[j], 0), w - 1)
                    f = 0
                    for c in range(nc):
                        f |= flag[codes[j, y0, x0, c]]
                    state_j = 1 if f & 1 else (2 if f else 0)
                    if state_j == 1:
                        counts[y, j, 0] += 1
                    elif state_j == 2:
                        counts[y, j, 1] += 1
                    total = 0.0
                    for c in range(nc):
                        z = codes[j, y0, x0, c]
                        e = lut[j, z, c]
                        wt = weight[z, c]
                        acc_all[c] += wt * e
                        den_all[c] += wt
                        if j == 0:
                            first[c] = e
                        if j == p - 1:
                            last[c] = e
                        if state_j == 0:
                            acc[c] += wt * e
                            den[c] += wt
                            total += wt
                    if j == 0:
                        first_state = state_j
                    if j == p - 1:
                        last_state = state_j
                    if state_j == 0:
                        n += 1
                        wsum_total += total / nc
                code = 0
                if n == 0:
                    if first_state == 1:
                        code = 1
                        for c in range(nc):
                            acc[c] = first[c]
                            den[c] = 1.0
                    elif last_state == 2:
                        code = 2
                        for c in range(nc):
                            acc[c] = last[c]
                            den[c] = 1.0
                    else:
                        for c in range(nc):
                            if den_all[c] > 0.0:
                                acc[c] = acc_all[c]
                                den[c] = den_all[c]
                            else:
                                acc[c] = first[c]
                                den[c] = 1.0
                for c in range(nc):
                    out[y, x, c] = acc[c] / den[c] if den[c] > 0.0 else 0.0
                votes[y, x] = n
                wsum[y, x] = wsum_total
                status[y, x] = code
                continue
            for j in range(p):
                iy = int(shift_y[j])
                ix = int(shift_x[j])
                fy = frac_y[j]
                fx = frac_x[j]
                y0 = min(max(y + iy, 0), h - 1)
                x0 = min(max(x + ix, 0), w - 1)
                y1 = min(max(y + iy + 1, 0), h - 1)
                x1 = min(max(x + ix + 1, 0), w - 1)
                hi = False
                lo = False
                sig[j] = 0.0
                if fy == 0.0 and fx == 0.0:  # a whole-pixel shift (or none): one tap
                    s_j = 0.0
                    for c in range(nc):
                        z = codes[j, y0, x0, c]
                        f = flag[z]
                        if f == 1:
                            hi = True
                        elif f == 2:
                            lo = True
                        est[j, c] = table[z, c] * inv_exposure[j]
                        wts[j, c] = weight[z, c]
                        s_j += slope[z, c]
                    sig[j] = s_j / nc
                else:
                    for c in range(nc):
                        lin = 0.0
                        wt = 0.0
                        sl = 0.0
                        for t in range(4):
                            ty = y0 if t < 2 else y1
                            tx = x0 if t % 2 == 0 else x1
                            tw = (1.0 - fy if t < 2 else fy) * (1.0 - fx if t % 2 == 0 else fx)
                            if tw <= 0.0:
                                continue
                            z = codes[j, ty, tx, c]
                            if z >= high:
                                hi = True
                            if z <= low:
                                lo = True
                            lin += tw * table[z, c]
                            wt += tw * weight[z, c]
                            sl += tw * slope[z, c]
                        est[j, c] = lin * inv_exposure[j]
                        wts[j, c] = wt
                        sig[j] += sl / nc
                state[j] = 1 if hi else (2 if lo else 0)
                if hi:
                    counts[y, j, 0] += 1
                elif lo:
                    counts[y, j, 1] += 1
            # the reference for the ghost test: the median of the unclipped frames' log levels,
            # one vote each (the frames that agree outvote one that saw something else, however
            # well exposed it is)
            ref_level = 0.0
            ref_sig = 0.0
            if ghost > 0.0:
                m = 0
                total_w = 0.0
                for j in range(p):
                    if state[j] == 0:
                        level = 0.0
                        for c in range(nc):
                            level += est[j, c]
                        if level > 0.0:
                            order_level[m] = math.log(level)
                            order_w[m] = 1.0
                            order_j[m] = j
                            total_w += 1.0
                            m += 1
                for a in range(1, m):  # insertion sort by level (m <= 64)
                    lv, wv, jv = order_level[a], order_w[a], order_j[a]
                    b = a - 1
                    while b >= 0 and order_level[b] > lv:
                        order_level[b + 1] = order_level[b]
                        order_w[b + 1] = order_w[b]
                        order_j[b + 1] = order_j[b]
                        b -= 1
                    order_level[b + 1] = lv
                    order_w[b + 1] = wv
                    order_j[b + 1] = jv
                run = 0.0
                for a in range(m):
                    run += order_w[a]
                    if run >= 0.5 * total_w:
                        ref_level = order_level[a]
                        ref_sig = sig[order_j[a]]
                        break
            n = 0
            wsum_total = 0.0
            for c in range(nc):
                out[y, x, c] = 0.0
            for c in range(nc):
                acc[c] = 0.0
                den[c] = 0.0
            for j in range(p):
                if state[j] != 0:
                    continue
                if ghost > 0.0:
                    level = 0.0
                    for c in range(nc):
                        level += est[j, c]
                    if level <= 0.0:
                        continue
                    if abs(math.log(level) - ref_level) > ghost + 3.0 * noise * (sig[j] + ref_sig):
                        counts[y, j, 2] += 1
                        continue
                n += 1
                total = 0.0
                for c in range(nc):
                    acc[c] += wts[j, c] * est[j, c]
                    den[c] += wts[j, c]
                    total += wts[j, c]
                wsum_total += total / nc
            code = 0
            if n == 0:
                if state[0] == 1:
                    code = 1  # the darkest frame is clipped: a lower bound
                    for c in range(nc):
                        acc[c] = est[0, c]
                        den[c] = 1.0
                elif state[p - 1] == 2:
                    code = 2  # the brightest frame is dark: an upper bound
                    for c in range(nc):
                        acc[c] = est[p - 1, c]
                        den[c] = 1.0
                else:  # each frame clipped in some channel: every channel on its own
                    for j in range(p):
                        for c in range(nc):
                            acc[c] += wts[j, c] * est[j, c]
                            den[c] += wts[j, c]
                    for c in range(nc):
                        if den[c] <= 0.0:
                            acc[c] = est[0, c]
                            den[c] = 1.0
            for c in range(nc):
                out[y, x, c] = acc[c] / den[c] if den[c] > 0.0 else 0.0
            votes[y, x] = n
            wsum[y, x] = wsum_total
            status[y, x] = code


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
    for r0 in progress.track(bands, f"merging {p} frames", total=len(bands)):
        _merge_rows(
            codes, table, weight, slope, low, high, inv_exposure, shifts,
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
