"""Rigid bodies for floating: mass, centre of mass, inertia tensor and sample points."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from bakeshop.buoyancy.sampling import SamplePoints, sample_points
from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    import trimesh


@dataclass(frozen=True)
class Body:
    """A uniform solid ready to float, in its body frame (origin at the centre of mass, axes
    those of the mesh it was made from).

    Attributes
    ----------
    mesh : trimesh.Trimesh
        The closed mesh, translated so the centre of mass is the origin (metres).
    density : float
        kg/m^3.
    mass : float
        kg, ``density * mesh.volume``.
    inertia : (3, 3) float64
        Full inertia tensor about the centre of mass in body axes, kg m^2.
    points : SamplePoints
        Buoyancy sample points in the body frame.
    offset : (3,) float64
        Where the centre of mass was in the original mesh's coordinates (metres).
    """

    mesh: trimesh.Trimesh
    density: float
    mass: float
    inertia: np.ndarray
    points: SamplePoints
    offset: np.ndarray

    @property
    def volume(self) -> float:
        """Mesh volume, m^3."""
        return float(self.mesh.volume)

    @cached_property
    def hull_vertices(self) -> np.ndarray:
        """(V, 3) vertices of the convex hull, body frame: the lowest point of the body is the
        lowest of these."""
        from scipy.spatial import ConvexHull

        points = np.asarray(self.mesh.vertices, dtype=np.float64)
        return points[np.sort(ConvexHull(points).vertices)]


def make_body(
    mesh: trimesh.Trimesh, density: float, *, resolution: int = 10, subsamples: int = 4
) -> Body:
    """Make a uniform rigid body of ``density`` (kg/m^3) from a closed mesh.

    Mass, centre of mass and inertia tensor are the exact volume integrals over the mesh
    (trimesh's polyhedral mass properties: Eberly, "Polyhedral Mass Properties (Revisited)",
    2002); the sample points come from :func:`bakeshop.buoyancy.sampling.sample_points` at
    ``resolution`` cells along the longest side.
    """
    density = float(density)
    if not (np.isfinite(density) and density > 0):
        raise ArgumentError(f"density must be a positive number of kg/m^3, got {density!r}")
    if not mesh.is_watertight or not mesh.volume > 0:
        raise ArgumentError(
            "the mesh must be closed with outward normals (load it with load_mesh, which "
            "welds, checks and orients it)"
        )
    centred = mesh.copy()
    offset = np.array(mesh.center_mass, dtype=np.float64)
    centred.apply_translation(-offset)
    centred.density = density
    points = sample_points(centred, resolution=resolution, subsamples=subsamples)
    return Body(
        mesh=centred,
        density=density,
        mass=float(centred.mass),
        inertia=np.array(centred.moment_inertia, dtype=np.float64),
        points=points,
        offset=offset,
    )


@dataclass(frozen=True)
class Fleet:
    """Bodies packed into flat arrays for the vectorised kernels (B bodies, P points in all).

    Attributes
    ----------
    bodies : tuple of Body
    offsets : (B + 1,) int64
        Points of body b are ``points[offsets[b]:offsets[b + 1]]``.
    points : (P, 3) float64
        Body-frame positions, metres.
    volumes : (P,) float64
        m^3.
    heights : (P,) float64
        Column height of each point, metres.
    mass : (B,) float64
        kg.
    volume : (B,) float64
        m^3.
    inertia, inverse_inertia : (B, 3, 3) float64
        Body-frame inertia tensors about the centre of mass (kg m^2) and their inverses.
    """

    bodies: tuple[Body, ...]
    offsets: np.ndarray
    points: np.ndarray
    volumes: np.ndarray
    heights: np.ndarray
    mass: np.ndarray
    volume: np.ndarray
    inertia: np.ndarray
    inverse_inertia: np.ndarray

    def __len__(self) -> int:
        return len(self.bodies)


def pack(bodies: Sequence[Body]) -> Fleet:
    """Pack a sequence of :class:`Body` into a :class:`Fleet`."""
    bodies = tuple(bodies)
    if not bodies:
        raise ArgumentError("a fleet needs at least one body")
    counts = [len(b.points) for b in bodies]
    inertia = np.stack([b.inertia for b in bodies])
    return Fleet(
        bodies=bodies,
        offsets=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
        points=np.ascontiguousarray(np.concatenate([b.points.positions for b in bodies])),
        volumes=np.concatenate([b.points.volumes for b in bodies]),
        heights=np.concatenate([b.points.heights for b in bodies]),
        mass=np.array([b.mass for b in bodies]),
        volume=np.array([b.volume for b in bodies]),
        inertia=inertia,
        inverse_inertia=np.linalg.inv(inertia),
    )
