"""Rotations of the environment: yaw, pitch and roll in degrees, or any orthogonal matrix."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError


def rotation_matrix(yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0) -> np.ndarray:
    """The 3x3 rotation ``R = R_y(yaw) R_x(pitch) R_z(roll)``, angles in degrees.

    Each factor is a right-handed (counter-clockwise seen from the axis' tip) rotation about a
    world axis: yaw about +Y (up), pitch about +X (right), roll about +Z (backward). Roll is
    applied first, yaw last. Rotating an environment by ``R`` moves what was seen in direction
    ``d`` to direction ``R d``: ``yaw=90`` brings the forward view (-Z) to the left (-X),
    ``pitch=90`` brings the forward view up (+Y).
    """
    y, p, r = np.radians([yaw, pitch, roll])
    cy, sy, cp, sp, cr, sr = np.cos(y), np.sin(y), np.cos(p), np.sin(p), np.cos(r), np.sin(r)
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    rz = np.array([[cr, -sr, 0], [sr, cr, 0], [0, 0, 1]])
    return ry @ rx @ rz


def as_rotation(rotation: ArrayLike | None) -> np.ndarray | None:
    """``rotation`` as an orthogonal 3x3 float64 matrix, or None for no rotation.

    Accepts None, a ``(yaw, pitch, roll)`` triple in degrees (see :func:`rotation_matrix`) or a
    3x3 orthogonal matrix (a reflection, determinant -1, is accepted: it mirrors the world).
    """
    if rotation is None:
        return None
    m = np.asarray(rotation, dtype=np.float64)
    if m.shape == (3,):
        m = rotation_matrix(*m)
    if m.shape != (3, 3) or not np.all(np.isfinite(m)):
        raise ArgumentError(
            f"rotation must be (yaw, pitch, roll) in degrees or a 3x3 matrix; got shape {m.shape}"
        )
    if not np.allclose(m @ m.T, np.eye(3), atol=1e-6):
        raise ArgumentError("a rotation matrix must be orthogonal (R @ R.T == I within 1e-6)")
    if np.allclose(m, np.eye(3), rtol=0, atol=1e-15):
        return None
    return m


def rotation_key(rotation: ArrayLike | None) -> bytes | None:
    """A hashable key of ``rotation`` (see :func:`as_rotation`) for the geometry caches."""
    m = as_rotation(rotation)
    return None if m is None else m.tobytes()


def key_matrix(key: bytes | None) -> np.ndarray:
    """The matrix of a :func:`rotation_key` (the identity for None)."""
    return np.eye(3) if key is None else np.frombuffer(key).reshape(3, 3)
