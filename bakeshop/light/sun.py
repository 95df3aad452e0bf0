"""The sun in a light probe: find it, measure it, and paint it out.

A sun is the brightest compact region of a probe that stands clearly above the sky around it
and dominates every other compact light in it. Overcast, indoor and dawn probes have none:
their brightest spots are dim against their surroundings (an overcast sky), or one of several
alike (ceiling lamps, softboxes). Once found, the sun is removed by filling its region from
the surrounding sky with a harmonic (Laplace) interpolation, solved on a small gnomonic patch
around it so that any layout, its seams and its poles are handled alike; what the fill took
away (the *excess*, probe minus fill) is the sun's own light.

Measurements (all from the excess, per channel where a colour is meant):

- ``direction``: the excess-luminance-weighted centroid of the region's directions, a unit
  ``[x, y, z]`` in DESIGN.md's frame (+Y up, -Z forward, +X right);
- ``solid_angle_sr``: the equivalent disk, ``sum(excess * omega) / plateau`` where the plateau
  is the mean excess of the texels within 10 % of the brightest (exact for a uniform disk; a
  sun clipped by the camera gives its clipped size);
- ``angular_radius_deg``: the radius of a disk of that solid angle;
- ``color``: the mean excess radiance over that disk, ``sum(excess * omega) / solid_angle``;
- ``irradiance``: the excess's irradiance on a surface facing the sun,
  ``sum excess * omega * max(0, s . w)`` (not divided by pi).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, with_article
from bakeshop.light.sun_texels import (
    ImageTexels,
    Piece,
    TexelArrays,
    TexelSource,
    texel_luminance,
)
from bakeshop.resources import Cost, require
from bakeshop.sphere import (
    STRIP_TEXELS,
    Environment,
    Layout,
    Texels,
    check_environment,
)
from bakeshop.sphere import layout as get_layout

#: bilinear samples of an environment's colour channels at directions: (..., 3) -> (..., colour).
Sampler = Callable[[np.ndarray], np.ndarray]
#: the sun's peak must exceed the sky around it (median of a ring) by this factor.
CONTRAST = 20.0
#: ... and its excess energy that of the next brightest compact light by this factor.
DOMINANCE = 8.0
#: largest sun accepted: the core (above half the peak) lies within this angle (degrees).
MAX_RADIUS_DEG = 10.0
#: the region removed reaches MASK_SCALE times the core's radius, plus two texels.
MASK_SCALE = 2.0
#: the mask extends while the mean luminance of its rim exceeds this many times the sky's.
GLARE = 2.0
#: texels whose excess is within this fraction of the brightest form the plateau.
PLATEAU = 0.9
#: the filled patch has at most this many pixels on a side.
PATCH_MAX = 256
#: Peak bytes per texel of the search (measured at 41 on an RGB latlong,
#: tests/test_resources.py), and of the painted copy (float32, up to 4 channels).
SEARCH_BYTES = 64
COPY_BYTES = 16
#: a light's measurement examines the texels within this angle of its brightest texel
#: (degrees; enough for any sun up to 1.3 degrees in radius), further if its core needs it.
REACH_DEG = 8.0
#: Peak bytes per texel a light's measurement examines (luminance and float32 angle, joined
#: from their pieces and binned into rings: 4 + 4, twice while joined, then 4 + 8 for the
#: rings), whatever the layout.
EXAMINED_BYTES = 20


@dataclass(frozen=True)
class Sun:
    """What :func:`find_sun` measures (see the module docstring for each definition).

    Attributes
    ----------
    direction : (3,) float64
        Unit vector towards the sun, world frame.
    angular_radius_deg : float
    solid_angle_sr : float
    color : (C,) float64
        Mean radiance of the sun's disk above the sky behind it.
    irradiance : (C,) float64
        Irradiance at normal incidence (E, not E / pi), in radiance units times sr.
    mask_radius_deg : float
        Angular radius of the region that :func:`remove_sun` fills.
    """

    direction: np.ndarray
    angular_radius_deg: float
    solid_angle_sr: float
    color: np.ndarray
    irradiance: np.ndarray
    mask_radius_deg: float

    def to_dict(self) -> dict:
        """The ``sun.json`` document: plain lists and floats."""
        return {
            "direction": [float(v) for v in self.direction],
            "angular_radius_deg": float(self.angular_radius_deg),
            "solid_angle_sr": float(self.solid_angle_sr),
            "color": [float(v) for v in self.color],
            "irradiance": [float(v) for v in self.irradiance],
            "mask_radius_deg": float(self.mask_radius_deg),
        }


def sun_document(sun: Sun | None) -> dict:
    """The ``sun.json`` document: :meth:`Sun.to_dict`, or ``{"sun": null}`` when none."""
    return {"sun": None} if sun is None else sun.to_dict()


@dataclass(frozen=True)
class _Candidate:
    centre: np.ndarray  # centroid of the core (above half the peak)
    peak: float  # the brightest texel's luminance
    sky: float  # median luminance of the ring around the core
    core_radius: float  # radians
    mask_radius: float  # radians
    excess: float  # sum of (luminance - sky)+ * omega within the mask
    pitch: float  # angular size of the brightest texel (radians)
    around: np.ndarray  # the texels examined lie within ``reach`` of this direction (the
    reach: float  # brightest texel's): a cap well beyond the mask


def _tangent_frame(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.array([0.0, 1.0, 0.0]) if abs(a[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    t1 = np.cross(helper, a)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(a, t1)


def _profile(
    lum: np.ndarray, ang: np.ndarray, pitch: float, peak: float
) -> tuple[float, float, float, float, float]:
    """Sky level, core radius, mask radius and half-peak level of a light.

    ``lum`` and ``ang`` (angle from the light's centre) are the texels around it. In rings one
    texel wide, the core ends at the first non-empty ring with no texel above half the peak
    (over the sky); the sky is the median of a ring outside the core; the two are iterated to
    agreement. Returns ``(sky, core, mask, half, reach)`` with ``reach`` the angle the
    measurement needed.
    """
    ring = (ang / pitch).astype(np.int64)
    counts = np.bincount(ring)

    def core_radius(half: float) -> float:
        bright = np.bincount(ring[lum >= half], minlength=counts.size)
        below = np.flatnonzero((bright == 0) & (counts > 0))
        return (below[0] if below.size else counts.size) * pitch

    sky, half = 0.0, 0.5 * peak
    core = core_radius(half)  # first guess: half the peak over a black sky
    inner = 0.0
    for _ in range(3):
        inner = max(3 * core, core + 3 * pitch, math.radians(2.0))
        in_ring = (ang > inner) & (ang < 2 * inner)
        sky = float(np.median(lum[in_ring])) if in_ring.any() else 0.0
        half = sky + 0.5 * (peak - sky)
        core = core_radius(half)
    # the mask covers the core's rim and the glare around it: it reaches at least MASK_SCALE
    # core radii, and on until the rings' mean luminance falls to GLARE times the sky's
    mask = MASK_SCALE * core + 2 * pitch
    ring_mean = np.bincount(ring, lum) / np.maximum(counts, 1)
    first = int(math.ceil(mask / pitch))
    faint = np.flatnonzero((ring_mean[first:] <= GLARE * sky) & (counts[first:] > 0))
    glare = (first + (faint[0] if faint.size else ring_mean.size)) * pitch
    mask = max(mask, min(glare, 1.5 * inner))
    return sky, core, mask, half, 2 * inner


def _cos(dirs: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Cosines of the angles between directions (n, 3) and ``centre``, texel by texel: the same
    number whichever texels are looked at together."""
    return dirs[:, 0] * centre[0] + dirs[:, 1] * centre[1] + dirs[:, 2] * centre[2]


def _angle(dirs: np.ndarray, centre: np.ndarray) -> np.ndarray:
    return np.arccos(np.clip(_cos(dirs, centre), -1, 1))


def _examined(texels: TexelSource, around: np.ndarray, reach: float) -> Iterator[Piece]:
    """The texels a light's measurement examines, those with a solid angle within ``reach`` of
    ``around`` (its brightest texel), piece by piece in index order."""
    limit = math.cos(reach)
    for index, values, dirs, omega in texels.caps(around, math.cos(min(reach + 1e-6, math.pi))):
        keep = (_cos(dirs, around) > limit) & (omega > 0)
        yield index[keep], values[keep], dirs[keep], omega[keep]


def _within(
    texels: TexelSource, around: np.ndarray, reach: float, centre: np.ndarray, radius: float
) -> Iterator[Piece]:
    """The examined texels (:func:`_examined`) closer than ``radius`` to ``centre``, piece by
    piece in index order."""
    limit = math.cos(reach)
    for index, values, dirs, omega in texels.caps(centre, math.cos(min(radius + 1e-6, math.pi))):
        keep = (_cos(dirs, around) > limit) & (omega > 0) & (_angle(dirs, centre) < radius)
        yield index[keep], values[keep], dirs[keep], omega[keep]


def _sum_in_order(total: np.ndarray, terms: np.ndarray) -> np.ndarray:
    """``total`` plus ``terms`` (n, ...) added one after the other (``np.cumsum`` adds in order,
    ``np.sum`` pairwise): the same number however the terms come in pieces."""
    return np.cumsum(np.concatenate([total[None], terms]), axis=0)[-1]


def _candidate(texels: TexelSource, k: int, max_core: float) -> _Candidate | None:
    """Measure the compact light whose brightest texel is ``k`` (of ``texels``, an
    :class:`TexelArrays` or :class:`ImageTexels`); None if it is not compact: its core is wider than
    ``max_core`` (radians) or not CONTRAST times brighter than the sky around it.

    The texels within reach of the peak (8 degrees, further if the light needs it) are passed
    over piece by piece: only their luminances and angles are held together
    (:data:`EXAMINED_BYTES` a texel at most: a cap at a pole of a 32k latlong spans every
    column, 24 M texels), and the core's and the mask's few texels are read again where they
    are summed in order as they come."""
    values_k, dirs_k, omega_k = texels.gather(np.array([k]))
    pitch = max(math.sqrt(omega_k[0]), 1e-6)
    peak = float(texel_luminance(values_k)[0])
    around, reach = dirs_k[0], math.radians(REACH_DEG)
    while True:
        centre = around
        # the brightest texel may lie anywhere in a uniform disk: measure again around the
        # luminance-weighted centroid of the core found around it
        for _ in range(2):
            measured_at = centre
            pieces = [  # angles in float32: rings are a texel wide, far above its rounding
                (texel_luminance(v), _angle(d, centre).astype(np.float32))
                for _, v, d, _ in _examined(texels, around, reach)
            ]
            lum, ang = (np.concatenate(a) for a in zip(*pieces, strict=True))
            del pieces
            sky, core, mask, half, needed = _profile(lum, ang, pitch, peak)
            del lum, ang
            c, bright = np.zeros(3), False
            for _, values, dirs, omega in _within(texels, around, reach, centre, core):
                lum = texel_luminance(values)
                b = lum >= half
                c = _sum_in_order(c, ((lum[b] - sky) * omega[b])[:, None] * dirs[b])
                bright |= bool(b.any())
            if not bright or not np.linalg.norm(c) > 0:
                break
            centre = c / np.linalg.norm(c)
        if core > max_core:
            return None
        if needed <= reach or reach >= math.pi:
            break
        reach = min(1.2 * needed + 2 * pitch, math.pi)
    if peak < CONTRAST * sky:
        return None
    excess = np.zeros(())
    for _, values, _, omega in _within(texels, around, reach, measured_at, mask):
        excess = _sum_in_order(excess, np.clip(texel_luminance(values) - sky, 0, None) * omega)
    return _Candidate(centre, peak, sky, core, mask, float(excess), pitch, around, reach)


def _detect(texels: TexelSource) -> _Candidate | None:
    k = texels.brightest(np.zeros(3), 2.0)
    if k < 0:
        return None
    sun = _candidate(texels, k, math.radians(MAX_RADIUS_DEG))
    if sun is None:
        return None
    # the next brightest light away from this one, if it is about as compact (not a broad
    # patch of bright sky), must be much weaker
    exclude = max(3 * sun.mask_radius, math.radians(4.0))
    k2 = texels.brightest(sun.centre, math.cos(exclude))
    if k2 >= 0:
        limit = min(math.radians(MAX_RADIUS_DEG), max(4 * sun.core_radius, math.radians(2.0)))
        rival = _candidate(texels, k2, limit)
        if rival is not None and sun.excess < DOMINANCE * rival.excess:
            return None
    return sun


def _harmonic_fill(sampler: Sampler, centre: np.ndarray, radius: float, pitch: float) -> Sampler:
    """Fill the disk of angular ``radius`` around ``centre`` harmonically from its surroundings,
    sampled by ``sampler`` (directions (..., 3) -> bilinear values (..., C)).

    Returns a function mapping directions inside the disk to filled values.
    """
    from scipy import sparse
    from scipy.ndimage import map_coordinates
    from scipy.sparse.linalg import splu

    t1, t2 = _tangent_frame(centre)
    extent = math.tan(min(radius + 4 * pitch, math.radians(80)))
    step = max(math.tan(pitch), 2 * extent / (PATCH_MAX - 1))
    half = int(math.ceil(extent / step))
    n = 2 * half + 1
    u = (np.arange(n) - half) * step
    uu, vv = np.meshgrid(u, u, indexing="xy")
    dirs = centre + uu[..., None] * t1 + vv[..., None] * t2
    dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
    patch = np.asarray(sampler(dirs), dtype=np.float64)
    if patch.ndim == 2:
        patch = patch[..., None]
    unknown = np.hypot(uu, vv) < math.tan(radius)
    unknown[[0, -1], :] = False  # a known border (the disk never reaches it)
    unknown[:, [0, -1]] = False
    ids = -np.ones((n, n), np.int64)
    ids[unknown] = np.arange(np.count_nonzero(unknown))
    rows, cols, rhs = [], [], np.zeros((np.count_nonzero(unknown), patch.shape[-1]))
    ys, xs = np.nonzero(unknown)
    me = ids[ys, xs]
    rows.append(me)
    cols.append(me)
    data = [np.full(me.size, 4.0)]
    for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
        ny, nx = ys + dy, xs + dx
        nb = ids[ny, nx]
        inner = nb >= 0
        rows.append(me[inner])
        cols.append(nb[inner])
        data.append(-np.ones(np.count_nonzero(inner)))
        np.add.at(rhs, me[~inner], patch[ny[~inner], nx[~inner]])
    if me.size:
        a = sparse.csc_matrix(
            (np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))),
            shape=(me.size, me.size),
        )
        patch[unknown] = splu(a).solve(rhs)

    def fill(d: np.ndarray) -> np.ndarray:
        w = d @ np.stack([t1, t2, centre], 1)
        x = w[:, 0] / w[:, 2] / step + half
        y = w[:, 1] / w[:, 2] / step + half
        return np.stack(
            [map_coordinates(patch[..., c], [y, x], order=1) for c in range(patch.shape[-1])], 1
        )

    return fill


@dataclass(frozen=True)
class Removal:
    """What :func:`split_texels` returns: the sun and how to paint it out."""

    #: the sun's measurements.
    sun: Sun
    #: (n,) int: flat indices of the texels to fill.
    index: np.ndarray
    #: (n, C): their new values (never above the old ones).
    filled: np.ndarray

    def paint(self, image: np.ndarray) -> None:
        """Paint the sun out of ``image`` (the environment it was found in, with its channel
        axis), in place."""
        flat = image.reshape(-1, image.shape[-1])
        flat[self.index, : self.filled.shape[1]] = self.filled


def split_texels(t: Texels | TexelSource, *, sampler: Sampler | None = None) -> Removal | None:
    """Find the sun among an environment's texels (:func:`bakeshop.sphere.texels`) and compute
    its fill: the texel-level form of :func:`remove_sun`, for callers that already hold the
    texels. Only the colour channels (the first three, or the one) are looked at and filled;
    alpha is left alone. None when there is no sun.

    ``t`` may hold only some texels of an environment (a chunked job passes the window around
    the brightest texel, and around its rival): the result is the same as from all of them
    when they include every texel within the sun's measurement reach. Then ``sampler`` (a
    function of directions (..., 3) giving the environment's bilinear samples of its colour
    channels, (..., colour)) stands in for ``t.environment``, which may be None. ``t`` may
    also be a :class:`TexelSource` (colour channels only): the removal's ``index`` is then in
    its indices."""
    if not isinstance(t, Texels):  # texels read where they are looked at (see TexelArrays)
        if sampler is None:
            raise TypeError("split_texels of a TexelSource needs its sampler")
        return _split(t, sampler)
    colour = min(3, t.values.shape[1])
    if sampler is None:
        if t.environment is None:
            raise ArgumentError("texels without their environment need a sampler")
        sampler = _image_sampler(t.environment, colour)
    return _split(TexelArrays(t.values[:, :colour], t.dirs, t.omega), sampler)


def split_sun(image: ArrayLike, layout: str | Layout) -> Removal | None:
    """Find the sun of a probe and compute its fill (:func:`split_texels`) from the image
    itself: its texels' directions are computed strip by strip where they are looked at, so
    a 16k probe costs no per-texel geometry (the whole layout's would be 32 bytes a texel).

    Parameters
    ----------
    image : (..., C) array_like
        The probe in ``layout`` (:func:`bakeshop.sphere.check_environment`).
    layout : str

    Returns
    -------
    Removal or None
        The sun and its fill (flat texel indices of the image and their new colour values).
    """
    return split_environment(check_environment(image, layout))


def split_environment(env: Environment) -> Removal | None:
    """:func:`split_sun` of an environment already checked
    (:func:`bakeshop.sphere.check_environment`)."""
    colour = min(3, env.image.shape[-1])
    return _split(ImageTexels(env, colour), _image_sampler(env, colour))


def _image_sampler(env: Environment, colour: int) -> Sampler:
    """Bilinear samples of an environment's colour channels at directions (its texels are
    checked already: a base layout is sampled directly)."""
    from bakeshop.sphere import sample
    from bakeshop.sphere.windows import gather_taps, sample_taps

    lay, image = env.layout, env.image
    if lay.base is not lay:  # a cross or strip: sampled as its cube

        def view_sampler(d: np.ndarray) -> np.ndarray:
            return sample(image[..., :colour], lay, d, filter="bilinear")

        return view_sampler
    flat = image.reshape(-1, image.shape[-1])

    def sampler(d: np.ndarray) -> np.ndarray:
        d = np.asarray(d, dtype=np.float64)
        taps, frac = sample_taps(lay, image.shape[:-1], d.reshape(-1, 3))
        values = gather_taps(flat, taps, frac.astype(flat.dtype))[:, :colour]
        return values.reshape(d.shape[:-1] + (colour,))

    return sampler


def _split(texels: TexelSource, sampler: Sampler) -> Removal | None:
    cand = _detect(texels)
    if cand is None:
        return None
    centre = cand.centre
    pieces = list(_within(texels, cand.around, cand.reach, centre, cand.mask_radius))
    index, values, dirs, omega = (np.concatenate(a) for a in zip(*pieces, strict=True))
    fill = _harmonic_fill(sampler, centre, cand.mask_radius, cand.pitch)
    filled = np.minimum(fill(dirs), values)  # removing light never adds any
    excess = values.astype(np.float64) - filled
    energy = excess * omega[:, None]
    ex_lum = texel_luminance(excess)
    weight = np.clip(ex_lum, 0, None) * omega
    centroid = (weight[:, None] * dirs).sum(0)
    direction = centroid / np.linalg.norm(centroid) if weight.sum() > 0 else centre
    plateau_set = ex_lum >= PLATEAU * ex_lum.max()
    plateau = float(ex_lum[plateau_set].mean())
    total = energy.sum(0)
    solid_angle = (
        float(min(texel_luminance(total[None])[0] / plateau, 4 * math.pi)) if plateau > 0 else 0.0
    )
    radius = math.degrees(math.acos(max(1 - solid_angle / (2 * math.pi), -1.0)))
    cosine = np.clip(dirs @ direction, 0, None)
    sun = Sun(
        direction=direction,
        angular_radius_deg=radius,
        solid_angle_sr=solid_angle,
        color=total / solid_angle if solid_angle > 0 else np.zeros_like(total),
        irradiance=(energy * cosine[:, None]).sum(0),
        mask_radius_deg=math.degrees(cand.mask_radius),
    )
    return Removal(sun, index, filled.astype(values.dtype))


def find_sun_cost(shape: Sequence[int], layout: str) -> Cost:
    """What :func:`find_sun` (or :func:`remove_sun`) of a probe of ``shape`` in ``layout``
    holds at its peak: :data:`SEARCH_BYTES` per texel of the strips and caps it reads at once
    (four :data:`bakeshop.sphere.STRIP_TEXELS` at most: its texels' directions, solid angles
    and values, the search's work arrays), and :data:`COPY_BYTES` per texel of the probe (the
    painted copy of :func:`remove_sun`)."""
    lay = get_layout(layout)
    n = math.prod(shape[: 3 if lay.cubic else 2])
    memory = SEARCH_BYTES * min(n, 4 * STRIP_TEXELS) + COPY_BYTES * n
    return Cost(memory, n, f"the sun's search in {with_article(lay.name)} probe of {n} texels")


def find_sun(image: ArrayLike, layout: str) -> Sun | None:
    """Find and measure the sun of a light probe.

    Parameters
    ----------
    image : (..., C) array_like
        The probe's radiance in ``layout`` (``(H, W, C)``, or ``(6, S, S, C)`` for a cube).
    layout : str
        Its layout (:func:`bakeshop.sphere.layout`).

    Returns
    -------
    Sun or None
        None when the probe has no sun (no compact light CONTRAST times brighter than the sky
        around it and DOMINANCE times stronger than any other).
    """
    require(find_sun_cost(np.shape(image), layout))
    found = split_sun(image, layout)
    return None if found is None else found.sun


def remove_sun(image: ArrayLike, layout: str) -> tuple[np.ndarray, Sun | None]:
    """The probe with its sun painted out, and the sun.

    Parameters
    ----------
    image : (..., C) array_like
        The probe in ``layout``.
    layout : str

    Returns
    -------
    probe : (..., C) array
        A float copy of ``image`` (float32, float64 for float64 input; alpha kept) whose sun
        region is filled harmonically from the sky around it; an unchanged copy when there is
        no sun.
    sun : Sun or None
    """
    require(find_sun_cost(np.shape(image), layout))
    env = check_environment(image, layout)
    found = split_sun(env.image, env.layout)
    out = env.image.copy()  # the fill is fractional: a float copy
    if found is not None:
        found.paint(out)
    return env.shaped(out), None if found is None else found.sun
