"""Underwater murk: how light fades and fogs along a path through water, per sRGB channel, from
measured spectra (SI units: metres, 1/m).

Two different attenuations
--------------------------
The **beam attenuation** c = a + b (absorption plus scattering) says how the light of an object
seen through water fades along the line of sight: T(d) = exp(-c d). The **diffuse attenuation**
Kd says how the ambient light fades with depth, E(z) = E(0) exp(-Kd z). Kd is what Jerlov
measured (the water types are defined by it); c is always larger where particles scatter, so
using Kd for the view (as some engines do) makes murky water look too clear.

Spectra (tables shipped in ``bakeshop/water/data`` with their sources):

- pure water absorption a_w: Pope and Fry 1997 (380-700 nm);
- pure (sea) water scattering b_w = 0.00288 (lambda / 500 nm)^-4.32 1/m, fresh water 0.00222
  (Morel 1974), half of it backwards, phase function 0.06225 (1 + 0.835 cos^2 psi) / sr;
- Jerlov's water types: Kd from Jerlov 1976, Table XXVII.

For a Jerlov type, the inherent properties come from its Kd with established relations:

- total absorption from Gordon 1989: Kd = 1.0395 D0 (a + b_b), D0 = 1 / cos(theta_w) for the
  sun at ``sun_zenith`` refracted into the water (Jerlov's profiles are for a high sun; 30
  degrees by default), floored at pure water's a_w;
- particle scattering from a chlorophyll-equivalent concentration: Chl from Kd(490) =
  0.0166 + 0.0773 Chl^0.6715 (Morel et al. 2007), b_p(550) = 0.30 Chl^0.62 (Gordon and Morel
  1983), b_p proportional to 1 / lambda, backscattering ratio 0.0183 and Henyey-Greenstein
  g = 0.924 (Petzold's average particle, Mobley 1994).

This is a case-1 (open ocean) scattering model: for the coastal types, whose particles are
mostly mineral, it is a lower bound of b (so c is a lower bound too); Solonenko and Mobley 2015
fit full inherent optical properties to the same Kd spectra.

Channels
--------
Spectra become linear sRGB through the CIE 1931 2-degree colour matching functions (Wyman,
Sloan and Shirley's multi-lobe fit) and the XYZ to linear sRGB matrix of IEC 61966-2-1, for
white light (a 6504 K blackbody, D65's correlated colour temperature). A channel's transmittance
T_c(d) = sum w_c(l) exp(-c(l) d) / sum w_c(l) is not exactly exponential (its spectrum reddens
or bluens with distance), so bakeshop gives both per-channel coefficients (fits) and lookup
tables of the exact band integrals.

In-scatter
----------
Light scattered into a horizontal view at depth z from the downwelling light: with the sun
overhead (scattering angle 90 degrees), per unit E(0) / pi (the radiance of a white matte
surface at the surface),

    L_in(d, z) = pi beta(90) / c (1 - exp(-c d)) exp(-Kd z),
    beta(90) = b_w 0.06225 + b_p p_HG(90; g)

single scattering only. Unreal's Single Layer Water integrates the same medium itself given its
absorption, scattering and phase g.

References
----------
R. M. Pope and E. S. Fry, Appl. Opt. 36(33), 8710-8723, 1997, doi:10.1364/AO.36.008710.
N. G. Jerlov, *Marine Optics*, 2nd ed., Elsevier, 1976.
M. G. Solonenko and C. D. Mobley, "Inherent optical properties of Jerlov water types", Appl.
Opt. 54(17), 5392-5401, 2015, doi:10.1364/AO.54.005392.
A. Morel, "Optical properties of pure water and pure sea water", in Optical Aspects of
Oceanography, Academic Press, 1974, 1-24.
H. R. Gordon, "Can the Lambert-Beer law be applied to the diffuse attenuation coefficient of
ocean water?", Limnol. Oceanogr. 34(8), 1389-1409, 1989, doi:10.4319/lo.1989.34.8.1389.
H. R. Gordon and A. Morel, *Remote Assessment of Ocean Color for Interpretation of Satellite
Visible Imagery*, Springer, 1983.
A. Morel et al., "Examining the consistency of products derived from various ocean color
sensors in open ocean (Case 1) waters...", Remote Sens. Environ. 111, 69-88, 2007,
doi:10.1016/j.rse.2007.03.012.
C. D. Mobley, *Light and Water*, Academic Press, 1994 (Petzold's phase functions).
C. Wyman, P.-P. Sloan and P. Shirley, "Simple Analytic Approximations to the CIE XYZ Color
Matching Functions", JCGT 2(2), 1-11, 2013.
R. J. Davies-Colley, "Measuring water clarity with a black disk", Limnol. Oceanogr. 33(4),
616-623, 1988, doi:10.4319/lo.1988.33.4.0616 (sighting range 4.8 / c).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources

import numpy as np
from numpy.typing import ArrayLike
from scipy import optimize

from bakeshop.errors import ArgumentError, validate_choice

#: Jerlov's water types (Jerlov 1976), clearest first, and pure water.
WATER_TYPES = ("pure", "I", "IA", "IB", "II", "III", "1C", "3C", "5C", "7C", "9C")
#: Index of refraction of water (DESIGN's fresnel default).
WATER_IOR = 1.333
#: Petzold's average particle: backscattering ratio and mean cosine (Mobley 1994).
PARTICLE_BACKSCATTER = 0.0183
PARTICLE_G = 0.924
#: Davies-Colley 1988: a black disk is sighted at 4.8 / c (c photopic).
SIGHTING = 4.8
#: XYZ -> linear sRGB (IEC 61966-2-1).
XYZ_TO_SRGB = np.array(
    [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]]
)


# --- spectra ------------------------------------------------------------------------------------


def _table(name: str) -> tuple[list[str], np.ndarray]:
    text = resources.files("bakeshop.water").joinpath("data").joinpath(name).read_text()
    rows = [line for line in text.splitlines() if line and not line.startswith("#")]
    header = rows[0].split(",")
    return header, np.array([[float(v) for v in r.split(",")] for r in rows[1:]])


@functools.cache
def wavelengths() -> np.ndarray:
    """The spectral grid, nm: 380 to 700 in 2.5 nm steps (Pope and Fry's)."""
    return _table("pope_fry_1997.csv")[1][:, 0].copy()


@functools.cache
def pure_water_absorption() -> np.ndarray:
    """a_w on :func:`wavelengths`, 1/m (Pope and Fry 1997)."""
    return _table("pope_fry_1997.csv")[1][:, 1].copy()


def pure_water_scattering(*, sea: bool = True) -> np.ndarray:
    """b_w on :func:`wavelengths`, 1/m (Morel 1974): 0.00288 (l / 500)^-4.32 for sea water,
    0.00222 (l / 500)^-4.32 for fresh water."""
    return (0.00288 if sea else 0.00222) * (wavelengths() / 500.0) ** -4.32


@functools.cache
def jerlov_kd_table() -> tuple[tuple[str, ...], np.ndarray, np.ndarray]:
    """(type names, wavelengths in nm (350-700 by 25), Kd (W, types) in 1/m): Jerlov 1976."""
    header, data = _table("jerlov_1976_kd.csv")
    return tuple(header[1:]), data[:, 0].copy(), data[:, 1:].copy()


def colour_matching() -> np.ndarray:
    """CIE 1931 2-degree x, y, z colour matching functions on :func:`wavelengths`, (W, 3),
    by Wyman, Sloan and Shirley's (2013) multi-lobe Gaussian fit."""
    lam = wavelengths()

    def g(mu: float, s1: float, s2: float) -> np.ndarray:
        s = np.where(lam < mu, s1, s2)
        return np.exp(-0.5 * ((lam - mu) / s) ** 2)

    x = 1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) - 0.065 * g(501.1, 20.4, 26.2)
    y = 0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1)
    z = 1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8)
    return np.stack([x, y, z], -1)


def white_light() -> np.ndarray:
    """Spectral radiance of a 6504 K blackbody on :func:`wavelengths` (relative)."""
    lam = wavelengths() * 1e-9
    h, c, k = 6.62607015e-34, 2.99792458e8, 1.380649e-23
    return 1.0 / (lam**5 * np.expm1(h * c / (lam * k * 6504.0)))


@functools.cache
def channel_weights() -> np.ndarray:
    """W (W, 4): the linear sRGB R, G, B and the luminance Y of white light per wavelength,
    each normalised to sum to 1."""
    cmf = colour_matching() * white_light()[:, None]
    w = np.concatenate([cmf @ XYZ_TO_SRGB.T, cmf[:, 1:2]], axis=1)
    return w / w.sum(0)


def band(spectral_transmittance: ArrayLike) -> np.ndarray:
    """(..., W) spectral factors -> (..., 4) linear sRGB R, G, B and luminance Y of white light
    after them, relative to the unattenuated light. A spectrum outside sRGB's gamut (water
    far enough turns light a purer blue-green than sRGB's primaries hold) has a negative
    channel; :func:`transmittance` and :func:`inscatter` clip those at 0."""
    return np.asarray(spectral_transmittance) @ channel_weights()


# --- water ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Water:
    """Inherent and apparent optical properties of a water on :func:`wavelengths` (1/m).

    Attributes
    ----------
    name : str
    absorption, scattering, backscattering, kd : (W,) float64
        a, b, b_b and the diffuse attenuation Kd.
    particle_scattering : (W,) float64
        b_p (part of b), with Henyey-Greenstein g = :data:`PARTICLE_G`.
    chlorophyll : float or None
        The chlorophyll-equivalent concentration (mg/m^3) behind b_p.
    floored : float
        Fraction of wavelengths where Gordon's inversion fell below pure water's absorption
        and was floored there.
    """

    name: str
    absorption: np.ndarray
    scattering: np.ndarray
    backscattering: np.ndarray
    kd: np.ndarray
    particle_scattering: np.ndarray
    chlorophyll: float | None = None
    floored: float = 0.0

    @property
    def attenuation(self) -> np.ndarray:
        """Beam attenuation c = a + b, 1/m."""
        return self.absorption + self.scattering

    @property
    def phase_g(self) -> np.ndarray:
        """Mean cosine of the scattering phase function (water molecules 0, particles g)."""
        return PARTICLE_G * self.particle_scattering / self.scattering

    @property
    def side_scattering(self) -> np.ndarray:
        """beta(90 degrees), 1/(m sr): water molecules (Morel 1974) plus particles (HG)."""
        bw = self.scattering - self.particle_scattering
        g = PARTICLE_G
        hg90 = (1 - g * g) / (4 * math.pi * (1 + g * g) ** 1.5)
        return 0.06225 * bw + hg90 * self.particle_scattering

    def scaled(self, factor: float, name: str | None = None) -> Water:
        """The same water with its non-water part (everything beyond pure sea water) times
        ``factor`` >= 0: murkier (> 1) or clearer (< 1) water of the same kind."""
        if not (math.isfinite(factor) and factor >= 0):
            raise ArgumentError(f"scale factor must be >= 0, got {factor!r}")
        aw, bw = pure_water_absorption(), pure_water_scattering()
        kw = _kd_of(aw, bw / 2)
        return Water(
            name or f"{self.name} x{factor:.3g}",
            aw + factor * (self.absorption - aw),
            bw + factor * (self.scattering - bw),
            bw / 2 + factor * (self.backscattering - bw / 2),
            kw + factor * (self.kd - kw),
            factor * self.particle_scattering,
            None if self.chlorophyll is None else self.chlorophyll * factor,
            self.floored,
        )


def _refracted_cosine(sun_zenith: float) -> float:
    s = math.sin(math.radians(sun_zenith)) / WATER_IOR
    return math.sqrt(1 - s * s)


def _kd_of(a: np.ndarray, bb: np.ndarray, sun_zenith: float = 30.0) -> np.ndarray:
    return 1.0395 * (a + bb) / _refracted_cosine(sun_zenith)


def water(name: str = "IB", *, sun_zenith: float = 30.0) -> Water:
    """The optical properties of pure water (``"pure"``, sea water) or a Jerlov water type
    (see the module notes for how a and b follow from Jerlov's Kd).

    Parameters
    ----------
    name : {"pure", "I", "IA", "IB", "II", "III", "1C", "3C", "5C", "7C", "9C"}
    sun_zenith : float
        Degrees, 0 to 80: the sun of the Kd profiles, for Gordon's D0 = 1 / cos(theta_w).
    """
    validate_choice(name, WATER_TYPES, "water type")
    if not (0 <= sun_zenith <= 80):
        raise ArgumentError(f"sun zenith must be 0 to 80 degrees, got {sun_zenith!r}")
    aw = pure_water_absorption()
    bw = pure_water_scattering()
    lam = wavelengths()
    if name == "pure":
        kd = _kd_of(aw, bw / 2, sun_zenith)
        return Water("pure", aw, bw, bw / 2, kd, np.zeros_like(aw), None, 0.0)
    names, grid, table = jerlov_kd_table()
    kd = np.interp(lam, grid, table[:, names.index(name)])
    kd490 = float(np.interp(490.0, grid, table[:, names.index(name)]))
    chl = (max(kd490 - 0.0166, 1e-6) / 0.0773) ** (1 / 0.6715)
    bp = 0.30 * chl**0.62 * (550.0 / lam)
    bb = bw / 2 + PARTICLE_BACKSCATTER * bp
    a = kd * _refracted_cosine(sun_zenith) / 1.0395 - bb
    floored = a < aw
    a = np.maximum(a, aw)
    return Water(name, a, bw + bp, bb, kd, bp, chl, float(floored.mean()))


# --- channels -------------------------------------------------------------------------------


def transmittance(w: Water, distances: ArrayLike) -> np.ndarray:
    """Band transmittance of white light after ``distances`` (m) of water, (..., 4):
    linear sRGB R, G, B and luminance Y (exact band integrals of exp(-c d))."""
    d = np.asarray(distances, dtype=np.float64)
    if (d < 0).any() or not np.isfinite(d).all():
        raise ArgumentError("distances must be finite and >= 0 m")
    return np.maximum(band(np.exp(-d[..., None] * w.attenuation)), 0.0)


def depth_transmittance(w: Water, depths: ArrayLike) -> np.ndarray:
    """Band fraction of the downwelling light left at ``depths`` (m): exp(-Kd z), (..., 4)."""
    z = np.asarray(depths, dtype=np.float64)
    if (z < 0).any() or not np.isfinite(z).all():
        raise ArgumentError("depths must be finite and >= 0 m")
    return np.maximum(band(np.exp(-z[..., None] * w.kd)), 0.0)


def inscatter(w: Water, distances: ArrayLike, depth: ArrayLike = 0.0) -> np.ndarray:
    """In-scattered radiance along a horizontal view of ``distances`` (m) at ``depth`` (m),
    per E(0) / pi, band-integrated (..., 4) (see the module notes)."""
    d = np.asarray(distances, dtype=np.float64)[..., None]
    z = np.asarray(depth, dtype=np.float64)[..., None]
    c = w.attenuation
    spectral = math.pi * w.side_scattering / c * -np.expm1(-c * d) * np.exp(-w.kd * z)
    return np.maximum(band(spectral), 0.0)


def _e_folding(spectral: np.ndarray, channel: int, level: float = math.exp(-1)) -> float:
    """Distance (m) where the band integral of exp(-spectral d) in ``channel`` falls to
    ``level``."""
    top = 50.0 / float(spectral.min())
    return float(optimize.brentq(lambda x: band(np.exp(-x * spectral))[channel] - level, 0, top))


def channel_coefficients(w: Water, *, which: str = "beam") -> dict:
    """Per-channel exponential coefficients (1/m) for shaders: c_ch = 1 / d_ch, with d_ch the
    distance where the channel's exact band transmittance falls to 1/e.

    ``which="beam"`` is the line of sight exp(-c d), ``"diffuse"`` the ambient light with depth
    exp(-Kd z). Returns ``rgb`` (3,), ``luminance``, ``e_folding`` (3,) and
    ``e_folding_luminance`` (m), and ``max_error``: the largest |exp(-c_ch d) - T_ch(d)| while
    T_ch is above 5 % (the band integrals are not exactly exponential).
    """
    validate_choice(which, ("beam", "diffuse"), "attenuation")
    spectral = w.attenuation if which == "beam" else w.kd
    folds = np.array([_e_folding(spectral, ch) for ch in range(4)])
    error = 0.0
    for ch in range(4):
        reach = _e_folding(spectral, ch, 0.05)
        d = np.linspace(0, reach, 300)
        exact = band(np.exp(-d[:, None] * spectral))[:, ch]
        error = max(error, float(np.abs(np.exp(-d / folds[ch]) - exact).max()))
    return {
        "rgb": 1 / folds[:3],
        "luminance": float(1 / folds[3]),
        "e_folding": folds[:3],
        "e_folding_luminance": float(folds[3]),
        "max_error": error,
    }


def from_visibility(visibility: float, kind: str = "IB") -> Water:
    """A water of the kind ``kind`` whose black-disk sighting range is ``visibility`` metres:
    the type's non-water part scaled so that 4.8 / c_Y = visibility (Davies-Colley 1988), c_Y
    the luminance-weighted beam attenuation at short range. Refuses a visibility that even pure
    sea water does not reach."""
    v = float(visibility)
    if not (math.isfinite(v) and v > 0):
        raise ArgumentError(f"visibility must be a positive number of metres, got {visibility!r}")
    base = water(kind)
    y = channel_weights()[:, 3]

    def c_y(f: float) -> float:
        return float((base.scaled(f).attenuation * y).sum())

    clearest = SIGHTING / c_y(0.0)
    if v >= clearest:
        raise ArgumentError(
            f"a visibility of {v:g} m is beyond pure sea water's {clearest:.1f} m; "
            "nothing in water is clearer"
        )
    target = SIGHTING / v
    hi = 1.0
    while c_y(hi) < target:
        hi *= 2
    factor = optimize.brentq(lambda f: c_y(f) - target, 0.0, hi, xtol=1e-12)
    return base.scaled(factor, name=f"{kind} at {v:g} m visibility")


def visibility(w: Water) -> float:
    """Black-disk sighting range, m: 4.8 / c_Y (Davies-Colley 1988)."""
    return SIGHTING / float((w.attenuation * channel_weights()[:, 3]).sum())


# --- paths ----------------------------------------------------------------------------------


def underwater_path(eye_height: float, target_depth: float, horizontal: float, *,
                    refraction: bool = False, ior: float = WATER_IOR) -> float:  # fmt: skip
    """Length (m) of the part under water of the view from an eye ``eye_height`` m above a flat
    surface to a point ``target_depth`` m below it, ``horizontal`` m away.

    Without refraction the path is straight and its underwater fraction is
    p / (e + p) (similar triangles); with refraction the ray bends at the surface by Snell's law
    (found by Fermat's principle: the crossing point minimises e-path + ior x p-path). A negative
    ``eye_height`` is an eye under water: then the whole straight path is under water.
    """
    e, p, x = float(eye_height), float(target_depth), float(horizontal)
    if not (math.isfinite(e) and math.isfinite(p) and math.isfinite(x)) or p < 0 or x < 0:
        raise ArgumentError("heights and distances must be finite; depth and distance >= 0")
    if e <= 0:
        return math.hypot(x, p - (-e)) if p >= -e else math.hypot(x, p + e)
    if p == 0:
        return 0.0
    if not refraction:
        return math.hypot(x, e + p) * p / (e + p)

    def slope(s: float) -> float:  # d/ds of the optical path, zero at Snell's law
        return s / math.hypot(s, e) - ior * (x - s) / math.hypot(x - s, p)

    if x == 0:
        return p
    s = optimize.brentq(slope, 0.0, x, xtol=1e-14)
    return math.hypot(x - s, p)


# --- engine outputs -------------------------------------------------------------------------


def murk_lut(w: Water, *, max_distance: float, max_depth: float, distances: int = 64,
             depths: int = 32) -> dict:  # fmt: skip
    """Lookup tables for shaders: ``transmittance`` (distances, 3) over path length, and
    ``inscatter`` (depths, distances, 3) over (depth of the view, path length), linear sRGB;
    row i at depth max_depth i / (depths - 1), column j at max_distance j / (distances - 1)."""
    d = np.linspace(0, float(max_distance), int(distances))
    z = np.linspace(0, float(max_depth), int(depths))
    return {
        "distances": d,
        "depths": z,
        "transmittance": transmittance(w, d)[:, :3].astype(np.float32),
        "inscatter": inscatter(w, d[None, :], z[:, None])[..., :3].astype(np.float32),
    }


def source_fog(w: Water) -> dict:
    """Source-engine style linear water fog ($fogstart, $fogend, $fogcolor): the ramp
    clamp((d - start) / (end - start), 0, 1) closest (smallest largest difference) to the fog
    amount 1 - T_Y(d) of the luminance out to where T_Y falls to 1 %, and the in-scatter colour
    at infinity near the surface (linear sRGB, per E(0) / pi)."""
    far = _e_folding(w.attenuation, 3, 0.01)
    d = np.linspace(0, far, 600)
    fog = 1 - transmittance(w, d)[:, 3]

    def error(p: Sequence[float] | np.ndarray) -> float:
        start, end = p[0], max(p[1], p[0] + 1e-6)
        return np.abs(np.clip((d - start) / (end - start), 0, 1) - fog).max()

    best = optimize.minimize(error, [0.0, 0.5 * far], method="Nelder-Mead",
                             options={"xatol": 1e-6 * far, "fatol": 1e-9})  # fmt: skip
    start = max(float(best.x[0]), 0.0)
    end = max(float(best.x[1]), start + 1e-6)
    return {"fog_start_m": start, "fog_end_m": end, "max_error": float(error([start, end])),
            "fog_colour_linear": inscatter(w, 1e6, 0.0)[:3]}  # fmt: skip


def engine_constants(w: Water) -> dict:
    """Per-engine constants for this water (see docs/water.md for how each is meant).

    - ``unreal_single_layer_water``: absorption and scattering coefficients (1/cm, Unreal's
      units), and PhaseG, for the Single Layer Water material's inputs;
    - ``unity_hdrp``: absorption distance (m, where the luminance falls to 1/e) and the
      scattering colour (in-scatter at infinity near the surface, linear sRGB);
    - ``crest``: absorption and scattering per channel (1/m);
    - ``glsl``: the per-channel beam coefficients (1/m) of :func:`glsl_function`;
    - ``source``: :func:`source_fog`.
    """
    weights = channel_weights()[:, :3]
    a = w.absorption @ weights
    b = w.scattering @ weights
    g = float((w.phase_g * w.scattering) @ channel_weights()[:, 3] /
              (w.scattering @ channel_weights()[:, 3]))  # fmt: skip
    beam = channel_coefficients(w)
    return {
        "unreal_single_layer_water": {
            "absorption_coefficients_per_cm": a / 100,
            "scattering_coefficients_per_cm": b / 100,
            "phase_g": g,
        },
        "unity_hdrp": {
            "absorption_distance_m": beam["e_folding_luminance"],
            "scattering_color_linear": inscatter(w, 1e6, 0.0)[:3],
        },
        "crest": {"absorption_per_m": a, "scattering_per_m": b},
        "glsl": {"beam_attenuation_per_m": beam["rgb"]},
        "source": source_fog(w),
    }


def glsl_function(w: Water, *, name: str = "waterTransmittance") -> str:
    """A GLSL function returning the linear sRGB transmittance after ``d`` metres and the
    in-scatter along that path at depth ``z`` (per unit E(0) / pi)."""
    beam = channel_coefficients(w)["rgb"]
    far = inscatter(w, 1e6, 0.0)[:3]
    kd = channel_coefficients(w, which="diffuse")["rgb"]

    def v(x: np.ndarray) -> str:
        return "vec3(" + ", ".join(f"{float(t):.6g}" for t in x) + ")"

    return (
        f"// {w.name} water: beam attenuation (1/m), in-scatter at infinity, Kd (1/m)\n"
        f"const vec3 WATER_C = {v(beam)};\n"
        f"const vec3 WATER_INSCATTER = {v(far)};\n"
        f"const vec3 WATER_KD = {v(kd)};\n"
        f"vec3 {name}(float d) {{ return exp(-WATER_C * d); }}\n"
        f"vec3 {name}Inscatter(float d, float z) {{\n"
        f"    return WATER_INSCATTER * (1.0 - exp(-WATER_C * d)) * exp(-WATER_KD * z);\n"
        "}\n"
    )
