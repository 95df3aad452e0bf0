"""Aligning hand-held brackets: median-threshold bitmaps, then a sub-pixel refinement.

Frames of different exposure cannot be compared value for value, but a monotonic response keeps
the *order* of values. Two steps use that:

1. **Median-threshold bitmaps** (Ward 2003, doi:10.1080/10867651.2003.10487583): each frame,
   reduced to grey, becomes a bitmap of "brighter than its own median" (or, when the median is
   clipped, of a percentile both frames see unclipped), with pixels within a few codes of the
   threshold excluded. An image pyramid finds the whole-pixel shift that minimises the
   rate of differing bits, a pixel of search per level (two at the last), up to
   ``max_shift`` pixels.
2. **Sub-pixel refinement**: each frame is mapped through its own cumulative histogram (its
   codes become ranks in [0, 1], comparable across exposures), lightly blurred, and the
   translation is refined by Lucas-Kanade iterations (Lucas & Kanade 1981) on the most
   textured tiles that neither frame clips, interpolating with cubic splines.

The result is one ``(dy, dx)`` per frame: frame ``j`` read at ``(y + dy, x + dx)`` matches the
reference frame at ``(y, x)``; :func:`bakeshop.photo.merge_stack` and
:func:`bakeshop.photo.recover_response` take it as ``shifts``. Only translation is estimated
(a tripod-free bracket taken in a second rotates by a small fraction of a degree).
"""

from __future__ import annotations

import math

import numpy as np

from bakeshop.errors import ArgumentError

__all__ = ["align_stack"]

#: offsets searched at full resolution around twice the coarser level's answer (Ward searches
#: +-1 at every level; +-2 at the last also corrects a coarser level that was a whole pixel off,
#: which halving makes common; wider at the coarse levels finds false minima).
SEARCH = (-2, -1, 0, 1, 2)
#: pixels within this fraction of full scale of the threshold are excluded (Ward: 4 of 255).
EXCLUSION = 4 / 255
#: tiles used by the refinement, and their side in pixels.
TILES = 24
TILE = 96
#: Lucas-Kanade iterations and the step (pixels) below which they stop.
ITERATIONS = 20
CONVERGED = 1e-3
#: Gaussian blur of the rank images before the refinement (pixels).
BLUR = 1.0


def _grey(frame: np.ndarray) -> np.ndarray:
    """(H, W, C) codes -> (H, W) float32 grey (Ward's 54 R + 183 G + 19 B) / 256."""
    f = frame.astype(np.float32)
    if f.shape[2] == 1:
        return f[..., 0]
    return (54 * f[..., 0] + 183 * f[..., 1] + 19 * f[..., 2]) / 256


def _halve(a: np.ndarray) -> np.ndarray:
    h, w = a.shape[0] // 2 * 2, a.shape[1] // 2 * 2
    a = a[:h, :w]
    return 0.25 * (a[0::2, 0::2] + a[1::2, 0::2] + a[0::2, 1::2] + a[1::2, 1::2])


def _shifted(bits: np.ndarray, dy: int, dx: int) -> np.ndarray:
    """``bits`` moved so that out[y, x] = bits[y + dy, x + dx]; False where it has no source."""
    out = np.zeros_like(bits)
    h, w = bits.shape
    ys, yd = (slice(dy, h), slice(0, h - dy)) if dy >= 0 else (slice(0, h + dy), slice(-dy, h))
    xs, xd = (slice(dx, w), slice(0, w - dx)) if dx >= 0 else (slice(0, w + dx), slice(-dx, w))
    out[yd, xd] = bits[ys, xs]
    return out


def _bitmaps(grey: np.ndarray, level_value: float, band: float) -> tuple[np.ndarray, np.ndarray]:
    return grey > level_value, np.abs(grey - level_value) > band


def _mtb_shift(
    ref_grey: np.ndarray, grey: np.ndarray, top: int, levels: int, ref_q: float, q: float
) -> tuple[int, int]:
    """Whole-pixel shift of ``grey`` onto ``ref_grey`` by the median-threshold pyramid."""
    pyr_ref, pyr = [ref_grey], [grey]
    for _ in range(levels):
        pyr_ref.append(_halve(pyr_ref[-1]))
        pyr.append(_halve(pyr[-1]))
    dy = dx = 0
    band = EXCLUSION * top
    for level in range(levels, -1, -1):
        dy, dx = 2 * dy, 2 * dx
        tb_r, eb_r = _bitmaps(pyr_ref[level], ref_q, band)
        tb, eb = _bitmaps(pyr[level], q, band)
        best: tuple[float, int, int] | None = None
        search = SEARCH if level == 0 else SEARCH[1:-1]
        for sy in search:
            for sx in search:
                ty, tx = dy + sy, dx + sx
                compared = eb_r & _shifted(eb, ty, tx)
                diff = (tb_r ^ _shifted(tb, ty, tx)) & compared
                # a rate, not a count: a shift that pushes part of the frame out of the picture
                # compares fewer pixels and must not win for it
                err = np.count_nonzero(diff) / max(int(np.count_nonzero(compared)), 1)
                if best is None or err < best[0]:
                    best = (err, ty, tx)
        assert best is not None  # the search has at least one shift
        _, dy, dx = best
    return dy, dx


def _thresholds(
    ref_grey: np.ndarray, grey: np.ndarray, top: int, low: int, high: int
) -> tuple[float, float]:
    """A common percentile both frames see unclipped: the median when it lies well inside the
    range both see (a quarter of it from either end), else the middle of that range."""
    n = ref_grey.size
    lo = max(np.count_nonzero(ref_grey <= low), np.count_nonzero(grey <= low)) / n
    hi = 1 - max(np.count_nonzero(ref_grey >= high), np.count_nonzero(grey >= high)) / n
    if hi - lo < 0.02:
        return float("nan"), float("nan")
    margin = 0.25 * (hi - lo)  # keep the threshold well inside what both frames see
    q = 0.5 if lo + margin <= 0.5 <= hi - margin else 0.5 * (lo + hi)
    return float(np.quantile(ref_grey, q)), float(np.quantile(grey, q))


def _ranks(grey: np.ndarray, top: int) -> np.ndarray:
    """Each code replaced by the fraction of the frame's pixels at or below it."""
    codes = np.clip(np.rint(grey), 0, top).astype(np.int64)
    cdf = np.cumsum(np.bincount(codes.ravel(), minlength=top + 1)) / codes.size
    return cdf[codes].astype(np.float64)


def _tiles(ref_rank: np.ndarray, usable: np.ndarray, dy: float, dx: float) -> list[tuple[int, int]]:
    """Corners of the most textured tiles that both frames see (never near the border)."""
    h, w = ref_rank.shape
    margin = int(max(abs(dy), abs(dx))) + 8
    gy, gx = np.gradient(ref_rank)
    energy = gy * gy + gx * gx
    corners = []
    for y in range(margin, h - margin - TILE + 1, TILE):
        for x in range(margin, w - margin - TILE + 1, TILE):
            if usable[y : y + TILE, x : x + TILE].mean() < 0.9:
                continue
            corners.append((float(energy[y : y + TILE, x : x + TILE].mean()), y, x))
    corners.sort(reverse=True)
    return [(y, x) for _, y, x in corners[:TILES]]


def _refine(
    ref_rank: np.ndarray, rank: np.ndarray, usable: np.ndarray, dy: float, dx: float
) -> tuple[float, float]:
    """Lucas-Kanade translation from the whole-pixel start (dy, dx)."""
    from scipy.ndimage import map_coordinates, spline_filter

    tiles = _tiles(ref_rank, usable, dy, dx)
    if not tiles:
        return float(dy), float(dx)
    pad = int(max(abs(dy), abs(dx))) + 4
    patches = []
    for y, x in tiles:
        r = ref_rank[y : y + TILE, x : x + TILE]
        gy, gx = np.gradient(r)
        m = usable[y : y + TILE, x : x + TILE]
        y0, x0 = max(y - pad, 0), max(x - pad, 0)
        src = rank[y0 : y + TILE + pad, x0 : x + TILE + pad]
        patches.append((r, gy[m], gx[m], m, spline_filter(src, order=3), y - y0, x - x0))
    jtj = np.zeros((2, 2))
    for _, gy, gx, *_ in patches:
        jtj += [[gy @ gy, gy @ gx], [gx @ gy, gx @ gx]]
    if np.linalg.cond(jtj) > 1e6:
        return float(dy), float(dx)
    ty, tx = float(dy), float(dx)
    yy, xx = np.mgrid[0:TILE, 0:TILE].astype(np.float64)
    for _ in range(ITERATIONS):
        b = np.zeros(2)
        for r, gy, gx, m, coef, oy, ox in patches:
            moved = map_coordinates(
                coef, [yy + oy + ty, xx + ox + tx], order=3, prefilter=False, mode="nearest"
            )
            e = (r - moved)[m]
            b += [gy @ e, gx @ e]
        step = np.linalg.solve(jtj, b)
        # M(p + t + s) ~ M(p + t) + grad R . s (the reference's gradient stands in for the
        # moved frame's): s solves the least squares of R - M(p + t) = grad R . s
        ty += step[0]
        tx += step[1]
        if math.hypot(*step) < CONVERGED:
            break
    return ty, tx


def align_stack(
    codes: np.ndarray,
    *,
    reference: int | None = None,
    max_shift: int = 64,
    subpixel: bool = True,
    clip_low: float | None = None,
    clip_high: float | None = None,
) -> np.ndarray:
    """Translations that align every frame of a stack with a reference frame.

    Parameters
    ----------
    codes : (P, H, W, C) uint8 or uint16
        The frames (sorted by exposure or not).
    reference : int, optional
        Index of the frame the others are aligned to; default the middle one.
    max_shift : int
        Largest shift searched, in pixels (1-1024): the pyramid has ``ceil(log2(max_shift))``
        levels.
    subpixel : bool
        Refine the whole-pixel shifts (see the module notes).
    clip_low, clip_high : float, optional
        Clipped ends, fractions of full scale (as :func:`bakeshop.photo.merge_stack`).

    Returns
    -------
    (P, 2) float64
        ``(dy, dx)`` per frame; the reference's is ``(0, 0)``. A frame that shares too little
        unclipped range with the reference is aligned to its neighbour towards it and the
        shifts are composed; one that shares too little with both takes its neighbour's
        shift.
    """
    from scipy.ndimage import gaussian_filter

    from bakeshop import progress
    from bakeshop.photo.stack import clip_codes

    codes = np.asarray(codes)
    if codes.ndim != 4 or codes.dtype not in (np.uint8, np.uint16):
        raise ArgumentError("codes must be a (P, H, W, C) uint8 or uint16 stack")
    p = codes.shape[0]
    reference = p // 2 if reference is None else int(reference)
    if not 0 <= reference < p:
        raise ArgumentError(f"reference frame {reference} is not one of 0..{p - 1}")
    if not 1 <= max_shift <= 1024:
        raise ArgumentError(f"max_shift must be within 1-1024, not {max_shift}")
    top = int(np.iinfo(codes.dtype).max)
    low, high = clip_codes(8 if top == 255 else 16, clip_low, clip_high)
    min_side = min(codes.shape[1:3])
    levels = max(0, min(math.ceil(math.log2(max_shift)), int(math.log2(max(min_side, 2))) - 4))

    def frame(j: int) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        grey = _grey(codes[j])
        ok = (codes[j] > low).all(axis=-1) & (codes[j] < high).all(axis=-1)
        rank = gaussian_filter(_ranks(grey, top), BLUR) if subpixel else None
        return grey, ok, rank

    def step(
        near: tuple[np.ndarray, np.ndarray, np.ndarray | None],
        far: tuple[np.ndarray, np.ndarray, np.ndarray | None],
    ) -> tuple[float, float] | None:
        """Shift of frame ``far`` onto its neighbour ``near`` (None: too little overlap)."""
        ref_grey, ref_ok, ref_rank = near
        grey, ok, rank = far
        ref_q, q = _thresholds(ref_grey, grey, top, low, high)
        if math.isnan(q):
            return None
        dy, dx = _mtb_shift(ref_grey, grey, top, levels, ref_q, q)
        if ref_rank is None or rank is None:  # ranks are made only for subpixel
            return float(dy), float(dx)
        return _refine(ref_rank, rank, ref_ok & _shifted(ok, dy, dx), dy, dx)

    # each frame is aligned to the reference; one too dark or too bright to share a
    # well-exposed range with it is aligned to its neighbour towards the reference and the
    # shifts composed (frame j at q + s_near + d matches its neighbour at q + s_near, which
    # matches the reference at q: s_j = s_near + d)
    shifts = np.zeros((p, 2))
    with progress.step(f"aligning {p} frames"):
        ref = frame(reference)
        for direction in (-1, 1):
            near = ref
            j = reference + direction
            while 0 <= j < p:
                far = frame(j)
                d = step(ref, far)
                if d is not None:
                    shifts[j] = d
                else:
                    d = step(near, far)
                    shifts[j] = shifts[j - direction] + (d if d is not None else (0.0, 0.0))
                near = far
                j += direction
    return shifts
