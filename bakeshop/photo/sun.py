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

1. finds the region every frame clipped that holds the most light (the sun, not a glint), and
   every clipped texel within ``search_deg`` of it (a region cut by a seam of the layout);
2. fits ``L(theta) = sky + A theta^gamma`` to the measured ring outside them (to six times
   their radius, at least 8 degrees beyond: the aureole reaches far, so the sky level is fitted
   with it), ``gamma`` on luminance, ``sky`` and ``A`` per channel;
3. reads ``chi`` from ``gamma`` (the branch ``chi <= 0.2`` on which ``gamma`` is monotonic:
   clear to hazy skies), hence ``kappa`` and ``L0 = A / exp(kappa)``;
4. writes the model into the clipped texels: sky plus the aureole averaged over each texel's
   footprint, plus the disk's energy spread over the texels it covers in proportion to their
   covered area (so its integral is exact even when the disk is smaller than a texel), and
   marks them ``MODELLED`` in the status;
5. measures the result with :func:`bakeshop.light.sun.find_sun`, the same disk-and-excess
   measurement ``bake-probe`` makes, so what the merge reports is what the bake will see.

A fitted sun is believed only within a physical bound (:func:`disk_ceiling`): the darkest frame
clipped the rim of the region at its clipping level, and the disk's centre can be brighter
than the aureole there by at most the ratio that the sunshape of the clearest sky allowed
(``chi`` = :data:`CLEAREST_CSR`) gives at that angle. A fit beyond (an aureole flattened by a
horizon, a cloud or noise reads as a very clear sky, and ``L0 = A / exp(kappa)`` grows
without bound as ``chi`` falls: 1.5e13 times the clipped light was seen) is refused: the clipped
values stay, as lower bounds, and :attr:`SunRecovery.reason` says why.

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
    theta: np.ndarray, values: np.ndarray, omega: np.ndarray
) -> tuple[float, np.ndarray, np.ndarray] | None:
    """Fit ``L = sky + A theta^gamma`` to ring texels: gamma on luminance by variable
    projection (for each gamma on a grid, sky and A are linear least squares with relative
    weights), then sky and A per channel. None when no decaying aureole fits."""
    lum = _luminance(values)
    keep = lum > 0
    theta, values, omega, lum = theta[keep], values[keep], omega[keep], lum[keep]
    if lum.size < MIN_RING:
        return None
    w = omega / lum**2  # relative errors
    best = None
    for gamma in np.arange(-4.0, -0.5, 0.01):
        basis = np.stack([np.ones_like(theta), theta**gamma], axis=1)
        coef = _weighted_lstsq(basis, lum, w)
        if coef is None or coef[1] <= 0:
            continue
        err = float(np.sum(w * (basis @ coef - lum) ** 2))
        if best is None or err < best[0]:
            best = (err, gamma)
    if best is None:
        return None
    gamma = best[1]
    basis = np.stack([np.ones_like(theta), theta**gamma], axis=1)
    columns = []
    for c in range(values.shape[1]):
        column = _weighted_lstsq(basis, values[:, c], w)
        if column is None:
            return None
        columns.append(column)
    coef = np.stack(columns)
    if not np.isfinite(coef).all():
        return None
    return gamma, coef[:, 0], np.maximum(coef[:, 1], 0)


def _weighted_lstsq(basis: np.ndarray, y: np.ndarray, w: np.ndarray) -> np.ndarray | None:
    a = basis.T @ (w[:, None] * basis)
    if np.linalg.cond(a) > 1e12:
        return None
    return np.linalg.solve(a, basis.T @ (w * y))


def _brightest_clipped(clipped: np.ndarray, values: np.ndarray, omega: np.ndarray) -> int:
    """Flat index of the centre texel of the clipped region holding the most light (the sum of
    its lower bounds times solid angle): the sun, rather than a glint."""
    from scipy import ndimage

    labels, count = ndimage.label(clipped, structure=np.ones((3, 3)))
    flat = labels.reshape(-1)
    energy = np.bincount(flat, _luminance(values) * omega, minlength=count + 1)
    energy[0] = -1
    best = np.flatnonzero(flat == int(np.argmax(energy)))
    return int(best[np.argmax(omega[best] * _luminance(values[best]))])


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
        fit; its ``source`` is ``"clipped"`` when a fit beyond :func:`disk_ceiling` was
        refused (the radiance and status are then returned unchanged).
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
    shape = radiance.shape[:-1]  # (H, W), checked above
    seed = _brightest_clipped(status == CLIPPED, values, omega)
    near = clipped_all & (dirs @ dirs[seed] > math.cos(math.radians(search_deg)))
    centre = (omega[near, None] * dirs[near]).sum(0)
    centre /= np.linalg.norm(centre)
    ang = np.arccos(np.clip(dirs @ centre, -1, 1))
    pitch = math.sqrt(float(np.median(omega[near])))
    clip_radius = float(ang[near].max()) + 0.5 * pitch
    region = np.flatnonzero(ang <= clip_radius + 0.5 * pitch)
    region = region[omega[region] > 0]
    outer = max(RING_SCALE * clip_radius, clip_radius + math.radians(RING_DEG))
    measured = status.reshape(-1) == MEASURED
    ring = (ang > clip_radius + pitch) & (ang < outer) & measured & (omega > 0)
    theta_mrad = ang * 1e3
    slope = chi = amplitude = None
    sky = np.zeros(values.shape[1])
    if np.count_nonzero(ring) >= MIN_RING:
        fit = _fit_aureole(theta_mrad[ring], values[ring].astype(np.float64), omega[ring])
        if fit is not None:
            slope, sky, amplitude = fit
            slope = float(slope)
            chi = _chi_from_gamma(slope)
    if amplitude is None:  # no aureole to fit: the sky is the median of the ring
        near_sky = (ang > clip_radius + pitch) & (ang < outer) & (omega > 0)
        if near_sky.any():
            sky = np.median(values[near_sky], axis=0).astype(np.float64)
    before = values[region].astype(np.float64) - sky
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
    if irradiance is not None:
        colour = amplitude if amplitude is not None and amplitude.sum() > 0 else before.mean(0)
        colour = np.maximum(np.asarray(colour, np.float64), 0)
        colour_lum = float(_luminance(colour[None])[0])
        colour = colour / colour_lum if colour_lum > 0 else np.ones_like(colour)
        disk_irr = np.maximum(irradiance * colour - aureole_irr, 0)
        source = "given"
    elif amplitude is not None and chi is not None:  # fitted together
        l0 = amplitude / math.exp(float(_kappa(chi)))
        disk_irr = l0 * _disk_integral()
        source = "aureole"
    else:
        return radiance, status, None
    out, new_status, reason = radiance, status, None
    if source == "aureole":
        level = float(_luminance(values[near]).max())  # the darkest frame's clipping level
        ceiling = disk_ceiling(level, clip_radius * 1e3)
        fitted = float(_luminance(disk_irr[None])[0])
        if not fitted <= ceiling:  # NaN and infinity too
            source, model = "clipped", values[region].astype(np.float64)
            reason = (
                f"the aureole's fit (slope {slope:.2f}) puts {fitted:.4g} in the disk, more "
                f"than the {ceiling:.4g} that the clearest sky's sunshape allows above the "
                "clipping level"
            )
    if reason is None:
        weight = coverage * omega[region]
        if weight.sum() <= 0:  # the disk falls between sub-samples: the nearest texel takes it
            coverage = np.zeros_like(coverage)
            coverage[np.argmin(ang[region])] = 1.0
            weight = coverage * omega[region]
        model += disk_irr[None, :] * coverage[:, None] / weight.sum()
        model = np.maximum(model, values[region])  # a clipped value is a lower bound
        out = radiance.copy()
        out.reshape(-1, out.shape[-1])[region] = model.astype(np.float32)
        new_status = status.copy()
        new_status.reshape(-1)[region] = MODELLED
    flat = out.reshape(-1, out.shape[-1])
    total_irr = (model - sky) * (omega[region] * cos)[:, None]
    sun_irr = total_irr.sum(0)
    facing = np.clip(dirs @ centre, 0, None) * omega
    everything = float(_luminance((flat.astype(np.float64) * facing[:, None]).sum(0)[None])[0])
    halo = (ang < outer) & (omega > 0)
    halo_excess = np.clip(flat[halo].astype(np.float64) - sky, 0, None) * facing[halo, None]
    sun_total = float(_luminance(halo_excess.sum(0)[None])[0])
    recovery = SunRecovery(
        direction=centre,
        clipped_radius_deg=math.degrees(clip_radius),
        source=source,
        aureole_slope=slope,
        circumsolar_ratio=chi,
        irradiance=sun_irr,
        merged_irradiance=merged_irr,
        share=sun_total / everything if everything > 0 else 0.0,
        texels=0 if reason else int(region.size),
        measured=find_sun(out, layout),
        reason=reason,
    )
    return out, new_status, recovery
