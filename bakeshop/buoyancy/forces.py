"""Buoyancy, fluid friction and the predictive stabiliser, evaluated per sample point.

Every sample point i of a body carries a volume V_i and stands for a vertical column of height
h_i (its cell's side, or less where the solid ends inside the cell). With the water surface eta
at the point, the submerged fraction of the column is

    f_i = clamp((eta - y_i) / h_i + 1/2, 0, 1)

(linear in depth, so the force changes continuously and exactly as the surface crosses the cell),
and the point receives Archimedes' force ``rho_water * g * V_i * f_i`` upwards at its own
position; the torque about the centre of mass follows from where the points are.

Fluid friction comes in two kinds:

``team``
    The game team's damping: a force ``-c_lin * s * m * v`` and a torque ``-c_ang * s * I w``,
    scaled by ``s = log(1 + n) / log(1 + N)`` for n of the body's N points submerged, so that a few
    wet points already damp strongly and a fully submerged body gets the whole of it.
``drag``
    Quadratic drag of the submerged part: each point gets ``-1/2 rho C_d A_i |u| u`` with u its
    velocity relative to the water and a frontal area ``A_i = f_i V_i / L`` shared out by volume
    (L = V^(1/3), the body's size), so that a submerged body of volume V sees about
    ``1/2 rho C_d V^(2/3) |u| u``; rotation is resisted by the points' own velocities. Held for
    a time T (the horizon), explicit drag overshoots (reverses the velocity) once
    ``k |u| T > m``; each point's drag is therefore capped at what stops its share of the mass,
    ``rho_body V_i |u| / T``, the limit an implicit step would reach.

The predictive stabiliser (the team's hack) scales a point's buoyancy by M when the point,
moved on by its velocity for C times the time the force will be held, would be above the water:
here, when its whole column would be out. (Testing the point's centre instead would also scale
resting points whose centre is just above the surface, and sink every body deeper than
Archimedes says: 1 to 4 % for the test shapes.)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from bakeshop.buoyancy.hydrostatics import GRAVITY, RHO_WATER
from bakeshop.buoyancy.state import rotation
from bakeshop.errors import ArgumentError, validate_choice

if TYPE_CHECKING:
    from bakeshop.buoyancy.mass import Fleet
    from bakeshop.buoyancy.state import State
    from bakeshop.buoyancy.water import Water

DAMPINGS = ("team", "drag", "none")
#: Below this many points a force evaluation runs on one thread: waking a thread pool costs
#: more than the work (milliseconds on a loaded machine).
PARALLEL_MIN_POINTS = 100_000
STABILIZERS = ("none", "predict", "clamp", "predict+clamp")


@dataclass(frozen=True)
class ForceModel:
    """Choices and constants of the force model.

    Attributes
    ----------
    damping : {"team", "drag", "none"}
    linear_damping, angular_damping : float
        ``c_lin`` and ``c_ang`` of the team damping, 1/s.
    drag_coefficient : float
        ``C_d`` of the drag model.
    stabilize : {"none", "predict", "clamp", "predict+clamp"}
    predict_c, predict_m : float
        C > 1 and 0 < M < 1 of the predictive stabiliser.
    clamp_speed : float
        Speed limit (m/s) of velocity clamping while a body is partly submerged.
    rho_water : float
        kg/m^3.
    gravity : float
        m/s^2.
    """

    damping: str = "team"
    linear_damping: float = 5.0
    angular_damping: float = 5.0
    drag_coefficient: float = 1.0
    stabilize: str = "predict"
    predict_c: float = 2.5
    predict_m: float = 0.1
    clamp_speed: float = 1.0
    rho_water: float = RHO_WATER
    gravity: float = GRAVITY

    def __post_init__(self) -> None:
        validate_choice(self.damping, DAMPINGS, "damping")
        validate_choice(self.stabilize, STABILIZERS, "stabiliser")
        if not self.predict_c > 1 or not 0 < self.predict_m < 1:
            raise ArgumentError("the predictive stabiliser needs C > 1 and 0 < M < 1")
        for name in ("linear_damping", "angular_damping", "drag_coefficient", "clamp_speed"):
            if not getattr(self, name) >= 0:
                raise ArgumentError(f"{name} must be >= 0")

    @property
    def predicts(self) -> bool:
        """True when the predictive stabiliser is on."""
        return self.stabilize in ("predict", "predict+clamp")

    @property
    def clamps(self) -> bool:
        """True when the speed clamp is on."""
        return self.stabilize in ("clamp", "predict+clamp")


@dataclass
class Forces:
    """Result of one evaluation for B bodies: ``force`` (B, 3) N and ``torque`` (B, 3) N m about
    the centre of mass (world frame, gravity excluded), ``submerged_points`` (B,) int64 and
    ``submerged_volume`` (B,) m^3."""

    force: np.ndarray
    torque: np.ndarray
    submerged_points: np.ndarray
    submerged_volume: np.ndarray


def evaluate(
    fleet: Fleet, state: State, water: Water, model: ForceModel, time: float, horizon: float
) -> Forces:
    """Buoyancy and friction on every body of ``fleet`` in ``state`` at ``time`` (s).

    ``horizon`` (s) is how long the forces will be held (the frame time in per-frame mode, the
    solver step in per-substep mode): the predictive stabiliser looks ``C * horizon`` ahead.
    """
    n = len(fleet)
    out = Forces(np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n, np.int64), np.zeros(n))
    threads = numba.get_num_threads()
    numba.set_num_threads(threads if len(fleet.points) >= PARALLEL_MIN_POINTS else 1)
    try:
        _point_forces(
            fleet.offsets, fleet.points, fleet.volumes, fleet.heights, fleet.volume,
            fleet.mass, fleet.inertia,
            state.position, state.quaternion, state.velocity, state.angular_velocity,
            water.table, water.level, float(time), model.rho_water, model.gravity,
            DAMPINGS.index(model.damping), model.linear_damping, model.angular_damping,
            model.drag_coefficient, model.predicts, model.predict_c, model.predict_m,
            float(horizon), out.force, out.torque, out.submerged_points, out.submerged_volume,
        )  # fmt: skip
    finally:
        numba.set_num_threads(threads)
    return out


@numba.njit(cache=True, inline="always")
def _surface(waves: np.ndarray, level: float, x: float, z: float, t: float) -> float:
    eta = level
    for w in range(waves.shape[0]):
        eta += waves[w, 0] * np.sin(
            waves[w, 1] * x + waves[w, 2] * z - waves[w, 3] * t + waves[w, 4]
        )
    return eta


@numba.njit(cache=True, parallel=True, fastmath=True)
def _point_forces(
    offsets: np.ndarray, points: np.ndarray, volumes: np.ndarray, heights: np.ndarray,
    body_volume: np.ndarray, mass: np.ndarray, inertia: np.ndarray,
    position: np.ndarray, quaternion: np.ndarray, velocity: np.ndarray, omega: np.ndarray,
    waves: np.ndarray, level: float, t: float, rho: float, g: float,
    damping: int, c_lin: float, c_ang: float, c_drag: float, predict: bool, c_predict: float,
    m_predict: float, horizon: float,
    force: np.ndarray, torque: np.ndarray, submerged_points: np.ndarray,
    submerged_volume: np.ndarray,
) -> None:  # fmt: skip
    for b in numba.prange(offsets.shape[0] - 1):
        r = rotation(quaternion[b, 0], quaternion[b, 1], quaternion[b, 2], quaternion[b, 3])
        px, py, pz = position[b, 0], position[b, 1], position[b, 2]
        vx, vy, vz = velocity[b, 0], velocity[b, 1], velocity[b, 2]
        wx, wy, wz = omega[b, 0], omega[b, 1], omega[b, 2]
        drag_k = 0.5 * rho * c_drag / body_volume[b] ** (1.0 / 3.0)
        density = mass[b] / body_volume[b]
        fx = fy = fz = tx = ty = tz = 0.0
        count = 0
        wet = 0.0
        for i in range(offsets[b], offsets[b + 1]):
            bx, by, bz = points[i, 0], points[i, 1], points[i, 2]
            rx = r[0, 0] * bx + r[0, 1] * by + r[0, 2] * bz
            ry = r[1, 0] * bx + r[1, 1] * by + r[1, 2] * bz
            rz = r[2, 0] * bx + r[2, 1] * by + r[2, 2] * bz
            x, y, z = px + rx, py + ry, pz + rz
            eta = _surface(waves, level, x, z, t)
            frac = (eta - y) / heights[i] + 0.5
            if frac <= 0.0:
                continue
            if frac > 1.0:
                frac = 1.0
            count += 1
            v = volumes[i] * frac
            wet += v
            # point velocity v + w x r
            ux = vx + wy * rz - wz * ry
            uy = vy + wz * rx - wx * rz
            uz = vz + wx * ry - wy * rx
            lift = rho * g * v
            if predict:
                ax = x + ux * horizon * c_predict
                ay = y + uy * horizon * c_predict
                az = z + uz * horizon * c_predict
                if ay - 0.5 * heights[i] > _surface(waves, level, ax, az, t):
                    lift *= m_predict
            gx, gy, gz = 0.0, lift, 0.0
            if damping == 1:  # drag relative to the water's orbital velocity
                for w in range(waves.shape[0]):
                    theta = waves[w, 1] * x + waves[w, 2] * z - waves[w, 3] * t + waves[w, 4]
                    k = waves[w, 5]
                    speed = waves[w, 0] * waves[w, 3] * np.exp(min(k * (y - eta), 0.0))
                    ux -= speed * np.sin(theta) * waves[w, 1] / k
                    uz -= speed * np.sin(theta) * waves[w, 2] / k
                    uy += speed * np.cos(theta)
                # never more than stops the point's share of mass within the horizon
                s = min(
                    np.sqrt(ux * ux + uy * uy + uz * uz) * drag_k * v,
                    density * volumes[i] / horizon,
                )
                gx -= s * ux
                gy -= s * uy
                gz -= s * uz
            fx += gx
            fy += gy
            fz += gz
            tx += ry * gz - rz * gy
            ty += rz * gx - rx * gz
            tz += rx * gy - ry * gx
        if damping == 0 and count > 0:  # team damping
            n_all = offsets[b + 1] - offsets[b]
            s = np.log(1.0 + count) / np.log(1.0 + n_all)
            k = c_lin * s * mass[b]
            fx -= k * vx
            fy -= k * vy
            fz -= k * vz
            # world inertia R I R^T applied to w
            bw0 = r[0, 0] * wx + r[1, 0] * wy + r[2, 0] * wz
            bw1 = r[0, 1] * wx + r[1, 1] * wy + r[2, 1] * wz
            bw2 = r[0, 2] * wx + r[1, 2] * wy + r[2, 2] * wz
            l0 = inertia[b, 0, 0] * bw0 + inertia[b, 0, 1] * bw1 + inertia[b, 0, 2] * bw2
            l1 = inertia[b, 1, 0] * bw0 + inertia[b, 1, 1] * bw1 + inertia[b, 1, 2] * bw2
            l2 = inertia[b, 2, 0] * bw0 + inertia[b, 2, 1] * bw1 + inertia[b, 2, 2] * bw2
            k = c_ang * s
            tx -= k * (r[0, 0] * l0 + r[0, 1] * l1 + r[0, 2] * l2)
            ty -= k * (r[1, 0] * l0 + r[1, 1] * l1 + r[1, 2] * l2)
            tz -= k * (r[2, 0] * l0 + r[2, 1] * l1 + r[2, 2] * l2)
        force[b, 0], force[b, 1], force[b, 2] = fx, fy, fz
        torque[b, 0], torque[b, 1], torque[b, 2] = tx, ty, tz
        submerged_points[b] = count
        submerged_volume[b] = wet
