"""The built-in rigid-body integrator: semi-implicit Euler, vectorised over bodies.

One step of length dt, as game engines take it:

    v <- v + dt (F / m + g)
    w_b <- w_b + dt I^-1 (tau_b - w_b x I w_b)     (body frame, full inertia tensor)
    x <- x + dt v
    q <- exp(dt w / 2) q                             (exact rotation by the new w, renormalised)

Semi-implicit (symplectic) Euler keeps the energy of an undamped oscillator bounded but is only
stable for ``omega * dt < 2``; see docs/buoyancy.md.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numba
import numpy as np

from bakeshop.buoyancy.state import State, rotation

if TYPE_CHECKING:
    from bakeshop.buoyancy.mass import Fleet


class BuiltinBackend:
    """Integrates a :class:`~bakeshop.buoyancy.mass.Fleet` with semi-implicit Euler.

    Bodies do not collide with each other (use the MuJoCo backend for that).
    """

    name = "builtin"

    def __init__(self, fleet: Fleet, state: State, *, timestep: float, gravity: float) -> None:
        self.fleet = fleet
        self._state = state.copy()
        self.timestep = float(timestep)
        self.gravity = float(gravity)

    def state(self) -> State:
        """The current state (a copy)."""
        return self._state.copy()

    def set_velocities(self, velocity: np.ndarray, angular_velocity: np.ndarray) -> None:
        """Overwrite linear (B, 3) and angular (B, 3) world velocities."""
        self._state.velocity[:] = velocity
        self._state.angular_velocity[:] = angular_velocity

    def step(self, force: np.ndarray, torque: np.ndarray) -> None:
        """Advance one solver step under external ``force`` and ``torque`` (B, 3), plus
        gravity."""
        s = self._state
        _step(
            s.position, s.quaternion, s.velocity, s.angular_velocity, force, torque,
            self.fleet.mass, self.fleet.inertia, self.fleet.inverse_inertia,
            self.timestep, self.gravity,
        )  # fmt: skip


@numba.njit(cache=True)
def _step(
    position: np.ndarray,
    quaternion: np.ndarray,
    velocity: np.ndarray,
    omega: np.ndarray,
    force: np.ndarray,
    torque: np.ndarray,
    mass: np.ndarray,
    inertia: np.ndarray,
    inverse: np.ndarray,
    dt: float,
    g: float,
) -> None:
    for b in range(position.shape[0]):
        for a in range(3):
            velocity[b, a] += dt * force[b, a] / mass[b]
        velocity[b, 1] -= dt * g
        r = rotation(quaternion[b, 0], quaternion[b, 1], quaternion[b, 2], quaternion[b, 3])
        wb = r.T @ omega[b]
        tb = r.T @ torque[b]
        lb = inertia[b] @ wb
        gyro = np.cross(wb, lb)
        wb = wb + dt * (inverse[b] @ (tb - gyro))
        omega[b] = r @ wb
        for a in range(3):
            position[b, a] += dt * velocity[b, a]
        # q <- dq q with dq the rotation by |w| dt about w
        wx, wy, wz = omega[b, 0], omega[b, 1], omega[b, 2]
        angle = np.sqrt(wx * wx + wy * wy + wz * wz) * dt
        if angle > 0.0:
            s = np.sin(0.5 * angle) / (angle / dt)
            d0, d1, d2, d3 = np.cos(0.5 * angle), wx * s, wy * s, wz * s
            q0, q1, q2, q3 = quaternion[b, 0], quaternion[b, 1], quaternion[b, 2], quaternion[b, 3]
            n0 = d0 * q0 - d1 * q1 - d2 * q2 - d3 * q3
            n1 = d0 * q1 + d1 * q0 + d2 * q3 - d3 * q2
            n2 = d0 * q2 - d1 * q3 + d2 * q0 + d3 * q1
            n3 = d0 * q3 + d1 * q2 - d2 * q1 + d3 * q0
            norm = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
            quaternion[b, 0], quaternion[b, 1] = n0 / norm, n1 / norm
            quaternion[b, 2], quaternion[b, 3] = n2 / norm, n3 / norm
