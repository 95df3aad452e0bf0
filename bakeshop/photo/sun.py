"""A clipped sun recovered from its unclipped aureole, or from a measured irradiance.

Even the darkest frame of a bracket usually clips the sun's disk (the disk is 10^5-10^6 times
brighter than the sky), so a merge holds a lower bound there and loses most of the light a
probe's sun casts. Around the clipped core, the darkest frames still see the *aureole*, the
forward-scattered halo whose radiance falls as a power of the angle from the sun. Buie, Monger
and Dey's sunshape (Solar Energy 74(2), 2003, doi:10.1016/S0038-092X(03)00125-7) ties the
aureole to the disk through one parameter, the circumsolar ratio ``chi`` (aureole energy over
disk plus aureole), for angles ``theta`` in mrad:

- disk (``theta <= 4.65``): ``phi(theta) = cos(0.326 theta) / cos(0.308 theta)``;
- aureole (``theta > 4.65``): ``phi(theta) = exp(kappa) theta^gamma`` with
  ``gamma = 2.2 ln(0.52 chi) chi^0.43 - 0.1`` and ``kappa = 0.9 ln(13.5 chi) chi^-0.3``,

relative to the radiance ``L0`` of the disk's centre. :func:`recover_sun`:

1. takes each region every frame clipped (the :data:`MAX_CANDIDATES` holding the most light),
   with every clipped texel within ``search_deg`` of it (a region cut by a seam of the layout);
2. fits ``L(theta) = sky + g . t + A theta^gamma`` to the measured ring outside it (to six
   times its radius, at least 8 degrees beyond: the aureole reaches far, so the sky is fitted
   with it, as a local plane in the offsets ``t`` from the sun, tilted by a horizon or a
   gradient of the sky), ``gamma`` on luminance, the rest per channel;
3. reads ``chi`` from ``gamma`` (the branch ``chi <= 0.2`` on which ``gamma`` is monotonic:
   clear to hazy skies), hence ``kappa`` and ``L0 = A / exp(kappa)``;
4. writes the model into the clipped texels: sky plus the aureole averaged over each texel's
   footprint, plus the disk's energy spread over the texels it covers in proportion to their
   covered area (so its integral is exact even when the disk is smaller than a texel), and
   marks them ``MODELLED`` in the status;
5. models the region whose believable fit has the brightest disk centre ``L0`` (the sun is
   the brightest thing in the sky: a bright cloud clipped in every frame can hold more clipped
   light, and its fit a dimmer disk), and
6. measures the result with :func:`bakeshop.light.sun.find_sun`, the same disk-and-excess
   measurement ``bake-probe`` makes, so what the merge reports is what the bake will see.

A fitted sun is believed only within a physical bound (:func:`disk_ceiling`): the darkest frame
clipped the rim of the region at its clipping level, and the disk's centre can be brighter
than the aureole there by at most the ratio that the sunshape of the clearest sky allowed
(``chi`` = :data:`CLEAREST_CSR`) gives at that angle. A fit beyond (an aureole flattened by a
horizon, a cloud or noise reads as a very clear sky, and ``L0 = A / exp(kappa)`` grows
without bound as ``chi`` falls: 1.5e13 times the clipped light was seen) is refused: the clipped
values stay, as lower bounds, and :attr:`SunRecovery.reason` says why. So is a region that is
not round (it fills less than :data:`MIN_FILL` of the circle around it), a fit that misses its
ring by more than :data:`FIT_RESIDUAL` RMS (relative: a horizon, the ground or a cloud in it,
which a sky plane cannot follow), a model that holds :data:`FIT_RESIDUAL` less light than
the clipped lower bounds it replaces (it does not explain the clipping), and a ring that does
not determine the disk: its inner and outer halves, fitted alone, imply disks more than
:data:`RING_AGREEMENT` times apart (a sunshape gives both the same disk; an aureole that is not
one, or a sky's gradient read as aureole, biases the slope, which moves the disk by tens of
percent per 0.1).

With ``irradiance=`` (a light meter's reading of the direct sun, in the merge's units: lux for
an absolute stack), the disk's energy is set so that the modelled sun (disk plus the aureole
inside the clipped region) has that irradiance at normal incidence, its colour taken from the
aureole (or from the clipped values when no aureole could be fitted).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    from bakeshop.sphere.layouts import Layout

__all__ = ["SUN_DISK_MRAD", "SunRecovery", "buie_sunshape", "disk_ceiling", "recover_sun"]

#: the solar disk's angular radius in Buie's model (mrad).
SUN_DISK_MRAD = 4.65
#: clipped texels up to this angle from the sun belong to it (degrees).
SEARCH_DEG = 12.0
#: the circumsolar ratios the aureole's slope is read on (gamma is monotonic there).
CSR_RANGE = (1e-4, 0.2)
#: the aureole is fitted out to RING_SCALE times the clipped radius, and at least RING_DEG
#: degrees beyond it (the sky level is fitted with it: the aureole reaches far).
RING_SCALE = 6.0
RING_DEG = 8.0
#: fewest ring texels for an aureole fit.
MIN_RING = 12
#: sub-samples per texel edge when the model is averaged over texel footprints.
SUBSAMPLES = 8
#: the clearest sky a fitted sun may imply: typical clear skies have circumsolar ratios of
#: 0.01-0.05, and the disk's part of the sunshape grows without bound as the ratio falls.
CLEAREST_CSR = 0.005
#: clipped regions examined as suns, the ones holding the most light first.
MAX_CANDIDATES = 8
#: least part of the circle around a clipped region that it fills to be a sun (round).
MIN_FILL = 0.4
#: most RMS relative error of the aureole's fit on its ring, and most shortfall of the model
#: below the clipped lower bounds, for a fit to be believed.
FIT_RESIDUAL = 0.1
#: most ratio between the disks that the ring's inner and outer halves imply alone, for a fit
#: to be believed (8-bit brackets of Buie's sunshape give up to 1.4).
RING_AGREEMENT = 2.0


def _gamma(chi: np.ndarray | float) -> np.ndarray | float:
    return 2.2 * np.log(0.52 * chi) * chi**0.43 - 0.1


def _kappa(chi: np.ndarray | float) -> np.ndarray | float:
    return 0.9 * np.log(13.5 * chi) * chi ** (-0.3)


def buie_sunshape(theta_mrad: ArrayLike, chi: float) -> np.ndarray:
    """Buie's sunshape: radiance relative to the disk's centre at ``theta_mrad`` from the sun.

    Parameters
    ----------
    theta_mrad : array_like
        Angle from the sun's centre, milliradians.
    chi : float
        Circumsolar ratio, 0 < chi < 1 (the model's fit covers about 0.0-0.4).
    """
    t = np.asarray(theta_mrad, dtype=np.float64)
    if not 0 < chi < 1:
        raise ArgumentError(f"the circumsolar ratio must be within (0, 1), not {chi!r}")
    disk = np.cos(0.326 * t) / np.cos(0.308 * np.minimum(t, SUN_DISK_MRAD))
    aureole = np.exp(_kappa(chi)) * np.maximum(t, SUN_DISK_MRAD) ** _gamma(chi)
    return np.where(t <= SUN_DISK_MRAD, disk, aureole)


def _disk_integral() -> float:
    """Integral of Buie's disk profile over the disk, sr, per unit centre radiance."""
    t = np.linspace(0.0, SUN_DISK_MRAD, 4001)
    f = np.cos(0.326 * t) / np.cos(0.308 * t) * 2 * np.pi * np.sin(t * 1e-3) * 1e-3
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t)))  # trapezoid rule


def disk_ceiling(level: float, rim_mrad: float) -> float:
    """The most light a sun's disk can hold, at normal incidence, when ``level`` is the
    radiance of its aureole ``rim_mrad`` from its centre: ``level / phi(rim) * integral of the
    disk's profile``, with the sunshape ``phi`` of the clearest sky allowed
    (:data:`CLEAREST_CSR`). Units: ``level``'s times sr."""
    rim = max(rim_mrad, SUN_DISK_MRAD)
    return level / float(buie_sunshape(rim, CLEAREST_CSR)) * _disk_integral()


def _chi_from_gamma(gamma: float) -> float:
    chis = np.geomspace(*CSR_RANGE, 2000)
    gammas = _gamma(chis)  # decreasing on this branch
    return float(np.interp(-gamma, -gammas, chis))


def _disk_centre(gamma: float, amplitude: np.ndarray) -> np.ndarray:
    """The disk's centre radiance ``L0 = A / exp(kappa)`` (per channel) that an aureole
    ``A theta^gamma`` implies through Buie's sunshape."""
    return amplitude / math.exp(float(_kappa(_chi_from_gamma(gamma))))


def _halves(
    theta: np.ndarray, tangent: np.ndarray, values: np.ndarray, omega: np.ndarray
) -> tuple[float, float]:
    """The disk centres that the ring's inner and outer halves (split at the geometric mean
    of its angles) imply when each is fitted alone; NaN for a half that no aureole fits.
    A sunshape's aureole gives both the same disk, whatever the ring's extent."""
    log = np.log(theta)
    inner = log < 0.5 * (log.min() + log.max())
    peaks = []
    for part in (inner, ~inner):
        fit = _fit_aureole(theta[part], tangent[part], values[part], omega[part])
        centre = math.nan if fit is None else _luminance(_disk_centre(fit[0], fit[2])[None])[0]
        peaks.append(float(centre))
    return peaks[0], peaks[1]


@dataclass(frozen=True)
class SunRecovery:
    """What :func:`recover_sun` did.

    Attributes
    ----------
    direction : (3,) float64
        Unit vector to the centre of the clipped region (the layout's frame).
    clipped_radius_deg : float
        Angular radius of the region every frame clipped.
    source : str
        ``"aureole"`` (fitted), ``"given"`` (from ``irradiance=``) or ``"clipped"`` (the fit
        was refused and the clipped lower bounds kept: see ``reason``).
    aureole_slope : float or None
        The fitted power ``gamma`` (None when no aureole could be fitted).
    circumsolar_ratio : float or None
        Buie's ``chi`` read from it.
    irradiance : (C,) float64
        The modelled sun's irradiance at normal incidence: its light above the sky inside the
        clipped region (disk plus aureole), radiance units times sr.
    merged_irradiance : (C,) float64
        The same integral over the clipped merge before: what the lower bound held.
    share : float
        The sun's (modelled region plus measured aureole) part of the whole probe's luminance
        irradiance on a surface facing it.
    texels : int
        Texels modelled (0 when the fit was refused).
    measured : bakeshop.light.sun.Sun or None
        :func:`bakeshop.light.sun.find_sun` on the result.
    reason : str or None
        Why a fit was refused (``source == "clipped"``).
    """

    direction: np.ndarray
    clipped_radius_deg: float
    source: str
    aureole_slope: float | None
    circumsolar_ratio: float | None
    irradiance: np.ndarray
    merged_irradiance: np.ndarray
    share: float
    texels: int
    measured: object = None
    reason: str | None = None


def _luminance(values: np.ndarray) -> np.ndarray:
    from bakeshop.image import luminance

    return luminance(values)


def _subsample_directions(lay: Layout, shape: tuple[int, ...], index: np.ndarray) -> np.ndarray:
    """Directions of SUBSAMPLES^2 points in each texel of ``index``: (n, S*S, 3)."""
    h, w = shape[-2:]
    rows, cols = np.divmod(index, w)
    offs = (np.arange(SUBSAMPLES) + 0.5) / SUBSAMPLES
    oy, ox = np.meshgrid(offs, offs, indexing="ij")
    coords = np.stack(
        [cols[:, None] + ox.ravel()[None, :], rows[:, None] + oy.ravel()[None, :]], axis=-1
    )
    return lay.directions_at(coords, shape)


def _fit_aureole(
    theta: np.ndarray, tangent: np.ndarray, values: np.ndarray, omega: np.ndarray
) -> tuple[float, np.ndarray, np.ndarray, float] | None:
    """Fit ``L = sky + g . t + A theta^gamma`` to ring texels (``t``: their offsets from the
    sun in its tangent plane, so that the sky is a local plane, tilted by a horizon, not a
    constant): gamma on luminance by variable projection (for each gamma on a grid, the other
    terms are linear least squares with relative weights), then per channel. Returns gamma,
    the sky at the sun, A and the fit's RMS relative residual on luminance (weighted by solid
    angle); None when no decaying aureole fits."""
    lum = _luminance(values)
    keep = lum > 0
    theta, tangent, values, omega, lum = (
        theta[keep], tangent[keep], values[keep], omega[keep], lum[keep]
    )  # fmt: skip
    if lum.size < MIN_RING:
        return None
    w = omega / lum**2  # relative errors
    plane = np.column_stack([np.ones_like(theta), tangent])
    best = None
    for gamma in np.arange(-4.0, -0.5, 0.01):
        basis = np.column_stack([plane, theta**gamma])
        coef = _weighted_lstsq(basis, lum, w)
        if coef is None or coef[-1] <= 0:
            continue
        err = float(np.sum(w * (basis @ coef - lum) ** 2))
        if best is None or err < best[0]:
            best = (err, gamma)
    if best is None:
        return None
    gamma = best[1]
    basis = np.column_stack([plane, theta**gamma])
    columns = []
    for c in range(values.shape[1]):
        column = _weighted_lstsq(basis, values[:, c], w)
        if column is None:
            return None
        columns.append(column)
    coef = np.stack(columns)
    if not np.isfinite(coef).all():
        return None
    relative = _luminance(basis @ coef.T) / lum - 1
    residual = math.sqrt(float(np.sum(omega * relative**2) / omega.sum()))
    return gamma, coef[:, 0], np.maximum(coef[:, -1], 0), residual


def _weighted_lstsq(basis: np.ndarray, y: np.ndarray, w: np.ndarray) -> np.ndarray | None:
    a = basis.T @ (w[:, None] * basis)
    if np.linalg.cond(a) > 1e12:
        return None
    return np.linalg.solve(a, basis.T @ (w * y))


def _clipped_seeds(clipped: np.ndarray, values: np.ndarray, omega: np.ndarray) -> list[int]:
    """Flat indices of the brightest texel of each clipped region, the regions holding the most
    light (the sum of their lower bounds times solid angle) first, at most MAX_CANDIDATES."""
    from scipy import ndimage

    labels, count = ndimage.label(clipped, structure=np.ones((3, 3)))
    flat = labels.reshape(-1)
    weight = _luminance(values) * omega
    energy = np.bincount(flat, weight, minlength=count + 1)[1:]
    seeds = []
    for label in np.argsort(-energy, kind="stable")[:MAX_CANDIDATES] + 1:
        members = np.flatnonzero(flat == label)
        seeds.append(int(members[np.argmax(weight[members])]))
    return seeds


def recover_sun(
    radiance: np.ndarray,
    status: np.ndarray,
    layout: str,
    *,
    irradiance: float | None = None,
    search_deg: float = SEARCH_DEG,
) -> tuple[np.ndarray, np.ndarray, SunRecovery | None]:
    """Replace a clipped sun by Buie's sunshape fitted to its aureole (or scaled to a reading).

    Parameters
    ----------
    radiance : (H, W, C) float32
        A merged environment in ``layout`` (an equirectangular panorama, an angular map...).
    status : (H, W) uint8
        The merge's status map (:attr:`bakeshop.photo.Merged.status`): ``CLIPPED`` texels are
        the ones every frame saturated.
    layout : str
        The environment's layout (:func:`bakeshop.sphere.layout`); not a cube.
    irradiance : float, optional
        The sun's irradiance at normal incidence, as a luminance in the merge's units (lux for
        an absolute stack): the disk is scaled to it.
    search_deg : float
        Clipped texels within this angle of the sun are its (1-45).

    Returns
    -------
    radiance : (H, W, C) float32
        A copy with the sun modelled (the input unchanged when nothing was done).
    status : (H, W) uint8
        A copy with the modelled texels marked ``MODELLED``.
    recovery : SunRecovery or None
        None when the environment has no sun or its sun is not clipped or has no aureole to
        fit; its ``source`` is ``"clipped"`` when no clipped region's model was believed
        (the radiance and status are then returned unchanged, ``reason`` says why).
    """
    from bakeshop.light.sun import find_sun
    from bakeshop.photo.merge import CLIPPED, MEASURED, MODELLED
    from bakeshop.sphere import layout as get_layout
    from bakeshop.sphere import texels

    lay = get_layout(layout)
    if lay.cubic:
        raise ArgumentError("sun recovery works on a single-image layout, not a cube")
    radiance = np.asarray(radiance, dtype=np.float32)
    status = np.asarray(status)
    if radiance.ndim != 3 or status.shape != radiance.shape[:2]:
        raise ArgumentError("radiance must be (H, W, C) and status (H, W)")
    if irradiance is not None and not (math.isfinite(irradiance) and irradiance > 0):
        raise ArgumentError(f"the sun's irradiance must be a positive number, not {irradiance!r}")
    if not (math.isfinite(search_deg) and 1 <= search_deg <= 45):
        raise ArgumentError(f"search angle must be within 1-45 degrees, not {search_deg!r}")
    clipped_all = status.reshape(-1) == CLIPPED
    if not clipped_all.any():
        return radiance, status, None
    values, dirs, omega, _ = texels(radiance, layout)
    measured = status.reshape(-1) == MEASURED
    candidates: list[_Candidate] = []
    for seed in _clipped_seeds(status == CLIPPED, values, omega):
        if not any(c.near[seed] for c in candidates):  # a region cut by a seam is one sun
            candidates.append(
                _model_candidate(
                    lay, radiance.shape[:-1], values, dirs, omega, clipped_all, measured, seed,
                    irradiance=irradiance, search_deg=search_deg,
                )
            )  # fmt: skip
    accepted = [c for c in candidates if c.reason is None and c.source != "none"]
    if accepted:  # the sun is the brightest: the highest fitted peak, else the most light
        best = max(accepted, key=lambda c: (c.peak, c.light))
    else:  # why the region holding the most light is not a sun
        best = max(candidates, key=lambda c: (c.reason is not None, c.light))
    if best.source == "none" and best.reason is None:
        return radiance, status, None
    out, new_status, model = radiance, status, values[best.region].astype(np.float64)
    if best.reason is None:
        out = radiance.copy()
        out.reshape(-1, out.shape[-1])[best.region] = best.model.astype(np.float32)
        new_status = status.copy()
        new_status.reshape(-1)[best.region] = MODELLED
        model = best.model
    flat = out.reshape(-1, out.shape[-1])
    cos = np.clip(dirs[best.region] @ best.centre, 0, None)
    sun_irr = ((model - best.sky) * (omega[best.region] * cos)[:, None]).sum(0)
    facing = np.clip(dirs @ best.centre, 0, None) * omega
    everything = float(_luminance((flat.astype(np.float64) * facing[:, None]).sum(0)[None])[0])
    halo = (np.arccos(np.clip(dirs @ best.centre, -1, 1)) < best.outer) & (omega > 0)
    halo_excess = np.clip(flat[halo].astype(np.float64) - best.sky, 0, None) * facing[halo, None]
    sun_total = float(_luminance(halo_excess.sum(0)[None])[0])
    recovery = SunRecovery(
        direction=best.centre,
        clipped_radius_deg=math.degrees(best.clip_radius),
        source=best.source if best.reason is None else "clipped",
        aureole_slope=best.slope,
        circumsolar_ratio=best.chi,
        irradiance=sun_irr,
        merged_irradiance=best.merged_irr,
        share=sun_total / everything if everything > 0 else 0.0,
        texels=0 if best.reason else int(best.region.size),
        measured=find_sun(out, layout),
        reason=best.reason,
    )
    return out, new_status, recovery


@dataclass(frozen=True)
class _Candidate:
    """One clipped region modelled as a sun (see :func:`_model_candidate`)."""

    near: np.ndarray  # (N,) bool: its clipped texels
    centre: np.ndarray
    clip_radius: float  # radians
    outer: float  # radians: the ring's outer edge
    region: np.ndarray  # flat indices of the modelled texels
    light: float  # luminance of its lower bounds times solid angle
    sky: np.ndarray
    slope: float | None
    chi: float | None
    merged_irr: np.ndarray
    model: np.ndarray  # (len(region), C) the modelled values
    peak: float  # the model's disk centre luminance (0 when not fitted)
    source: str  # "aureole", "given" or "none" (nothing to model)
    reason: str | None  # why it is not a sun, or its fit is refused


def _model_candidate(
    lay: Layout,
    shape: tuple[int, ...],
    values: np.ndarray,
    dirs: np.ndarray,
    omega: np.ndarray,
    clipped_all: np.ndarray,
    measured: np.ndarray,
    seed: int,
    *,
    irradiance: float | None,
    search_deg: float,
) -> _Candidate:
    """Model the clipped region around texel ``seed`` as a sun (steps 1-4 of the module's
    description), and say why not when it is not compact or its fit is not believable."""
    near = clipped_all & (dirs @ dirs[seed] > math.cos(math.radians(search_deg)))
    centre = (omega[near, None] * dirs[near]).sum(0)
    centre /= np.linalg.norm(centre)
    ang = np.arccos(np.clip(dirs @ centre, -1, 1))
    pitch = math.sqrt(float(np.median(omega[near])))
    clip_radius = float(ang[near].max()) + 0.5 * pitch
    outer = max(RING_SCALE * clip_radius, clip_radius + math.radians(RING_DEG))
    light = float(np.sum(_luminance(values[near]) * omega[near]))
    fill = float(omega[near].sum()) / (2 * math.pi * (1 - math.cos(clip_radius)))
    if fill < MIN_FILL:  # before the model's work, which grows with the region
        none = np.zeros(values.shape[1])
        not_round = (
            f"the region clipped in every frame is not round ({fill:.0%} of the circle around "
            f"it, less than {MIN_FILL:.0%}): a cloud or a glint, not a sun"
        )
        return _Candidate(
            near, centre, clip_radius, outer, np.zeros(0, np.int64), light, none, None, None,
            none, np.zeros((0, none.size)), 0.0, "none", not_round,
        )  # fmt: skip
    region = np.flatnonzero(ang <= clip_radius + 0.5 * pitch)
    region = region[omega[region] > 0]
    ring = (ang > clip_radius + pitch) & (ang < outer) & measured & (omega > 0)
    theta_mrad = ang * 1e3
    slope = chi = amplitude = None
    residual, halves = 0.0, (math.nan, math.nan)
    sky = np.zeros(values.shape[1])
    if np.count_nonzero(ring) >= MIN_RING:
        offsets = dirs[ring] - centre * (dirs[ring] @ centre)[:, None]
        axes = np.linalg.svd(np.eye(3) - np.outer(centre, centre))[0][:, :2]
        ring_fit = (theta_mrad[ring], offsets @ axes, values[ring].astype(np.float64), omega[ring])
        fit = _fit_aureole(*ring_fit)
        if fit is not None:
            slope, sky, amplitude, residual = fit
            slope = float(slope)
            chi = _chi_from_gamma(slope)
            halves = _halves(*ring_fit)
    if amplitude is None:  # no aureole to fit: the sky is the median of the ring
        near_sky = (ang > clip_radius + pitch) & (ang < outer) & (omega > 0)
        if near_sky.any():
            sky = np.median(values[near_sky], axis=0).astype(np.float64)
    lower = values[region].astype(np.float64)
    before = lower - sky
    cos = np.clip(dirs[region] @ centre, 0, None)
    merged_irr = (before * (omega[region] * cos)[:, None]).sum(0)
    # the model's aureole averaged over each texel (the disk's own part left to the deposit)
    sub = _subsample_directions(lay, shape, region)
    sub_t = np.arccos(np.clip(sub @ centre, -1, 1)) * 1e3
    in_disk = sub_t <= SUN_DISK_MRAD
    coverage = in_disk.mean(axis=1)
    model = np.broadcast_to(sky, (region.size, values.shape[1])).copy()
    if amplitude is not None:
        aureole = np.where(in_disk, 0.0, np.maximum(sub_t, SUN_DISK_MRAD) ** slope).mean(axis=1)
        model += aureole[:, None] * amplitude[None, :]
    aureole_irr = ((model - sky) * (omega[region] * cos)[:, None]).sum(0)
    peak, reason = 0.0, None
    if amplitude is not None and slope is not None:  # the fitted disk's centre
        l0 = _disk_centre(slope, amplitude)
        peak = float(_luminance(l0[None])[0])
    if irradiance is not None:
        colour = amplitude if amplitude is not None and amplitude.sum() > 0 else before.mean(0)
        colour = np.maximum(np.asarray(colour, np.float64), 0)
        colour_lum = float(_luminance(colour[None])[0])
        colour = colour / colour_lum if colour_lum > 0 else np.ones_like(colour)
        disk_irr = np.maximum(irradiance * colour - aureole_irr, 0)
        source = "given"
    elif peak > 0:  # fitted together
        disk_irr = l0 * _disk_integral()
        source = "aureole"
    else:
        disk_irr, source = np.zeros(values.shape[1]), "none"
    weight = coverage * omega[region]
    if weight.sum() <= 0:  # the disk falls between sub-samples: the nearest texel takes it
        coverage = np.zeros_like(coverage)
        coverage[np.argmin(ang[region])] = 1.0
        weight = coverage * omega[region]
    model += disk_irr[None, :] * coverage[:, None] / weight.sum()
    level = float(_luminance(values[near]).max())  # the darkest frame's clipping level
    ceiling = disk_ceiling(level, clip_radius * 1e3)
    fitted = float(_luminance(disk_irr[None])[0])
    inside = clipped_all[region]
    short = 1 - float(np.sum(_luminance(model[inside]) * omega[region][inside])) / float(
        np.sum(_luminance(lower[inside]) * omega[region][inside])
    )
    if source == "aureole" and residual > FIT_RESIDUAL:
        reason = (
            f"the aureole's fit misses the measured ring around the sun by {residual:.0%} RMS, "
            f"more than {FIT_RESIDUAL:.0%} (a horizon, a cloud or the ground in it)"
        )
    elif source == "aureole" and not fitted <= ceiling:  # NaN and infinity too
        reason = (
            f"the aureole's fit (slope {slope:.2f}) puts {fitted:.4g} in the disk, more "
            f"than the {ceiling:.4g} that the clearest sky's sunshape allows above the "
            "clipping level"
        )
    elif source == "aureole" and short > FIT_RESIDUAL:
        reason = (
            f"the aureole's fit holds {short:.0%} less light than the clipped lower bounds "
            f"around the sun, more than {FIT_RESIDUAL:.0%}: it does not explain the clipping"
        )
    elif source == "aureole" and not max(halves) <= RING_AGREEMENT * min(halves):  # NaN too
        inner, outer = (h / peak for h in halves)
        reason = (
            f"the inner and outer halves of the ring around the sun, fitted alone, put "
            f"{inner:.2g} and {outer:.2g} times the fitted disk's light in it, more than "
            f"{RING_AGREEMENT:g}x apart: the aureole does not follow one sunshape, so it does "
            "not determine the sun's energy"
        )
    model = np.maximum(model, lower)  # a clipped value is a lower bound
    return _Candidate(
        near, centre, clip_radius, outer, region, light, sky, slope, chi, merged_irr, model,
        peak, source, reason,
    )  # fmt: skip
