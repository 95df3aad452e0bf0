"""Meshes of floating bodies: loading from files and the built-in test shapes.

Every mesh this module returns is a closed, consistently oriented :class:`trimesh.Trimesh` in
metres, +Y up (the bakeshop world frame). Built-in shapes are about a metre across; ``size``
rescales them (a number sets the longest side, three numbers set the bounding box's extents).
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Callable, Sequence

import numpy as np
import trimesh
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.errors import ArgumentError, FormatError, UnsupportedError, validate_choice
from bakeshop.io.mesh import Mesh
from bakeshop.resources import Cost, require

#: Peak bytes per triangle of closing a mesh and making its body (trimesh's processed mesh,
#: its edge tables and normals, then the body's voxel sample points and convex hull): measured
#: at 520 for the closing and 754 with the body, on a 1.3-million-triangle icosphere.
FACE_BYTES = 800
#: Seconds per triangle to close a mesh and then sample its body (measured: 9.9 s for a
#: 327,680-triangle icosphere on two busy cores, 4.5 s on quiet ones).
FACE_SECONDS = 30e-6
#: Closing a mesh estimated to take (with its sampling) longer than this says so in its
#: progress line.
SLOW_SECONDS = 10

#: Names of the built-in shapes, in the order the test bench lists them.
SHAPES = ("box", "sphere", "capsule", "cylinder", "torus", "peep", "hull")


def make_shape(
    name: str, *, size: float | tuple[float, float, float] | None = None
) -> trimesh.Trimesh:
    """Build one of the :data:`SHAPES` as a closed mesh centred on its bounding box.

    Parameters
    ----------
    name : str
        ``box`` (1 m cube), ``sphere`` (1 m diameter), ``capsule`` (1 m long, 0.5 m thick,
        lying along X), ``cylinder`` (1 m long, 1 m diameter, lying along X), ``torus``
        (1 m across, tube 0.25 m, lying flat), ``peep`` (a marshmallow-peep-like bird, 1 m
        long) or ``hull`` (a boat hull, 1 m long, 0.4 m beam, deck on top).
    size : float or (3,) float, optional
        Longest side in metres, or the extents (X, Y, Z) of the bounding box in metres.

    Returns
    -------
    trimesh.Trimesh
        Watertight mesh, outward normals, metres.
    """
    validate_choice(name, SHAPES, "shape")
    if name == "box":
        mesh = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    elif name == "sphere":
        mesh = trimesh.creation.icosphere(subdivisions=5, radius=0.5)
    elif name == "capsule":
        mesh = trimesh.creation.capsule(height=0.5, radius=0.25, count=(64, 64))
        mesh.apply_transform(_rotation_to_x())
    elif name == "cylinder":
        mesh = trimesh.creation.cylinder(radius=0.5, height=1.0, sections=256)
        mesh.apply_transform(_rotation_to_x())
    elif name == "torus":
        mesh = trimesh.creation.torus(0.375, 0.125, major_sections=96, minor_sections=48)
        mesh.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1, 0, 0)))
    elif name == "peep":
        mesh = resize(_peep(), 1.0)
    else:
        mesh = _hull()
    mesh.apply_translation(-mesh.bounds.mean(axis=0))
    return resize(mesh, size)


def resize(
    mesh: trimesh.Trimesh, size: float | tuple[float, float, float] | None
) -> trimesh.Trimesh:
    """Scale ``mesh`` in place so its longest side is ``size`` (a number) or its bounding box
    has extents ``size`` (three numbers, metres); ``None`` leaves it alone. Returns ``mesh``."""
    if size is None:
        return mesh
    target = np.asarray(size, dtype=np.float64)
    if target.ndim > 1 or target.size not in (1, 3) or not np.all(np.isfinite(target)):
        raise ArgumentError(f"size must be one number or three numbers, got {size!r}")
    if np.any(target <= 0):
        raise ArgumentError(f"size must be positive, got {size!r}")
    extents = mesh.extents
    scale = target / extents.max() if target.size == 1 else target / extents
    mesh.apply_transform(np.diag([*np.broadcast_to(scale, 3), 1.0]))
    return mesh


def closed_mesh(
    mesh: Mesh | trimesh.Trimesh, *, repair: bool = False, path: str | os.PathLike | None = None
) -> trimesh.Trimesh:
    """A mesh as a closed body for floating: welded and checked.

    Vertices that are duplicated only for texture or normal seams are welded, and the mesh
    must then be watertight with a positive volume.

    Parameters
    ----------
    mesh : bakeshop.io.mesh.Mesh or trimesh.Trimesh
        As :func:`bakeshop.io.load_mesh` reads it, in metres, +Y up.
    repair : bool
        Try to close the mesh (fill holes, fix winding) instead of refusing it. A mesh that is
        still open afterwards is refused anyway.
    path : path-like, optional
        The file it came from, named in errors.

    Returns
    -------
    trimesh.Trimesh
        Watertight, outward normals.

    Raises
    ------
    FormatError
        Not watertight (without a successful repair), or no volume.
    """
    vertices = mesh.positions if isinstance(mesh, Mesh) else mesh.vertices
    cost = require(closed_mesh_cost(len(mesh.faces)), path)
    seconds = round(FACE_SECONDS * cost.work)
    slow = f", about {seconds} s with its sampling" if seconds > SLOW_SECONDS else ""
    with progress.step(f"closing the mesh ({cost.work:,} triangles{slow})"):
        return _closed(vertices, mesh.faces, repair, path)


def closed_mesh_cost(faces: int) -> Cost:
    """What :func:`closed_mesh` of a mesh of ``faces`` triangles holds at its peak
    (:data:`FACE_BYTES` per triangle); ``work`` is in triangles."""
    return Cost(FACE_BYTES * faces, faces, f"closing a mesh of {faces:,} triangles")


def _closed(
    vertices: ArrayLike, faces: ArrayLike, repair: bool, path: str | os.PathLike | None
) -> trimesh.Trimesh:
    body = trimesh.Trimesh(np.asarray(vertices), np.asarray(faces), process=True)
    if not np.all(np.isfinite(body.vertices)):
        raise FormatError("the mesh has non-finite vertex coordinates", path)
    body.merge_vertices(merge_tex=True, merge_norm=True)
    body.remove_unreferenced_vertices()
    if not body.is_watertight and repair:
        if importlib.util.find_spec("networkx") is None:
            raise UnsupportedError(
                "repairing a mesh needs networkx: pip install 'bakeshop[buoyancy]'", path
            )
        trimesh.repair.fill_holes(body)
        body.merge_vertices(merge_tex=True, merge_norm=True)
    if not body.is_watertight:
        hint = "" if repair else " (repair=True / --repair tries to close it)"
        raise FormatError(
            f"the mesh is not watertight: {_edge_defects(body)}, so it has no inside to "
            f"float{hint}",
            path,
        )
    trimesh.repair.fix_normals(body)
    if not body.volume > 0:
        raise FormatError("the mesh encloses no volume", path)
    return body


def _edge_defects(mesh: trimesh.Trimesh) -> str:
    """What keeps a welded mesh from being closed: edges of one triangle (holes) and edges of
    three or more (non-manifold: fins, T-junctions, meshes touching along an edge)."""
    _, uses = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
    defects = [
        f"{n:,} {what}"
        for n, what in (
            (int((uses == 1).sum()), "open edges (of one triangle)"),
            (int((uses > 2).sum()), "non-manifold edges (shared by 3 or more triangles)"),
        )
        if n
    ]
    return " and ".join(defects)


def _rotation_to_x() -> np.ndarray:
    """Turn trimesh's Z-axis primitives to lie along X."""
    return trimesh.transformations.rotation_matrix(np.pi / 2, (0, 1, 0))


def _star_mesh(
    inside: Callable[[np.ndarray], np.ndarray],
    centre: np.ndarray,
    radius: float,
    subdivisions: int = 4,
) -> trimesh.Trimesh:
    """Mesh the outermost surface of the implicit solid ``inside(p) < 0`` seen from ``centre``.

    Each vertex of an icosphere is pushed along its ray to where the solid's boundary is last
    crossed (marched inwards from ``radius``, then bisected), so the result has the icosphere's
    closed topology; concave necks that rays cannot see are bridged.
    """
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    dirs = sphere.vertices
    steps = np.linspace(radius, 0.0, 160)
    values = np.stack([inside(centre + dirs * r) for r in steps])  # (steps, V)
    first_inside = np.argmax(values < 0, axis=0)
    hi = steps[np.maximum(first_inside - 1, 0)]  # outside
    lo = steps[first_inside]  # inside
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        out = inside(centre + dirs * mid[:, None]) >= 0
        hi = np.where(out, mid, hi)
        lo = np.where(out, lo, mid)
    vertices = centre + dirs * (0.5 * (lo + hi))[:, None]
    return trimesh.Trimesh(vertices, sphere.faces, process=False)


def _ellipsoid(p: np.ndarray, centre: ArrayLike, axes: Sequence[float]) -> np.ndarray:
    q = (p - np.asarray(centre)) / np.asarray(axes)
    return (np.linalg.norm(q, axis=-1) - 1.0) * min(axes)


def _smooth_min(a: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    h = np.clip(0.5 + 0.5 * (b - a) / k, 0.0, 1.0)
    return b + (a - b) * h - k * h * (1.0 - h)


def _peep() -> trimesh.Trimesh:
    """A marshmallow peep: flat-bottomed body, raised head in front, a tail tuft behind."""

    def inside(p: np.ndarray) -> np.ndarray:
        body = _ellipsoid(p, (0.0, 0.22, 0.0), (0.42, 0.24, 0.2))
        head = _ellipsoid(p, (0.24, 0.48, 0.0), (0.16, 0.17, 0.15))
        tail = _ellipsoid(p, (-0.36, 0.36, 0.0), (0.12, 0.1, 0.09))
        blob = _smooth_min(_smooth_min(body, head, 0.1), tail, 0.06)
        return np.maximum(blob, 0.02 - p[..., 1])  # flat bottom

    return _star_mesh(inside, np.array([0.02, 0.3, 0.0]), 1.0)


def _hull(stations: int = 64, ring: int = 48) -> trimesh.Trimesh:
    """A boat hull: lofted U sections with a flat deck, fine bow (+X) and a transom stern."""
    length, beam, deck, keel = 1.0, 0.4, 0.1, 0.16
    x = np.linspace(-0.5, 0.5, stations) * length
    u = np.clip(x / (0.5 * length), -1.0, 1.0)
    half_beam = 0.5 * beam * np.where(u > 0, np.sqrt(np.clip(1 - u**2, 0, 1)), 1 - 0.3 * u**4)
    half_beam = np.maximum(half_beam, 0.004)
    depth = keel * np.where(u > 0, np.sqrt(np.clip(1 - u**3, 0, 1)), 1 - 0.5 * u**2)
    depth = np.maximum(depth, 0.01)
    t = np.linspace(-np.pi / 2, np.pi / 2, ring)
    # A U section: sides flare out near the deck, the bottom is rounded.
    z = np.sin(t)[None, :] * half_beam[:, None]
    y = deck - (deck + depth[:, None]) * np.cos(t)[None, :] ** 0.6
    rings = np.stack([np.broadcast_to(x[:, None], z.shape), y, z], axis=-1)  # (S, R, 3)
    return _loft(rings)


def _loft(rings: np.ndarray) -> trimesh.Trimesh:
    """Close a stack of closed polygon rings (S, R, 3) into a watertight tube with end caps."""
    n_st, n_r, _ = rings.shape
    vertices = rings.reshape(-1, 3)
    idx = np.arange(n_st * n_r).reshape(n_st, n_r)
    a = idx[:-1]
    b = np.roll(idx[:-1], -1, axis=1)
    c = idx[1:]
    d = np.roll(idx[1:], -1, axis=1)
    sides = np.concatenate([np.stack([a, b, d], -1), np.stack([a, d, c], -1)]).reshape(-1, 3)
    centres = rings[[0, -1]].mean(axis=1)
    first, last = len(vertices), len(vertices) + 1
    ring0, ring1 = idx[0], idx[-1]
    cap0 = np.stack([np.full(n_r, first), np.roll(ring0, -1), ring0], -1)
    cap1 = np.stack([np.full(n_r, last), ring1, np.roll(ring1, -1)], -1)
    mesh = trimesh.Trimesh(
        np.vstack([vertices, centres]), np.vstack([sides, cap0, cap1]), process=True
    )
    trimesh.repair.fix_normals(mesh)
    return mesh
