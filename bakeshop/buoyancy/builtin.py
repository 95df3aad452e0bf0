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

import numpy as np

from bakeshop.buoyancy import _native
from bakeshop.buoyancy.state import State

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
        _native.builtin_step(
            s.position, s.quaternion, s.velocity, s.angular_velocity, force, torque,
            self.fleet.mass, self.fleet.inertia, self.fleet.inverse_inertia,
            self.timestep, self.gravity,
        )  # fmt: skip
