"""Shared references for the buoyancy tests: closed-form drafts, exact clipping by manifold3d,
the heave period of a trace and the energy-boundedness check."""

import manifold3d
import numpy as np
import trimesh
from scipy.optimize import brentq

from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.metrics import energy
from bakeshop.buoyancy.water import Water

UNDAMPED = ForceModel(damping="none", stabilize="none")


def clipped_below(mesh, level):
    """The part of a closed trimesh below y = level, clipped by manifold3d, as a trimesh."""
    solid = manifold3d.Manifold(
        manifold3d.Mesh(
            vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
            tri_verts=np.asarray(mesh.faces, dtype=np.uint32),
        )
    )
    # trim_by_plane keeps the side the normal points to: normal (0, -1, 0), offset -level.
    part = solid.trim_by_plane((0.0, -1.0, 0.0), -level).to_mesh()
    return trimesh.Trimesh(part.vert_properties[:, :3], part.tri_verts, process=True)


def sphere_draft(radius, density):
    mass_volume = density / 1000 * 4 / 3 * np.pi * radius**3
    return brentq(lambda d: np.pi * d * d * (3 * radius - d) / 3 - mass_volume, 0, 2 * radius)


def cylinder_draft(radius, density):
    """Horizontal cylinder: the circular segment's area is the density ratio of the circle's."""
    target = density / 1000 * np.pi * radius**2

    def segment(d):
        return radius**2 * np.arccos((radius - d) / radius) - (radius - d) * np.sqrt(
            2 * radius * d - d * d
        )

    return brentq(lambda d: segment(d) - target, 0, 2 * radius)


def heave_period(trace, body=0):
    y = trace.position[:, body, 1]
    y = y - y.mean()
    up = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    # interpolate the crossing times
    t = trace.time[up] - y[up] * (trace.time[1] - trace.time[0]) / (y[up + 1] - y[up])
    return np.diff(t).mean()


def assert_energy_bounded(fleet, trace):
    e = energy(fleet, trace, Water(), UNDAMPED)[:, 0]
    oscillation = (0.5 * fleet.mass[0] * (trace.velocity[:, 0] ** 2).sum(-1)).max()
    h = trace.time[1]
    omega = 2 * np.pi / heave_period(trace)
    # semi-implicit Euler conserves a nearby energy: a wobble of about omega h, no drift
    assert e.max() - e.min() < 1.5 * omega * h * oscillation
    second = len(e) // 60
    assert abs(e[-10 * second :].mean() - e[: 10 * second].mean()) < 0.01 * oscillation


def body(path, *, repair: bool = False):
    """A mesh file as a closed floating body, as ``bakeshop float MESH`` loads it."""
    from bakeshop.buoyancy.shapes import closed_mesh
    from bakeshop.io import load_mesh

    return closed_mesh(load_mesh(path), repair=repair, path=path)
