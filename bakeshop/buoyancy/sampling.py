"""Voxelisation of a closed mesh into buoyancy sample points.

The mesh's bounding box is cut into cubic cells; each cell that holds some of the solid becomes
one sample point at the centroid of its inside part, carrying the inside volume. Inside volume
is integrated by casting vertical rays through a grid of ``subsamples x subsamples`` columns per
cell: along each ray the solid's extent is exact (the crossings of the ray with the triangles,
signed by the triangle's facing, give a winding number), so only the horizontal integral is
sampled (midpoint rule). Volumes therefore converge quickly to the mesh volume and are exact for
boxes aligned with the grid.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from bakeshop.buoyancy import _native
from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    import trimesh

#: Upper bound on cells (points before culling) so a typo cannot allocate gigabytes.
MAX_CELLS = 4_000_000


@dataclass(frozen=True)
class SamplePoints:
    """Buoyancy sample points of one body, in the mesh's frame.

    Attributes
    ----------
    positions : (N, 3) float64
        Centroid of the inside part of each cell, metres.
    volumes : (N,) float64
        Inside volume of each cell, m^3; sums to the mesh volume (within the sampling error).
    heights : (N,) float64
        Height of the vertical column each point stands for, metres: its volume divided by the
        horizontal area of its cell that holds some solid (the cell side for a full cell, less
        where the solid ends inside the cell, e.g. at the bottom of a sphere).
    cell : float
        Cell side, metres.
    """

    positions: np.ndarray
    volumes: np.ndarray
    heights: np.ndarray
    cell: float

    def __len__(self) -> int:
        return len(self.volumes)


def sample_points(
    mesh: trimesh.Trimesh, *, resolution: int = 10, subsamples: int = 4
) -> SamplePoints:
    """Voxelise a closed mesh into sample points with the volume of their cell's inside.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Closed, outward-oriented mesh (as :func:`bakeshop.buoyancy.shapes.load_mesh` returns).
    resolution : int
        Cells along the longest side of the bounding box; the cell side is
        ``max(extents) / resolution``.
    subsamples : int
        Vertical rays per cell along X and along Z (``subsamples**2`` rays per cell).

    Returns
    -------
    SamplePoints
    """
    if not (isinstance(resolution, int | np.integer) and 1 <= resolution <= 1000):
        raise ArgumentError(f"resolution must be an integer in 1..1000, got {resolution!r}")
    if not (isinstance(subsamples, int | np.integer) and 1 <= subsamples <= 64):
        raise ArgumentError(f"subsamples must be an integer in 1..64, got {subsamples!r}")
    lo, hi = mesh.bounds
    cell = float((hi - lo).max()) / resolution
    shape = np.maximum(np.ceil((hi - lo) / cell - 1e-9).astype(np.int64), 1)
    if int(np.prod(shape)) > MAX_CELLS:
        raise ArgumentError(f"{int(np.prod(shape))} cells exceed the limit of {MAX_CELLS}")
    triangles = np.ascontiguousarray(mesh.triangles, dtype=np.float64)
    # A tiny irrational offset keeps rays off vertices and edges that sit on grid lines.
    jitter = cell * np.array([1.2345678e-7, 0.0, 2.7182818e-7])
    volume, moment, area = _voxelise(triangles, lo + jitter, cell, shape, subsamples)
    keep = volume > 1e-12 * cell**3
    volumes = volume[keep]
    positions = moment[keep] / volumes[:, None]
    heights = np.minimum(volumes / area[keep], cell)
    return SamplePoints(positions=positions - jitter, volumes=volumes, heights=heights, cell=cell)


def _voxelise(
    triangles: np.ndarray, origin: np.ndarray, cell: float, shape: np.ndarray, sub: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    nx, nz = int(shape[0]) * sub, int(shape[2]) * sub
    step = cell / sub
    counts = np.zeros(nx * nz, dtype=np.int64)
    empty_f, empty_i = np.zeros(0), np.zeros(0, dtype=np.int64)
    # rays (i, k) at (x0 + (i + 0.5) step, z0 + (k + 0.5) step): first count the hits per ray,
    # then write each hit's height and winding sign into the CSR lists
    _native.crossings(
        triangles, origin[0], origin[2], step, nx, nz, counts, empty_f, empty_i, counts, False
    )
    offsets = np.zeros(nx * nz + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    hits_y = np.empty(offsets[-1])
    hits_w = np.empty(offsets[-1], dtype=np.int64)
    counts[:] = 0
    _native.crossings(
        triangles, origin[0], origin[2], step, nx, nz, counts, hits_y, hits_w, offsets, True
    )
    n_cells = int(np.prod(shape))
    volume = np.zeros(n_cells)
    moment = np.zeros((n_cells, 3))
    area = np.zeros(n_cells)
    # the inside intervals of every ray into the cells: volume, first moments, wet area
    _native.accumulate(
        hits_y,
        hits_w,
        offsets,
        origin[0],
        origin[1],
        origin[2],
        cell,
        np.asarray(shape, dtype=np.int64),
        sub,
        volume,
        moment,
        area,
    )
    return volume, moment, area
