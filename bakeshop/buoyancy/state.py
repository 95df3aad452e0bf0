"""Poses and velocities of a fleet of rigid bodies, and the quaternion helpers they need.

Quaternions are ``(w, x, y, z)`` (MuJoCo's order), unit length, rotating body coordinates into
world coordinates. Angular velocities are in world coordinates, rad/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.buoyancy import _native


@dataclass
class State:
    """Positions of the centres of mass (B, 3) m, orientations (B, 4), linear velocities
    (B, 3) m/s and angular velocities (B, 3) rad/s, all float64 in world coordinates."""

    position: np.ndarray
    quaternion: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray

    def copy(self) -> State:
        """A deep copy (the arrays copied)."""
        return State(
            self.position.copy(),
            self.quaternion.copy(),
            self.velocity.copy(),
            self.angular_velocity.copy(),
        )


def quaternion_to_matrix(q: np.ndarray) -> np.ndarray:
    """(..., 4) unit quaternions (w, x, y, z) -> (..., 3, 3) rotation matrices."""
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=np.float64), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def axis_angle_quaternion(axis: ArrayLike, degrees: float) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation by ``degrees`` about ``axis``."""
    axis = np.asarray(axis, dtype=np.float64)
    half = np.radians(degrees) / 2
    return np.concatenate([[np.cos(half)], np.sin(half) * axis / np.linalg.norm(axis)])


def rotation(q0: float, q1: float, q2: float, q3: float) -> np.ndarray:
    """Rotation matrix (3, 3) of a unit quaternion (w, x, y, z), as the compiled kernels
    compute it (``src/buoyancy/state.hpp``)."""
    out = np.empty((3, 3))
    _native.rotation(float(q0), float(q1), float(q2), float(q3), out)
    return out
