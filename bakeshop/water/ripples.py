"""Impact ripples: the analytic ring of a drop, and a wave-equation height field for many
impacts and floating objects (SI units).

The analytic ring
-----------------
A drop leaves a crater, modelled as an initial depression eta0(r) = -A exp(-r^2 / a^2) of the
still surface with no initial velocity (the Cauchy-Poisson problem). Linear theory gives every
axisymmetric mode its own frequency from the capillary-gravity dispersion
omega^2 = (g k + sigma k^3 / rho) tanh(k d), and viscosity damps each mode's amplitude as
exp(-2 nu k^2 t) (Lamb 1932, sec. 348):

    eta(r, t)  = int_0^inf  E(k) J0(k r) cos(omega t) exp(-2 nu k^2 t) k dk
    deta/dr    = -int_0^inf E(k) J1(k r) cos(omega t) exp(-2 nu k^2 t) k^2 dk
    E(k)       = -A a^2 / 2 exp(-k^2 a^2 / 4)          (Hankel transform of eta0)

evaluated by quadrature over k (the integrand is negligible beyond k = 8 / a). The slope is the
exact radial derivative, so the normals are exact: n ~ (-deta/dr x/r, -deta/dr y/r, 1). Energy
travels outwards at the group velocity of each wave number (the ring's front moves at c_g of the
crater's dominant k = sqrt(2) / a), and spreads over a circle: the amplitude along a crest falls
as 1 / sqrt(r) on top of dispersion. The displaced volume -pi A a^2 is conserved.

The crater from a drop: the wave energy is a fraction ``energy_fraction`` of the drop's kinetic
energy 1/2 m V^2 (a choice, not a splash model), put into the depression's potential energy
E = pi rho g A^2 a^2 / 4 + pi sigma A^2 / 2, with the crater width a a multiple of the drop
diameter.

The wave equation
-----------------
d^2 h / dt^2 = c^2 lap(h) - gamma dh/dt + f, with the 9-point isotropic Laplacian
lap(h) ~ (4 (N + S + E + W) + (NE + NW + SE + SW) - 20 h) / (6 dx^2) (its error is isotropic to
leading order, so rings stay round), damping on the velocity only (gamma, 1/s; a still surface
is not pulled anywhere), and a leapfrog step
v <- ((1 - gamma dt / 2) v + dt (c^2 lap(h) + f)) / (1 + gamma dt / 2); h <- h + dt v. It is
stable for c dt / dx <= sqrt(3) / 2 (the stencil's largest eigenvalue is 16 / (3 dx^2)); larger
steps are refused. Edges: ``periodic`` (tileable), ``reflect`` (mirror: dh/dn = 0) or
``absorb`` (Mur's first-order condition, exact at normal incidence). This is Hugo Elias' classic
two-buffer ripple with a stencil that keeps rings round and a stated stability bound.

References
----------
H. Lamb, *Hydrodynamics*, 6th ed., 1932, sec. 228, 255 (Cauchy-Poisson), 267, 348 (viscous
damping).
J. Tessendorf, "Interactive Water Surfaces", Game Programming Gems 4, 2004 (iWave).
H. Elias, "2D water" (the two-buffer ripple), c. 1998.
G. Mur, "Absorbing boundary conditions for the finite-difference approximation of the
time-domain electromagnetic-field equations", IEEE Trans. EMC 23(4), 377-382, 1981,
doi:10.1109/TEMC.1981.303970.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike
from scipy import special

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.water import _native
from bakeshop.water.spectra import (
    GRAVITY,
    KINEMATIC_VISCOSITY,
    SURFACE_TENSION,
    WATER_DENSITY,
    dispersion,
    group_velocity,
)

EDGES = ("periodic", "reflect", "absorb")
#: Largest stable Courant number c dt / dx of the 9-point isotropic stencil with leapfrog.
CFL_LIMIT = math.sqrt(3) / 2


def _positive(value: float, what: str, *, zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ArgumentError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not zero):
        raise ArgumentError(
            f"{what} must be a finite number {'>=' if zero else '>'} 0, got {value!r}"
        )
    return v


@dataclass(frozen=True)
class Crater:
    """The initial depression eta0(r) = -amplitude exp(-r^2 / width^2) of an impact, with the
    water it lies in (SI units). Make one from a drop with :func:`drop_crater`."""

    amplitude: float  # m
    width: float  # m
    depth: float = math.inf  # m
    gravity: float = GRAVITY  # m/s^2
    surface_tension: float = SURFACE_TENSION  # N/m
    density: float = WATER_DENSITY  # kg/m^3
    viscosity: float = KINEMATIC_VISCOSITY  # m^2/s (0: no damping)

    def __post_init__(self) -> None:
        _positive(self.amplitude, "crater amplitude (m)", zero=True)
        _positive(self.width, "crater width (m)")
        if not (self.depth > 0):
            raise ArgumentError(f"depth must be > 0 m, got {self.depth!r}")
        _positive(self.gravity, "gravity (m/s^2)")
        _positive(self.surface_tension, "surface tension (N/m)", zero=True)
        _positive(self.density, "density (kg/m^3)")
        _positive(self.viscosity, "kinematic viscosity (m^2/s)", zero=True)

    @property
    def energy(self) -> float:
        """Potential energy of the depression, J: pi rho g A^2 a^2 / 4 + pi sigma A^2 / 2."""
        a2 = self.amplitude**2
        return math.pi * a2 * (self.density * self.gravity * self.width**2 / 4 +
                               self.surface_tension / 2)  # fmt: skip

    @property
    def dominant_wavenumber(self) -> float:
        """k0 = sqrt(2) / a, rad/m, where |E(k)| k (the ring's radial spectrum) peaks."""
        return math.sqrt(2) / self.width

    def omega(self, k: ArrayLike) -> np.ndarray:
        """Angular frequency (rad/s) of wavenumber k (rad/m) on this water."""
        return dispersion(k, depth=self.depth, gravity=self.gravity,
                          surface_tension=self.surface_tension, density=self.density)  # fmt: skip

    def group_velocity(self, k: ArrayLike) -> np.ndarray:
        """Group velocity (m/s) of wavenumber k (rad/m) on this water."""
        return group_velocity(k, depth=self.depth, gravity=self.gravity,
                              surface_tension=self.surface_tension,
                              density=self.density)  # fmt: skip

    @property
    def front_speed(self) -> float:
        """c_g(k0), m/s: the speed of the ring's energy."""
        return float(self.group_velocity(self.dominant_wavenumber))

    def to_dict(self) -> dict:
        """The drop as a JSON-ready dict (SI units in the keys)."""
        return {
            "amplitude_m": self.amplitude,
            "width_m": self.width,
            "depth_m": self.depth if math.isfinite(self.depth) else None,
            "gravity_m_s2": self.gravity,
            "surface_tension_n_m": self.surface_tension,
            "density_kg_m3": self.density,
            "viscosity_m2_s": self.viscosity,
            "energy_j": self.energy,
            "dominant_wavenumber_rad_m": self.dominant_wavenumber,
            "front_speed_m_s": self.front_speed,
        }


def drop_crater(
    *,
    drop_diameter: float,
    drop_speed: float,
    energy_fraction: float = 0.05,
    width_factor: float = 2.0,
    energy: float | None = None,
    **water: float,
) -> Crater:
    """The crater of a drop of ``drop_diameter`` (m) hitting at ``drop_speed`` (m/s).

    The wave energy is ``energy_fraction`` of the drop's kinetic energy (or ``energy`` in J
    when given), the crater width ``width_factor`` drop diameters; ``water`` takes the
    :class:`Crater` fields depth, gravity, surface_tension, density, viscosity.
    """
    d = _positive(drop_diameter, "drop diameter (m)")
    density = float(water.get("density", WATER_DENSITY))
    if energy is None:
        v = _positive(drop_speed, "drop speed (m/s)", zero=True)
        f = _positive(energy_fraction, "energy fraction", zero=True)
        if f > 1:
            raise ArgumentError(f"energy fraction must be in [0, 1], got {energy_fraction!r}")
        mass = density * math.pi * d**3 / 6
        energy = f * 0.5 * mass * v * v
    energy = _positive(energy, "wave energy (J)", zero=True)
    width = _positive(width_factor, "crater width factor") * d
    unit = Crater(1.0, width, **water).energy  # energy of a unit-amplitude crater
    return Crater(math.sqrt(energy / unit), width, **water)


def _k_nodes(
    crater: Crater, r_max: float, t_max: float, nodes: int | None
) -> tuple[np.ndarray, np.ndarray]:
    k_max = 8.0 / crater.width
    if nodes is None:
        reach = r_max + float(crater.group_velocity(k_max)) * t_max + crater.width
        nodes = int(min(max(2048, 8 * k_max * reach / (2 * math.pi)), 1 << 20))
    k = np.linspace(0.0, k_max, nodes + 1)
    w = np.full(k.size, k[1] - k[0])  # trapezoid weights (the integrand vanishes at both ends)
    w[0] = w[-1] = 0.5 * (k[1] - k[0])
    return k, w


def ring(
    crater: Crater,
    r: ArrayLike,
    times: ArrayLike,
    *,
    damping: bool = True,
    nodes: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Height and radial slope of the analytic ring at radii ``r`` (m) and ``times`` (s).

    Returns
    -------
    eta : (T, R) float64, m
    slope : (T, R) float64, d eta / dr (m/m)
    """
    r = np.asarray(r, dtype=np.float64).ravel()
    t = np.asarray(times, dtype=np.float64).ravel()
    if (r < 0).any() or not np.isfinite(r).all() or (t < 0).any() or not np.isfinite(t).all():
        raise ArgumentError("radii and times must be finite and >= 0")
    k, w = _k_nodes(crater, float(r.max(initial=0)), float(t.max(initial=0)), nodes)
    e = -crater.amplitude * crater.width**2 / 2 * np.exp(-((k * crater.width) ** 2) / 4)
    # weights (K, T) of every time, then one matrix product per Bessel function: the Bessel
    # values J(k r) do not depend on time
    weight = (e * w)[:, None] * np.cos(np.outer(crater.omega(k), t))
    if damping and crater.viscosity > 0:
        weight *= np.exp(-2 * crater.viscosity * np.outer(k * k, t))
    eta = np.empty((t.size, r.size))
    slope = np.empty((t.size, r.size))
    step = max(1, (1 << 22) // k.size)
    for s in range(0, r.size, step):
        kr = np.outer(r[s : s + step], k)
        eta[:, s : s + step] = (special.j0(kr) @ (weight * k[:, None])).T
        slope[:, s : s + step] = -(special.j1(kr) @ (weight * (k * k)[:, None])).T
    return eta, slope


def _radial_to_grid(
    values: np.ndarray, r_nodes: np.ndarray, x: np.ndarray, y: np.ndarray, cx: float, cy: float
) -> np.ndarray:
    rr = np.hypot(x - cx, y - cy)
    return np.interp(rr, r_nodes, values, right=0.0)


def ring_normals(crater: Crater, *, size: float, resolution: int, times: ArrayLike,
                 damping: bool = True, nodes: int | None = None) -> np.ndarray:  # fmt: skip
    """Unit normals of one ring centred on a ``size`` x ``size`` m texture, (T, N, N, 3).

    The radial profile is computed exactly on a fine radial grid (four samples per texel) and
    interpolated; n = (-s x / r, -s y / r, 1) / |.| with s = d eta / dr (tangent frame: x along
    u, y up the picture).
    """
    size = _positive(size, "texture size (m)")
    n = int(resolution)
    texel = size / n
    r_nodes = np.arange(0, size * 0.75, texel / 4)
    _, slope = ring(crater, r_nodes, times, damping=damping, nodes=nodes)
    c = (np.arange(n) + 0.5) * texel
    x, y = np.meshgrid(c, size - c)
    cx = cy = size / 2
    rr = np.hypot(x - cx, y - cy)
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.where(rr > 0, (x - cx) / rr, 0.0)
        uy = np.where(rr > 0, (y - cy) / rr, 0.0)
    out = np.empty((slope.shape[0], n, n, 3), np.float32)
    for i in range(slope.shape[0]):
        s = np.interp(rr, r_nodes, slope[i], right=0.0)
        v = np.stack([-s * ux, -s * uy, np.ones_like(s)], -1)
        out[i] = v / np.linalg.norm(v, axis=-1, keepdims=True)
    return out


def ring_lut(crater: Crater, *, radius: float, duration: float, radii: int = 256,
             steps: int = 256, damping: bool = True) -> np.ndarray:  # fmt: skip
    """The ring as a lookup table over (time, radius) for shaders: ``(steps, radii, 3)``
    float32, row i at t = duration i / (steps - 1) (row 0 at the top), column j at
    r = radius j / (radii - 1); channels (eta in m, d eta / dr in m/m, 0).

    A shader animates a drop by sampling it at (r / radius, t / duration), so one small
    texture drives any number of drops; see :func:`rain_atlas`.
    """
    r = np.linspace(0, _positive(radius, "ring radius (m)"), int(radii))
    t = np.linspace(0, _positive(duration, "ring duration (s)"), int(steps))
    eta, slope = ring(crater, r, t, damping=damping)
    out = np.zeros((t.size, r.size, 3), np.float32)
    out[..., 0] = eta
    out[..., 1] = slope
    return out


def ring_texture(crater: Crater, *, size: float, resolution: int, duration: float,
                 steps: int = 256, damping: bool = True) -> tuple[np.ndarray, dict]:  # fmt: skip
    """One ring as a single RGBA texture with time in a channel, for shaders that animate it
    with a wavelet (the Lagarde-style ripple texture), ``(N, N, 4)`` float32 over a
    ``size`` x ``size`` m square centred on the drop.

    - R, G: the outward direction (x / r, y / r), packed (d + 1) / 2 (tangent frame, y up);
    - B: the time at which the slope at this radius is strongest, / ``duration`` (the arrival
      of the ring's energy, from the exact solution);
    - A: that strongest |d eta / dr|, / its largest value over the texture (the energy spreading
      over the circle and viscous decay, from the exact solution).

    Returns the texture and ``info``: ``slope_max`` (m/m, the A = 1 slope), ``duration`` (s),
    ``period`` (s, 2 pi / omega(k0): the wavelet's period) and ``k0`` (rad/m).
    A shader reconstructs d eta / dr ~ A slope_max sin(2 pi (t - B duration) / period) w(t)
    with a window w a period or two wide: an approximation of the ring that
    :func:`ring_lut` tabulates exactly.
    """
    n = int(resolution)
    size = _positive(size, "texture size (m)")
    texel = size / n
    r_nodes = np.arange(0, size * 0.75, texel / 2)
    t = np.linspace(0, _positive(duration, "duration (s)"), int(steps))
    _, slope = ring(crater, r_nodes, t, damping=damping)
    peak = np.abs(slope).max(0)
    when = t[np.argmax(np.abs(slope), axis=0)]
    c = (np.arange(n) + 0.5) * texel - size / 2
    x, y = np.meshgrid(c, -c)
    rr = np.hypot(x, y)
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.where(rr > 0, x / rr, 0.0)
        uy = np.where(rr > 0, y / rr, 0.0)
    out = np.empty((n, n, 4), np.float32)
    out[..., 0] = (ux + 1) / 2
    out[..., 1] = (uy + 1) / 2
    out[..., 2] = np.interp(rr, r_nodes, when) / t[-1]
    top = float(peak.max()) or 1.0
    out[..., 3] = np.interp(rr, r_nodes, peak) / top
    k0 = crater.dominant_wavenumber
    info = {"slope_max": top, "duration_s": float(t[-1]),
            "period_s": float(2 * math.pi / crater.omega(k0)), "k0_rad_m": k0}  # fmt: skip
    return out, info


def rain_atlas(*, resolution: int, cells: int, seed: int = 0, margin: float = 0.35) -> np.ndarray:
    """A tileable atlas of drop positions and phases: one drop per cell of a ``cells`` x
    ``cells`` grid, at a random place and with a random phase, ``(N, N, 4)`` float32.

    - R, G: offset from the texel to its cell's drop centre in cell widths, packed (d + 1) / 2
      (d in [-1, 1]; the drop's ring reaches ``margin`` cell widths at most);
    - B: the drop's phase in [0, 1) (its time offset as a fraction of the ring duration);
    - A: 1 where the texel lies within ``margin`` cell widths of its drop, else 0.

    Centres stay ``margin`` cell widths from their cell's edges, so no ring crosses into a
    neighbour cell, and the cells tile: the atlas tiles. A shader computes the distance
    r = |d| cell_size, the drop's time t = fract(time / duration + B) duration, and the slope
    from :func:`ring_lut`.
    """
    n = int(resolution)
    cells = int(cells)
    if not (1 <= cells <= n and n % cells == 0):
        raise ArgumentError(f"cells must divide the resolution {n}, got {cells}")
    if not (0 < margin <= 0.5):
        raise ArgumentError(f"margin must be in (0, 0.5] cell widths, got {margin!r}")
    rng = np.random.default_rng(seed)
    cell = n // cells
    # centres within [margin, 1 - margin] of each cell (a single point when margin = 0.5)
    centre = margin + rng.random((cells, cells, 2)) * (1 - 2 * margin)
    phase = rng.random((cells, cells))
    coords = (np.arange(n) + 0.5) / cell
    cx, cy = np.meshgrid(coords, coords)  # in cells; row 0 at the top
    ix, iy = np.floor(cx).astype(int), np.floor(cy).astype(int)
    dx = centre[iy, ix, 0] - (cx - ix)
    dy = (cy - iy) - centre[iy, ix, 1]  # +y up the picture
    inside = np.hypot(dx, dy) <= margin
    out = np.empty((n, n, 4), np.float32)
    out[..., 0] = (np.clip(-dx, -1, 1) + 1) / 2  # offset from the centre to the texel
    out[..., 1] = (np.clip(-dy, -1, 1) + 1) / 2
    out[..., 2] = phase[iy, ix]
    out[..., 3] = inside
    return out


# --- the wave equation ------------------------------------------------------------------------


@dataclass
class Source:
    """A Gaussian forcing term f = strength exp(-|x - p(t)|^2 / radius^2) (m/s^2), active for
    start <= t < stop: a floating object pressing on the water as it moves.

    ``position`` is (x, y) in m, or a callable t -> (x, y)."""

    position: tuple[float, float] | Callable[[float], tuple[float, float]]
    radius: float
    strength: float
    start: float = 0.0
    stop: float = math.inf

    def at(self, t: float) -> tuple[float, float]:
        """Position (x, z) in metres at time t (s)."""
        p = self.position(t) if callable(self.position) else self.position
        return float(p[0]), float(p[1])


@dataclass
class Impact:
    """A Gaussian dent -amplitude exp(-|x - p|^2 / width^2) added to the height at time t."""

    x: float
    y: float
    t: float
    amplitude: float
    width: float


def _neighbours(n: int, periodic: bool, reflect: bool) -> tuple[np.ndarray, np.ndarray]:
    """Index of the previous and next cell along an axis of ``n`` cells: wrapped (periodic),
    mirrored about the edge cell (reflect: dh/dn = 0), or the edge cell itself (for Mur)."""
    i = np.arange(n)
    prev, nxt = i - 1, i + 1
    if periodic:
        return prev % n, nxt % n
    prev[0] = 1 if reflect else 0
    nxt[-1] = n - 2 if reflect else n - 1
    return prev, nxt


@dataclass
class WaveEquation:
    """A damped 2-D wave equation on a grid (see the module notes), stepped with
    :meth:`step`; heights in m.

    Attributes
    ----------
    resolution : int
        Cells per side.
    size : float
        Side of the square domain, m.
    speed : float
        Wave speed c, m/s.
    dt : float
        Time step, s; c dt / dx must not exceed :data:`CFL_LIMIT`.
    damping : float
        gamma, 1/s (amplitudes decay as exp(-gamma t / 2)).
    edges : {"periodic", "reflect", "absorb"}
    """

    resolution: int
    size: float
    speed: float
    dt: float
    damping: float = 0.0
    edges: str = "periodic"
    height: np.ndarray = field(init=False, repr=False)
    velocity: np.ndarray = field(init=False, repr=False)
    time: float = field(init=False, default=0.0)

    def __post_init__(self) -> None:
        validate_choice(self.edges, EDGES, "edge condition")
        n = int(self.resolution)
        if not 8 <= n <= 8192:
            raise ArgumentError(f"resolution must be 8 to 8192 cells, got {self.resolution!r}")
        self.resolution = n
        self.size = _positive(self.size, "domain size (m)")
        self.speed = _positive(self.speed, "wave speed (m/s)")
        self.dt = _positive(self.dt, "time step (s)")
        self.damping = _positive(self.damping, "damping (1/s)", zero=True)
        courant = self.speed * self.dt / self.dx
        if courant > CFL_LIMIT:
            raise ArgumentError(
                f"time step {self.dt:g} s is unstable: c dt / dx = {courant:.3f} exceeds the "
                f"9-point stencil's limit sqrt(3)/2 = {CFL_LIMIT:.3f}; use dt <= "
                f"{CFL_LIMIT * self.dx / self.speed:.3g} s"
            )
        self.height = np.zeros((n, n))
        self.velocity = np.zeros((n, n))
        rows = _neighbours(n, self.edges == "periodic", self.edges == "reflect")
        self._neighbours = (*rows, *rows)

    @property
    def dx(self) -> float:
        """Grid spacing (m)."""
        return self.size / self.resolution

    @property
    def courant(self) -> float:
        """The Courant number c dt / dx (stable below sqrt(3) / 2)."""
        return self.speed * self.dt / self.dx

    def positions(self) -> tuple[np.ndarray, np.ndarray]:
        """Cell centres (x, y), m, row 0 at the top (y = size - (j + 1/2) dx)."""
        c = (np.arange(self.resolution) + 0.5) * self.dx
        return np.meshgrid(c, self.size - c)

    def _gaussian(self, px: float, py: float, width: float) -> np.ndarray:
        x, y = self.positions()
        ddx = x - px
        ddy = y - py
        if self.edges == "periodic":  # nearest image on the torus
            ddx -= self.size * np.round(ddx / self.size)
            ddy -= self.size * np.round(ddy / self.size)
        return np.exp(-(ddx * ddx + ddy * ddy) / (width * width))

    def add_impact(self, x: float, y: float, *, amplitude: float, width: float) -> None:
        """Press a Gaussian dent of ``amplitude`` (m) and ``width`` (m) into the surface."""
        self.height -= float(amplitude) * self._gaussian(x, y, _positive(width, "width (m)"))

    def step(self, steps: int = 1, sources: Sequence[Source] = ()) -> None:
        """Advance ``steps`` time steps, applying each source's forcing at its position."""
        a = 1 - self.damping * self.dt / 2
        b = 1 + self.damping * self.dt / 2
        zero = np.zeros_like(self.height)
        for _ in range(int(steps)):
            force = zero
            active = [s for s in sources if s.start <= self.time < s.stop]
            if active:
                force = np.zeros_like(self.height)
                for s in active:
                    force += s.strength * self._gaussian(*s.at(self.time), s.radius)
            old = self.height.copy() if self.edges == "absorb" else None
            _native.laplacian_step(self.height, self.velocity, self.speed**2, a, b, self.dt,
                            self.dx**2, force, *self._neighbours)  # fmt: skip
            if old is not None:
                self._mur(old)
            self.time += self.dt

    def _mur(self, old: np.ndarray) -> None:
        """Mur's first-order absorbing condition on the four edges (corners: mean)."""
        k = (self.courant - 1) / (self.courant + 1)
        h = self.height
        new = h.copy()
        new[0, :] = old[1, :] + k * (h[1, :] - old[0, :])
        new[-1, :] = old[-2, :] + k * (h[-2, :] - old[-1, :])
        new[:, 0] = old[:, 1] + k * (h[:, 1] - old[:, 0])
        new[:, -1] = old[:, -2] + k * (h[:, -2] - old[:, -1])
        for r, c in ((0, 0), (0, -1), (-1, 0), (-1, -1)):
            new[r, c] = 0.5 * (
                new[r, c + (1 if c == 0 else -1)] + new[r + (1 if r == 0 else -1), c]
            )
        self.height[...] = new
        # keep v consistent with the edge heights that Mur set
        self.velocity[[0, -1], :] = (new[[0, -1], :] - old[[0, -1], :]) / self.dt
        self.velocity[:, [0, -1]] = (new[:, [0, -1]] - old[:, [0, -1]]) / self.dt

    def normals(self) -> np.ndarray:
        """Unit normals of the height field by central differences (wrapping when periodic,
        one-sided at other edges), (N, N, 3) float32."""
        return height_normals(self.height, self.dx, periodic=self.edges == "periodic")


def height_normals(height: ArrayLike, spacing: float, *, periodic: bool = True) -> np.ndarray:
    """Unit normals (-dh/dx, -dh/dy, 1) / |.| of a height field ``(..., N, N)`` (m) with texel
    ``spacing`` (m), by central differences; y is up the picture (row 0 at the top)."""
    h = np.asarray(height, dtype=np.float64)
    if periodic:
        hx = (np.roll(h, -1, -1) - np.roll(h, 1, -1)) / (2 * spacing)
        hy = (np.roll(h, 1, -2) - np.roll(h, -1, -2)) / (2 * spacing)  # row above is +y
    else:
        hx = np.gradient(h, spacing, axis=-1)
        hy = -np.gradient(h, spacing, axis=-2)
    n = np.stack([-hx, -hy, np.ones_like(h)], -1)
    return (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(np.float32)


def simulate(
    sim: WaveEquation,
    *,
    frames: int,
    steps_per_frame: int,
    impacts: Sequence[Impact] = (),
    sources: Sequence[Source] = (),
) -> Iterator[tuple[float, np.ndarray]]:
    """Run ``sim`` and yield (time, height copy) after every ``steps_per_frame`` steps, adding
    each impact at the first step at or after its time."""
    pending = sorted(impacts, key=lambda i: i.t)
    for _ in range(int(frames)):
        for _ in range(int(steps_per_frame)):
            while pending and pending[0].t <= sim.time + 1e-12:
                i = pending.pop(0)
                sim.add_impact(i.x, i.y, amplitude=i.amplitude, width=i.width)
            sim.step(1, sources)
        yield sim.time, sim.height.copy()
