"""Ocean wave spectra and the dispersion relation, in SI units.

A sea state is a :class:`Spectrum`: a frequency spectrum S(omega) (Pierson-Moskowitz, JONSWAP,
TMA) times a directional spreading D(theta), or Tessendorf's Phillips spectrum written directly
over wave vectors. :meth:`Spectrum.density` turns either into the wave-vector density F(kx, ky)
that the FFT synthesis samples on a patch's lattice.

Units: wave number k in rad/m, angular frequency omega in rad/s, S(omega) in m^2 s/rad,
F(kx, ky) in m^4 (variance per unit area of wave-vector space, m^2 / (rad/m)^2), lengths in m,
speeds in m/s. Directions are angles in the texture plane in degrees, measured from +u (+X)
towards +v (up the picture, world -Z).

Conventions
-----------
F(k) is the variance of waves *travelling towards* k / |k|: a directional spectrum, not the
symmetrised spectrum of a snapshot. Its integral over the plane is the elevation variance m0, and
the significant wave height is Hs = 4 sqrt(m0).

Dispersion (Lamb 1932, sec. 228 and 267): omega^2 = (g k + sigma k^3 / rho) tanh(k d), with
gravity g, surface tension sigma, density rho and depth d (tanh = 1 in deep water).

From S(omega) D(theta) to F: the variance in d omega d theta equals the variance in
k dk d theta, so F(k, theta) = S(omega(k)) D(theta; omega) c_g(k) / k with c_g = d omega / dk.

References
----------
J. Tessendorf, "Simulating Ocean Water", SIGGRAPH 2001 course notes (Phillips spectrum, eq. 40;
small-wave suppression, eq. 41).
W. J. Pierson and L. Moskowitz, "A proposed spectral form for fully developed wind seas based on
the similarity theory of S. A. Kitaigorodskii", J. Geophys. Res. 69(24), 5181-5190, 1964,
doi:10.1029/JZ069i024p05181.
K. Hasselmann et al., "Measurements of wind-wave growth and swell decay during the Joint North
Sea Wave Project (JONSWAP)", Dtsch. Hydrogr. Z. A8(12), 1973.
E. Bouws, H. Guenther, W. Rosenthal and C. L. Vincent, "Similarity of the wind wave spectrum in
finite depth water: 1. Spectral form", J. Geophys. Res. 90(C1), 975-986, 1985,
doi:10.1029/JC090iC01p00975 (TMA; the Kitaigorodskii depth factor phi).
H. Mitsuyasu et al., "Observations of the directional spectrum of ocean waves using a cloverleaf
buoy", J. Phys. Oceanogr. 5(4), 750-760, 1975, doi:10.1175/1520-0485(1975)005<0750:OOTDSO>2.0.CO;2.
M. S. Longuet-Higgins, D. E. Cartwright and N. D. Smith, "Observations of the directional
spectrum of sea waves using the motions of a floating buoy", Ocean Wave Spectra, 1963 (cos^2s).
R. H. Stewart, *Introduction to Physical Oceanography*, 2008, sec. 16.3 (U19.5 = 1.026 U10).
C. J. Horvath, "Empirical directional wave spectra for computer graphics", DigiPro 2015,
doi:10.1145/2791261.2791267.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy import integrate, special

from bakeshop.errors import ArgumentError, validate_choice

#: Standard gravity used across bakeshop (DESIGN: g = 9.81 m/s^2).
GRAVITY = 9.81
#: Density of water, kg/m^3 (DESIGN).
WATER_DENSITY = 1000.0
#: Surface tension of clean water against air at 20 C, N/m.
SURFACE_TENSION = 0.0728
#: Kinematic viscosity of water at 20 C, m^2/s.
KINEMATIC_VISCOSITY = 1.0e-6

SpectrumKind = Literal["phillips", "pierson-moskowitz", "jonswap", "tma"]
SPECTRA = ("phillips", "pierson-moskowitz", "jonswap", "tma")
Spreading = Literal["mitsuyasu", "cos2s", "cos2"]
SPREADINGS = ("mitsuyasu", "cos2s", "cos2")

#: Pierson-Moskowitz constants (Pierson and Moskowitz 1964): S = alpha g^2 / w^5
#: exp(-beta (g / (U19.5 w))^4).
PM_ALPHA = 8.1e-3
PM_BETA = 0.74
#: U19.5 / U10 for a neutral log profile (Stewart 2008, sec. 16.3).
U19_5_PER_U10 = 1.026
#: JONSWAP peak widths below and above the peak (Hasselmann et al. 1973).
JONSWAP_SIGMA = (0.07, 0.09)
#: Dimensionless fetch g F / U10^2 beyond which JONSWAP's peak would fall below the fully
#: developed Pierson-Moskowitz peak; the fetch is capped there (fully developed sea).
JONSWAP_DEVELOPED_FETCH = (22.0 / (0.877 / U19_5_PER_U10)) ** 3
#: Slowest wind accepted, m/s. The spectra are wind-sea forms whose peak wavelength grows as U^2
#: (2 pi U^2 / g): at 0.1 m/s it is 6 mm, far below any lattice, and slower winds only push
#: the spectra's U^2 and U^-4 terms towards underflow and overflow.
MIN_WIND_SPEED = 0.1


def dispersion(
    k: ArrayLike,
    *,
    depth: float = math.inf,
    gravity: float = GRAVITY,
    surface_tension: float = SURFACE_TENSION,
    density: float = WATER_DENSITY,
) -> np.ndarray:
    """Angular frequency of capillary-gravity waves of wave number ``k``.

    omega = sqrt((g k + sigma k^3 / rho) tanh(k d)) (Lamb 1932, sec. 228, 267). Deep water
    (``depth=inf``) drops the tanh; ``surface_tension=0`` gives pure gravity waves.

    Parameters
    ----------
    k : array_like
        Wave number, rad/m (>= 0).
    depth : float
        Water depth, m (> 0, may be inf).
    gravity, surface_tension, density : float
        m/s^2, N/m, kg/m^3.

    Returns
    -------
    omega : ndarray, rad/s, shape of ``k``.
    """
    k = np.asarray(k, dtype=np.float64)
    w2 = gravity * k + (surface_tension / density) * k**3
    if math.isfinite(depth):
        with np.errstate(over="ignore"):  # k d past the float range: tanh is 1 (deep water)
            w2 = w2 * np.tanh(k * depth)
    return np.sqrt(w2)


def group_velocity(
    k: ArrayLike,
    *,
    depth: float = math.inf,
    gravity: float = GRAVITY,
    surface_tension: float = SURFACE_TENSION,
    density: float = WATER_DENSITY,
) -> np.ndarray:
    """Group velocity d omega / dk of :func:`dispersion`, m/s (exact derivative).

    With a = g k + s k^3 (s = sigma / rho) and T = tanh(k d):
    2 omega c_g = (g + 3 s k^2) T + a d (1 - T^2). At k = 0 the deep-water limit is infinite
    for gravity waves; the value returned there is 0 (no wave has k = 0).
    """
    k = np.asarray(k, dtype=np.float64)
    s = surface_tension / density
    a = gravity * k + s * k**3
    da = gravity + 3 * s * k**2
    if math.isfinite(depth):
        with np.errstate(over="ignore"):  # k d past the float range: tanh is 1 (deep water)
            t = np.tanh(k * depth)
        w2 = a * t
        # d (1 - T^2) first: 0 in deep water even when a d would overflow (a huge finite depth)
        d2 = da * t + a * (depth * (1 - t * t))
    else:
        w2, d2 = a, da
    w = np.sqrt(w2)
    with np.errstate(divide="ignore", invalid="ignore"):
        cg = np.where(w > 0, d2 / (2 * np.where(w > 0, w, 1)), 0.0)
    return cg


def tma_depth_factor(k: ArrayLike, depth: float) -> np.ndarray:
    """Kitaigorodskii's depth factor phi of the TMA spectrum, exact (Bouws et al. 1985).

    phi = (k^-3 dk/domega) at depth d over the same in deep water, at the same omega, for gravity
    waves: phi = tanh^2(k d) / (1 + 2 k d / sinh(2 k d)), with k the finite-depth wave number.
    It tends to 1 in deep water and to omega_h^2 / 2 in shallow water (omega_h = omega sqrt(d/g)).
    """
    k = np.asarray(k, dtype=np.float64)
    if not math.isfinite(depth):
        return np.ones_like(k)
    with np.errstate(over="ignore"):  # k d past the float range: deep water
        kd = k * depth
    t = np.tanh(kd)
    with np.errstate(over="ignore"):
        g = np.where(kd < 350, 2 * kd / np.sinh(np.minimum(2 * kd, 700)), 0.0)
    return np.where(kd > 0, t * t / (1 + g), 0.0)


def cos2s_normalisation(s: ArrayLike) -> np.ndarray:
    """N(s) such that N(s) cos^(2s)(theta / 2) integrates to 1 over (-pi, pi]:
    N = Gamma(s + 1) / (2 sqrt(pi) Gamma(s + 1/2)) (Longuet-Higgins et al. 1963)."""
    s = np.asarray(s, dtype=np.float64)
    return np.exp(special.gammaln(s + 1) - special.gammaln(s + 0.5)) / (2 * math.sqrt(math.pi))


@dataclass(frozen=True)
class Spectrum:
    """A sea state: spectrum model, wind, fetch, depth and directional spreading (SI units).

    Attributes
    ----------
    kind : {"phillips", "pierson-moskowitz", "jonswap", "tma"}
        ``phillips``: Tessendorf's F = A exp(-1 / (k L)^2) / k^4 (k_hat . w_hat)^2, L = U^2 / g.
        ``pierson-moskowitz``: fully developed sea (1964). ``jonswap``: fetch-limited sea
        (Hasselmann et al. 1973). ``tma``: JONSWAP times Kitaigorodskii's depth factor (Bouws et
        al. 1985), for finite ``depth``.
    wind_speed : float
        U10, m/s, wind 10 m above the sea (>= :data:`MIN_WIND_SPEED`).
    wind_direction : float
        Degrees in the texture plane from +u towards +v (up the picture).
    fetch : float
        Metres of open water upwind (JONSWAP, TMA); capped where the sea is fully developed
        (g F / U10^2 = :data:`JONSWAP_DEVELOPED_FETCH`).
    depth : float
        Water depth, m (inf: deep water). Enters the dispersion relation of every kind, and the
        spectrum itself for ``tma``.
    gamma : float
        JONSWAP peak enhancement (3.3 is the mean of Hasselmann et al.).
    spreading : {"mitsuyasu", "cos2s", "cos2"}
        Directional spreading of the frequency spectra: ``mitsuyasu`` is cos^(2s)(theta / 2)
        with s(omega) from Mitsuyasu et al. 1975 (narrow at the peak, wider away from it);
        ``cos2s`` the same with a fixed ``spread`` = s; ``cos2`` is (2 / pi) cos^2(theta),
        waves only with the wind.
    spread : float
        s of ``cos2s`` (> 0; larger is narrower: s = 10 keeps 90 % of the energy within
        +-37 degrees).
    cutoff : float
        Small-wave cut-off length l, m: F is multiplied by exp(-k^2 l^2) (Tessendorf eq. 41);
        0 for none.
    amplitude : float
        A of ``phillips`` (dimensionless; F in m^4). Tessendorf's per-mode constant is
        A (2 pi / size)^2 / 2 on a patch of ``size`` metres.
    against_wind : float
        ``phillips`` only: factor on waves travelling against the wind (1 keeps Tessendorf's
        symmetric cos^2, 0 removes them).
    gravity, surface_tension, water_density : float
        m/s^2, N/m, kg/m^3 (surface_tension 0 for pure gravity waves).
    """

    kind: SpectrumKind = "jonswap"
    wind_speed: float = 10.0
    wind_direction: float = 0.0
    fetch: float = 100_000.0
    depth: float = math.inf
    gamma: float = 3.3
    spreading: Spreading = "mitsuyasu"
    spread: float = 10.0
    cutoff: float = 0.0
    amplitude: float = 1.0e-3
    against_wind: float = 1.0
    gravity: float = GRAVITY
    surface_tension: float = SURFACE_TENSION
    water_density: float = WATER_DENSITY

    def __post_init__(self) -> None:
        validate_choice(self.kind, SPECTRA, "spectrum")
        validate_choice(self.spreading, SPREADINGS, "directional spreading")
        checks = {
            "wind speed (m/s)": (self.wind_speed, MIN_WIND_SPEED, True),
            "fetch (m)": (self.fetch, 0, False),
            "depth (m)": (self.depth, 0, False),
            "gamma": (self.gamma, 1, True),
            "spread s": (self.spread, 0, False),
            "cut-off length (m)": (self.cutoff, 0, True),
            "Phillips amplitude": (self.amplitude, 0, False),
            "gravity (m/s^2)": (self.gravity, 0, False),
            "surface tension (N/m)": (self.surface_tension, 0, True),
            "water density (kg/m^3)": (self.water_density, 0, False),
        }
        for name, (value, low, inclusive) in checks.items():
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ArgumentError(f"{name} must be a number, got {value!r}") from None
            ok = value >= low if inclusive else value > low
            if math.isnan(value) or not ok:
                bound = f">= {low}" if inclusive else f"> {low}"
                raise ArgumentError(f"{name} must be a number {bound}, got {value!r}")
            if name != "depth (m)" and not math.isfinite(value):
                raise ArgumentError(f"{name} must be finite, got {value!r}")
        if not math.isfinite(self.wind_direction):
            raise ArgumentError(f"wind direction must be finite, got {self.wind_direction!r}")
        if not 0 <= self.against_wind <= 1:
            raise ArgumentError(f"against_wind must be in [0, 1], got {self.against_wind!r}")
        if self.kind == "tma" and not math.isfinite(self.depth):
            raise ArgumentError("the TMA spectrum is for finite depth: give depth= in metres")

    # --- dispersion ------------------------------------------------------------------------

    def _dispersion_options(self) -> dict:
        return dict(
            depth=self.depth,
            gravity=self.gravity,
            surface_tension=self.surface_tension,
            density=self.water_density,
        )

    def omega(self, k: ArrayLike) -> np.ndarray:
        """Angular frequency (rad/s) of wave number ``k`` (rad/m): :func:`dispersion`."""
        return dispersion(k, **self._dispersion_options())

    def group_velocity(self, k: ArrayLike) -> np.ndarray:
        """D omega / dk (m/s) of wave number ``k`` (rad/m): :func:`group_velocity`."""
        return group_velocity(k, **self._dispersion_options())

    # --- frequency spectra -------------------------------------------------------------------

    @property
    def dimensionless_fetch(self) -> float:
        """G F / U10^2, capped at :data:`JONSWAP_DEVELOPED_FETCH` (fully developed)."""
        return min(self.gravity * self.fetch / self.wind_speed**2, JONSWAP_DEVELOPED_FETCH)

    @property
    def peak_frequency(self) -> float:
        """omega_p, rad/s, of the frequency spectrum (Phillips: where its k^2 F(k) peaks)."""
        g, u = self.gravity, self.wind_speed
        if self.kind == "pierson-moskowitz":
            return (4 * PM_BETA / 5) ** 0.25 * g / (U19_5_PER_U10 * u)
        if self.kind in ("jonswap", "tma"):
            return 22.0 * g / u * self.dimensionless_fetch ** (-1 / 3)
        # Phillips: k^2 F ~ exp(-1/(kL)^2) / k^2 peaks at k L = 1, omega = sqrt(g / L) = g / U.
        return g / u

    @property
    def phillips_alpha(self) -> float:
        """JONSWAP's Phillips constant alpha = 0.076 (g F / U10^2)^-0.22 (Hasselmann 1973)."""
        return 0.076 * self.dimensionless_fetch ** (-0.22)

    def frequency_density(self, omega: ArrayLike) -> np.ndarray:
        """S(omega), m^2 s/rad, of the deep-water frequency spectrum (without the TMA factor).

        Pierson-Moskowitz: alpha g^2 / w^5 exp(-beta (g / (U19.5 w))^4), alpha = 8.1e-3,
        beta = 0.74. JONSWAP: alpha g^2 / w^5 exp(-5/4 (w_p / w)^4) gamma^r,
        r = exp(-(w - w_p)^2 / (2 sigma^2 w_p^2)), sigma = 0.07 below the peak and 0.09 above,
        with alpha and w_p from the fetch (Hasselmann et al. 1973).
        """
        if self.kind == "phillips":
            raise ArgumentError("the Phillips spectrum is defined over wave vectors, not omega")
        w = np.asarray(omega, dtype=np.float64)
        g = self.gravity
        out = np.zeros_like(w)
        pos = w > 0
        wp = w[pos]
        if self.kind == "pierson-moskowitz":
            w0 = g / (U19_5_PER_U10 * self.wind_speed)
            out[pos] = PM_ALPHA * g * g / wp**5 * np.exp(-PM_BETA * (w0 / wp) ** 4)
            return out
        peak = self.peak_frequency
        sigma = np.where(wp <= peak, JONSWAP_SIGMA[0], JONSWAP_SIGMA[1])
        r = np.exp(-((wp - peak) ** 2) / (2 * sigma**2 * peak**2))
        out[pos] = (
            self.phillips_alpha * g * g / wp**5 * np.exp(-1.25 * (peak / wp) ** 4) * self.gamma**r
        )
        return out

    def spreading_exponent(self, omega: ArrayLike) -> np.ndarray:
        """S of cos^(2s)(theta / 2) at ``omega``: Mitsuyasu's s(omega) or the fixed spread.

        Mitsuyasu et al. 1975: s_p = 11.5 (w_p U10 / g)^-2.5; s = s_p (w / w_p)^5 below the
        peak and s_p (w / w_p)^-2.5 above.
        """
        w = np.asarray(omega, dtype=np.float64)
        if self.spreading != "mitsuyasu":
            return np.full_like(w, self.spread)
        peak = self.peak_frequency
        sp = 11.5 * (peak * self.wind_speed / self.gravity) ** -2.5
        ratio = w / peak
        return np.where(ratio <= 1, sp * ratio**5, sp * ratio**-2.5)

    def directional_spreading(self, theta: ArrayLike, omega: ArrayLike) -> np.ndarray:
        """D(theta; omega), 1/rad, normalised to 1 over a full turn; theta in radians from the
        wind direction."""
        theta = np.asarray(theta, dtype=np.float64)
        if self.spreading == "cos2":
            c = np.cos(theta)
            return np.where(c > 0, (2 / math.pi) * c * c, 0.0)
        s = self.spreading_exponent(omega)
        c = np.abs(np.cos(0.5 * theta))
        with np.errstate(divide="ignore"):
            return cos2s_normalisation(s) * np.exp(2 * s * np.log(c))

    # --- the wave-vector density -------------------------------------------------------------

    def density_polar(self, k: ArrayLike, theta: ArrayLike) -> np.ndarray:
        """F(k, theta) k, m^2 / (rad/m) / rad: the variance per dk dtheta at wave number ``k``
        (rad/m) and direction ``theta`` (radians from +u). Integrates to m0 over k and theta."""
        k = np.asarray(k, dtype=np.float64)
        theta = np.asarray(theta, dtype=np.float64)
        return self._density(k, theta) * k

    def density(self, kx: ArrayLike, ky: ArrayLike) -> np.ndarray:
        """F(kx, ky), m^4: variance per unit area of wave-vector space of waves travelling
        towards (kx, ky) (rad/m, kx along +u, ky along +v). F(0) = 0.

        The integral over the plane is the elevation variance m0 (m^2).
        """
        kx = np.asarray(kx, dtype=np.float64)
        ky = np.asarray(ky, dtype=np.float64)
        k = np.hypot(kx, ky)
        return self._density(k, np.arctan2(ky, kx))

    def _density(self, k: np.ndarray, theta: np.ndarray) -> np.ndarray:
        k, theta = np.broadcast_arrays(k, theta)
        out = np.zeros(k.shape)
        pos = k > 0
        kp = k[pos]
        rel = theta[pos] - math.radians(self.wind_direction)
        if self.kind == "phillips":
            big_l = self.wind_speed**2 / self.gravity
            cos_w = np.cos(rel)
            f = self.amplitude * np.exp(-1.0 / (kp * big_l) ** 2) / kp**4 * cos_w * cos_w
            f = np.where(cos_w < 0, f * self.against_wind, f)
        else:
            w = self.omega(kp)
            f = self.frequency_density(w) * self.group_velocity(kp) / kp
            f = f * self.directional_spreading(rel, w)
            if self.kind == "tma":
                f = f * tma_depth_factor(kp, self.depth)
        if self.cutoff > 0:
            f = f * np.exp(-((kp * self.cutoff) ** 2))
        out[pos] = f
        return out

    # --- integrals ---------------------------------------------------------------------------

    def variance(self, k_min: float = 0.0, k_max: float = math.inf) -> float:
        """m0 = the integral of F over k_min <= |k| < k_max (m^2), by adaptive quadrature.

        The frequency spectra's spreading integrates to 1 over direction, so for them this is
        the integral of S(omega(k)) c_g(k) phi(k) dk; Phillips is integrated over direction too.
        """
        if self.kind == "phillips":

            def radial(k: float) -> float:
                return integrate.quad(
                    lambda t: float(self.density_polar(k, t)), -math.pi, math.pi, limit=200
                )[0]
        else:

            def radial(k: float) -> float:
                w = self.omega(k)
                f = float(self.frequency_density(w) * self.group_velocity(k))
                if self.kind == "tma":
                    f *= float(tma_depth_factor(k, self.depth))
                if self.cutoff > 0:
                    f *= math.exp(-((k * self.cutoff) ** 2))
                return f

        peak_k = self._peak_wavenumber()
        points = [p for p in (peak_k / 4, peak_k, 4 * peak_k) if k_min < p < k_max]
        edges = [k_min, *points, k_max]
        total = 0.0
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            total += integrate.quad(radial, a, b, limit=400, epsabs=0, epsrel=1e-10)[0]
        return total

    def significant_wave_height(self, k_min: float = 0.0, k_max: float = math.inf) -> float:
        """Hs = 4 sqrt(m0), m, over the wave numbers in [k_min, k_max)."""
        return 4.0 * math.sqrt(self.variance(k_min, k_max))

    def _peak_wavenumber(self) -> float:
        w = self.peak_frequency
        # invert the gravity part of the dispersion relation by Newton's method
        k = w * w / self.gravity
        for _ in range(50):
            f = self.omega(k) - w
            k = max(k - float(f / max(float(self.group_velocity(k)), 1e-12)), 1e-9)
        return k

    def to_dict(self) -> dict:
        """The parameters as plain JSON-able values (depth inf becomes None)."""
        d = asdict(self)
        if not math.isfinite(self.depth):
            d["depth"] = None
        units = {
            "wind_speed": "m/s",
            "wind_direction": "degrees",
            "fetch": "m",
            "depth": "m",
            "cutoff": "m",
            "gravity": "m/s^2",
            "surface_tension": "N/m",
            "water_density": "kg/m^3",
        }
        d["units"] = units
        return d
