"""Photographs of a mirror ball: find the ball, unwrap it, merge two views, correct its tint.

Geometry. A camera far from a mirror ball (orthographic view along its axis) sees, at the
ball-plane point ``(a, b)`` (``a`` right, ``b`` up, in ball radii, ``r^2 = a^2 + b^2 <= 1``),
the surface normal ``n = (a, b, sqrt(1 - r^2))`` and the reflection of its view ray
``v = (0, 0, -1)``:

    d = v - 2 (v . n) n = (2 n_z a, 2 n_z b, 2 n_z^2 - 1),

so the angle ``theta`` from the ball's centre direction obeys ``r = sin(theta / 2)``. This is the
*physical* convention (``convention="physical"``): the centre of the ball shows +Z, what is
behind the camera (the photographer), the rim shows -Z. HDRShop reads the same picture with the
centre looking forward (-Z) and the rim behind: its directions are the physical ones with z
negated, ``d = (a/r sin(theta), b/r sin(theta), -cos(theta))`` (DESIGN.md, "World frame and
layouts"). ``convention="hdrshop"``, the default, makes what HDRShop makes from the same photo;
``"physical"`` is the world as it was, for matching a photographed set.

Finding the ball: a gradient Hough transform on a reduced copy gives the centre and radius to a
pixel or two; then, along 720 rays from the centre, the position of the strongest edge is found
to a fraction of a pixel (parabolic peak of the derivative of the blurred profile), and a circle
is fitted to those points by geometric least squares with outliers (the stand, a rim that
blends into the background) rejected.

Two views: a ball photographed from two positions 90 degrees apart around the vertical shows
the photographer and the camera at each view's centre direction, and stretches the other side
into its rim. Each view weighs each direction by ``(1 + cos(theta)) / 2`` (the ratio of the
ball's radial to tangential resolution there, 0 at the rim) times a ramp that is 0 within
``exclude_deg`` of its own centre direction (the photographer) and 1 beyond 1.5 times that, and
the merge is the weighted mean: the photographer of one view is filled by the other.

Reflectance: a chrome ball reflects 60-80 % of the light, not all of it; divide by a known
value, or measure it as the ratio of a grey card's reflection in the ball to the card seen
directly in the same photo (:func:`card_reflectance`). The reflectance is taken as the same
at every angle (a metal's Fresnel reflectance rises only near grazing incidence, at the rim).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice, with_article

__all__ = [
    "BALL_CONVENTIONS",
    "UNWRAP_LAYOUTS",
    "Circle",
    "ball_coordinates",
    "ball_directions",
    "best_yaw",
    "card_reflectance",
    "crop_ball",
    "find_ball",
    "layout_directions",
    "merge_views",
    "unwrap",
    "view_weight",
]

BallConvention = Literal["hdrshop", "physical"]
BALL_CONVENTIONS = ("hdrshop", "physical")
UnwrapLayout = Literal["latlong", "angular", "mirrorball"]
UNWRAP_LAYOUTS = ("latlong", "angular", "mirrorball")

#: rays cast from the centre when refining the rim.
RIM_RAYS = 720
#: the coarse search works on a copy at most this many pixels on a side.
COARSE_SIDE = 512
#: photographer cone of each view, degrees (the default of ``exclude_deg``).
EXCLUDE_DEG = 25.0


@dataclass(frozen=True)
class Circle:
    """The ball in a photo: centre ``(x, y)`` and ``radius`` in pixels; pixel ``(i, j)`` covers
    ``[i, i + 1] x [j, j + 1]`` (its centre is at ``i + 0.5``), ``y`` down; ``residual`` is the
    RMS distance of the rim points to the circle, ``points`` how many were kept."""

    x: float
    y: float
    radius: float
    residual: float = 0.0
    points: int = 0


# --- geometry ---------------------------------------------------------------------------------


def ball_directions(
    a: ArrayLike, b: ArrayLike, convention: BallConvention = "hdrshop"
) -> np.ndarray:
    """World directions seen at ball-plane points ``(a, b)`` (``b`` up, ball radii).

    Points outside the disk are clamped to its rim. Returns ``(..., 3)`` float64.
    """
    validate_choice(convention, BALL_CONVENTIONS, "ball convention")
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    r = np.hypot(a, b)
    scale = np.where(r > 1, 1 / np.maximum(r, 1e-300), 1.0)
    a, b = a * scale, b * scale
    nz = np.sqrt(np.clip(1 - a * a - b * b, 0, None))
    d = np.stack([2 * nz * a, 2 * nz * b, 2 * nz * nz - 1], axis=-1)
    if convention == "hdrshop":
        d[..., 2] = -d[..., 2]
    return d


def ball_coordinates(dirs: ArrayLike, convention: BallConvention = "hdrshop") -> np.ndarray:
    """Ball-plane points ``(a, b)`` where directions are seen: the inverse of
    :func:`ball_directions`. Returns ``(..., 2)``; the direction straight behind the ball
    (the rim's) goes to ``(0, -1)``."""
    validate_choice(convention, BALL_CONVENTIONS, "ball convention")
    d = np.asarray(dirs, dtype=np.float64)
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    toward = d[..., 2] if convention == "physical" else -d[..., 2]  # cos(theta) from the centre
    r = np.sqrt(np.clip((1 - toward) / 2, 0, 1))  # sin(theta / 2)
    side = np.hypot(d[..., 0], d[..., 1])
    safe = np.where(side > 1e-12, side, 1.0)
    a = np.where(side > 1e-12, d[..., 0] / safe * r, 0.0)
    b = np.where(side > 1e-12, d[..., 1] / safe * r, -r)
    return np.stack([a, b], axis=-1)


def layout_directions(layout: UnwrapLayout, size: int) -> tuple[np.ndarray, np.ndarray]:
    """Texel-centre directions of an output layout, from DESIGN.md's formulas.

    ``latlong`` is ``(size, 2 size)``: ``phi = 2 pi (u - 1/2)``, ``theta = pi v``,
    ``d = (sin theta sin phi, cos theta, -sin theta cos phi)``. ``angular`` is ``(size, size)``,
    HDRShop's: ``a = 2u - 1``, ``b = 1 - 2v``, ``theta = pi r``,
    ``d = (a/r sin theta, b/r sin theta, -cos theta)``, valid for ``r <= 1``. ``mirrorball``
    is HDRShop's ball picture: ``r = sin(theta / 2)``, the same ``(a, b)``, centre -Z.

    Returns ``dirs (H, W, 3)`` and ``valid (H, W)``.
    """
    validate_choice(layout, UNWRAP_LAYOUTS, "layout")
    if not 1 <= size <= 32768:
        raise ArgumentError(f"output size must be within 1-32768, not {size}")
    if layout == "latlong":
        v = (np.arange(size) + 0.5) / size
        u = (np.arange(2 * size) + 0.5) / (2 * size)
        theta = np.pi * v[:, None]
        phi = 2 * np.pi * (u[None, :] - 0.5)
        d = np.stack(
            np.broadcast_arrays(
                np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)
            ),
            axis=-1,
        )
        return d, np.ones(d.shape[:2], bool)
    c = (np.arange(size) + 0.5) / size
    a = 2 * c[None, :] - 1
    b = 1 - 2 * c[:, None]
    a, b = np.broadcast_arrays(a, b)
    r = np.hypot(a, b)
    valid = r <= 1
    if layout == "mirrorball":
        return ball_directions(a, b, "hdrshop"), valid
    theta = np.pi * np.minimum(r, 1)
    safe = np.where(r > 0, r, 1.0)
    d = np.stack([a / safe * np.sin(theta), b / safe * np.sin(theta), -np.cos(theta)], axis=-1)
    return d, valid


def _yaw(degrees: float) -> np.ndarray:
    t = math.radians(degrees)
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def view_weight(
    dirs: ArrayLike, convention: BallConvention = "hdrshop", *, exclude_deg: float = EXCLUDE_DEG
) -> np.ndarray:
    """How well a ball view sees each direction (in the view's own frame): ``(1 + cos theta)/2``
    with ``theta`` the angle from the view's centre direction (1 there, 0 at the rim), times a
    smooth ramp from 0 within ``exclude_deg`` of the centre direction (the photographer) to 1
    at 1.5 times that."""
    d = np.asarray(dirs, dtype=np.float64)
    toward = d[..., 2] if convention == "physical" else -d[..., 2]
    from_centre = np.degrees(np.arccos(np.clip(toward, -1, 1)))
    resolution = (1 + toward) / 2
    if exclude_deg <= 0:
        return resolution
    ramp = np.clip((from_centre - exclude_deg) / (0.5 * exclude_deg), 0, 1)
    return resolution * ramp * ramp * (3 - 2 * ramp)


# --- unwrapping -------------------------------------------------------------------------------


def _check_photo(photo: ArrayLike) -> np.ndarray:
    a = np.asarray(photo)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in (1, 3, 4):
        raise ArgumentError(f"a photo must be (H, W, C) with C in 1, 3, 4; got {a.shape}")
    return a.astype(np.float32, copy=False)


def _sample(photo: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """Bilinear samples at continuous pixel coordinates (pixel centres at i + 0.5)."""
    from scipy.ndimage import map_coordinates

    coords = [np.asarray(ys) - 0.5, np.asarray(xs) - 0.5]
    return np.stack(
        [
            map_coordinates(photo[..., c], coords, order=1, mode="nearest")
            for c in range(photo.shape[2])
        ],
        axis=-1,
    ).astype(np.float32)


def _check_circle(circle: Circle, photo: np.ndarray) -> None:
    h, w = photo.shape[:2]
    ok = all(math.isfinite(v) for v in (circle.x, circle.y, circle.radius))
    if not ok or circle.radius < 4 or circle.radius > 2 * max(h, w):
        raise ArgumentError(f"implausible ball circle {circle} for {with_article(w)}x{h} photo")


def crop_ball(photo: ArrayLike, circle: Circle, *, size: int | None = None) -> np.ndarray:
    """The square picture of the ball (HDRShop's mirror-ball image): the circle fills it.

    ``size`` defaults to the ball's diameter in pixels (rounded up). Texels outside the disk
    hold what the photo has there.
    """
    photo = _check_photo(photo)
    _check_circle(circle, photo)
    size = int(math.ceil(2 * circle.radius)) if size is None else int(size)
    if not 1 <= size <= 32768:
        raise ArgumentError(f"crop size must be within 1-32768, not {size}")
    c = (np.arange(size) + 0.5) / size * 2 - 1
    a, b = np.meshgrid(c, -c)
    return _sample(photo, circle.x + a * circle.radius, circle.y - b * circle.radius)


def unwrap(
    photo: ArrayLike,
    circle: Circle,
    *,
    to: UnwrapLayout = "latlong",
    size: int | None = None,
    convention: BallConvention = "hdrshop",
    yaw_deg: float = 0.0,
) -> np.ndarray:
    """Unwrap a photographed mirror ball into an environment.

    Parameters
    ----------
    photo : (H, W, C) array
        The photograph (linear radiance for an HDR result).
    circle : Circle
        The ball (:func:`find_ball`).
    to : {"latlong", "angular", "mirrorball"}
        Output layout, DESIGN.md's (see :func:`layout_directions`).
    size : int, optional
        Output height (latlong) or edge. Default: the ball's diameter in pixels.
    convention : {"hdrshop", "physical"}
        How ball points map to directions (see the module notes). Default HDRShop's.
    yaw_deg : float
        The view turned about +Y (degrees, counter-clockwise seen from above) before it is
        written: the rotation that brings a second view into the first one's frame.

    Returns
    -------
    (H', W', C) float32
        Zero outside the disk of angular and mirror-ball outputs.
    """
    photo = _check_photo(photo)
    _check_circle(circle, photo)
    validate_choice(to, UNWRAP_LAYOUTS, "layout")
    validate_choice(convention, BALL_CONVENTIONS, "ball convention")
    if not math.isfinite(yaw_deg):
        raise ArgumentError("yaw must be finite")
    size = int(math.ceil(2 * circle.radius)) if size is None else int(size)
    if to == "mirrorball" and convention == "hdrshop" and yaw_deg == 0:
        return crop_ball(photo, circle, size=size)
    dirs, valid = layout_directions(to, size)
    own = dirs @ _yaw(yaw_deg)  # world -> the view's frame: R^T d, written as d R
    ab = ball_coordinates(own, convention)
    out = _sample(
        photo, circle.x + ab[..., 0] * circle.radius, circle.y - ab[..., 1] * circle.radius
    )
    out[~valid] = 0
    return out


def merge_views(
    photos: Sequence[ArrayLike],
    circles: Sequence[Circle],
    *,
    yaws_deg: Sequence[float],
    to: UnwrapLayout = "latlong",
    size: int | None = None,
    convention: BallConvention = "hdrshop",
    exclude_deg: float = EXCLUDE_DEG,
) -> tuple[np.ndarray, np.ndarray]:
    """Merge photographs of one ball taken from different sides into one environment.

    Parameters
    ----------
    photos : sequence of (H, W, C) arrays
    circles : sequence of Circle
    yaws_deg : sequence of float
        Each view's turn about +Y into the first view's frame (the first is usually 0; a view
        taken after walking 90 degrees around the ball is +90 or -90: see :func:`best_yaw`).
    to, size, convention
        As :func:`unwrap`.
    exclude_deg : float
        Half-angle of the cone around each view's centre direction (the photographer and the
        camera) that the view does not contribute to (0-60).

    Returns
    -------
    image : (H', W', C) float32
        The weighted mean of the views (each weighted by :func:`view_weight`).
    weight : (H', W') float32
        The sum of the weights: where it is 0 no view saw the direction (the image holds the
        first view's value there).
    """
    if not len(photos) == len(circles) == len(yaws_deg) >= 1:
        raise ArgumentError("give one circle and one yaw per photo")
    if not (math.isfinite(exclude_deg) and 0 <= exclude_deg <= 60):
        raise ArgumentError(f"exclude_deg must be within 0-60, not {exclude_deg!r}")
    size = int(math.ceil(2 * max(c.radius for c in circles))) if size is None else int(size)
    dirs, valid = layout_directions(to, size)
    total = None
    weights = np.zeros(dirs.shape[:2])
    first = None
    for photo, circle, yaw in zip(photos, circles, yaws_deg, strict=True):
        image = unwrap(photo, circle, to=to, size=size, convention=convention, yaw_deg=yaw)
        w = view_weight(dirs @ _yaw(yaw), convention, exclude_deg=exclude_deg) * valid
        first = image if first is None else first
        total = image * w[..., None] if total is None else total + image * w[..., None]
        weights += w
    assert first is not None and total is not None  # one photograph at least
    seen = weights > 0
    out = np.where(seen[..., None], total / np.where(seen, weights, 1)[..., None], first)
    return out.astype(np.float32), weights.astype(np.float32)


def best_yaw(
    photos: Sequence[ArrayLike],
    circles: Sequence[Circle],
    *,
    angle_deg: float = 90.0,
    convention: BallConvention = "hdrshop",
    size: int = 256,
) -> tuple[float, float, float]:
    """Which way the second view turned: ``+angle_deg`` or ``-angle_deg``, whichever makes the
    two unwrapped views agree better where both see well (weighted RMS of the log ratio).

    Returns ``(yaw, disagreement_plus, disagreement_minus)``.
    """
    dirs, _ = layout_directions("latlong", size)
    a = unwrap(photos[0], circles[0], size=size, convention=convention)
    wa = view_weight(dirs, convention)
    scores = []
    for sign in (1.0, -1.0):
        yaw = sign * angle_deg
        b = unwrap(photos[1], circles[1], size=size, convention=convention, yaw_deg=yaw)
        w = wa * view_weight(dirs @ _yaw(yaw), convention)
        la = np.log(np.maximum(a.mean(-1), 1e-6))
        lb = np.log(np.maximum(b.mean(-1), 1e-6))
        d = la - lb - np.average(la - lb, weights=w + 1e-12)
        scores.append(float(np.sqrt(np.average(d * d, weights=w + 1e-12))))
    return (angle_deg if scores[0] <= scores[1] else -angle_deg), scores[0], scores[1]


def card_reflectance(
    photo: ArrayLike, direct: Sequence[float], reflected: Sequence[float]
) -> np.ndarray:
    """The ball's reflectance from a grey card seen directly and in the ball.

    Parameters
    ----------
    photo : (H, W, C) array
        Linear values.
    direct, reflected : (x, y, width, height)
        Pixel boxes of the card itself and of its reflection in the ball.

    Returns
    -------
    (C,) float64
        Mean of the reflection over mean of the card, per channel.
    """
    photo = _check_photo(photo)
    means = []
    for box in (direct, reflected):
        x, y, w, h = (int(v) for v in box)
        if w < 1 or h < 1 or x < 0 or y < 0 or x + w > photo.shape[1] or y + h > photo.shape[0]:
            raise ArgumentError(
                f"box {box} is not inside the {photo.shape[1]}x{photo.shape[0]} photo"
            )
        means.append(photo[y : y + h, x : x + w].reshape(-1, photo.shape[2]).mean(0))
    if (means[0] <= 0).any():
        raise ArgumentError("the grey card's box is black in some channel")
    return np.asarray(means[1] / means[0], dtype=np.float64)


# --- finding the ball -------------------------------------------------------------------------


def _grey_log(photo: np.ndarray) -> np.ndarray:
    lum = photo[..., :3].mean(-1) if photo.shape[2] >= 3 else photo[..., 0]
    positive = lum[lum > 0]
    floor = float(np.quantile(positive, 0.01)) if positive.size else 1.0
    return np.log(np.maximum(lum, floor * 0.5) + floor).astype(np.float32)


def _coarse(grey: np.ndarray, min_radius: float, max_radius: float) -> tuple[float, float, float]:
    """Gradient Hough: every strong edge votes along its gradient line for centres; the radius
    is the peak of the distance histogram of edges pointing at the centre."""
    from scipy import ndimage

    gy = ndimage.sobel(grey, axis=0)
    gx = ndimage.sobel(grey, axis=1)
    mag = np.hypot(gx, gy)
    thr = np.quantile(mag, 0.95)
    ys, xs = np.nonzero(mag > thr)
    if ys.size < 16:
        raise ArgumentError("no edges: cannot find a ball in this photo")
    if ys.size > 40000:
        pick = np.random.default_rng(0).choice(ys.size, 40000, replace=False)
        ys, xs = ys[pick], xs[pick]
    ux, uy = gx[ys, xs] / mag[ys, xs], gy[ys, xs] / mag[ys, xs]
    h, w = grey.shape
    acc = np.zeros((h, w))
    radii = np.arange(int(min_radius), int(max_radius) + 1)
    for sign in (1, -1):
        cx = np.rint(xs[:, None] + sign * ux[:, None] * radii[None, :]).astype(np.int64)
        cy = np.rint(ys[:, None] + sign * uy[:, None] * radii[None, :]).astype(np.int64)
        ok = (cx >= 0) & (cx < w) & (cy >= 0) & (cy < h)
        np.add.at(acc, (cy[ok], cx[ok]), 1)
    acc = ndimage.gaussian_filter(acc, 1.0)
    cy, cx = np.unravel_index(int(np.argmax(acc)), acc.shape)
    dx, dy = xs - cx, ys - cy
    dist = np.hypot(dx, dy)
    radial = np.abs(dx * ux + dy * uy) / np.maximum(dist, 1e-9)
    good = (radial > 0.9) & (dist >= min_radius) & (dist <= max_radius)
    if not good.any():
        raise ArgumentError("no round edge: cannot find a ball in this photo")
    hist = np.bincount(np.rint(dist[good]).astype(np.int64), weights=mag[ys[good], xs[good]])
    hist = ndimage.gaussian_filter1d(hist, 1.0)
    return float(cx) + 0.5, float(cy) + 0.5, float(np.argmax(hist))


def _fit_circle(px: np.ndarray, py: np.ndarray) -> tuple[float, float, float, np.ndarray]:
    """Least-squares circle: algebraic (Kasa) start, then Gauss-Newton on the distances."""
    a = np.stack([px, py, np.ones_like(px)], axis=1)
    sol, *_ = np.linalg.lstsq(a, px * px + py * py, rcond=None)
    cx, cy = sol[0] / 2, sol[1] / 2
    r = math.sqrt(max(sol[2] + cx * cx + cy * cy, 1e-12))
    for _ in range(20):
        dx, dy = px - cx, py - cy
        d = np.hypot(dx, dy)
        res = d - r
        jac = np.stack([-dx / d, -dy / d, -np.ones_like(d)], axis=1)
        step, *_ = np.linalg.lstsq(jac, -res, rcond=None)
        cx, cy, r = cx + step[0], cy + step[1], r + step[2]
        if np.abs(step).max() < 1e-6:
            break
    res = np.hypot(px - cx, py - cy) - r
    return cx, cy, r, res


def _refine(grey: np.ndarray, cx: float, cy: float, r: float, reach: float) -> Circle:
    """Sub-pixel rim points along RIM_RAYS rays, then a robust circle fit."""
    from scipy.ndimage import gaussian_filter, map_coordinates

    smooth = gaussian_filter(grey, 1.0)
    step = 0.1
    offsets = np.arange(-reach, reach + step / 2, step)
    angles = np.arange(RIM_RAYS) * 2 * np.pi / RIM_RAYS
    ca, sa = np.cos(angles), np.sin(angles)
    for _ in range(3):
        rr = r + offsets[None, :]
        xs = cx + rr * ca[:, None]
        ys = cy + rr * sa[:, None]
        prof = map_coordinates(smooth, [ys - 0.5, xs - 0.5], order=3, mode="nearest")
        deriv = np.abs(np.gradient(prof, step, axis=1))
        k = np.clip(np.argmax(deriv[:, 1:-1], axis=1) + 1, 1, offsets.size - 2)
        rows = np.arange(RIM_RAYS)
        y0, y1, y2 = deriv[rows, k - 1], deriv[rows, k], deriv[rows, k + 1]
        denom = y0 - 2 * y1 + y2
        frac = np.where(np.abs(denom) > 1e-12, 0.5 * (y0 - y2) / denom, 0.0)
        edge = r + offsets[k] + np.clip(frac, -1, 1) * step
        strength = y1
        keep = strength > 0.3 * np.median(strength)
        px, py = cx + edge * ca, cy + edge * sa
        for _ in range(3):
            if np.count_nonzero(keep) < 12:
                raise ArgumentError("the ball's rim is too faint to fit a circle to")
            cx, cy, r, res = _fit_circle(px[keep], py[keep])
            full = np.hypot(px - cx, py - cy) - r
            mad = float(np.median(np.abs(res))) + 1e-3
            keep = keep & (np.abs(full) < max(4 * 1.4826 * mad, 0.05))
        reach = min(reach, 3.0)
    res = np.hypot(px[keep] - cx, py[keep] - cy) - r
    return Circle(float(cx), float(cy), float(r), float(np.sqrt(np.mean(res**2))), int(keep.sum()))


def find_ball(photo: ArrayLike, *, guess: Circle | None = None) -> Circle:
    """Find a mirror ball in a photograph, to a fraction of a pixel.

    Parameters
    ----------
    photo : (H, W, C) array
        The photo (linear or display-encoded: only edges matter).
    guess : Circle, optional
        A rough circle (within a few pixels, for a photo with other round things in it); the
        coarse search is skipped.

    Returns
    -------
    Circle
        With the rim fit's RMS residual (pixels) and the number of rim points kept.
    """
    from scipy import ndimage

    photo = _check_photo(photo)
    grey = _grey_log(photo)
    h, w = grey.shape
    if min(h, w) < 16:
        raise ArgumentError(f"{with_article(w)}x{h} photo is too small to find a ball in")
    if guess is not None:
        _check_circle(guess, photo)
        return _refine(grey, guess.x, guess.y, guess.radius, max(4.0, 0.05 * guess.radius))
    factor = max(1, int(math.ceil(max(h, w) / COARSE_SIDE)))
    small = (
        grey
        if factor == 1
        else ndimage.zoom(ndimage.uniform_filter(grey, factor), 1 / factor, order=1)
    )
    sh, sw = small.shape
    cx, cy, r = _coarse(small, 0.05 * min(sh, sw), 0.5 * min(sh, sw))
    sx, sy = w / sw, h / sh
    return _refine(grey, cx * sx, cy * sy, r * 0.5 * (sx + sy), 2.0 * max(sx, sy) + 2)
